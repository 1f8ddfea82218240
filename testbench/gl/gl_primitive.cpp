#include "testbench/gl/gl_primitive.h"

#include "testbench/gl/gl_enums.h"

namespace gpusim::gl {

std::optional<GlAssembly> assemble_gl_primitive(uint32_t mode, uint32_t n) {
  GlAssembly a;
  std::vector<uint32_t>& out = a.indices;
  const auto tri = [&](uint32_t i, uint32_t j, uint32_t k) { out.insert(out.end(), {i, j, k}); };
  switch (mode) {
    case en::POINTS:
      a.type = PrimitiveType::points;
      for (uint32_t i = 0; i < n; ++i) out.push_back(i);
      break;
    case en::LINES:
      a.type = PrimitiveType::lines;
      for (uint32_t i = 0; i + 1 < n; i += 2) out.insert(out.end(), {i, i + 1});
      break;
    case en::LINE_STRIP:
    case en::LINE_LOOP:
      a.type = mode == en::LINE_STRIP ? PrimitiveType::line_strip : PrimitiveType::line_loop;
      if (n >= 2) {
        for (uint32_t i = 0; i < n; ++i) out.push_back(i);
      }
      break;
    case en::TRIANGLES:
      for (uint32_t i = 0; i + 2 < n; i += 3) tri(i, i + 1, i + 2);
      break;
    case en::TRIANGLE_STRIP:
      // Odd triangles swap their first two vertices (one winding); the last
      // is GL's provoking vertex, i + 2, either way.
      for (uint32_t i = 0; i + 2 < n; ++i) {
        if (i % 2 == 0) {
          tri(i, i + 1, i + 2);
        } else {
          tri(i + 1, i, i + 2);
        }
      }
      break;
    case en::TRIANGLE_FAN:
      for (uint32_t i = 1; i + 1 < n; ++i) tri(0, i, i + 1);
      break;
    case en::QUADS:
      for (uint32_t i = 0; i + 3 < n; i += 4) tri(i, i + 1, i + 3), tri(i + 1, i + 2, i + 3);
      break;
    case en::QUAD_STRIP:
      // Quad i is the polygon (2i, 2i+1, 2i+3, 2i+2), provoked by 2i+3.
      for (uint32_t i = 0; i + 3 < n; i += 2) tri(i + 2, i, i + 3), tri(i, i + 1, i + 3);
      break;
    case en::POLYGON:
      // The fan (0, i, i+1) rotated to (i, i+1, 0): same winding, vertex 0 last.
      for (uint32_t i = 1; i + 1 < n; ++i) tri(i, i + 1, 0);
      break;
    default:
      return std::nullopt;
  }
  return a;
}

const char* gl_primitive_name(uint32_t mode) {
  static const char* const names[] = {
      "GL_POINTS",         "GL_LINES",        "GL_LINE_LOOP", "GL_LINE_STRIP", "GL_TRIANGLES",
      "GL_TRIANGLE_STRIP", "GL_TRIANGLE_FAN", "GL_QUADS",     "GL_QUAD_STRIP", "GL_POLYGON"};
  return mode <= en::POLYGON ? names[mode] : "an unknown primitive";
}

}  // namespace gpusim::gl
