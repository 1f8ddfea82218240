// Golden model: depth formats, depth test, polygon offset, blending, colour
// mask and colour formats (docs/pipeline-spec.md sections 10-12). Expected
// stored values are worked out by hand in the comments; the exhaustive
// blending table is checked against a double-precision evaluation of the
// spec's formula.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "hw/pixel_formats.h"
#include "testbench/golden/golden_model.h"

namespace gpusim {
namespace {

Scene frame(int w, int h, ColorFormat cf, DepthFormat df, glm::vec4 clear_color = {0, 0, 0, 0},
            float clear_depth = 1.0f) {
  Scene s;
  s.framebuffer.width = w;
  s.framebuffer.height = h;
  s.framebuffer.color_format = cf;
  s.framebuffer.depth_format = df;
  s.framebuffer.clear_color = clear_color;
  s.framebuffer.clear_depth = clear_depth;
  return s;
}

// Clip position (w = 1) of window point (x, y) pixels in a W x H framebuffer
// with depth z_w: x / (W/2) - 1 etc., exact for the values used.
glm::vec4 at(float x, float y, float zw, int W, int H) {
  return {x / (0.5f * static_cast<float>(W)) - 1.0f, y / (0.5f * static_cast<float>(H)) - 1.0f,
          2.0f * zw - 1.0f, 1.0f};
}

// The 8 x 8 framebuffer covered by two triangles at constant window depth zw.
// area2 = 2048^2 = 2^22, so every edge value converts to float exactly and the
// interpolated z of a dyadic zw (0.25, 0.5, 0.75) is exact.
Draw square_8x8(float zw, glm::vec4 color) {
  Draw d;
  d.positions = {at(0, 0, zw, 8, 8), at(8, 0, zw, 8, 8), at(8, 8, zw, 8, 8),
                 at(0, 0, zw, 8, 8), at(8, 8, zw, 8, 8), at(0, 8, zw, 8, 8)};
  d.colors.assign(6, color);
  d.state.shading = Shading::flat;
  return d;
}

// ---------------------------------------------------------------------------
// Section 11: formats and clear.

struct DepthCase {
  DepthFormat format;
  float z;
  uint32_t stored;
};

// By hand: unorm16 stores nearbyint(z * 65535), unorm24 nearbyint(z * 16777215)
// (ties to even), float32 the bits.
//   0.5:  32767.5 -> 32768;  8388607.5 -> 8388608;  0x3F000000.
//   float(1/3) = 11184811 / 2^25: * 65535 = 21845.33 - 0.33 = 21845.0006 -> 21845;
//         * 16777215 = 5592405.5 - 0.33 -> 5592405;  0x3EAAAAAB.
//   0.25: 16383.75 -> 16384;   4194303.75 -> 4194304;  0x3E800000.
//   0.75: 49151.25 -> 49151;  12582911.25 -> 12582911.
const DepthCase kDepthCases[] = {
    {DepthFormat::unorm16, 0.0f, 0},           {DepthFormat::unorm16, 1.0f, 65535},
    {DepthFormat::unorm16, 0.5f, 32768},       {DepthFormat::unorm16, 1.0f / 3.0f, 21845},
    {DepthFormat::unorm16, 0.25f, 16384},      {DepthFormat::unorm16, 0.75f, 49151},
    {DepthFormat::unorm24, 0.0f, 0},           {DepthFormat::unorm24, 1.0f, 16777215},
    {DepthFormat::unorm24, 0.5f, 8388608},     {DepthFormat::unorm24, 1.0f / 3.0f, 5592405},
    {DepthFormat::unorm24, 0.25f, 4194304},    {DepthFormat::unorm24, 0.75f, 12582911},
    {DepthFormat::float32, 0.0f, 0},           {DepthFormat::float32, 1.0f, 0x3F800000},
    {DepthFormat::float32, 0.5f, 0x3F000000},  {DepthFormat::float32, 1.0f / 3.0f, 0x3EAAAAAB},
    {DepthFormat::float32, 0.25f, 0x3E800000},
};

TEST(GoldenDepth, ClearEncodesTheClearDepth) {
  for (const DepthCase& c : kDepthCases) {
    const Scene s = frame(4, 4, ColorFormat::rgba8, c.format, {0, 0, 0, 0}, c.z);
    const golden::Result r = golden::render(s);
    for (DepthValue v : r.framebuffer.depth) {
      ASSERT_EQ(v, c.stored) << to_string(c.format) << " " << c.z;
    }
  }
  // Out of range clear depths clamp to [0, 1].
  EXPECT_EQ(golden::render(frame(1, 1, ColorFormat::rgba8, DepthFormat::unorm16, {}, 1.5f))
                .framebuffer.depth[0],
            65535u);
  EXPECT_EQ(golden::render(frame(1, 1, ColorFormat::rgba8, DepthFormat::float32, {}, -0.5f))
                .framebuffer.depth[0],
            0u);
}

TEST(GoldenDepth, ClearEncodesTheClearColour) {
  // rgba8: 0.5 * 255 = 127.5 -> 128 (even); 0.25 -> 63.75 -> 64; 1/3 -> 85.0000
  // -> 85; 1.5 clamps to 255, -1 to 0; 0.2 -> 51.
  const golden::Result a = golden::render(
      frame(2, 2, ColorFormat::rgba8, DepthFormat::unorm24, {0.5f, 0.25f, 1.0f / 3.0f, 1.0f}));
  const golden::Result b = golden::render(
      frame(2, 2, ColorFormat::rgba8, DepthFormat::unorm24, {1.5f, -1.0f, 0.2f, 0.8f}));
  // rgba16f: half(0.5) = 0x3800, half(0.25) = 0x3400, half(1/3): exponent -2
  // (0x3400) and mantissa round(1024 * (4/3 - 1)) = 341 = 0x155 -> 0x3555;
  // half(1) = 0x3C00; unclamped: half(2) = 0x4000, half(-1) = 0xBC00.
  const golden::Result c = golden::render(
      frame(2, 2, ColorFormat::rgba16f, DepthFormat::unorm24, {0.5f, 0.25f, 1.0f / 3.0f, 1.0f}));
  const golden::Result d = golden::render(
      frame(2, 2, ColorFormat::rgba16f, DepthFormat::unorm24, {2.0f, -1.0f, 0.0f, 1.0f}));
  for (int i = 0; i < 4; ++i) {
    const std::vector<ColorChannel> px_a(a.framebuffer.color_at(i % 2, i / 2),
                                         a.framebuffer.color_at(i % 2, i / 2) + 4);
    EXPECT_EQ(px_a, (std::vector<ColorChannel>{128, 64, 85, 255}));
    const std::vector<ColorChannel> px_b(b.framebuffer.color_at(i % 2, i / 2),
                                         b.framebuffer.color_at(i % 2, i / 2) + 4);
    EXPECT_EQ(px_b, (std::vector<ColorChannel>{255, 0, 51, 204}));
    const std::vector<ColorChannel> px_c(c.framebuffer.color_at(i % 2, i / 2),
                                         c.framebuffer.color_at(i % 2, i / 2) + 4);
    EXPECT_EQ(px_c, (std::vector<ColorChannel>{0x3800, 0x3400, 0x3555, 0x3C00}));
    const std::vector<ColorChannel> px_d(d.framebuffer.color_at(i % 2, i / 2),
                                         d.framebuffer.color_at(i % 2, i / 2) + 4);
    EXPECT_EQ(px_d, (std::vector<ColorChannel>{0x4000, 0xBC00, 0x0000, 0x3C00}));
  }
}

// Depth through the rasterizer: a right triangle whose right-angle vertex v0
// sits on the centre of pixel (4, 4), legs of 2048 subpixels (area2 = 2^22).
// At that pixel E1 = E2 = 0, so z = z0 + (0 + 0) / A = z0 exactly (section
// 9), and z_w = (z_ndc + 1) / 2 reproduces z0 exactly for these values
// (2 float(1/3) - 1 is exact). So the stored value is the hand encoding.
TEST(GoldenDepth, FragmentDepthIsEncodedPerFormat) {
  for (const DepthCase& c : kDepthCases) {
    Scene s = frame(16, 16, ColorFormat::rgba8, c.format, {0, 0, 0, 0}, 1.0f);
    Draw d;
    d.positions = {at(4.5f, 4.5f, c.z, 16, 16), at(12.5f, 4.5f, c.z, 16, 16),
                   at(4.5f, 12.5f, c.z, 16, 16)};
    d.state.depth_func = CompareFunc::always;
    s.draws.push_back(d);
    const golden::Result r = golden::render(s);
    ASSERT_EQ(r.last_writer[4 * 16 + 4], 0);
    EXPECT_EQ(r.framebuffer.depth[4 * 16 + 4], c.stored) << to_string(c.format) << " " << c.z;
  }
}

// Section 9: z = z0 + (f1 (z1 - z0) + f2 (z2 - z0)) / A is exact for a
// triangle of constant depth, whatever its size. Two large triangles (one of
// each winding) in 256 x 256 with vertices off the pixel grid: area2 is about
// 3.9e9 and 3.7e9 subpixel^2, so most E_k exceed 2^24 and float(E_k) rounds.
// Every vertex has clip z = 0.1f, w = 1, so z_w = (0.1f + 1) * 0.5 in float:
// 0.1f = 0x3DCCCCCD, 0.1f + 1 rounds to 1.1f = 0x3F8CCCCD = 1.10000002384...,
// times 0.5 is 0x3F0CCCCD = 0.550000011920929 exactly. With z1 - z0 =
// z2 - z0 = 0 every fragment's z is z_w, so (by hand):
//   unorm16: 0.550000011920929 * 65535    = 36044.25   -> 36044
//   unorm24: 0.550000011920929 * 16777215 = 9227468.45 -> 9227468
//   float32: 0x3F0CCCCD
// and `equal` against a buffer cleared to the same float passes everywhere.
// (The former (f0 z0 + f1 z1 + f2 z2) / A gives 9227468 and 9227469 on the
// first triangle, 9227467 to 9227469 on the second: not constant.)
TEST(GoldenDepth, ConstantDepthIsExactOnLargeTriangles) {
  const float zw = (0.1f + 1.0f) * 0.5f;
  ASSERT_EQ(bits_from_float(zw), 0x3F0CCCCDu);
  const struct {
    DepthFormat format;
    uint32_t stored;
  } cases[] = {{DepthFormat::unorm16, 36044u},
               {DepthFormat::unorm24, 9227468u},
               {DepthFormat::float32, 0x3F0CCCCDu}};
  const float corners[2][3][2] = {{{3.3f, 7.1f}, {250.7f, 20.2f}, {30.9f, 249.6f}},
                                  {{5.2f, 3.9f}, {12.4f, 240.3f}, {251.1f, 131.7f}}};  // cw
  for (const auto& c : cases) {
    for (const auto& tri : corners) {
      Scene s = frame(256, 256, ColorFormat::rgba8, c.format, {0, 0, 0, 0}, zw);
      Draw d;
      for (const auto& v : tri) {
        d.positions.push_back({v[0] / 128.0f - 1.0f, v[1] / 128.0f - 1.0f, 0.1f, 1.0f});
      }
      d.colors.assign(3, {1, 1, 1, 1});
      d.state.depth_func = CompareFunc::equal;
      s.draws.push_back(d);
      const golden::Result r = golden::render(s);
      ASSERT_GT(r.stats.fragments_generated, 25000u);
      EXPECT_EQ(r.stats.fragments_passed_depth, r.stats.fragments_generated) << to_string(c.format);
      for (size_t p = 0; p < r.framebuffer.depth.size(); ++p) {
        ASSERT_EQ(r.framebuffer.depth[p], c.stored) << to_string(c.format) << " pixel " << p;
      }
    }
  }
}

// Section 9 on a sloped plane where every step is exact: v0 on the centre of
// pixel (4, 4) at z 0.25, v1 8 pixels to the right at 0.5, v2 8 pixels up at
// 0.375 (area2 = 2048^2 = 2^22). At the centre of pixel (x, y), E1 = 2048 *
// 256 (x - 4) and E2 = 2048 * 256 (y - 4) (below 2^24: exact in float), so
// f1 (z1 - z0) = 2^19 (x - 4) / 4, f2 (z2 - z0) = 2^19 (y - 4) / 8, and
// dividing by 2^22 gives (x - 4) / 32 + (y - 4) / 64, all exact: z is the
// plane 0.25 + (x - 4) / 32 + (y - 4) / 64, a multiple of 2^-6, encoded as
// nearbyint(z (2^n - 1)) in unorm16 and unorm24 and as itself in float32.
TEST(GoldenDepth, SlopedDepthIsThePlaneThroughTheVertices) {
  for (DepthFormat f : {DepthFormat::unorm16, DepthFormat::unorm24, DepthFormat::float32}) {
    Scene s = frame(16, 16, ColorFormat::rgba8, f);
    Draw d;
    d.positions = {at(4.5f, 4.5f, 0.25f, 16, 16), at(12.5f, 4.5f, 0.5f, 16, 16),
                   at(4.5f, 12.5f, 0.375f, 16, 16)};
    d.colors.assign(3, {1, 1, 1, 1});
    d.state.depth_func = CompareFunc::always;
    s.draws.push_back(d);
    const golden::Result r = golden::render(s);
    uint64_t checked = 0;
    for (int y = 0; y < 16; ++y) {
      for (int x = 0; x < 16; ++x) {
        const size_t p = static_cast<size_t>(y) * 16 + x;
        if (r.last_writer[p] != 0) continue;
        const double z = 0.25 + (x - 4) / 32.0 + (y - 4) / 64.0;
        uint32_t want = 0;
        switch (f) {
          case DepthFormat::unorm16:
            want = static_cast<uint32_t>(std::nearbyint(z * 65535.0));
            break;
          case DepthFormat::unorm24:
            want = static_cast<uint32_t>(std::nearbyint(z * 16777215.0));
            break;
          case DepthFormat::float32:
            want = bits_from_float(static_cast<float>(z));
            break;
        }
        EXPECT_EQ(r.framebuffer.depth[p], want) << to_string(f) << " pixel " << x << ", " << y;
        ++checked;
      }
    }
    EXPECT_EQ(checked, r.stats.fragments_generated);
    EXPECT_GE(checked, 36u);  // the 9 x 9 half-square: at least the 8 + 7 + ... + 1 interior
  }
}

// Each compare function against a buffer cleared to 0.5, with fragments at
// 0.25, 0.5 and 0.75 (exact, see square_8x8), in every format.
TEST(GoldenDepth, CompareFunctions) {
  struct FuncCase {
    CompareFunc func;
    bool pass[3];  // fragment 0.25, 0.5, 0.75 against stored 0.5, by hand
  };
  const FuncCase funcs[] = {
      {CompareFunc::never, {false, false, false}},  {CompareFunc::less, {true, false, false}},
      {CompareFunc::equal, {false, true, false}},   {CompareFunc::lequal, {true, true, false}},
      {CompareFunc::greater, {false, false, true}}, {CompareFunc::notequal, {true, false, true}},
      {CompareFunc::gequal, {false, true, true}},   {CompareFunc::always, {true, true, true}},
  };
  struct FormatCase {
    DepthFormat format;
    uint32_t encoded[3];  // 0.25, 0.5, 0.75 (hand, see kDepthCases)
    uint32_t cleared;     // 0.5
  };
  const FormatCase formats[] = {
      {DepthFormat::unorm16, {16384, 32768, 49151}, 32768},
      {DepthFormat::unorm24, {4194304, 8388608, 12582911}, 8388608},
      {DepthFormat::float32, {0x3E800000, 0x3F000000, 0x3F400000}, 0x3F000000},
  };
  const float zs[3] = {0.25f, 0.5f, 0.75f};
  for (const FormatCase& f : formats) {
    for (const FuncCase& fc : funcs) {
      for (int k = 0; k < 3; ++k) {
        Scene s = frame(8, 8, ColorFormat::rgba8, f.format, {0, 0, 0, 0}, 0.5f);
        Draw d = square_8x8(zs[k], {1, 1, 1, 1});
        d.state.depth_func = fc.func;
        s.draws.push_back(d);
        const golden::Result r = golden::render(s);
        SCOPED_TRACE(::testing::Message()
                     << to_string(f.format) << " " << to_string(fc.func) << " z " << zs[k]);
        EXPECT_EQ(r.stats.fragments_generated, 64u);
        EXPECT_EQ(r.stats.fragments_passed_depth, fc.pass[k] ? 64u : 0u);
        EXPECT_EQ(r.stats.fragments_written, fc.pass[k] ? 64u : 0u);
        for (int p = 0; p < 64; ++p) {
          ASSERT_EQ(r.framebuffer.depth[p], fc.pass[k] ? f.encoded[k] : f.cleared) << p;
          ASSERT_EQ(r.framebuffer.color[p * 4], fc.pass[k] ? 255 : 0) << p;
        }
      }
    }
  }
}

TEST(GoldenDepth, DepthWriteFalseTestsButDoesNotWrite) {
  Scene s = frame(8, 8, ColorFormat::rgba8, DepthFormat::unorm16, {0, 0, 0, 0}, 0.5f);
  Draw a = square_8x8(0.25f, {1, 0, 0, 1});
  a.state.depth_write = false;
  s.draws.push_back(a);
  // Nearer than the clear value but farther than draw a: passes, since a did
  // not write.
  Draw b = square_8x8(0.375f, {0, 1, 0, 1});
  b.state.depth_write = false;
  s.draws.push_back(b);
  // Farther than the clear value: fails.
  Draw c = square_8x8(0.75f, {0, 0, 1, 1});
  s.draws.push_back(c);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.fragments_generated, 192u);
  EXPECT_EQ(r.stats.fragments_passed_depth, 128u);
  for (int p = 0; p < 64; ++p) {
    EXPECT_EQ(r.framebuffer.depth[p], 32768u);  // the clear value, never overwritten
    EXPECT_EQ(r.framebuffer.color[p * 4 + 1], 255);
    // Each square is two triangles: b's ids are 2 and 3.
    EXPECT_TRUE(r.last_writer[p] == 2 || r.last_writer[p] == 3) << r.last_writer[p];
  }
}

TEST(GoldenDepth, DepthTestOffPassesEverythingAndNeverWrites) {
  Scene s = frame(8, 8, ColorFormat::rgba8, DepthFormat::unorm24, {0, 0, 0, 0}, 0.5f);
  Draw d = square_8x8(0.75f, {1, 1, 1, 1});
  d.state.depth_test = false;
  d.state.depth_func = CompareFunc::never;  // ignored
  d.state.depth_write = true;               // ignored
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.fragments_passed_depth, 64u);
  EXPECT_EQ(r.stats.fragments_written, 64u);
  for (int p = 0; p < 64; ++p) {
    EXPECT_EQ(r.framebuffer.depth[p], 8388608u);
    EXPECT_EQ(r.framebuffer.color[p * 4], 255);
  }
}

// ---------------------------------------------------------------------------
// Section 10: polygon offset.

// A sloped triangle in a 64 x 64 framebuffer: window (8, 8) z 0.3,
// (40, 8) z 0.45, (8, 24) z 0.35. Every interpolated z is in [0.3, 0.45].
Draw sloped(glm::vec4 color) {
  Draw d;
  d.positions = {at(8, 8, 0.3f, 64, 64), at(40, 8, 0.45f, 64, 64), at(8, 24, 0.35f, 64, 64)};
  d.colors.assign(3, color);
  d.state.shading = Shading::flat;
  return d;
}

// Two identical triangles, red then green. Without offset the second computes
// bit-identical depths: `less` rejects it everywhere, `lequal` accepts it
// everywhere. With units = -1 in unorm24, r = float(1 / (2^24 - 1)) = 2^-24
// (1/(2^24-1) = 2^-24 (1 + 2^-24 + ...), nearer 2^-24 than any other float).
// z in [0.25, 0.5) is a multiple of 2^-25, so z - 2^-24 is exact and encodes
// to z (2^24 - 1) - 1 + 2^-24: exactly one step below z's encoding (z (2^24-1)
// is never within 2^-24 of a tie for such z). So `less` accepts every pixel
// and the stored value drops by exactly 1. With units = +1 the second is one
// step farther and `lequal` rejects it everywhere.
TEST(GoldenPolygonOffset, CoplanarTrianglesZFightExactlyAsPredicted) {
  struct Case {
    CompareFunc func;
    float units;
    bool second_wins;
    int depth_delta;  // second's stored depth minus first's, where it wins
  };
  const Case cases[] = {
      {CompareFunc::less, 0.0f, false, 0},
      {CompareFunc::lequal, 0.0f, true, 0},
      {CompareFunc::less, -1.0f, true, -1},
      {CompareFunc::lequal, 1.0f, false, 0},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::Message() << to_string(c.func) << " units " << c.units);
    Scene first_only = frame(64, 64, ColorFormat::rgba8, DepthFormat::unorm24);
    Draw a = sloped({1, 0, 0, 1});
    a.state.depth_func = c.func;
    first_only.draws.push_back(a);
    Scene both = first_only;
    Draw b = sloped({0, 1, 0, 1});
    b.state.depth_func = c.func;
    b.state.offset_units = c.units;
    both.draws.push_back(b);
    const golden::Result r1 = golden::render(first_only);
    const golden::Result r2 = golden::render(both);
    int covered = 0;
    for (size_t p = 0; p < r1.last_writer.size(); ++p) {
      if (r1.last_writer[p] < 0) {
        EXPECT_LT(r2.last_writer[p], 0);
        continue;
      }
      ++covered;
      const int64_t want_writer = c.second_wins ? 1 : 0;
      ASSERT_EQ(r2.last_writer[p], want_writer) << "pixel " << p % 64 << ", " << p / 64;
      ASSERT_EQ(r2.framebuffer.color[p * 4 + 1], c.second_wins ? 255 : 0);
      ASSERT_EQ(static_cast<int64_t>(r2.framebuffer.depth[p]) -
                    static_cast<int64_t>(r1.framebuffer.depth[p]),
                c.depth_delta);
    }
    EXPECT_GT(covered, 200);
  }
}

// Offset magnitude: window v0 (8, 24) z 0.25, v1 (8, 8) z 0.5, v2 (40, 8)
// z 0.75 (counter-clockwise). By hand: dx1 = 0, dy1 = -16, dx2 = 32,
// dy2 = -16, dz1 = 0.25, dz2 = 0.5, a = 512; dzdx = (0.25 (-16) - 0.5 (-16))
// / 512 = 1/128, dzdy = (0.5 * 0 - 0.25 * 32) / 512 = -1/64; m = 1/64 (all
// exact in float). factor 2 -> offset 1/32.
// float32: r = 2^(e - 23), e = exponent of the largest |z_i|, 0.75: e = -1,
// r = 2^-24 (v0's 0.25 would give 2^-25).
TEST(GoldenPolygonOffset, SlopeAndUnitsMagnitudeFloat32) {
  auto render_with = [](float factor, float units, bool clockwise) {
    Scene s = frame(64, 64, ColorFormat::rgba8, DepthFormat::float32);
    Draw d;
    d.positions = {at(8, 24, 0.25f, 64, 64), at(8, 8, 0.5f, 64, 64), at(40, 8, 0.75f, 64, 64)};
    if (clockwise) std::swap(d.positions[1], d.positions[2]);
    d.state.depth_func = CompareFunc::always;
    d.state.offset_factor = factor;
    d.state.offset_units = units;
    s.draws.push_back(d);
    return golden::render(s);
  };
  const golden::Result base = render_with(0, 0, false);
  const golden::Result slope = render_with(2, 0, false);
  const golden::Result slope_cw = render_with(2, 0, true);
  const golden::Result unit = render_with(0, 1, false);
  int covered = 0, checked_units = 0;
  for (size_t p = 0; p < base.last_writer.size(); ++p) {
    if (base.last_writer[p] < 0) continue;
    ++covered;
    const float z = float_from_bits(base.framebuffer.depth[p]);
    const float zs = float_from_bits(slope.framebuffer.depth[p]);
    // z + 1/32 rounded once: within half an ulp of values below 1 (2^-25).
    EXPECT_NEAR(zs - z, 1.0f / 32.0f, std::ldexp(1.0f, -24)) << "pixel " << p;
    // The winding does not change the offset.
    EXPECT_EQ(slope_cw.framebuffer.depth[p], slope.framebuffer.depth[p]) << "pixel " << p;
    // Units: + 2^-24 is exact for z in [0.5, 1 - 2^-24] (ulp 2^-24: one step)
    // and for z in [0.25, 0.5 - 2^-24] (ulp 2^-25: two steps).
    const uint32_t zb = base.framebuffer.depth[p], zu = unit.framebuffer.depth[p];
    if (z >= 0.5f && z <= 1.0f - std::ldexp(1.0f, -24)) {
      EXPECT_EQ(zu, zb + 1) << "pixel " << p << " z " << z;
      ++checked_units;
    } else if (z >= 0.25f && z <= 0.5f - std::ldexp(1.0f, -24)) {
      EXPECT_EQ(zu, zb + 2) << "pixel " << p << " z " << z;
      ++checked_units;
    }
  }
  EXPECT_GT(covered, 200);
  EXPECT_GT(checked_units, 200);
}

// units = -1 moves a constant z = 0.25 exactly one unorm step nearer.
// unorm16: 1/65535 = 2^-16 (1 + 2^-16 + 2^-32 + ...), so r = float(1/65535)
// = 2^-16 (1 + 2^-16); 0.25 - r = 0.25 - 2^-16 - 2^-32 rounds (float spacing
// 2^-26 below 0.25) to 0.25 - 2^-16; times 65535: 16383.75 - 0.99998 =
// 16382.75 -> 16383, one below 16384.
// unorm24: r = 2^-24 (see above); 0.25 - 2^-24 is exact; times (2^24 - 1):
// 4194303.75 - 1 + 2^-24 -> 4194303, one below 4194304.
TEST(GoldenPolygonOffset, UnitsAreOneUnormStep) {
  for (DepthFormat f : {DepthFormat::unorm16, DepthFormat::unorm24}) {
    Scene s = frame(8, 8, ColorFormat::rgba8, f);
    Draw d = square_8x8(0.25f, {1, 1, 1, 1});
    d.state.offset_units = -1.0f;
    s.draws.push_back(d);
    const golden::Result r = golden::render(s);
    const uint32_t want = f == DepthFormat::unorm16 ? 16383u : 4194303u;
    for (int p = 0; p < 64; ++p) ASSERT_EQ(r.framebuffer.depth[p], want) << to_string(f);
  }
}

// A large negative offset clamps to 0, a large positive one to 1 (section 11).
TEST(GoldenPolygonOffset, OffsetDepthIsClamped) {
  for (float units : {-100.0f, 100.0f}) {
    Scene s = frame(8, 8, ColorFormat::rgba8, DepthFormat::unorm16, {0, 0, 0, 0}, 0.5f);
    Draw d = square_8x8(units < 0 ? 0.0f : 1.0f, {1, 1, 1, 1});
    d.state.depth_func = CompareFunc::always;
    d.state.offset_units = units;
    s.draws.push_back(d);
    const golden::Result r = golden::render(s);
    for (int p = 0; p < 64; ++p) ASSERT_EQ(r.framebuffer.depth[p], units < 0 ? 0u : 65535u);
  }
}

// float32 with every vertex at z = 0: the largest |z_i| is 0. Spec: r =
// 2^(e - 23), "not below 2^-149". Zero has no exponent of its own; taken as
// -infinity (or as IEEE's minimum exponent -126 shared with subnormals) the
// rule gives the floor 2^-149, so units = 1 stores the smallest subnormal
// (bits 0x00000001).
TEST(GoldenPolygonOffset, Float32UnitsAtZeroDepthUseTheFloor) {
  Scene s = frame(8, 8, ColorFormat::rgba8, DepthFormat::float32);
  Draw d = square_8x8(0.0f, {1, 1, 1, 1});
  d.state.depth_func = CompareFunc::always;
  d.state.offset_units = 1.0f;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.framebuffer.depth[0], 1u) << "stored " << float_from_bits(r.framebuffer.depth[0]);
}

// ---------------------------------------------------------------------------
// Section 12: blending, colour mask, colour formats.

// One pixel, covered by one flat-shaded triangle of colour s.
golden::Result blend_one(ColorFormat cf, glm::vec4 clear, glm::vec4 s, const RenderState& st) {
  Scene sc = frame(1, 1, cf, DepthFormat::unorm24, clear);
  Draw d;
  // Window (-1, -1), (3, -1), (-1, 3): clip x / 0.5 - 1.
  d.positions = {{-3, -3, 0, 1}, {5, -3, 0, 1}, {-3, 5, 0, 1}};
  d.colors.assign(3, s);
  d.state = st;
  d.state.shading = Shading::flat;
  d.state.depth_test = false;
  sc.draws.push_back(d);
  return golden::render(sc);
}

std::vector<ColorChannel> pixel0(const golden::Result& r) {
  return {r.framebuffer.color.begin(), r.framebuffer.color.begin() + 4};
}

RenderState blending(BlendFactor src, BlendFactor dst, BlendEquation eq) {
  RenderState st;
  st.blend = true;
  st.blend_src = src;
  st.blend_dst = dst;
  st.blend_equation = eq;
  return st;
}

using V = std::vector<ColorChannel>;

TEST(GoldenBlend, HandComputedCases) {
  using F = BlendFactor;
  using E = BlendEquation;
  // Classic alpha: s = (1, 0, 0, 0.25) over d = (0, 0, 1, 1):
  // r 0.25 -> 63.75 -> 64; b 0.75 -> 191.25 -> 191;
  // a 0.25 * 0.25 + 1 * 0.75 = 0.8125 -> 207.1875 -> 207.
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, {0, 0, 1, 1}, {1, 0, 0, 0.25f},
                             blending(F::src_alpha, F::one_minus_src_alpha, E::add))),
            (V{64, 0, 191, 207}));
  // Additive, clamped: s = (0.75, 0.25, 0, 1), d = (1, 51/255, 0, 1):
  // r 1.75 -> 255; g 0.25 + 0.2 = 0.45 -> 114.75 -> 115; a 2 -> 255.
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, {1, 0.2f, 0, 1}, {0.75f, 0.25f, 0, 1},
                             blending(F::one, F::one, E::add))),
            (V{255, 115, 0, 255}));
  // Subtract: s = (0.25, 0.75, 0.5, 1) - d = (1, 0.2, 0, 1):
  // r -0.75 -> 0; g 0.55 -> 140.25 -> 140; b 0.5 -> 127.5 -> 128 (tie, even);
  // a 0.
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, {1, 0.2f, 0, 1}, {0.25f, 0.75f, 0.5f, 1},
                             blending(F::one, F::one, E::subtract))),
            (V{0, 140, 128, 0}));
  // Reverse subtract: d - s: r 0.75 -> 191; g -0.55 -> 0; b -0.5 -> 0; a 0.
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, {1, 0.2f, 0, 1}, {0.25f, 0.75f, 0.5f, 1},
                             blending(F::one, F::one, E::reverse_subtract))),
            (V{191, 0, 0, 0}));
  // src_alpha_saturate: s = (1, 0.5, 0, 0.75), d.a = 153/255 = 0.6:
  // f = min(0.75, 0.4) = 0.4 for rgb: r 0.4 -> 102; g 0.2 -> 51;
  // alpha factor 1: a 0.75 -> 191.25 -> 191. dst factor zero.
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, {0, 0, 0, 0.6f}, {1, 0.5f, 0, 0.75f},
                             blending(F::src_alpha_saturate, F::zero, E::add))),
            (V{102, 51, 0, 191}));
  // Modulate (dst_color, zero): s = (0.5, 1, 0.25, 1) times d = (0.4, 0.6, 1, 0.8):
  // 0.2 -> 51; 0.6 -> 153; 0.25 -> 63.75 -> 64; 0.8 -> 204.
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, {0.4f, 0.6f, 1, 0.8f}, {0.5f, 1, 0.25f, 1},
                             blending(F::dst_color, F::zero, E::add))),
            (V{51, 153, 64, 204}));
  // one_minus_dst_alpha / dst_alpha with d.a = 0.6, s = (1, 0, 0.5, 1),
  // d = (0, 1, 0.5, 0.6) [0.5 clears to 128, read back as 128/255]:
  // r 1 * 0.4 + 0 = 0.4 -> 102; g 0 + 1 * 0.6 = 0.6 -> 153;
  // b 0.5 * 0.4 + (128/255) * 0.6 = 0.2 + 0.30118 = 0.50118 -> 127.8 -> 128;
  // a 1 * 0.4 + 0.6 * 0.6 = 0.76 -> 193.8 -> 194.
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, {0, 1, 0.5f, 0.6f}, {1, 0, 0.5f, 1},
                             blending(F::one_minus_dst_alpha, F::dst_alpha, E::add))),
            (V{102, 153, 128, 194}));
}

// Every factor pair and equation on one source and destination, against the
// spec's formula evaluated in double from the same float inputs. Where the
// exact value lies within 1e-3 of a rounding tie, float and double may round
// differently, so either neighbour is accepted (counted, and bounded).
TEST(GoldenBlend, AllFactorsAndEquationsRgba8) {
  const glm::vec4 clear(0.2f, 0.8f, 0.4f, 0.6f);  // stores 51, 204, 102, 153
  const double d[4] = {51 / 255.0, 204 / 255.0, 102 / 255.0, 153 / 255.0};
  const glm::vec4 s(0.77f, 0.29f, 0.61f, 0.45f);  // no result near a rounding tie
  const double sd[4] = {s.r, s.g, s.b, s.a};
  auto factor = [&](BlendFactor f, int k) -> double {
    switch (f) {
      case BlendFactor::zero:
        return 0;
      case BlendFactor::one:
        return 1;
      case BlendFactor::src_color:
        return sd[k];
      case BlendFactor::one_minus_src_color:
        return 1 - sd[k];
      case BlendFactor::dst_color:
        return d[k];
      case BlendFactor::one_minus_dst_color:
        return 1 - d[k];
      case BlendFactor::src_alpha:
        return sd[3];
      case BlendFactor::one_minus_src_alpha:
        return 1 - sd[3];
      case BlendFactor::dst_alpha:
        return d[3];
      case BlendFactor::one_minus_dst_alpha:
        return 1 - d[3];
      case BlendFactor::src_alpha_saturate:
        return k < 3 ? std::min(sd[3], 1 - d[3]) : 1;
    }
    return NAN;
  };
  int near_ties = 0, checked = 0;
  for (int fs = 0; fs <= static_cast<int>(BlendFactor::src_alpha_saturate); ++fs) {
    for (int fd = 0; fd <= static_cast<int>(BlendFactor::src_alpha_saturate); ++fd) {
      for (int eq = 0; eq <= static_cast<int>(BlendEquation::reverse_subtract); ++eq) {
        const auto F_s = static_cast<BlendFactor>(fs), F_d = static_cast<BlendFactor>(fd);
        const auto E = static_cast<BlendEquation>(eq);
        const V got = pixel0(blend_one(ColorFormat::rgba8, clear, s, blending(F_s, F_d, E)));
        for (int k = 0; k < 4; ++k) {
          const double a = sd[k] * factor(F_s, k), b = d[k] * factor(F_d, k);
          double out = E == BlendEquation::add        ? a + b
                       : E == BlendEquation::subtract ? a - b
                                                      : b - a;
          out = std::min(1.0, std::max(0.0, out)) * 255.0;
          const double frac = out - std::floor(out);
          SCOPED_TRACE(::testing::Message() << to_string(F_s) << " " << to_string(F_d) << " "
                                            << to_string(E) << " channel " << k);
          ++checked;
          if (std::fabs(frac - 0.5) < 1e-3) {
            ++near_ties;
            EXPECT_TRUE(got[k] == std::floor(out) || got[k] == std::ceil(out)) << out;
          } else {
            EXPECT_EQ(static_cast<long>(got[k]), std::lround(out)) << out;
          }
        }
      }
    }
  }
  EXPECT_EQ(checked, 11 * 11 * 3 * 4);
  EXPECT_LT(near_ties, 3);
}

TEST(GoldenBlend, ColourMask) {
  const glm::vec4 clear(0.2f, 0.8f, 0.4f, 0.6f);  // 51, 204, 102, 153
  // No blending, mask r and b: s = (0.25, 0.5, 0.75, 0.125) writes r 64, b 191.
  RenderState st;
  st.color_mask = {true, false, true, false};
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, clear, {0.25f, 0.5f, 0.75f, 0.125f}, st)),
            (V{64, 204, 191, 153}));
  // Blending one/one, mask g only: g = 0.8 + 0.125 = 0.925 -> 235.875 -> 236.
  RenderState sb = blending(BlendFactor::one, BlendFactor::one, BlendEquation::add);
  sb.color_mask = {false, true, false, false};
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, clear, {0.25f, 0.125f, 0.75f, 0.125f}, sb)),
            (V{51, 236, 102, 153}));
}

// All channels masked: the fragment passes the depth test and writes depth,
// but changes no colour, is not counted as written, and is no last writer.
TEST(GoldenBlend, FullyMaskedFragmentWritesOnlyDepth) {
  Scene s = frame(8, 8, ColorFormat::rgba8, DepthFormat::unorm16, {0.2f, 0.8f, 0.4f, 0.6f}, 1.0f);
  Draw d = square_8x8(0.5f, {1, 1, 1, 1});
  d.state.color_mask = {false, false, false, false};
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.fragments_generated, 64u);
  EXPECT_EQ(r.stats.fragments_passed_depth, 64u);
  EXPECT_EQ(r.stats.fragments_written, 0u);
  for (int p = 0; p < 64; ++p) {
    EXPECT_EQ(r.framebuffer.depth[p], 32768u);
    EXPECT_EQ(r.last_writer[p], -1);
    EXPECT_EQ(V(r.framebuffer.color.begin() + p * 4, r.framebuffer.color.begin() + p * 4 + 4),
              (V{51, 204, 102, 153}));
  }
}

// rgba16f keeps blended values outside [0, 1]; rgba8 clamps them.
// d = (0.75, -0.25, 3, 0.5) (exact halves), s = (0.75, 0.5, 1, 1):
// add: (1.5, 0.25, 4, 1.5) -> 0x3E00, 0x3400, 0x4400, 0x3E00;
// subtract: (0, 0.75, -2, 0.5) -> 0x0000, 0x3A00, 0xC000, 0x3800.
TEST(GoldenBlend, Rgba16fStoresUnclampedValues) {
  const glm::vec4 clear(0.75f, -0.25f, 3.0f, 0.5f);
  const glm::vec4 s(0.75f, 0.5f, 1.0f, 1.0f);
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba16f, clear, s,
                             blending(BlendFactor::one, BlendFactor::one, BlendEquation::add))),
            (V{0x3E00, 0x3400, 0x4400, 0x3E00}));
  EXPECT_EQ(
      pixel0(blend_one(ColorFormat::rgba16f, clear, s,
                       blending(BlendFactor::one, BlendFactor::one, BlendEquation::subtract))),
      (V{0x0000, 0x3A00, 0xC000, 0x3800}));
  // Unblended: the source as is; half(1/3) = 0x3555, half(0.1): exponent -4
  // (0x2C00), mantissa round(1024 * (1.6 - 1)) = round(614.4) = 614 = 0x266.
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba16f, clear, {1.0f / 3.0f, 0.1f, 0.0f, 1.0f},
                             RenderState{})),
            (V{0x3555, 0x2E66, 0x0000, 0x3C00}));
  // rgba8 clamps the same additive blend: d stores (191, 0, 255, 128) [0.75 ->
  // 191.25; -0.25 -> 0; 3 -> 255; 0.5 -> 127.5 -> 128], read back /255:
  // r 0.75 + 191/255 > 1 -> 255; g 0.5 + 0 -> 127.5 -> 128 (tie, even);
  // b 1 + 1 -> 255; a 1 + 128/255 -> 255.
  EXPECT_EQ(pixel0(blend_one(ColorFormat::rgba8, clear, s,
                             blending(BlendFactor::one, BlendFactor::one, BlendEquation::add))),
            (V{255, 128, 255, 255}));
}

}  // namespace
}  // namespace gpusim
