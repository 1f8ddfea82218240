// Textures as the GPU's registers and memory hold them (docs/pipeline-spec.md,
// section 9c): the stored texel formats and how a stored texel becomes the
// RGBA8 value the sampler filters, a texture's sampler state, and the
// texture environment that combines the filtered texel with the fragment's
// colour. Number formats and spec constants only: the golden model and the
// texture unit each implement the sampling arithmetic themselves.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <ostream>
#include <vector>

#include "hw/render_state.h"

namespace gpusim {

// GL's largest texture side here (llvmpipe's is 16384): 12 bits of integer
// texel coordinate, and a mipmap chain of at most 13 levels.
constexpr int kMaxTextureSize = 4096;
constexpr unsigned kMaxTextureLevels = 13;
// The largest texture cache line (texture.cache_line_bytes). Texture levels
// are placed and padded in memory to multiples of it, so a line fill never
// reaches past the memory's end.
constexpr unsigned kMaxTextureCacheLine = 1024;

// Bytes one stored texel takes.
unsigned texel_bytes(TextureFormat f);

// A texel as the sampler filters it: r, g, b, a in 8 bits each, after GL's
// base-format expansion (GL 1.5, table 3.15 and section 3.8.13): ALPHA is
// (0, 0, 0, A), LUMINANCE (L, L, L, 255), LUMINANCE_ALPHA (L, L, L, A),
// INTENSITY (I, I, I, I), RGB (R, G, B, 255). RGB565 and RGBA4444 widen each
// channel to 8 bits by bit replication (v << 3 | v >> 2 for 5 bits), which
// is v * 255 / (2^n - 1) rounded to nearest for every n-bit value.
using Texel = std::array<uint8_t, 4>;
Texel expand_texel(TextureFormat f, const uint8_t* stored);
// A filtered texel channel as the texture environment reads it: v times the
// float nearest 1/255 (llvmpipe's conversion, measured: 1 ulp above the
// correctly rounded v / 255 for 126 of the 256 values).
inline float texel_value(uint8_t v) {
  return static_cast<float>(v) * (1.0f / 255.0f);
}
// The largest float below 1: the fraction a NEAREST REPEAT of a side that is
// not a power of two scales (spec section 9c).
constexpr float kBelowOne = 0.99999994f;
// Whether the format has colour channels (not ALPHA) and alpha (not RGB,
// LUMINANCE, RGB565): what the texture environment's table asks (GL 1.5,
// tables 3.22 and 3.23), by the format's base format.
enum class BaseFormat : uint8_t { alpha, luminance, luminance_alpha, intensity, rgb, rgba };
BaseFormat base_format(TextureFormat f);

// GL's default GL_TEXTURE_MIN_LOD is -1000, GL_TEXTURE_MAX_LOD 1000.
constexpr float kDefaultLodLimit = 1000.0f;

// A texture object's sampling state (GL's glTexParameter).
struct TextureSampler {
  TextureWrap wrap_s = TextureWrap::repeat;
  TextureWrap wrap_t = TextureWrap::repeat;
  // GL's defaults: NEAREST_MIPMAP_LINEAR minification, LINEAR magnification.
  TextureFilter min_filter = TextureFilter::nearest_mipmap_linear;
  TextureFilter mag_filter = TextureFilter::linear;
  // GL_TEXTURE_LOD_BIAS, GL_TEXTURE_MIN_LOD and GL_TEXTURE_MAX_LOD, in levels.
  float lod_bias = 0.0f;
  float min_lod = -kDefaultLodLimit;
  float max_lod = kDefaultLodLimit;

  bool operator==(const TextureSampler& o) const {
    return wrap_s == o.wrap_s && wrap_t == o.wrap_t && min_filter == o.min_filter &&
           mag_filter == o.mag_filter && lod_bias == o.lod_bias && min_lod == o.min_lod &&
           max_lod == o.max_lod;
  }
  // Whether the level of detail is the plain 0.5 log2(rho^2): no bias and no
  // clamp that could bite (llvmpipe then picks a NEAREST_MIPMAP level from
  // rho^2's exponent alone; spec section 9c).
  bool plain_lod() const {
    return lod_bias == 0.0f && min_lod <= 0.0f && max_lod == kDefaultLodLimit;
  }
  // Whether sampling needs the level of detail: mipmaps, or two filters
  // between which it chooses.
  bool needs_lod() const;
  bool operator!=(const TextureSampler& o) const { return !(*this == o); }
};
std::ostream& operator<<(std::ostream& os, const TextureSampler& s);

// Whether a minification filter reads more than the base level.
inline bool uses_mipmaps(TextureFilter f) {
  return f != TextureFilter::nearest && f != TextureFilter::linear;
}
inline bool TextureSampler::needs_lod() const {
  return uses_mipmaps(min_filter) || min_filter != mag_filter;
}
// The filter a minification filter applies within a level: NEAREST or LINEAR.
inline TextureFilter level_filter(TextureFilter f) {
  return f == TextureFilter::nearest || f == TextureFilter::nearest_mipmap_nearest ||
                 f == TextureFilter::nearest_mipmap_linear
             ? TextureFilter::nearest
             : TextureFilter::linear;
}
// Whether it blends two levels (the *_MIPMAP_LINEAR filters).
inline bool blends_levels(TextureFilter f) {
  return f == TextureFilter::nearest_mipmap_linear || f == TextureFilter::linear_mipmap_linear;
}

// The texture environment of a texture stage (GL's glTexEnv): how the
// filtered texel Ct combines with the incoming colour Cf. `color` is
// GL_TEXTURE_ENV_COLOR, BLEND's constant.
struct TextureEnv {
  TextureEnvMode mode = TextureEnvMode::modulate;
  glm::vec4 color{0.0f};

  bool operator==(const TextureEnv& o) const { return mode == o.mode && color == o.color; }
  bool operator!=(const TextureEnv& o) const { return !(*this == o); }
};

// One mipmap level in GPU memory: row-major from the bottom row (t = 0),
// tightly packed texels of the texture's format.
struct TextureLevel {
  uint64_t address = 0;
  int32_t width = 0, height = 0;
  bool operator==(const TextureLevel& o) const {
    return address == o.address && width == o.width && height == o.height;
  }
};

// The texture bound to a draw's texture stage: the registers a driver
// programs. levels.empty(): the stage is off, and the fragment keeps its colour.
struct TextureBinding {
  TextureFormat format = TextureFormat::rgba8;
  TextureSampler sampler;
  std::vector<TextureLevel> levels;
  TextureEnv env;

  bool enabled() const { return !levels.empty(); }
  bool operator==(const TextureBinding& o) const {
    return format == o.format && sampler == o.sampler && levels == o.levels && env == o.env;
  }
};

}  // namespace gpusim
