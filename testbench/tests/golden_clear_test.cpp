// Golden model: clears in the middle of the draw list (docs/pipeline-spec.md
// section 15). Expected stored values are worked out by hand in the
// comments, from the section 11 and 12 conversions.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "hw/pixel_formats.h"
#include "testbench/golden/golden_model.h"

namespace gpusim {
namespace {

Scene frame(int w, int h, DepthFormat df = DepthFormat::unorm16,
            ColorFormat cf = ColorFormat::rgba8) {
  Scene s;
  s.framebuffer.width = w;
  s.framebuffer.height = h;
  s.framebuffer.color_format = cf;
  s.framebuffer.depth_format = df;
  s.framebuffer.clear_color = {0, 0, 0, 0};
  s.framebuffer.clear_depth = 1.0f;
  return s;
}

// Clip position (w = 1) of window point (x, y) in a W x H framebuffer at
// window depth zw; exact for the values used.
glm::vec4 at(float x, float y, float zw, int W, int H) {
  return {x / (0.5f * static_cast<float>(W)) - 1.0f, y / (0.5f * static_cast<float>(H)) - 1.0f,
          2.0f * zw - 1.0f, 1.0f};
}

// Two triangles covering the W x H framebuffer at constant window depth zw
// (dyadic zw: every pixel's interpolated z is exactly zw), one flat colour.
Draw full_screen(float zw, glm::vec4 color, int W, int H) {
  Draw d;
  d.positions = {at(0, 0, zw, W, H), at(W, 0, zw, W, H), at(W, H, zw, W, H),
                 at(0, 0, zw, W, H), at(W, H, zw, W, H), at(0, H, zw, W, H)};
  d.colors.assign(6, color);
  d.state.shading = Shading::flat;
  return d;
}

ClearState clear_color(glm::vec4 c, uint32_t before_draw) {
  ClearState s;
  s.color = true;
  s.color_value = c;
  s.before_draw = before_draw;
  return s;
}

ClearState clear_depth(float z, uint32_t before_draw) {
  ClearState s;
  s.depth = true;
  s.depth_value = z;
  s.before_draw = before_draw;
  return s;
}

void expect_every_color(const Framebuffer& fb, const std::vector<uint32_t>& rgba) {
  for (int y = 0; y < fb.height; ++y) {
    for (int x = 0; x < fb.width; ++x) {
      for (int k = 0; k < 4; ++k) EXPECT_EQ(fb.color_at(x, y)[k], rgba[k]) << x << "," << y;
    }
  }
}

void expect_every_pixel(const Framebuffer& fb, const std::vector<uint32_t>& rgba, uint32_t depth) {
  expect_every_color(fb, rgba);
  for (int y = 0; y < fb.height; ++y) {
    for (int x = 0; x < fb.width; ++x)
      EXPECT_EQ(fb.depth[fb.pixel_index(x, y)], depth) << x << "," << y;
  }
}

// The depth-partition trick in its smallest form: a surface at 0.25, then
// one at 0.5 with depth_func less. Without a clear between them the second
// fails (32768 > 16384 in unorm16); after a depth clear to 0.75 (49151,
// section 11: nearbyint(0.75 * 65535) = nearbyint(49151.25)) it passes and
// stores 32768 (nearbyint(32767.5), ties to even).
TEST(GoldenClear, Section15DepthClearBetweenDrawsLetsTheNextDrawPass) {
  Scene s = frame(8, 8);
  s.draws.push_back(full_screen(0.25f, {1, 0, 0, 1}, 8, 8));
  s.draws.push_back(full_screen(0.5f, {0, 1, 0, 1}, 8, 8));
  const golden::Result without = golden::render(s);
  expect_every_pixel(without.framebuffer, {255, 0, 0, 255}, 16384);

  s.clears.push_back(clear_depth(0.75f, 1));
  const golden::Result with = golden::render(s);
  expect_every_pixel(with.framebuffer, {0, 255, 0, 255}, 32768);
  EXPECT_EQ(with.stats.fragments_passed_depth, 128u);  // both draws, 64 pixels each
  EXPECT_EQ(with.stats.depth_clears, 2u);              // the frame's and the draw list's
  EXPECT_EQ(with.stats.color_clears, 1u);
  // The second draw's primitives (ids 2 and 3: two per draw) wrote last.
  for (const int64_t w : with.last_writer) EXPECT_TRUE(w == 2 || w == 3) << w;
}

// A colour clear leaves depth alone: the second surface still fails against
// the first one's depth, so the clear colour shows where the first was. It
// also forgets the last writers (no primitive wrote those pixels since).
// rgba8 of (0.2, 0.4, 0.6, 1): nearbyint(51) = 51, nearbyint(102.00000152)
// = 102, nearbyint(153.0000023) = 153, 255.
TEST(GoldenClear, Section15ColorClearKeepsTheDepthBuffer) {
  Scene s = frame(8, 8);
  s.draws.push_back(full_screen(0.25f, {1, 0, 0, 1}, 8, 8));
  s.draws.push_back(full_screen(0.5f, {0, 1, 0, 1}, 8, 8));
  s.clears.push_back(clear_color({0.2f, 0.4f, 0.6f, 1.0f}, 1));
  const golden::Result r = golden::render(s);
  expect_every_pixel(r.framebuffer, {51, 102, 153, 255}, 16384);
  for (const int64_t w : r.last_writer) EXPECT_EQ(w, -1);
  EXPECT_EQ(r.stats.color_clears, 2u);
  EXPECT_EQ(r.stats.depth_clears, 1u);
  EXPECT_EQ(r.stats.fragments_passed_depth, 64u);
}

// The values convert as the frame clear's do (sections 11 and 12): unorm24
// nearbyint(z * 16777215), float32 the bits; rgba16f the nearest half.
// 1/3: unorm24 5592405, float32 0x3EAAAAAB; half(1/3) = 0x3555, half(0.5) =
// 0x3800, half(2.5) = 0x4100 (rgba16f is unclamped), half(1) = 0x3C00.
TEST(GoldenClear, Section15ValuesConvertAsTheFrameClearDoes) {
  struct Case {
    DepthFormat format;
    float z;
    uint32_t stored;
  };
  for (const Case c : {Case{DepthFormat::unorm24, 1.0f / 3.0f, 5592405},
                       Case{DepthFormat::float32, 1.0f / 3.0f, 0x3EAAAAABu},
                       Case{DepthFormat::unorm16, 0.0f, 0}}) {
    Scene s = frame(4, 4, c.format, ColorFormat::rgba16f);
    s.draws.push_back(full_screen(0.5f, {1, 1, 1, 1}, 4, 4));
    ClearState both = clear_color({1.0f / 3.0f, 0.5f, 2.5f, 1.0f}, 1);
    both.depth = true;
    both.depth_value = c.z;
    s.clears.push_back(both);
    const golden::Result r = golden::render(s);
    expect_every_pixel(r.framebuffer, {0x3555, 0x3800, 0x4100, 0x3C00}, c.stored);
  }
}

// Several clears at one place run in list order; a clear after the last
// draw runs too (its depth is the output's); one before the first draw
// follows the frame clear.
TEST(GoldenClear, Section15ClearsRunInListOrderWhereverTheyAre) {
  Scene s = frame(4, 4);
  s.draws.push_back(full_screen(0.5f, {0, 0, 1, 1}, 4, 4));
  s.clears.push_back(clear_color({1, 0, 0, 1}, 0));
  s.clears.push_back(clear_depth(0.25f, 0));  // the draw at 0.5 fails against it
  s.clears.push_back(clear_color({0, 1, 0, 1}, 1));
  s.clears.push_back(clear_color({1, 1, 0, 1}, 1));
  s.clears.push_back(clear_depth(0.75f, 1));
  const golden::Result r = golden::render(s);
  expect_every_pixel(r.framebuffer, {255, 255, 0, 255}, 49151);
  EXPECT_EQ(r.stats.fragments_passed_depth, 0u);
  EXPECT_EQ(r.stats.color_clears, 4u);
  EXPECT_EQ(r.stats.depth_clears, 3u);
}

// Multisampled (section 14): a clear writes every sample. A triangle
// covering part of the samples of its edge pixels is drawn, then the colour
// is cleared: any sample the clear missed would show in the resolve's
// average. Then a depth clear to 0.75 and a full-screen draw at 0.5: every
// sample passes only if every sample's depth was cleared (the triangle's
// were at 0.25), so every output pixel is exactly the draw's colour.
TEST(GoldenClear, Section15MultisampledClearsWriteEverySample) {
  for (const unsigned n : {2u, 4u, 8u, 16u}) {
    Scene s = frame(8, 8);
    s.framebuffer.samples = n;
    Draw tri;
    tri.positions = {at(0.3f, 0.2f, 0.25f, 8, 8), at(7.6f, 1.3f, 0.25f, 8, 8),
                     at(2.4f, 7.7f, 0.25f, 8, 8)};
    tri.colors.assign(3, {1, 1, 1, 1});
    s.draws.push_back(tri);
    s.clears.push_back(clear_color({0.2f, 0.4f, 0.6f, 1.0f}, 1));
    const golden::Result colour = golden::render(s);
    // (The output depth is sample 0's, which the triangle may have written.)
    expect_every_color(colour.framebuffer, {51, 102, 153, 255});
    s.clears.push_back(clear_depth(0.75f, 1));
    s.draws.push_back(full_screen(0.5f, {0, 1, 0, 1}, 8, 8));
    const golden::Result both = golden::render(s);
    expect_every_pixel(both.framebuffer, {0, 255, 0, 255}, 32768);
  }
}

// Supersampled (section 14): a clear covers the whole render target, k^2
// pixels per output pixel, so the box filter returns the clear colour.
TEST(GoldenClear, Section15SupersampledClearsCoverTheRenderTarget) {
  Scene s = frame(6, 5);
  s.framebuffer.supersample = 3;
  Draw tri;
  tri.positions = {at(0.2f, 0.1f, 0.25f, 6, 5), at(5.7f, 2.1f, 0.25f, 6, 5),
                   at(1.3f, 4.9f, 0.25f, 6, 5)};
  tri.colors.assign(3, {1, 1, 1, 1});
  s.draws.push_back(tri);
  s.clears.push_back(clear_color({0.2f, 0.4f, 0.6f, 1.0f}, 1));
  s.clears.push_back(clear_depth(0.75f, 1));
  const golden::Result r = golden::render(s);
  expect_every_pixel(r.framebuffer, {51, 102, 153, 255}, 49151);
  ASSERT_EQ(r.last_writer.size(), 18u * 15u);
  for (const int64_t w : r.last_writer) EXPECT_EQ(w, -1);
}

}  // namespace
}  // namespace gpusim
