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

float fast_log2(float x) {
  int e = 0;
  const float f = std::frexp(x, &e);  // x = f 2^e, f in [0.5, 1)
  return static_cast<float>(e - 2) + 2.0f * f;
}

LevelChoice choose_level(const Texture& texture, const TexcoordDerivatives& d) {
  const TextureSampler& sm = texture.sampler;
  LevelChoice c;
  if (!sm.needs_lod()) return c;  // one filter, one level: no level of detail
  const float w = static_cast<float>(texture.levels[0].width);
  const float h = static_cast<float>(texture.levels[0].height);
  const float sx = d[0] * w, tx = d[1] * h, sy = d[2] * w, ty = d[3] * h;
  const float rho2 = std::max(sx * sx + tx * tx, sy * sy + ty * ty);
  if (!(rho2 > 0.0f)) return c;  // a constant coordinate: magnified
  float lod = 0.5f * fast_log2(rho2) + sm.lod_bias;
  lod = std::min(std::max(lod, sm.min_lod), sm.max_lod);
  if (!(lod > 0.0f)) return c;
  c.minified = true;
  const TextureFilter f = sm.min_filter;
  if (!uses_mipmaps(f)) return c;
  const unsigned last = static_cast<unsigned>(texture.levels.size() - 1);
  if (blends_levels(f)) {
    const float base = std::floor(lod);
    c.level = static_cast<unsigned>(base);
    c.weight = static_cast<unsigned>(static_cast<int>((lod - base) * 256.0f));
    if (c.level >= last) c.level = last, c.weight = 0;
  } else {
    // The nearest level: from rho^2's exponent alone when the level of
    // detail is plain (ties go up), else lod rounded half to even.
    int e = 0;
    std::frexp(rho2, &e);
    const int exponent = e - 1;  // floor(log2 rho^2)
    const long level = sm.plain_lod() ? (exponent + 1) >> 1 : std::lrint(lod);
    c.level = static_cast<unsigned>(std::clamp<long>(level, 0, last));
  }
  return c;
}

Texel sample(const Texture& texture, const glm::vec2& st, const TexcoordDerivatives& d) {
  const LevelChoice c = choose_level(texture, d);
  if (!c.minified) {
    return sample_level(texture, texture.levels[0], texture.sampler.mag_filter, st.x, st.y);
  }
  const TextureFilter f = level_filter(texture.sampler.min_filter);
  const Texel t0 = sample_level(texture, texture.levels[c.level], f, st.x, st.y);
  if (c.weight == 0) return t0;
  const Texel t1 = sample_level(texture, texture.levels[c.level + 1], f, st.x, st.y);
  Texel out;
  for (int k = 0; k < 4; ++k) out[k] = lerp8(t0[k], t1[k], c.weight);
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
