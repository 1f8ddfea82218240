#include "testbench/golden/texture_sampling.h"

#include <algorithm>
#include <cmath>

#include "hw/pixel_formats.h"

namespace gpusim::golden {
namespace {

bool power_of_two(int n) {
  return (n & (n - 1)) == 0;
}

// Index i wrapped onto [0, size).
int wrap_index(int64_t i, int size, TextureWrap wrap) {
  if (wrap == TextureWrap::repeat) {
    const int64_t m = i % size;
    return static_cast<int>(m < 0 ? m + size : m);
  }
  return static_cast<int>(i < 0 ? 0 : i >= size ? size - 1 : i);
}

}  // namespace

int nearest_texel(float s, int size, TextureWrap wrap) {
  if (std::fpclassify(s) == FP_SUBNORMAL) s = 0.0f;  // flushed to zero
  if (wrap == TextureWrap::repeat && !power_of_two(size)) {
    // The fraction, kept below 1, scaled and truncated.
    const float f = std::min(s - std::floor(s), kBelowOne);
    return static_cast<int>(f * static_cast<float>(size));
  }
  const float u = s * static_cast<float>(size);
  return wrap_index(static_cast<int64_t>(std::floor(u)), size, wrap);
}

LinearTexels linear_texels(float s, int size, TextureWrap wrap) {
  // REPEAT on a side that is not a power of two wraps the coordinate first,
  // in float; a power of two wraps the integer texel index.
  if (wrap == TextureWrap::repeat && !power_of_two(size)) s = s - std::floor(s);
  // 8 fraction bits of texel coordinate, the half texel taken off.
  const int64_t u =
      static_cast<int64_t>(std::nearbyint(s * static_cast<float>(size) * 256.0f)) - 128;
  LinearTexels r;
  const int64_t i = u >> 8;  // floor: an arithmetic shift
  r.weight = static_cast<unsigned>(u & 0xff);
  r.i0 = wrap_index(i, size, wrap);
  r.i1 = wrap_index(i + 1, size, wrap);
  return r;
}

uint8_t lerp8(uint8_t v0, uint8_t v1, unsigned weight) {
  const int d = int{v1} - int{v0};
  return static_cast<uint8_t>((v0 + ((static_cast<int>(weight) * d + 128) >> 8)) & 0xff);
}

Texel sample_level(const Texture& texture, const TextureImage& level, TextureFilter filter, float s,
                   float t) {
  const unsigned bytes = texel_bytes(texture.format);
  const auto texel = [&](int x, int y) {
    const size_t i = static_cast<size_t>(y) * static_cast<size_t>(level.width) + x;
    return expand_texel(texture.format, &level.texels[i * bytes]);
  };
  const TextureSampler& sm = texture.sampler;
  if (filter == TextureFilter::nearest) {
    return texel(nearest_texel(s, level.width, sm.wrap_s),
                 nearest_texel(t, level.height, sm.wrap_t));
  }
  const LinearTexels x = linear_texels(s, level.width, sm.wrap_s);
  const LinearTexels y = linear_texels(t, level.height, sm.wrap_t);
  const Texel t00 = texel(x.i0, y.i0), t10 = texel(x.i1, y.i0);
  const Texel t01 = texel(x.i0, y.i1), t11 = texel(x.i1, y.i1);
  Texel out;
  for (int c = 0; c < 4; ++c) {
    out[c] = lerp8(lerp8(t00[c], t10[c], x.weight), lerp8(t01[c], t11[c], x.weight), y.weight);
  }
  return out;
}

glm::vec4 apply_texture_env(const TextureEnv& env, TextureFormat format, const Texel& texel,
                            const glm::vec4& cf) {
  glm::vec4 ct;
  for (int c = 0; c < 4; ++c) ct[c] = texel_value(texel[c]);
  const BaseFormat base = base_format(format);
  const bool has_color = base != BaseFormat::alpha;
  const bool has_alpha = base == BaseFormat::alpha || base == BaseFormat::luminance_alpha ||
                         base == BaseFormat::intensity || base == BaseFormat::rgba;
  const bool intensity = base == BaseFormat::intensity;
  glm::vec4 out = cf;
  switch (env.mode) {
    case TextureEnvMode::replace:
      for (int c = 0; c < 3; ++c) out[c] = has_color ? ct[c] : cf[c];
      out[3] = has_alpha ? ct[3] : cf[3];
      break;
    case TextureEnvMode::modulate:
      for (int c = 0; c < 3; ++c) out[c] = has_color ? cf[c] * ct[c] : cf[c];
      out[3] = has_alpha ? cf[3] * ct[3] : cf[3];
      break;
    case TextureEnvMode::decal:
      // GL defines DECAL for RGB and RGBA textures only; the others leave
      // the fragment as it is.
      if (base == BaseFormat::rgb) {
        for (int c = 0; c < 3; ++c) out[c] = ct[c];
      } else if (base == BaseFormat::rgba) {
        for (int c = 0; c < 3; ++c) out[c] = cf[c] * (1.0f - ct[3]) + ct[c] * ct[3];
      }
      break;
    case TextureEnvMode::blend:
      for (int c = 0; c < 3; ++c) {
        out[c] = has_color ? cf[c] * (1.0f - ct[c]) + env.color[c] * ct[c] : cf[c];
      }
      out[3] = intensity   ? cf[3] * (1.0f - ct[3]) + env.color[3] * ct[3]
               : has_alpha ? cf[3] * ct[3]
                           : cf[3];
      break;
    case TextureEnvMode::add:
      for (int c = 0; c < 3; ++c) out[c] = has_color ? cf[c] + ct[c] : cf[c];
      out[3] = intensity ? cf[3] + ct[3] : has_alpha ? cf[3] * ct[3] : cf[3];
      break;
  }
  for (int c = 0; c < 4; ++c) out[c] = clamp01(out[c]);
  return out;
}

}  // namespace gpusim::golden
