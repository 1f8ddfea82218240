// Golden model: the accuracy of multisampling (docs/pipeline-spec.md section
// 14), measured the way piglit's ext_framebuffer_multisample/accuracy does
// (tests/spec/ext_framebuffer_multisample/common.cpp, the "color" test):
//
// - the test pattern is piglit's Triangles: 8 x 8 triangles (-0.5, -1),
//   (0, 1), (0.5, -1) scaled by 0.8 / 8, triangle t rotated by t * 2pi / 64
//   and moved to the centre of cell (t % 8, 7 - t / 8), everything scaled by
//   0.95, white on a (0, 0, 0, 0) clear, in a 256 x 256 framebuffer;
// - the reference is the same pattern supersampled: piglit renders it 16x
//   larger in x and y and box-filters 16 x 16 pixels; here supersample 4 with
//   16 samples per render-target pixel, 256 samples per output pixel too;
// - edge pixels are the channels whose reference value is strictly between
//   0 and 1 ("partially lit"); the RMS of (test - reference) over them must
//   be below 0.333 * 0.62^log2(N). Channels the reference has fully lit or
//   unlit are counted and printed as well.
//
// Also: the error must decrease as N grows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <vector>

#include "hw/pixel_formats.h"
#include "testbench/golden/golden_model.h"

namespace gpusim {
namespace {

constexpr int kSize = 256;
constexpr double kPi = 3.14159265358979323846;

// piglit's Triangles pattern in clip space (w = 1; identity matrices).
Scene triangles_pattern(unsigned samples, unsigned supersample) {
  Scene s;
  s.framebuffer.width = kSize;
  s.framebuffer.height = kSize;
  s.framebuffer.samples = samples;
  s.framebuffer.supersample = supersample;
  s.framebuffer.color_format = ColorFormat::rgba8;
  s.framebuffer.clear_color = {0, 0, 0, 0};
  Draw d;
  d.state.depth_test = false;
  d.state.shading = Shading::flat;
  const float within[3][2] = {{-0.5f, -1.0f}, {0.0f, 1.0f}, {0.5f, -1.0f}};
  const int across = 8;
  const int count = across * across;
  const float tri_scale = 0.8f / across;
  const float rotation_delta = static_cast<float>(kPi * 2.0 / count);
  const float final_scale = 0.95f;
  for (int t = 0; t < count; ++t) {
    const float rotation = rotation_delta * static_cast<float>(t);
    const int i = t % across;
    const int j = across - 1 - t / across;
    for (const auto& v : within) {
      float x = tri_scale * v[0], y = tri_scale * v[1];
      // GLSL's mat2(c, s, -s, c) * pos (column-major).
      const float rx = std::cos(rotation) * x - std::sin(rotation) * y;
      const float ry = std::sin(rotation) * x + std::cos(rotation) * y;
      x = (rx + (static_cast<float>(i) * 2.0f + 1.0f) / across - 1.0f) * final_scale;
      y = (ry + (static_cast<float>(j) * 2.0f + 1.0f) / across - 1.0f) * final_scale;
      d.positions.push_back({x, y, 0.0f, 1.0f});
      d.colors.push_back({1.0f, 1.0f, 1.0f, 1.0f});
    }
  }
  s.draws.push_back(d);
  return s;
}

struct Accuracy {
  double rms = 0.0;       // over the partially lit channels of the reference
  int partial = 0;        // channels the reference has strictly between 0 and 1
  int wrong_extreme = 0;  // channels the reference has at 0 or 1 and the test not
};

std::vector<float> colours(const Framebuffer& fb) {
  std::vector<float> out(fb.color.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = decode_color(fb.color_format, fb.color[i]);
  return out;
}

Accuracy measure(const std::vector<float>& test, const std::vector<float>& ref) {
  Accuracy a;
  double sum = 0.0;
  for (size_t i = 0; i < ref.size(); ++i) {
    const double e = static_cast<double>(test[i]) - ref[i];
    if (ref[i] <= 0.0f || ref[i] >= 1.0f) {
      if (e != 0.0) ++a.wrong_extreme;
    } else {
      sum += e * e;
      ++a.partial;
    }
  }
  a.rms = a.partial > 0 ? std::sqrt(sum / a.partial) : 0.0;
  return a;
}

TEST(GoldenAntialias, PiglitAccuracyAgainstSupersampledReference) {
  const golden::Result reference = golden::render(triangles_pattern(16, 4));
  ASSERT_EQ(reference.framebuffer.width, kSize);
  ASSERT_EQ(reference.framebuffer.height, kSize);
  const std::vector<float> ref = colours(reference.framebuffer);
  const std::vector<float> coarse_ref =
      colours(golden::render(triangles_pattern(1, 4)).framebuffer);
  double previous = 1.0;
  for (unsigned n : {1u, 2u, 4u, 8u, 16u}) {
    const golden::Result test = golden::render(triangles_pattern(n, 1));
    ASSERT_EQ(test.framebuffer.width, kSize);
    const Accuracy a = measure(colours(test.framebuffer), ref);
    const double limit = 0.333 * std::pow(0.62, std::log2(static_cast<double>(n)));
    std::printf(
        "piglit accuracy, %2u samples: RMS error %.4f over %d partially lit channels "
        "(limit %.4f); %d fully lit or unlit channels differ\n",
        n, a.rms, a.partial, limit, a.wrong_extreme);
    // For comparison only: against supersample 4 alone (16 samples per
    // pixel on a regular 4 x 4 grid), a reference as coarse as the 16-sample
    // test itself.
    const Accuracy coarse = measure(colours(test.framebuffer), coarse_ref);
    std::printf("                            against supersample 4 x 1 sample: RMS %.4f over %d\n",
                coarse.rms, coarse.partial);
    EXPECT_GT(a.partial, 1000) << n << " samples: the pattern has edges";
    EXPECT_LT(a.rms, limit) << n << " samples";
    EXPECT_LT(a.rms, previous) << n << " samples: the error must decrease as N grows";
    previous = a.rms;
  }
}

// ---------------------------------------------------------------------------
// Analytic tests of the golden model's multisampling and supersampling
// against docs/pipeline-spec.md section 14, with the sample table copied from
// the spec (not from hw/sample_pattern.h): (x, y) in 1/16 pixel from the
// pixel's lower-left corner.

struct Pos {
  int x, y;
};
std::vector<Pos> spec_pattern(unsigned n) {
  switch (n) {
    case 1:
      return {{8, 8}};
    case 2:
      return {{12, 12}, {4, 4}};
    case 4:
      return {{6, 2}, {14, 6}, {2, 10}, {10, 14}};
    case 8:
      return {{9, 5}, {7, 11}, {13, 9}, {5, 3}, {3, 13}, {1, 7}, {11, 15}, {15, 1}};
    case 16:
      return {{9, 9},  {7, 5}, {5, 10}, {12, 7}, {3, 6}, {10, 13}, {13, 11}, {11, 3},
              {6, 14}, {8, 1}, {4, 2},  {2, 12}, {0, 8}, {15, 4},  {14, 15}, {1, 0}};
  }
  return {};
}

constexpr int kSmall = 16;  // a 16x16 frame: window x_w = (x_ndc + 1) * 8

// Window coordinate (pixels) to clip space for the 16x16 frame (exact for
// the multiples of 1/256 used here).
float ndc(float window) {
  return window / 8.0f - 1.0f;
}

Scene small_scene(unsigned samples, ColorFormat cf = ColorFormat::rgba8) {
  Scene s;
  s.framebuffer.width = kSmall;
  s.framebuffer.height = kSmall;
  s.framebuffer.samples = samples;
  s.framebuffer.color_format = cf;
  s.framebuffer.depth_format = DepthFormat::float32;
  s.framebuffer.clear_color = {0, 0, 0, 0};
  return s;
}

// A flat-shaded draw of one colour, no depth test, window coordinates.
Draw flat_draw(PrimitiveType type, const std::vector<glm::vec2>& window, glm::vec4 colour,
               float z = 0.0f) {
  Draw d;
  d.primitive = type;
  d.state.depth_test = false;
  d.state.shading = Shading::flat;
  for (const glm::vec2& p : window) {
    d.positions.push_back({ndc(p.x), ndc(p.y), z, 1.0f});
    d.colors.push_back(colour);
  }
  return d;
}

// The resolved rgba8 value of c white samples out of n on black (spec:
// floor((2 sum + n) / (2 n)) with sum = 255 c).
unsigned resolved8(unsigned c, unsigned n) {
  return (2 * 255 * c + n) / (2 * n);
}

// Counts, per pixel of the 16x16 frame, the samples (subpixel point of
// sample i: 256 x + 16 sx_i, 256 y + 16 sy_i) that `inside` accepts.
std::vector<unsigned> expected_counts(unsigned n, const std::function<bool(int, int)>& inside) {
  std::vector<unsigned> c(kSmall * kSmall, 0);
  for (int y = 0; y < kSmall; ++y) {
    for (int x = 0; x < kSmall; ++x) {
      for (const Pos& p : spec_pattern(n)) {
        if (inside(256 * x + 16 * p.x, 256 * y + 16 * p.y)) ++c[y * kSmall + x];
      }
    }
  }
  return c;
}

// Every channel of every pixel is resolved8(count) (white, alpha 1, on a
// black clear with alpha 0), and samples_generated is the total.
void expect_white_coverage(const golden::Result& r, unsigned n, const std::vector<unsigned>& counts,
                           const std::string& what) {
  uint64_t total = 0;
  int wrong = 0;
  for (int y = 0; y < kSmall; ++y) {
    for (int x = 0; x < kSmall; ++x) {
      const unsigned c = counts[y * kSmall + x];
      total += c;
      for (int ch = 0; ch < 4; ++ch) {
        const unsigned got = r.framebuffer.color_at(x, y)[ch];
        if (got != resolved8(c, n) && wrong++ < 5) {
          ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") channel " << ch << " is "
                        << got << ", want " << resolved8(c, n) << " (" << c << " of " << n
                        << " samples)";
        }
      }
    }
  }
  EXPECT_EQ(wrong, 0) << what;
  EXPECT_EQ(r.stats.samples_generated, total) << what;
}

TEST(GoldenAntialias, ResolveFormulaValues) {
  // The spec's rgba8 resolve by hand: the mean of c * 255 over n, half up.
  EXPECT_EQ(resolved8(2, 4), 128u);   // 127.5
  EXPECT_EQ(resolved8(1, 4), 64u);    // 63.75
  EXPECT_EQ(resolved8(3, 4), 191u);   // 191.25
  EXPECT_EQ(resolved8(4, 8), 128u);   // 127.5
  EXPECT_EQ(resolved8(8, 16), 128u);  // 127.5
  EXPECT_EQ(resolved8(1, 16), 16u);   // 15.9375
  EXPECT_EQ(resolved8(1, 2), 128u);   // 127.5
}

TEST(GoldenAntialias, HalfPlaneCoversThePatternPositionsOnItsSide) {
  // (a) A horizontal bottom edge at y_w = 8 + t/16: the triangle (-20, Y),
  // (40, Y), (10, 60) is counter-clockwise with the edge v0 -> v1 a bottom
  // edge (owning its boundary), so sample i of a pixel in row 8 is covered
  // iff sy_i >= t; rows above are fully covered, rows below not at all. The
  // other two edges lie outside the frame. And a vertical left edge at
  // x_w = 8 + t/16: (X, 60), (X, -20), (50, 20), covered iff sx_i >= t in
  // column 8 (a left edge owns its boundary).
  for (const unsigned n : {1u, 2u, 4u, 8u, 16u}) {
    for (int t = 0; t <= 16; ++t) {
      const float off = 8.0f + static_cast<float>(t) / 16.0f;
      const int sub = 256 * 8 + 16 * t;
      {
        Scene s = small_scene(n);
        s.draws.push_back(
            flat_draw(PrimitiveType::triangles, {{-20, off}, {40, off}, {10, 60}}, {1, 1, 1, 1}));
        expect_white_coverage(
            golden::render(s), n, expected_counts(n, [&](int, int py) { return py >= sub; }),
            "horizontal edge, " + std::to_string(n) + " samples, t=" + std::to_string(t));
      }
      {
        Scene s = small_scene(n);
        s.draws.push_back(
            flat_draw(PrimitiveType::triangles, {{off, 60}, {off, -20}, {50, 20}}, {1, 1, 1, 1}));
        expect_white_coverage(
            golden::render(s), n, expected_counts(n, [&](int px, int) { return px >= sub; }),
            "vertical edge, " + std::to_string(n) + " samples, t=" + std::to_string(t));
      }
    }
  }
  // The counts themselves for 4 samples (sy = 2, 6, 10, 14): t = 7 leaves 2.
  Scene s = small_scene(4);
  s.draws.push_back(flat_draw(PrimitiveType::triangles,
                              {{-20, 8 + 7 / 16.0f}, {40, 8 + 7 / 16.0f}, {10, 60}}, {1, 1, 1, 1}));
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.framebuffer.color_at(5, 8)[0], 128u);  // 2 of 4: 127.5 rounds up
  EXPECT_EQ(r.framebuffer.color_at(5, 9)[0], 255u);
  EXPECT_EQ(r.framebuffer.color_at(5, 7)[0], 0u);
  EXPECT_EQ(r.stats.samples_generated, 16u * 2u + 7u * 16u * 4u);
  EXPECT_EQ(r.stats.fragments_generated, 8u * 16u);
}

TEST(GoldenAntialias, ResolveRgba16fSumsThenRoundsToNearestEven) {
  // (b) rgba16f: 3 of 4 samples of colour 0.1 (stored as half(0.1) =
  // 0x2E66 = 1638/16384) and one sample cleared to 0. Sum 3 * 1638/16384,
  // exact in float; / 4 = 4914/65536 = 1.19970703125 * 2^-4, whose 10-bit
  // mantissa 1228.5 / 1024 is a tie: round to even gives 1228, i.e. half
  // 0x2C00 | 204 = 0x2CCC (round half up would give 0x2CCD). Alpha: 3 of 4
  // ones: 0.75 = 0x3A00. A half plane at y_w = 8 + 3/16 covers 3 of the 4
  // samples (sy = 6, 10, 14) of row 8.
  Scene s = small_scene(4, ColorFormat::rgba16f);
  const float y = 8 + 3 / 16.0f;
  s.draws.push_back(
      flat_draw(PrimitiveType::triangles, {{-20, y}, {40, y}, {10, 60}}, {0.1f, 0.1f, 0.1f, 1}));
  const golden::Result r = golden::render(s);
  for (int x = 0; x < kSmall; ++x) {
    EXPECT_EQ(r.framebuffer.color_at(x, 8)[0], 0x2CCCu) << x;
    EXPECT_EQ(r.framebuffer.color_at(x, 8)[3], 0x3A00u) << x;
    EXPECT_EQ(r.framebuffer.color_at(x, 9)[0], 0x2E66u) << x;  // 4 of 4: the value itself
    EXPECT_EQ(r.framebuffer.color_at(x, 7)[0], 0u) << x;
  }
  // 2 of 4 whites: 0.5 exactly = 0x3800.
  Scene h = small_scene(4, ColorFormat::rgba16f);
  const float y2 = 8 + 7 / 16.0f;
  h.draws.push_back(
      flat_draw(PrimitiveType::triangles, {{-20, y2}, {40, y2}, {10, 60}}, {1, 1, 1, 1}));
  EXPECT_EQ(golden::render(h).framebuffer.color_at(3, 8)[1], 0x3800u);
}

TEST(GoldenAntialias, WideMultisampledLineIsARectangle) {
  // (c) A horizontal line of width 2 from A = (3 + 6/16, 8 + 2/16) to
  // B = (12 + 10/16, 8 + 2/16): o = (0, iround(dx * 2 * 128 / dx)) = (0, 256),
  // the rectangle A - o, B - o, B + o, A + o: its bottom (owns: >=) and left
  // (owns) edges, its right and top edges not. So sample (px, py) is covered
  // iff Ax <= px < Bx and Ay - 256 <= py < Ay + 256: no end extension, and
  // with 4 samples the boundaries fall on samples (sx 6 at A, sx 10 at B,
  // sy 2 at both horizontal sides).
  const int ax = 256 * 3 + 96, bx = 256 * 12 + 160, ay = 256 * 8 + 32;
  for (const unsigned n : {2u, 4u, 8u, 16u}) {
    for (const LineRasterization rule :
         {LineRasterization::diamond_exit, LineRasterization::bresenham}) {
      Scene s = small_scene(n);
      Draw d = flat_draw(PrimitiveType::lines,
                         {{ax / 256.0f, ay / 256.0f}, {bx / 256.0f, ay / 256.0f}}, {1, 1, 1, 1});
      d.state.line_width = 2.0f;
      d.state.line_rasterization = rule;
      s.draws.push_back(d);
      expect_white_coverage(golden::render(s), n,
                            expected_counts(n,
                                            [&](int px, int py) {
                                              return ax <= px && px < bx && ay - 256 <= py &&
                                                     py < ay + 256;
                                            }),
                            "line, " + std::to_string(n) + " samples");
    }
  }
  // With 4 samples: pixel (3, 7) holds the corner A - o: of its samples
  // (6,2) (14,6) (2,10) (10,14) those with sx >= 6 and sy >= 2: 3.
  Scene s = small_scene(4);
  Draw d = flat_draw(PrimitiveType::lines, {{ax / 256.0f, ay / 256.0f}, {bx / 256.0f, ay / 256.0f}},
                     {1, 1, 1, 1});
  d.state.line_width = 2.0f;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.framebuffer.color_at(3, 7)[0], resolved8(3, 4));
  EXPECT_EQ(r.framebuffer.color_at(3, 9)[0], resolved8(0, 4));  // sy 2 of row 9: the top, open
}

TEST(GoldenAntialias, MultisampledPointIsItsSquare) {
  // (d) A point of size 3 at window (8 + 5/16, 7 + 11/16): F = 768,
  // X0 = iround((8.3125 - 0.5) * 256) - 384 = 2000 - 384 = 1616,
  // Y0 = iround((7.6875 - 0.5) * 256) - 384 = 1840 - 384 = 1456; sample
  // (px, py) is covered iff X0 <= px - 128 < X0 + F and likewise in y.
  const int x0 = 1616, y0 = 1456, f = 768;
  for (const unsigned n : {1u, 2u, 4u, 8u, 16u}) {
    Scene s = small_scene(n);
    Draw d = flat_draw(PrimitiveType::points, {{8 + 5 / 16.0f, 7 + 11 / 16.0f}}, {1, 1, 1, 1});
    d.state.point_size = 3.0f;
    s.draws.push_back(d);
    expect_white_coverage(golden::render(s), n,
                          expected_counts(n,
                                          [&](int px, int py) {
                                            return x0 <= px - 128 && px - 128 < x0 + f &&
                                                   y0 <= py - 128 && py - 128 < y0 + f;
                                          }),
                          "point, " + std::to_string(n) + " samples");
  }
}

TEST(GoldenAntialias, DepthIsTestedPerSample) {
  // (e) A green plane at z = 0 everywhere, then a red plane with
  // z_ndc = (x_w - 8.46875) / 64, depth test less: the red plane wins where
  // x_w < 8.46875, i.e. in pixel 8 at the samples with sx < 7.5 (16 sx < 120,
  // never on a sample: the planes meet 1/32 pixel from any sample column).
  // Columns 0..7 are all red, 9..15 all green. Every vertex's z is exact.
  const float xi = 8.46875f;
  const auto z = [&](float xw) { return (xw - xi) / 64.0f; };
  for (const unsigned n : {2u, 4u, 8u, 16u}) {
    Scene s = small_scene(n);
    Draw green =
        flat_draw(PrimitiveType::triangles, {{-20, -20}, {60, -20}, {-20, 60}}, {0, 1, 0, 1});
    green.state.depth_test = true;
    green.state.depth_func = CompareFunc::less;
    Draw red =
        flat_draw(PrimitiveType::triangles, {{-20, -20}, {60, -20}, {-20, 60}}, {1, 0, 0, 1});
    red.state.depth_test = true;
    red.state.depth_func = CompareFunc::less;
    for (glm::vec4& p : red.positions) p.z = z((p.x + 1.0f) * 8.0f);
    s.draws.push_back(green);
    s.draws.push_back(red);
    const golden::Result r = golden::render(s);
    unsigned split = 0;
    for (const Pos& p : spec_pattern(n)) split += 16 * p.x < 120 ? 1 : 0;
    ASSERT_GT(split, 0u);
    ASSERT_LT(split, n);
    for (int y = 0; y < kSmall; ++y) {
      for (int x = 0; x < kSmall; ++x) {
        const unsigned red_samples = x < 8 ? n : x > 8 ? 0 : split;
        EXPECT_EQ(r.framebuffer.color_at(x, y)[0], resolved8(red_samples, n))
            << n << " samples, pixel (" << x << ", " << y << ")";
        EXPECT_EQ(r.framebuffer.color_at(x, y)[1], resolved8(n - red_samples, n))
            << n << " samples, pixel (" << x << ", " << y << ")";
      }
    }
    // Red passes on the samples left of the line in every row.
    uint64_t red_total = 0;
    for (int x = 0; x < kSmall; ++x) red_total += x < 8 ? n : x > 8 ? 0 : split;
    EXPECT_EQ(r.stats.samples_passed_depth, 256u * n + 16u * red_total) << n;
  }
}

// A scene in clip space drawn at output size `size` with line widths and
// point sizes times `scale`: Gouraud triangles with depth, lines and points.
Scene mixed_scene(int size, unsigned samples, unsigned supersample, float scale) {
  Scene s;
  s.framebuffer.width = size;
  s.framebuffer.height = size;
  s.framebuffer.samples = samples;
  s.framebuffer.supersample = supersample;
  s.framebuffer.color_format = ColorFormat::rgba8;
  s.framebuffer.depth_format = DepthFormat::unorm24;
  s.framebuffer.clear_color = {0.1f, 0.2f, 0.3f, 1};
  Draw t;
  t.primitive = PrimitiveType::triangles;
  t.positions = {{-0.9f, -0.8f, 0.2f, 1}, {0.7f, -0.6f, -0.3f, 1}, {0.1f, 0.85f, 0.5f, 1},
                 {-0.5f, 0.6f, -0.6f, 1}, {0.3f, -0.9f, 0.4f, 1},  {0.9f, 0.4f, 0.0f, 1}};
  t.colors = {{1, 0, 0, 1},    {0, 1, 0, 1},    {0, 0, 1, 1},
              {1, 1, 0, 0.5f}, {0, 1, 1, 0.5f}, {1, 0, 1, 0.5f}};
  t.state.depth_func = CompareFunc::less;
  Draw l;
  l.primitive = PrimitiveType::lines;
  l.positions = {{-0.95f, -0.3f, -0.9f, 1},
                 {0.8f, 0.55f, -0.9f, 1},
                 {-0.2f, 0.9f, -0.9f, 1},
                 {0.15f, -0.95f, -0.9f, 1}};
  l.colors = {{1, 1, 1, 1}, {0.5f, 0.5f, 0.5f, 1}, {1, 0.5f, 0, 1}, {0, 0.5f, 1, 1}};
  l.state.line_width = 1.5f * scale;
  Draw p;
  p.primitive = PrimitiveType::points;
  p.positions = {{-0.6f, -0.6f, -0.95f, 1}, {0.55f, 0.3f, -0.95f, 1}, {0.02f, 0.01f, -0.95f, 1}};
  p.colors = {{1, 1, 1, 1}, {0.2f, 0.9f, 0.4f, 1}, {0.9f, 0.1f, 0.6f, 1}};
  p.state.point_size = 3.0f * scale;
  s.draws = {t, l, p};
  return s;
}

TEST(GoldenAntialias, SupersampleTwoIsTheDoubleSizeFrameBoxFiltered) {
  // (f) supersample 2 renders the frame at 2x size (line widths and point
  // sizes times 2) and box-filters 2 x 2 pixels: out = floor((2 sum + 4) / 8)
  // per rgba8 channel; depth = render pixel (2x, 2y)'s. Rendered here at
  // 2x size with one sample and filtered by hand. With 4 samples the 2x
  // frame's output is itself resolved, so only the render targets' counts
  // (statistics, last writers) can be compared.
  const int size = 40;
  for (const unsigned n : {1u, 4u}) {
    const golden::Result ss = golden::render(mixed_scene(size, n, 2, 1.0f));
    const golden::Result big = golden::render(mixed_scene(2 * size, n, 1, 2.0f));
    ASSERT_EQ(ss.framebuffer.width, size);
    ASSERT_EQ(big.framebuffer.width, 2 * size);
    int wrong = 0;
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) {
        for (int ch = 0; ch < 4; ++ch) {
          unsigned sum = 0;
          for (int j = 0; j < 2; ++j) {
            for (int i = 0; i < 2; ++i) {
              sum += big.framebuffer.color_at(2 * x + i, 2 * y + j)[ch];
            }
          }
          if (n == 1 && ss.framebuffer.color_at(x, y)[ch] != (2 * sum + 4) / 8 && wrong++ < 5) {
            ADD_FAILURE() << "pixel (" << x << ", " << y << ") channel " << ch << ": "
                          << ss.framebuffer.color_at(x, y)[ch] << ", want " << (2 * sum + 4) / 8;
          }
        }
        if (n == 1) {
          EXPECT_EQ(ss.framebuffer.depth[ss.framebuffer.pixel_index(x, y)],
                    big.framebuffer.depth[big.framebuffer.pixel_index(2 * x, 2 * y)]);
        }
      }
    }
    EXPECT_EQ(wrong, 0);
    // The statistics count render-target pixels and samples: the same frame.
    EXPECT_EQ(ss.stats.to_json(), big.stats.to_json()) << n << " samples";
    EXPECT_EQ(ss.last_writer, big.last_writer) << n << " samples";
  }
}

}  // namespace
}  // namespace gpusim
