// The golden model's texture sampling rules (docs/pipeline-spec.md, section
// 9c), each checked against values worked out by hand from the rule that
// llvmpipe was measured to follow (Mesa 22.3.6: a probe reading back every
// pixel's exact coordinate; the measured cases are quoted below).
#include <gtest/gtest.h>

#include "hw/texture_state.h"
#include "testbench/golden/texture_sampling.h"

namespace gpusim::golden {
namespace {

TEST(TextureSampling, LerpRoundsHalfUp) {
  // (w (b - a) + 128) >> 8: 128 * 255 = 32640, + 128 = 32768, >> 8 = 128.
  EXPECT_EQ(lerp8(0, 255, 128), 128);
  // The truncating lerp would give 0 + (1 * 255) >> 8 = 0; rounded: 383 >> 8 = 1.
  EXPECT_EQ(lerp8(0, 255, 1), 1);
  // A negative difference shifts arithmetically: 200 + ((64 * -100 + 128) >> 8) = 200 - 25.
  EXPECT_EQ(lerp8(200, 100, 64), 175);
  EXPECT_EQ(lerp8(37, 37, 200), 37);
  EXPECT_EQ(lerp8(10, 250, 0), 10);
}

TEST(TextureSampling, LinearCoordinateHasEightFractionBits) {
  // s = 0.5 on 2 texels: 0.5 * 2 * 256 = 256, - 128 = 128: texels 0, 1, half way.
  LinearTexels t = linear_texels(0.5f, 2, TextureWrap::repeat);
  EXPECT_EQ(t.i0, 0);
  EXPECT_EQ(t.i1, 1);
  EXPECT_EQ(t.weight, 128u);
  // s = 0 is the left edge: -128 is texel -1 at weight 128; REPEAT wraps it
  // to the last texel, CLAMP_TO_EDGE to the first.
  t = linear_texels(0.0f, 4, TextureWrap::repeat);
  EXPECT_EQ(t.i0, 3);
  EXPECT_EQ(t.i1, 0);
  EXPECT_EQ(t.weight, 128u);
  t = linear_texels(0.0f, 4, TextureWrap::clamp_to_edge);
  EXPECT_EQ(t.i0, 0);
  EXPECT_EQ(t.i1, 0);
  // Round half to even: s * 4 * 256 = 640.5 (s = 0.6254883) rounds to 640, - 128 = 512.
  t = linear_texels(640.5f / 1024.0f, 4, TextureWrap::repeat);
  EXPECT_EQ(t.i0, 2);
  EXPECT_EQ(t.weight, 0u);
  // 641.5 rounds to 642: 514 = texel 2, weight 2.
  t = linear_texels(641.5f / 1024.0f, 4, TextureWrap::repeat);
  EXPECT_EQ(t.weight, 2u);
}

TEST(TextureSampling, NonPowerOfTwoRepeatTakesTheFractionFirst) {
  // s = 2.5 on 3 texels: fract 0.5, 0.5 * 3 * 256 = 384, - 128 = 256: texels 1, 2.
  LinearTexels t = linear_texels(2.5f, 3, TextureWrap::repeat);
  EXPECT_EQ(t.i0, 1);
  EXPECT_EQ(t.i1, 2);
  EXPECT_EQ(t.weight, 0u);
  // NEAREST: trunc(min(fract(s), 0.99999994) * N). s = -1e-8 has fract 1 in
  // float, kept below 1: texel N - 1.
  EXPECT_EQ(nearest_texel(-1e-8f, 3, TextureWrap::repeat), 2);
  EXPECT_EQ(nearest_texel(-0.5f, 5, TextureWrap::repeat), 2);  // fract 0.5 * 5 = 2.5
  EXPECT_EQ(nearest_texel(1.0f, 5, TextureWrap::repeat), 0);
}

TEST(TextureSampling, NearestWrapsTheFloorOfTheScaledCoordinate) {
  EXPECT_EQ(nearest_texel(0.2499f, 4, TextureWrap::repeat), 0);
  EXPECT_EQ(nearest_texel(0.25f, 4, TextureWrap::repeat), 1);
  EXPECT_EQ(nearest_texel(-0.1f, 4, TextureWrap::repeat), 3);  // floor(-0.4) = -1
  EXPECT_EQ(nearest_texel(-0.1f, 4, TextureWrap::clamp_to_edge), 0);
  EXPECT_EQ(nearest_texel(7.0f, 4, TextureWrap::clamp_to_edge), 3);
  // A subnormal is 0: without the flush, floor(-tiny * 4) = -1 would wrap to 3.
  EXPECT_EQ(nearest_texel(-1e-40f, 4, TextureWrap::repeat), 0);
}

TEST(TextureSampling, PackedFormatsWidenByBitReplication) {
  // rgb565 red 3 (bits 00011): 00011 000 | 00 = 24, which llvmpipe reads
  // (round(3 * 255 / 31) would be 25).
  const uint16_t red3 = 3 << 11;
  const uint8_t bytes[2] = {static_cast<uint8_t>(red3), static_cast<uint8_t>(red3 >> 8)};
  EXPECT_EQ(expand_texel(TextureFormat::rgb565, bytes)[0], 24);
  const uint16_t green63 = 63 << 5;
  const uint8_t g[2] = {static_cast<uint8_t>(green63), static_cast<uint8_t>(green63 >> 8)};
  const Texel t = expand_texel(TextureFormat::rgb565, g);
  EXPECT_EQ(t[1], 255);
  EXPECT_EQ(t[3], 255);
  // rgba4444 0x1234: r 1, g 2, b 3, a 4, each times 17.
  const uint8_t n[2] = {0x34, 0x12};
  EXPECT_EQ(expand_texel(TextureFormat::rgba4444, n), (Texel{17, 34, 51, 68}));
  // Base formats (GL 1.5, table 3.15).
  const uint8_t la[2] = {90, 7};
  EXPECT_EQ(expand_texel(TextureFormat::luminance_alpha8, la), (Texel{90, 90, 90, 7}));
  EXPECT_EQ(expand_texel(TextureFormat::alpha8, la), (Texel{0, 0, 0, 90}));
  EXPECT_EQ(expand_texel(TextureFormat::intensity8, la), (Texel{90, 90, 90, 90}));
}

// A 128 x 128 texture with its 8 levels (texels unused here).
Texture mipmapped(TextureFilter min_filter) {
  Texture t;
  for (int side = 128; side >= 1; side /= 2) {
    t.levels.push_back(TextureImage{side, side, std::vector<uint8_t>(size_t(side) * side * 4)});
  }
  t.sampler.min_filter = min_filter;
  return t;
}

TEST(TextureSampling, FastLog2IsExponentPlusMantissa) {
  EXPECT_EQ(fast_log2(1.0f), 0.0f);
  EXPECT_EQ(fast_log2(8.0f), 3.0f);
  EXPECT_EQ(fast_log2(1.5625f), 0.5625f);  // 1.5625 2^0: -1 + 1.5625
  EXPECT_EQ(fast_log2(9.0f), 3.125f);      // 1.125 2^3: 2 + 1.125
  EXPECT_EQ(fast_log2(0.75f), -0.5f);      // 1.5 2^-1: -2 + 1.5
}

TEST(TextureSampling, LinearMipLevelsAsLlvmpipeChoseThem) {
  // s = x scale / 128: scale texels of level 0 a pixel, rho^2 = scale^2.
  // The levels and weights llvmpipe sampled at these scales (measured).
  const Texture t = mipmapped(TextureFilter::linear_mipmap_linear);
  const struct {
    float scale;
    unsigned level, weight;
  } cases[] = {{1.25f, 0, 72}, {1.5f, 0, 144}, {2.0f, 1, 0}, {3.0f, 1, 144}, {100.0f, 6, 156}};
  for (const auto& c : cases) {
    const float d = c.scale / 128.0f;
    const LevelChoice got = choose_level(t, TexcoordDerivatives(d, 0.0f, 0.0f, d));
    EXPECT_TRUE(got.minified) << c.scale;
    EXPECT_EQ(got.level, c.level) << c.scale;
    EXPECT_EQ(got.weight, c.weight) << c.scale;
  }
  // The larger of the two directions counts; at 1:1 (lod 0) it magnifies.
  EXPECT_EQ(choose_level(t, TexcoordDerivatives(0.0f, 2.0f / 128, 1.0f / 128, 0.0f)).level, 1u);
  EXPECT_FALSE(choose_level(t, TexcoordDerivatives(1.0f / 128, 0.0f, 0.0f, 1.0f / 128)).minified);
  EXPECT_FALSE(choose_level(t, TexcoordDerivatives(0.0f)).minified);
  // Past the last level: the last, one level.
  const LevelChoice far = choose_level(t, TexcoordDerivatives(1e6f, 0.0f, 0.0f, 0.0f));
  EXPECT_EQ(far.level, 7u);
  EXPECT_EQ(far.weight, 0u);
}

TEST(TextureSampling, NearestMipLevelTiesGoUpUnlessBiasedOrClamped) {
  Texture t = mipmapped(TextureFilter::nearest_mipmap_nearest);
  // rho^2 = 1 + 1 = 2: lod 0.5 exactly. The plain rule takes
  // (exponent 1 + 1) >> 1 = 1: ties go up.
  const TexcoordDerivatives half(1.0f / 128.0f, 1.0f / 128.0f, 0.0f, 0.0f);
  EXPECT_EQ(choose_level(t, half).level, 1u);
  // With max_lod set, lod is rounded half to even: 0.5 -> 0 (llvmpipe's
  // switch, measured with GL_TEXTURE_MAX_LOD 5).
  t.sampler.max_lod = 5.0f;
  EXPECT_EQ(choose_level(t, half).level, 0u);
  t.sampler.max_lod = kDefaultLodLimit;
  // A bias of 1 moves every pixel a level down the chain.
  t.sampler.lod_bias = 1.0f;
  EXPECT_EQ(choose_level(t, TexcoordDerivatives(4.0f / 128, 0.0f, 0.0f, 0.0f)).level, 3u);
}

TEST(TextureSampling, EnvironmentFollowsGlsTable) {
  const glm::vec4 cf(0.5f, 0.25f, 1.0f, 0.5f);
  const Texel texel{255, 0, 51, 102};  // 1, 0, 0.2, 0.4
  const TextureEnv modulate{TextureEnvMode::modulate, glm::vec4(0.0f)};
  glm::vec4 r = apply_texture_env(modulate, TextureFormat::rgba8, texel, cf);
  EXPECT_FLOAT_EQ(r.x, 0.5f);
  EXPECT_FLOAT_EQ(r.y, 0.0f);
  EXPECT_NEAR(r.z, 0.2f, 1e-6f);
  EXPECT_NEAR(r.w, 0.2f, 1e-6f);
  // RGB textures keep the fragment's alpha; ALPHA textures its colour.
  r = apply_texture_env(modulate, TextureFormat::rgb8, texel, cf);
  EXPECT_FLOAT_EQ(r.w, 0.5f);
  r = apply_texture_env(modulate, TextureFormat::alpha8, texel, cf);
  EXPECT_FLOAT_EQ(r.x, 0.5f);
  EXPECT_NEAR(r.w, 0.2f, 1e-6f);
  // DECAL on RGBA: cf (1 - At) + ct At, alpha kept.
  r = apply_texture_env({TextureEnvMode::decal, glm::vec4(0.0f)}, TextureFormat::rgba8, texel, cf);
  EXPECT_NEAR(r.x, 0.5f * 0.6f + 0.4f, 1e-6f);
  EXPECT_FLOAT_EQ(r.w, 0.5f);
  // BLEND on INTENSITY also blends alpha with the environment colour's.
  const TextureEnv blend{TextureEnvMode::blend, glm::vec4(0.0f, 1.0f, 0.0f, 1.0f)};
  r = apply_texture_env(blend, TextureFormat::intensity8, Texel{102, 102, 102, 102}, cf);
  EXPECT_NEAR(r.y, 0.25f * 0.6f + 0.4f, 1e-6f);
  EXPECT_NEAR(r.w, 0.5f * 0.6f + 0.4f, 1e-6f);
  // ADD clamps.
  r = apply_texture_env({TextureEnvMode::add, glm::vec4(0.0f)}, TextureFormat::rgba8, texel, cf);
  EXPECT_FLOAT_EQ(r.x, 1.0f);
  // The channel value is v times float(1/255), as llvmpipe converts it.
  EXPECT_EQ(texel_value(51), 51.0f * (1.0f / 255.0f));
}

}  // namespace
}  // namespace gpusim::golden
