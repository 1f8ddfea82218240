// Pipeline state set per draw: the enumerations of the spec and their names
// as they appear in scene files and statistics.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>

#include "hw/primitive_kind.h"

namespace gpusim {

// Largest line width and point size, as llvmpipe's (GL's minimum maximum is 1).
constexpr float kMaxLineWidth = 255.0f;

enum class PrimitiveType : uint8_t {
  triangles,
  triangle_strip,
  triangle_fan,
  points,
  lines,
  line_strip,
  line_loop,
};
// Whether a draw of this type assembles points, lines or triangles.
PrimitiveKind primitive_kind_of(PrimitiveType t);
// Primitives a draw of `slots` vertex slots assembles (docs/pipeline-spec.md,
// section 3): partial primitives are ignored.
uint64_t primitive_count(PrimitiveType t, uint64_t slots);
// How a line is turned into fragments (docs/pipeline-spec.md, section 8b).
enum class LineRasterization : uint8_t { diamond_exit, bresenham };
// How a triangle that survives culling is drawn: filled, as its edges, or as
// its vertices (GL's glPolygonMode).
enum class PolygonMode : uint8_t { fill, line, point };
enum class CullMode : uint8_t { none, back, front };
enum class FrontFace : uint8_t { ccw, cw };
enum class CompareFunc : uint8_t { never, less, equal, lequal, greater, notequal, gequal, always };
enum class BlendFactor : uint8_t {
  zero,
  one,
  src_color,
  one_minus_src_color,
  dst_color,
  one_minus_dst_color,
  src_alpha,
  one_minus_src_alpha,
  dst_alpha,
  one_minus_dst_alpha,
  src_alpha_saturate,
};
enum class BlendEquation : uint8_t { add, subtract, reverse_subtract };
// phong: lit triangles and lines light every pixel from their interpolated
// eye-space normal and position (docs/pipeline-spec.md, section 9b); on an
// unlit draw it is gouraud.
enum class Shading : uint8_t { flat, gouraud, phong };
// Which vertex of a primitive gives a flat-shaded primitive its colour (GL's
// glProvokingVertex; docs/pipeline-spec.md, section 3).
enum class ProvokingVertex : uint8_t { last, first };
// How varyings are interpolated across a primitive: perspective-correct, or
// affine in window space (GLSL's noperspective; docs/pipeline-spec.md,
// sections 4 and 9). Depth is affine in window space either way.
enum class Interpolation : uint8_t { perspective, screen };
enum class ColorFormat : uint8_t { rgba8, rgba16f };
// Texturing (docs/pipeline-spec.md, section 9c; hw/texture_state.h): stored
// texel formats, wrap modes, filters and texture environments, GL 1.x's.
enum class TextureFormat : uint8_t {
  alpha8,
  luminance8,
  luminance_alpha8,
  intensity8,
  rgb8,
  rgba8,
  rgb565,
  rgba4444,
};
enum class TextureWrap : uint8_t { repeat, clamp_to_edge, clamp, mirrored_repeat };
enum class TextureFilter : uint8_t {
  nearest,
  linear,
  nearest_mipmap_nearest,
  linear_mipmap_nearest,
  nearest_mipmap_linear,
  linear_mipmap_linear,
};
enum class TextureEnvMode : uint8_t { modulate, replace, decal, blend, add };
enum class DepthFormat : uint8_t { unorm16, unorm24, float32 };

// A rectangle of window pixels, [x, x + width) x [y, y + height): a viewport
// or a scissor (docs/pipeline-spec.md, sections 5 and 8d).
struct PixelRect {
  int32_t x = 0, y = 0, width = 0, height = 0;
  bool operator==(const PixelRect& o) const {
    return x == o.x && y == o.y && width == o.width && height == o.height;
  }
  bool operator!=(const PixelRect& o) const { return !(*this == o); }
};
std::ostream& operator<<(std::ostream& os, const PixelRect& r);

struct RenderState {
  CullMode cull = CullMode::none;
  FrontFace front_face = FrontFace::ccw;
  // depth_test == false is GL's disabled depth test: every fragment passes and
  // the depth buffer is not written, whatever depth_write says.
  bool depth_test = true;
  CompareFunc depth_func = CompareFunc::less;
  bool depth_write = true;
  float offset_factor = 0.0f;
  float offset_units = 0.0f;
  bool blend = false;
  BlendFactor blend_src = BlendFactor::one;
  BlendFactor blend_dst = BlendFactor::zero;
  BlendEquation blend_equation = BlendEquation::add;
  std::array<bool, 4> color_mask{true, true, true, true};
  Shading shading = Shading::gouraud;
  ProvokingVertex provoking_vertex = ProvokingVertex::last;
  Interpolation interpolation = Interpolation::perspective;
  // Lines and points (docs/pipeline-spec.md, sections 8b and 8c): sizes in
  // pixels, 0 < size <= kMaxLineWidth.
  float line_width = 1.0f;
  float point_size = 1.0f;
  LineRasterization line_rasterization = LineRasterization::diamond_exit;
  PolygonMode polygon_mode = PolygonMode::fill;
  // Viewport (docs/pipeline-spec.md, section 5) in window pixels of the
  // render target; absent: the whole render target. Depth range: window z
  // of NDC z -1 and +1 (either order).
  std::optional<PixelRect> viewport;
  float depth_near = 0.0f, depth_far = 1.0f;
  // Scissor rectangle (section 8d), window pixels; absent: off.
  std::optional<PixelRect> scissor;

  bool operator==(const RenderState& o) const;
  bool operator!=(const RenderState& o) const { return !(*this == o); }
};
std::ostream& operator<<(std::ostream& os, const RenderState& s);

// The viewport a draw uses on a render target of width x height pixels.
inline PixelRect viewport_of(const RenderState& s, int width, int height) {
  return s.viewport ? *s.viewport : PixelRect{0, 0, width, height};
}
// The draw rectangle (section 8d): the pixels a draw may produce fragments
// in, the render target's intersected with the viewport and the scissor.
// Inclusive bounds; empty when x0 > x1 or y0 > y1.
struct PixelBounds {
  int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  bool contains(int64_t x, int64_t y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
  bool operator==(const PixelBounds& o) const {
    return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1;
  }
};
PixelBounds draw_bounds(const RenderState& s, int width, int height);
// A rectangle scaled by the supersampling factor k (every coordinate times k).
inline PixelRect scaled(const PixelRect& r, int k) {
  return PixelRect{r.x * k, r.y * k, r.width * k, r.height * k};
}

// Names used in scene files and stats ("triangle_strip", "lequal", ...).
std::string_view to_string(PrimitiveType v);
std::string_view to_string(CullMode v);
std::string_view to_string(FrontFace v);
std::string_view to_string(CompareFunc v);
std::string_view to_string(BlendFactor v);
std::string_view to_string(BlendEquation v);
std::string_view to_string(Shading v);
std::string_view to_string(ProvokingVertex v);
std::string_view to_string(Interpolation v);
std::string_view to_string(LineRasterization v);
std::string_view to_string(PolygonMode v);
std::string_view to_string(ColorFormat v);
std::string_view to_string(DepthFormat v);
std::string_view to_string(TextureFormat v);
std::string_view to_string(TextureWrap v);
std::string_view to_string(TextureFilter v);
std::string_view to_string(TextureEnvMode v);

// Parse a name; std::nullopt when it names no value.
template <typename Enum>
std::optional<Enum> enum_from_string(std::string_view name);

// Every name of an enumeration, for error messages ("expected one of ...").
template <typename Enum>
std::string enum_names();

}  // namespace gpusim
