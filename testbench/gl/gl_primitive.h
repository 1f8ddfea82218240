// OpenGL 1.x primitives (glBegin / glDrawArrays modes) decomposed into what
// the GPU assembles (docs/replay.md, "The driver"): every triangle-class mode
// becomes an independent triangle list, GL_LINES a line list, GL_POINTS a
// point list; GL_LINE_STRIP and GL_LINE_LOOP stay as they are (their shared
// vertices are drawn once, which a line list would not reproduce).
//
// The GPU's flat shading takes each primitive's last vertex, so every
// triangle is written with OpenGL's provoking vertex last (quads and quad
// strips: the quad's last vertex; polygons: the first vertex; strips and fans:
// the triangle's last vertex), its winding kept. Quads are split along the
// diagonal from their second to their fourth vertex, as Mesa's draw module
// does: (0, 1, 3), (1, 2, 3).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "hw/render_state.h"

namespace gpusim::gl {

struct GlAssembly {
  PrimitiveType type = PrimitiveType::triangles;  // triangles, lines, points, line_strip, line_loop
  // Into the call's vertices: 3 per triangle, 2 per line, 1 per point; for a
  // line strip or loop, its vertices in order. Incomplete primitives are
  // dropped as GL drops them.
  std::vector<uint32_t> indices;
};

// std::nullopt for a mode that is not one of GL's ten primitives.
std::optional<GlAssembly> assemble_gl_primitive(uint32_t mode, uint32_t count);
// "GL_QUAD_STRIP"; "0x1234" for an unknown mode.
const char* gl_primitive_name(uint32_t mode);

}  // namespace gpusim::gl
