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

// The filtered texel of level 0 at (s, t) with `filter`.
Texel sample_level(const Texture& texture, const TextureImage& level, TextureFilter filter, float s,
                   float t);

// The texture environment (section 9c): the fragment colour `cf` combined
// with the filtered texel of a texture of `format`.
glm::vec4 apply_texture_env(const TextureEnv& env, TextureFormat format, const Texel& texel,
                            const glm::vec4& cf);

}  // namespace gpusim::golden
