// Texturing in the golden model (docs/pipeline-spec.md, section 9c): the
// sampler's arithmetic, chosen to match Mesa llvmpipe's 8-bit fixed-point
// path, and the texture environment. Free functions, so tests check each
// rule alone.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>

#include "hw/texture_state.h"
#include "testbench/scene/scene.h"

namespace gpusim::golden {

// NEAREST along one axis: the texel index of coordinate s on a side of
// `size` texels, wrapped.
int nearest_texel(float s, int size, TextureWrap wrap);

// LINEAR along one axis: the two texels and the 8-bit weight of the second.
struct LinearTexels {
  int i0 = 0, i1 = 0;
  unsigned weight = 0;  // 0..255, of texel i1
};
LinearTexels linear_texels(float s, int size, TextureWrap wrap);

// The 8.8 fixed-point lerp of two 8-bit channels by an 8-bit weight.
uint8_t lerp8(uint8_t v0, uint8_t v1, unsigned weight);

// The filtered texel of one level at (s, t) with `filter` (NEAREST or LINEAR).
Texel sample_level(const Texture& texture, const TextureImage& level, TextureFilter filter, float s,
                   float t);

// llvmpipe's log2 approximation: floor(log2 x) - 1 + x / 2^floor(log2 x),
// exact at powers of two, for x > 0.
float fast_log2(float x);

// The texture coordinate's derivatives over a pixel's 2x2 quad (section
// 9c): (ds/dx, dt/dx, ds/dy, dt/dy), from the quad's lower-left pixel to its
// right and upper neighbours.
using TexcoordDerivatives = glm::vec4;

// Where a quad samples: magnified (level 0 with the MAG filter), or
// minified: `level` and, blending two levels, the next one with 8-bit
// weight `weight`.
struct LevelChoice {
  bool minified = false;
  unsigned level = 0;
  unsigned weight = 0;  // of level + 1; 0 when one level is read
};
LevelChoice choose_level(const Texture& texture, const TexcoordDerivatives& d);

// The filtered texel at (s, t) for a pixel whose quad has derivatives `d`.
Texel sample(const Texture& texture, const glm::vec2& st, const TexcoordDerivatives& d);

// The texture environment (section 9c): the fragment colour `cf` combined
// with the filtered texel of a texture of `format`.
glm::vec4 apply_texture_env(const TextureEnv& env, TextureFormat format, const Texel& texel,
                            const glm::vec4& cf);

}  // namespace gpusim::golden
