// Per-frame and per-draw state as the GPU's stages read it: the register
// values a driver would program. Written once before the frame starts and
// immutable while it runs, so packets name a draw by its id instead of
// carrying its state.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "hw/render_state.h"
#include "hw/texture_state.h"
#include "hw/varying_layout.h"

namespace gpusim {

// The framebuffer a scene asks for: width x height is the image written out.
// Antialiasing (docs/pipeline-spec.md, section 14): `samples` coverage and
// depth samples per pixel (1, 2, 4, 8 or 16, at Direct3D's standard
// positions), and supersampling by `supersample` = k: the frame is rendered
// at k * width x k * height and box-filtered down. In FrameState, the GPU's
// registers, width and height are the render target's (already times k).
struct FramebufferDesc {
  int width = 256;
  int height = 256;
  unsigned samples = 1;
  unsigned supersample = 1;
  ColorFormat color_format = ColorFormat::rgba8;
  DepthFormat depth_format = DepthFormat::unorm24;
  glm::vec4 clear_color{0.0f, 0.0f, 0.0f, 1.0f};
  float clear_depth = 1.0f;
};

// A clear in the middle of a frame's draw list (docs/pipeline-spec.md,
// section 15): every sample of the colour buffer, the depth buffer or both
// (at least one) takes the value, converted as the frame's clear converts
// it, after draws [0, before_draw) and before the rest.
struct ClearState {
  bool color = false;
  bool depth = false;
  glm::vec4 color_value{0.0f, 0.0f, 0.0f, 1.0f};
  float depth_value = 1.0f;
  uint32_t before_draw = 0;
  bool operator==(const ClearState& o) const {
    return color == o.color && depth == o.depth && color_value == o.color_value &&
           depth_value == o.depth_value && before_draw == o.before_draw;
  }
};

enum class LightType : uint8_t { directional, point };

// A fixed-function light, already transformed into eye space.
struct Light {
  LightType type = LightType::directional;
  // directional: unit vector from the surface towards the light (eye space);
  // point: the light's position (eye space).
  glm::vec3 vector{0.0f, 0.0f, 1.0f};
  glm::vec4 ambient{0.0f, 0.0f, 0.0f, 1.0f};
  glm::vec4 diffuse{1.0f, 1.0f, 1.0f, 1.0f};
  glm::vec4 specular{1.0f, 1.0f, 1.0f, 1.0f};
  // Point lights: 1 / (constant + linear * d + quadratic * d^2).
  float constant_attenuation = 1.0f;
  float linear_attenuation = 0.0f;
  float quadratic_attenuation = 0.0f;
};

struct Material {
  glm::vec4 ambient{0.2f, 0.2f, 0.2f, 1.0f};
  glm::vec4 diffuse{0.8f, 0.8f, 0.8f, 1.0f};
  glm::vec4 specular{0.0f, 0.0f, 0.0f, 1.0f};
  glm::vec4 emission{0.0f, 0.0f, 0.0f, 1.0f};
  float shininess = 0.0f;
};

// Where a draw's arrays live in GPU memory. Attributes are tightly packed
// float32: position 16 bytes (x, y, z, w), normal 12 (x, y, z), colour 16
// (r, g, b, a), texture coordinate 8 (s, t); indices are uint32. An address
// of kNoBuffer means absent.
constexpr uint64_t kNoBuffer = ~uint64_t{0};
struct DrawBuffers {
  uint64_t positions = kNoBuffer;
  uint64_t normals = kNoBuffer;
  uint64_t colors = kNoBuffer;
  uint64_t texcoords = kNoBuffer;
  uint64_t indices = kNoBuffer;
  uint32_t vertex_count = 0;  // positions
  uint32_t slot_count = 0;    // indices when indexed, else vertex_count
};

struct DrawState {
  PrimitiveType primitive = PrimitiveType::triangles;
  DrawBuffers buffers;
  bool lighting = false;
  Material material;
  glm::mat4 model_view{1.0f};
  glm::mat4 mvp{1.0f};
  glm::mat3 normal_matrix{1.0f};
  RenderState state;
  // Texturing (docs/pipeline-spec.md, section 9c): the texture stage's
  // binding; off unless the draw is textured (it then has texcoords).
  TextureBinding texture;
  int64_t first_primitive_id = 0;  // id of the draw's first assembled primitive
  // What the components of its vertices' Varyings hold: varying_layout_for()
  // of this draw, set when the frame state is built. The default is the same
  // colour-only layout, so a DrawState built by hand (tests) is consistent.
  VaryingLayout varyings;
};

// The varyings a draw's vertices carry, laid out once per draw when the frame
// state is built (testbench/sim/gpu_run.cpp, load_frame). Every draw carries
// its colour (a point's, or a flat primitive's, even in a Phong draw). A lit
// Phong draw (lighting on, normals present) adds the eye-space normal and
// position (docs/pipeline-spec.md, section 9b): components 0-3 colour, 4-6
// normal, 7-9 position. A textured draw adds its texture coordinate (s, t)
// after them (section 9c).
inline bool lit_per_pixel(const DrawState& draw) {
  return draw.state.shading == Shading::phong && draw.lighting && draw.buffers.normals != kNoBuffer;
}
inline VaryingLayout varying_layout_for(const DrawState& draw) {
  VaryingLayout layout;
  layout.count = 0;
  layout.color = static_cast<uint8_t>(layout.append(kColorComponents));
  if (lit_per_pixel(draw)) {
    layout.normal = static_cast<uint8_t>(layout.append(3));
    layout.eye = static_cast<uint8_t>(layout.append(3));
  }
  if (draw.texture.enabled()) layout.texcoord = static_cast<uint8_t>(layout.append(2));
  return layout;
}

// The colour buffer stores 4 bytes (rgba8) or 8 bytes (rgba16f, half bits)
// per sample; the depth buffer 2 bytes (unorm16) or 4 (unorm24 in the low 24
// bits, float32). Both row-major, row 0 = bottom row, little endian, a
// pixel's samples adjacent.
struct FrameState {
  FramebufferDesc framebuffer;
  glm::vec4 global_ambient{0.2f, 0.2f, 0.2f, 1.0f};
  std::vector<Light> lights;
  std::vector<DrawState> draws;
  // The draw list's clears, in order (before_draw non-decreasing). The
  // command stream's clear tokens carry no value: a frame's n-th clear token
  // executes clear(n), the frame clear for n = 0 (docs/architecture.md,
  // "Clears").
  std::vector<ClearState> clears;
  uint64_t color_address = 0;  // N samples per pixel, adjacent
  uint64_t depth_address = 0;  // likewise
  // Multisampled or supersampled frames: where the resolve writes the
  // output image (width / supersample x height / supersample pixels, one
  // sample each, in the colour format).
  uint64_t resolve_address = 0;
  // Clear token n of the frame: 0 is the frame clear (both buffers, the
  // framebuffer's clear values), n > 0 is clears[n - 1].
  ClearState clear(size_t n) const {
    if (n > 0) return clears.at(n - 1);
    return ClearState{true, true, framebuffer.clear_color, framebuffer.clear_depth, 0};
  }
  bool needs_resolve() const { return framebuffer.samples > 1 || framebuffer.supersample > 1; }
  // Whether a draw is textured: the units then have texture units.
  bool textured() const {
    for (const DrawState& d : draws) {
      if (d.texture.enabled()) return true;
    }
    return false;
  }
};

inline unsigned color_bytes_per_pixel(ColorFormat f) {
  return f == ColorFormat::rgba8 ? 4 : 8;
}
inline unsigned depth_bytes_per_pixel(DepthFormat f) {
  return f == DepthFormat::unorm16 ? 2 : 4;
}

}  // namespace gpusim
