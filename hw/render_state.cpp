#include "hw/render_state.h"

#include <algorithm>
#include <tuple>

namespace gpusim {
namespace {

template <typename Enum, size_t N>
using NameTable = std::array<std::string_view, N>;

constexpr NameTable<PrimitiveType, 7> kPrimitiveNames{
    "triangles", "triangle_strip", "triangle_fan", "points", "lines", "line_strip", "line_loop"};
constexpr NameTable<LineRasterization, 2> kLineRasterizationNames{"diamond_exit", "bresenham"};
constexpr NameTable<PolygonMode, 3> kPolygonModeNames{"fill", "line", "point"};
constexpr NameTable<CullMode, 3> kCullNames{"none", "back", "front"};
constexpr NameTable<FrontFace, 2> kFrontFaceNames{"ccw", "cw"};
constexpr NameTable<CompareFunc, 8> kCompareNames{"never",   "less",     "equal",  "lequal",
                                                  "greater", "notequal", "gequal", "always"};
constexpr NameTable<BlendFactor, 11> kBlendFactorNames{"zero",
                                                       "one",
                                                       "src_color",
                                                       "one_minus_src_color",
                                                       "dst_color",
                                                       "one_minus_dst_color",
                                                       "src_alpha",
                                                       "one_minus_src_alpha",
                                                       "dst_alpha",
                                                       "one_minus_dst_alpha",
                                                       "src_alpha_saturate"};
constexpr NameTable<BlendEquation, 3> kBlendEquationNames{"add", "subtract", "reverse_subtract"};
constexpr NameTable<Shading, 3> kShadingNames{"flat", "gouraud", "phong"};
constexpr NameTable<ProvokingVertex, 2> kProvokingVertexNames{"last", "first"};
constexpr NameTable<Interpolation, 2> kInterpolationNames{"perspective", "screen"};
constexpr NameTable<ColorFormat, 2> kColorFormatNames{"rgba8", "rgba16f"};
constexpr NameTable<DepthFormat, 3> kDepthFormatNames{"unorm16", "unorm24", "float32"};
constexpr NameTable<TextureFormat, 8> kTextureFormatNames{
    "alpha8", "luminance8", "luminance_alpha8", "intensity8",
    "rgb8",   "rgba8",      "rgb565",           "rgba4444"};
constexpr NameTable<TextureWrap, 4> kTextureWrapNames{"repeat", "clamp_to_edge", "clamp",
                                                      "mirrored_repeat"};
constexpr NameTable<TextureFilter, 6> kTextureFilterNames{"nearest",
                                                          "linear",
                                                          "nearest_mipmap_nearest",
                                                          "linear_mipmap_nearest",
                                                          "nearest_mipmap_linear",
                                                          "linear_mipmap_linear"};
constexpr NameTable<TextureEnvMode, 5> kTextureEnvModeNames{"modulate", "replace", "decal", "blend",
                                                            "add"};

template <typename Enum>
constexpr const auto& names_of();
template <>
constexpr const auto& names_of<PrimitiveType>() {
  return kPrimitiveNames;
}
template <>
constexpr const auto& names_of<CullMode>() {
  return kCullNames;
}
template <>
constexpr const auto& names_of<FrontFace>() {
  return kFrontFaceNames;
}
template <>
constexpr const auto& names_of<CompareFunc>() {
  return kCompareNames;
}
template <>
constexpr const auto& names_of<BlendFactor>() {
  return kBlendFactorNames;
}
template <>
constexpr const auto& names_of<BlendEquation>() {
  return kBlendEquationNames;
}
template <>
constexpr const auto& names_of<LineRasterization>() {
  return kLineRasterizationNames;
}
template <>
constexpr const auto& names_of<PolygonMode>() {
  return kPolygonModeNames;
}
template <>
constexpr const auto& names_of<Shading>() {
  return kShadingNames;
}
template <>
constexpr const auto& names_of<ProvokingVertex>() {
  return kProvokingVertexNames;
}
template <>
constexpr const auto& names_of<Interpolation>() {
  return kInterpolationNames;
}
template <>
constexpr const auto& names_of<ColorFormat>() {
  return kColorFormatNames;
}
template <>
constexpr const auto& names_of<DepthFormat>() {
  return kDepthFormatNames;
}
template <>
constexpr const auto& names_of<TextureFormat>() {
  return kTextureFormatNames;
}
template <>
constexpr const auto& names_of<TextureWrap>() {
  return kTextureWrapNames;
}
template <>
constexpr const auto& names_of<TextureFilter>() {
  return kTextureFilterNames;
}
template <>
constexpr const auto& names_of<TextureEnvMode>() {
  return kTextureEnvModeNames;
}

template <typename Enum>
std::string_view name_of(Enum v) {
  const auto& names = names_of<Enum>();
  const auto i = static_cast<size_t>(v);
  return i < names.size() ? names[i] : std::string_view("invalid");
}

}  // namespace

std::string_view to_string(PrimitiveType v) {
  return name_of(v);
}
std::string_view to_string(CullMode v) {
  return name_of(v);
}
std::string_view to_string(FrontFace v) {
  return name_of(v);
}
std::string_view to_string(CompareFunc v) {
  return name_of(v);
}
std::string_view to_string(BlendFactor v) {
  return name_of(v);
}
std::string_view to_string(BlendEquation v) {
  return name_of(v);
}
std::string_view to_string(Shading v) {
  return name_of(v);
}
std::string_view to_string(ProvokingVertex v) {
  return name_of(v);
}
std::string_view to_string(Interpolation v) {
  return name_of(v);
}
std::string_view to_string(LineRasterization v) {
  return name_of(v);
}
std::string_view to_string(PolygonMode v) {
  return name_of(v);
}
std::string_view to_string(ColorFormat v) {
  return name_of(v);
}
std::string_view to_string(DepthFormat v) {
  return name_of(v);
}
std::string_view to_string(TextureFormat v) {
  return name_of(v);
}
std::string_view to_string(TextureWrap v) {
  return name_of(v);
}
std::string_view to_string(TextureFilter v) {
  return name_of(v);
}
std::string_view to_string(TextureEnvMode v) {
  return name_of(v);
}

template <typename Enum>
std::optional<Enum> enum_from_string(std::string_view name) {
  const auto& names = names_of<Enum>();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<Enum>(i);
  }
  return std::nullopt;
}

template <typename Enum>
std::string enum_names() {
  std::string out;
  for (auto n : names_of<Enum>()) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

#define GPUSIM_INSTANTIATE(E)                                      \
  template std::optional<E> enum_from_string<E>(std::string_view); \
  template std::string enum_names<E>();
GPUSIM_INSTANTIATE(PrimitiveType)
GPUSIM_INSTANTIATE(CullMode)
GPUSIM_INSTANTIATE(FrontFace)
GPUSIM_INSTANTIATE(CompareFunc)
GPUSIM_INSTANTIATE(BlendFactor)
GPUSIM_INSTANTIATE(BlendEquation)
GPUSIM_INSTANTIATE(Shading)
GPUSIM_INSTANTIATE(ProvokingVertex)
GPUSIM_INSTANTIATE(Interpolation)
GPUSIM_INSTANTIATE(LineRasterization)
GPUSIM_INSTANTIATE(PolygonMode)
GPUSIM_INSTANTIATE(ColorFormat)
GPUSIM_INSTANTIATE(DepthFormat)
GPUSIM_INSTANTIATE(TextureFormat)
GPUSIM_INSTANTIATE(TextureWrap)
GPUSIM_INSTANTIATE(TextureFilter)
GPUSIM_INSTANTIATE(TextureEnvMode)
#undef GPUSIM_INSTANTIATE

PrimitiveKind primitive_kind_of(PrimitiveType t) {
  switch (t) {
    case PrimitiveType::points:
      return PrimitiveKind::point;
    case PrimitiveType::lines:
    case PrimitiveType::line_strip:
    case PrimitiveType::line_loop:
      return PrimitiveKind::line;
    default:
      return PrimitiveKind::triangle;
  }
}

uint64_t primitive_count(PrimitiveType t, uint64_t n) {
  switch (t) {
    case PrimitiveType::triangles:
      return n / 3;
    case PrimitiveType::triangle_strip:
    case PrimitiveType::triangle_fan:
      return n >= 3 ? n - 2 : 0;
    case PrimitiveType::points:
      return n;
    case PrimitiveType::lines:
      return n / 2;
    case PrimitiveType::line_strip:
      return n >= 2 ? n - 1 : 0;
    case PrimitiveType::line_loop:
      return n >= 2 ? n : 0;
  }
  return 0;
}

bool RenderState::operator==(const RenderState& o) const {
  auto tie = [](const RenderState& s) {
    return std::tie(s.cull, s.front_face, s.depth_test, s.depth_func, s.depth_write,
                    s.offset_factor, s.offset_units, s.blend, s.blend_src, s.blend_dst,
                    s.blend_equation, s.color_mask, s.shading, s.line_width, s.point_size,
                    s.line_rasterization, s.polygon_mode, s.viewport, s.depth_near, s.depth_far,
                    s.scissor, s.provoking_vertex, s.interpolation);
  };
  return tie(*this) == tie(o);
}

std::ostream& operator<<(std::ostream& os, const RenderState& s) {
  os << "{cull=" << to_string(s.cull) << " front_face=" << to_string(s.front_face)
     << " depth=" << (s.depth_test ? to_string(s.depth_func) : "off")
     << " depth_write=" << s.depth_write << " offset=[" << s.offset_factor << "," << s.offset_units
     << "] blend=";
  if (s.blend) {
    os << to_string(s.blend_src) << "/" << to_string(s.blend_dst) << "/"
       << to_string(s.blend_equation);
  } else {
    os << "off";
  }
  os << " mask=" << s.color_mask[0] << s.color_mask[1] << s.color_mask[2] << s.color_mask[3]
     << " shading=" << to_string(s.shading) << " line_width=" << s.line_width
     << " point_size=" << s.point_size << " line_rasterization=" << to_string(s.line_rasterization)
     << " polygon_mode=" << to_string(s.polygon_mode) << " viewport=";
  if (s.viewport) {
    os << *s.viewport;
  } else {
    os << "full";
  }
  os << " depth_range=[" << s.depth_near << "," << s.depth_far << "] scissor=";
  if (s.scissor) {
    os << *s.scissor;
  } else {
    os << "off";
  }
  os << " provoking_vertex=" << to_string(s.provoking_vertex)
     << " interpolation=" << to_string(s.interpolation) << "}";
  return os;
}

std::ostream& operator<<(std::ostream& os, const PixelRect& r) {
  return os << "[" << r.x << "," << r.y << "," << r.width << "," << r.height << "]";
}

PixelBounds draw_bounds(const RenderState& s, int width, int height) {
  PixelBounds b{0, 0, width - 1, height - 1};
  const auto clip_to = [&b](const PixelRect& r) {
    b.x0 = std::max(b.x0, r.x);
    b.y0 = std::max(b.y0, r.y);
    b.x1 = std::min(b.x1, r.x + r.width - 1);
    b.y1 = std::min(b.y1, r.y + r.height - 1);
  };
  if (s.viewport) clip_to(*s.viewport);
  if (s.scissor) clip_to(*s.scissor);
  return b;
}

}  // namespace gpusim
