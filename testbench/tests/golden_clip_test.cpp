// Golden model: clipping (docs/pipeline-spec.md section 4) and its effect on
// rendering. Expected values are worked out by hand in the comments, or come
// from the reference coverage below (exact integers, written from the spec's
// fill rule, see golden_raster_test.cpp for its derivation).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "testbench/golden/golden_model.h"
#include "testbench/tests/golden_support.h"

namespace gpusim {
namespace {

using namespace golden_support;

using golden::ShadedVertex;

ShadedVertex sv(glm::vec4 clip, glm::vec4 color = glm::vec4(1.0f)) {
  ShadedVertex v;
  v.clip = clip;
  v.color = color;
  return v;
}

Draw draw_of(const std::vector<glm::vec4>& positions, const std::vector<glm::vec4>& colors = {}) {
  Draw d;
  d.positions = positions;
  d.colors = colors;
  d.state.depth_test = false;
  return d;
}

bool same_bits(const glm::vec4& a, const glm::vec4& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// --- Reference coverage (exact, subpixel integers; see golden_raster_test.cpp).
std::vector<int> ref_coverage(const std::vector<Pt>& t, int W, int H) {
  const int64_t area =
      (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[1].y - t[0].y) * (t[2].x - t[0].x);
  std::vector<int> c(static_cast<size_t>(W) * H, 0);
  if (area == 0) return c;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const Pt p{256 * x + 128, 256 * y + 128};
      bool in = true;
      for (int i = 0; i < 3; ++i) in = in && perturbed_side(t[i], t[(i + 1) % 3], p) == sgn(area);
      c[static_cast<size_t>(y) * W + x] = in;
    }
  }
  return c;
}
std::vector<int> coverage_of(const golden::Result& r) {
  std::vector<int> c(r.last_writer.size());
  for (size_t i = 0; i < c.size(); ++i) c[i] = r.last_writer[i] >= 0;
  return c;
}
int count(const std::vector<int>& c) {
  int n = 0;
  for (int v : c) n += v;
  return n;
}

// ---------------------------------------------------------------------------

TEST(GoldenClip, GuardBandFactors) {
  // sx = 2 * 32768 / W: W = 64 -> 1024, H = 32 -> 2048.
  const golden::GuardBand gb = golden::guard_band_for(64, 32);
  EXPECT_EQ(gb.left, 1025.0f);
  EXPECT_EQ(gb.right, 1023.0f);
  EXPECT_EQ(gb.bottom, 2049.0f);
  EXPECT_EQ(gb.top, 2047.0f);
  const golden::GuardBand g2 = golden::guard_band_for(256, 8192);
  EXPECT_EQ(g2.left, 257.0f);
  EXPECT_EQ(g2.right, 255.0f);
  EXPECT_EQ(g2.bottom, 9.0f);
  EXPECT_EQ(g2.top, 7.0f);
}

// Section 4 with a viewport (10, 20, 64, 32): gl = 2 (32768 + 10) / 64 + 1 =
// 1025.3125, gr = 2 (32768 - 10) / 64 - 1 = 1022.6875, gb = 2 (32768 + 20)
// / 32 + 1 = 2050.25, gt = 2 (32768 - 20) / 32 - 1 = 2045.75 (all exact), and
// at x/w = -gl the window x is (1 - 1025.3125) * 32 + 10 = -32768 = -L.
TEST(GoldenClip, GuardBandFollowsTheViewport) {
  const PixelRect vp{10, 20, 64, 32};
  const golden::GuardBand gb = golden::guard_band_for(vp);
  EXPECT_EQ(gb.left, 1025.3125f);
  EXPECT_EQ(gb.right, 1022.6875f);
  EXPECT_EQ(gb.bottom, 2050.25f);
  EXPECT_EQ(gb.top, 2045.75f);
  golden::ShadedVertex v;
  v.clip = {-gb.left, -gb.bottom, 0.0f, 1.0f};
  EXPECT_EQ(golden::window_xy(v, vp), glm::vec2(-32768.0f, -32768.0f));
  v.clip = {gb.right, gb.top, 0.0f, 1.0f};
  EXPECT_EQ(golden::window_xy(v, vp), glm::vec2(32768.0f, 32768.0f));
  // The whole target's viewport gives the guard band of its size.
  const golden::GuardBand full = golden::guard_band_for(PixelRect{0, 0, 64, 32});
  EXPECT_EQ(full.left, 1025.0f);
  EXPECT_EQ(full.top, 2047.0f);
}

TEST(GoldenClip, PlaneDistances) {
  const golden::GuardBand gb = golden::guard_band_for(64, 32);  // 1025, 1023, 2049, 2047
  const glm::vec4 v(3.0f, -5.0f, 0.5f, 2.0f);
  // w - 2^-32 rounds to 2 (2^-32 is far below half an ulp of 2).
  EXPECT_EQ(golden::clip_distance(0, v, gb), 2.0f);
  EXPECT_EQ(golden::clip_distance(1, v, gb), 2.5f);     // z + w
  EXPECT_EQ(golden::clip_distance(2, v, gb), 1.5f);     // w - z
  EXPECT_EQ(golden::clip_distance(3, v, gb), 2053.0f);  // 3 + 1025 * 2
  EXPECT_EQ(golden::clip_distance(4, v, gb), 2043.0f);  // 1023 * 2 - 3
  EXPECT_EQ(golden::clip_distance(5, v, gb), 4093.0f);  // -5 + 2049 * 2
  EXPECT_EQ(golden::clip_distance(6, v, gb), 4099.0f);  // 2047 * 2 + 5
  EXPECT_EQ(golden::clip_distance(0, {0, 0, 0, std::ldexp(1.0f, -32)}, gb), 0.0f);
  EXPECT_EQ(golden::clip_distance(0, {0, 0, 0, 0}, gb), -std::ldexp(1.0f, -32));
  EXPECT_LT(golden::clip_distance(0, {0, 0, 0, -1}, gb), 0.0f);
}

TEST(GoldenClip, InsideTriangleIsReturnedUnchanged) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  // Vertices exactly on the near and far planes count as inside (d = 0).
  const std::array<ShadedVertex, 3> tri = {sv({0.25f, 0.1f, -1.0f, 1.0f}, {1, 0, 0, 1}),
                                           sv({-0.5f, 0.3f, 2.0f, 2.0f}, {0, 1, 0, 1}),
                                           sv({0.1f, -0.7f, 0.3f, 0.5f}, {0, 0, 1, 0.5f})};
  const std::vector<ShadedVertex> out = golden::clip_triangle(tri, gb);
  ASSERT_EQ(out.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(same_bits(out[i].clip, tri[i].clip)) << i;
    EXPECT_TRUE(same_bits(out[i].color, tri[i].color)) << i;
  }
}

// v0 behind the near plane (d = z + w = -1), v1 and v2 in front (d = 1):
// t = 1 / (1 + 1) = 1/2 exactly. Walk: v0 -> v1 emits I01 (from v1 towards v0);
// v1 is emitted; v2 is emitted, then I20 (from v2 towards v0). Equal |d|:
// each cut starts from the inside endpoint (section 4).
TEST(GoldenClip, NearPlaneOneVertexOutsideGivesAQuad) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  const glm::vec4 blue(0, 0, 1, 1), red(1, 0, 0, 1), green(0, 1, 0, 1);
  const std::array<ShadedVertex, 3> tri = {sv({0.0f, 0.0f, -2.0f, 1.0f}, blue),
                                           sv({0.5f, 0.0f, 0.0f, 1.0f}, red),
                                           sv({0.0f, 0.5f, 0.0f, 1.0f}, green)};
  const std::vector<ShadedVertex> out = golden::clip_triangle(tri, gb);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].clip, glm::vec4(0.25f, 0.0f, -1.0f, 1.0f));
  EXPECT_EQ(out[0].color, glm::vec4(0.5f, 0.0f, 0.5f, 1.0f));
  EXPECT_TRUE(same_bits(out[1].clip, tri[1].clip));
  EXPECT_TRUE(same_bits(out[2].clip, tri[2].clip));
  EXPECT_EQ(out[3].clip, glm::vec4(0.0f, 0.25f, -1.0f, 1.0f));
  EXPECT_EQ(out[3].color, glm::vec4(0.0f, 0.5f, 0.5f, 1.0f));
}

TEST(GoldenClip, FarPlaneOneVertexOutside) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  // d = w - z: v0 -1, others 1 -> t = 1/2; new vertices at z = 1 = w.
  const std::array<ShadedVertex, 3> tri = {sv({0.0f, 0.0f, 2.0f, 1.0f}, {0, 0, 0, 0}),
                                           sv({0.5f, 0.0f, 0.0f, 1.0f}, {1, 1, 1, 1}),
                                           sv({0.0f, 0.5f, 0.0f, 1.0f}, {1, 0, 1, 0})};
  const std::vector<ShadedVertex> out = golden::clip_triangle(tri, gb);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].clip, glm::vec4(0.25f, 0.0f, 1.0f, 1.0f));
  EXPECT_EQ(out[0].color, glm::vec4(0.5f, 0.5f, 0.5f, 0.5f));
  EXPECT_EQ(out[3].clip, glm::vec4(0.0f, 0.25f, 1.0f, 1.0f));
  EXPECT_EQ(out[3].color, glm::vec4(0.5f, 0.0f, 0.5f, 0.0f));
}

// Two vertices behind the near plane: a smaller triangle. v0, v1 d = -1,
// v2 d = 1. Walk: v0 -> v1 nothing; v1 -> v2 emits I21 (from v2 towards v1);
// v2 emitted, then I20.
TEST(GoldenClip, NearPlaneTwoVerticesOutsideGivesATriangle) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  const std::array<ShadedVertex, 3> tri = {sv({0.0f, 0.0f, -2.0f, 1.0f}, {0, 0, 0, 1}),
                                           sv({0.5f, 0.0f, -2.0f, 1.0f}, {1, 0, 0, 1}),
                                           sv({0.0f, 0.5f, 0.0f, 1.0f}, {0, 1, 0, 1})};
  const std::vector<ShadedVertex> out = golden::clip_triangle(tri, gb);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].clip, glm::vec4(0.25f, 0.25f, -1.0f, 1.0f));
  EXPECT_EQ(out[0].color, glm::vec4(0.5f, 0.5f, 0.0f, 1.0f));
  EXPECT_TRUE(same_bits(out[1].clip, tri[2].clip));
  EXPECT_EQ(out[2].clip, glm::vec4(0.0f, 0.25f, -1.0f, 1.0f));
  EXPECT_EQ(out[2].color, glm::vec4(0.0f, 0.5f, 0.0f, 1.0f));

  // Rendered: one triangle after the clipper, counted as clipped.
  Scene s = make_scene(64, 64);
  s.draws.push_back(draw_of({tri[0].clip, tri[1].clip, tri[2].clip}));
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_clipped, 1u);
  EXPECT_EQ(r.stats.triangles_after_clip, 1u);
  EXPECT_EQ(r.stats.triangles_rasterized, 1u);
}

// A corner of the triangle beyond both the left and the bottom guard band
// (64 x 64: x >= -1025 w, y >= -1025 w). Left plane: v0 out -> quad
// (I1, v1, v2, I2) with I2.y = -2050 * 1035 / 2060 < -1025 (outside bottom),
// I1.y = -1020 (inside). Bottom plane cuts the quad's corner I2 -> pentagon.
TEST(GoldenClip, CornerCutByTwoPlanesGivesAPentagon) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  const std::array<ShadedVertex, 3> tri = {sv({-2050.0f, -2050.0f, 0.0f, 1.0f}),
                                           sv({0.0f, 10.0f, 0.0f, 1.0f}),
                                           sv({10.0f, 0.0f, 0.0f, 1.0f})};
  const std::vector<ShadedVertex> out = golden::clip_triangle(tri, gb);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ(out[0].clip, glm::vec4(-1025.0f, -1020.0f, 0.0f, 1.0f));  // t = 1/2 exactly
  EXPECT_TRUE(same_bits(out[1].clip, tri[1].clip));
  EXPECT_TRUE(same_bits(out[2].clip, tri[2].clip));
  for (const ShadedVertex& v : out) {
    // Inside every plane, up to rounding of the intersection.
    for (int p = 0; p < golden::kClipPlaneCount; ++p) {
      EXPECT_GE(golden::clip_distance(p, v.clip, gb), -1e-3f) << "plane " << p;
    }
  }
  EXPECT_NEAR(out[3].clip.y, -1025.0f, 1e-3f);
  EXPECT_NEAR(out[4].clip.y, -1025.0f, 1e-3f);
  EXPECT_NEAR(out[4].clip.x, -1025.0f, 1e-3f);

  Scene s = make_scene(64, 64);
  s.draws.push_back(draw_of({tri[0].clip, tri[1].clip, tri[2].clip}));
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_clipped, 1u);
  EXPECT_EQ(r.stats.triangles_after_clip, 3u);  // fan of a pentagon
}

// An edge shared by two triangles crossing the near plane is cut at the same
// point in both, whichever direction each triangle walks it: the cut starts
// from the endpoint nearer the plane (here A, |d| = 0.7 < 1.4), t = 0.7 / 2.1
// is not exact, so an interpolation in walk order would differ in the last bits.
TEST(GoldenClip, SharedEdgeIsCutAtTheSamePointInBothTriangles) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  const ShadedVertex A = sv({0.1f, 0.2f, -1.7f, 1.0f}, {0.9f, 0.1f, 0.3f, 1.0f});  // d = -0.7
  const ShadedVertex B = sv({0.3f, -0.1f, 0.4f, 1.0f}, {0.2f, 0.7f, 0.6f, 0.4f});  // d = 1.4
  const ShadedVertex C = sv({0.5f, 0.5f, 0.1f, 1.0f});
  const ShadedVertex D = sv({-0.5f, -0.2f, 0.2f, 1.0f});
  // T1 walks A -> B: emits the cut first.
  const std::vector<ShadedVertex> t1 = golden::clip_triangle({A, B, C}, gb);
  // T2 walks B -> A: emits B, then the cut.
  const std::vector<ShadedVertex> t2 = golden::clip_triangle({B, A, D}, gb);
  ASSERT_EQ(t1.size(), 4u);
  ASSERT_EQ(t2.size(), 4u);
  EXPECT_TRUE(same_bits(t1[0].clip, t2[1].clip));
  EXPECT_TRUE(same_bits(t1[0].color, t2[1].color));
  // And the cut lies on the near plane, up to rounding.
  EXPECT_NEAR(t1[0].clip.z, -t1[0].clip.w, 1e-6f);
}

TEST(GoldenClip, TriangleOutsideOnePlaneIsClippedAway) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  // Beyond the far plane (z > w) everywhere.
  EXPECT_TRUE(golden::clip_triangle(
                  {sv({0, 0, 1.5f, 1}), sv({0.5f, 0, 1.1f, 1}), sv({0, 0.5f, 3.0f, 1})}, gb)
                  .empty());
  // Entirely behind the eye (w < 0): the negation of a visible triangle.
  EXPECT_TRUE(golden::clip_triangle(
                  {sv({-0.5f, 0, 0, -1}), sv({0, -0.5f, 0, -1}), sv({0.5f, 0.5f, 0, -1})}, gb)
                  .empty());

  Scene s = make_scene(64, 64);
  s.draws.push_back(draw_of({{-0.5f, 0, 0, -1}, {0, -0.5f, 0, -1}, {0.5f, 0.5f, 0, -1}}));
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_in, 1u);
  EXPECT_EQ(r.stats.triangles_clipped_away, 1u);
  EXPECT_EQ(r.stats.triangles_after_clip, 0u);
  EXPECT_EQ(r.stats.fragments_generated, 0u);
  EXPECT_EQ(count(coverage_of(r)), 0);
}

// A vertex at infinity (w = 0) in direction +x: A (-0.5, -0.5, 0, 1),
// B (1, 0, 0, 0), C (-0.5, 0.5, 0, 1). A point aA + bB + cC has
// x/w = b / (a + c) - 0.5 >= -0.5 and y/w = (c - a) / (2 (a + c)) in
// [-0.5, 0.5]: the half-strip x_ndc >= -0.5, |y_ndc| <= 0.5. In 64 x 64 that
// is window x >= 16, 16 <= y <= 48: pixels x = 16..63, y = 16..47 (no centre
// on an edge), 48 * 32 = 1536 pixels.
TEST(GoldenClip, VertexWithZeroWIsClippedToAHalfStrip) {
  Scene s = make_scene(64, 64);
  s.draws.push_back(draw_of({{-0.5f, -0.5f, 0, 1}, {1, 0, 0, 0}, {-0.5f, 0.5f, 0, 1}}));
  const golden::Result r = golden::render(s);
  std::vector<int> want(64 * 64, 0);
  for (int y = 16; y <= 47; ++y) {
    for (int x = 16; x <= 63; ++x) want[y * 64 + x] = 1;
  }
  EXPECT_EQ(coverage_of(r), want);
  EXPECT_EQ(r.stats.triangles_clipped, 1u);
  EXPECT_EQ(r.stats.fragments_generated, 1536u);

  // Every vertex leaving the clipper has a finite, positive 1/w.
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  const auto out = golden::clip_triangle(
      {sv({-0.5f, -0.5f, 0, 1}), sv({1, 0, 0, 0}), sv({-0.5f, 0.5f, 0, 1})}, gb);
  ASSERT_GE(out.size(), 3u);
  for (const ShadedVertex& v : out) {
    EXPECT_GT(v.clip.w, 0.0f);
    EXPECT_TRUE(std::isfinite(1.0f / v.clip.w));
  }
}

// Spec section 4: "Plane 0 keeps 1/w finite." A vertex at the clip-space
// origin (0, 0, 0, 0) is outside plane 0 (d = -2^-32); the cut from v1
// (d = 1 - 2^-32, which is 1 in float) has t = 1 / (1 + 2^-32) = 1 in float,
// so the new vertex is v1 + 1 * (v0 - v1) = (0, 0, 0, 0) again, which is
// inside all the other planes (d = 0). Its 1/w is infinite and its window
// position 0 * inf = NaN. The exact image of this triangle is the segment
// from NDC (0.5, 0) to (0, 0.5) (points a v1 + b v2 + c v0 project to
// (a, b) / (2 (a + b))): zero area, nothing to draw.
TEST(GoldenClip, VertexAtClipOriginKeepsOneOverWFinite) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  const auto out =
      golden::clip_triangle({sv({0, 0, 0, 0}), sv({0.5f, 0, 0, 1}), sv({0, 0.5f, 0, 1})}, gb);
  for (const ShadedVertex& v : out) {
    EXPECT_TRUE(std::isfinite(1.0f / v.clip.w))
        << "clip (" << v.clip.x << ", " << v.clip.y << ", " << v.clip.z << ", " << v.clip.w << ")";
  }
  Scene s = make_scene(64, 64);
  s.draws.push_back(draw_of({{0, 0, 0, 0}, {0.5f, 0, 0, 1}, {0, 0.5f, 0, 1}}));
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.fragments_generated, 0u);
}

// Vertices at or next to the eye (w = 0 or tiny, of either sign) beside
// ordinary ones: whatever survives the clipper has w >= 2^-32 (section 4: "1/w
// stays finite"), and its window position lies within the guard band, up to a
// few ulps (section 6: |x_w|, |y_w| <= 32768 plus rounding).
TEST(GoldenClip, NearEyeVerticesStayFiniteAndInsideTheGuardBand) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  const float tiny = std::ldexp(1.0f, -40);
  const glm::vec4 odd[] = {{0, 0, 0, 0},           {0, 0, 0, -tiny},       {0, 0, 0, tiny},
                           {tiny, -tiny, 0, tiny}, {1, 0, 0, 0},           {0, -1, 0.5f, 0},
                           {3, 2, 0, -tiny},       {1e-30f, 0, 0, 1e-35f}, {0.5f, 0.5f, 0, -0.25f}};
  const glm::vec4 normal[] = {
      {0.5f, 0, 0, 1}, {0, 0.5f, 0, 1}, {-0.7f, 0.2f, 0.1f, 1}, {100, -80, 0, 2}};
  int survivors = 0;
  for (const glm::vec4& a : odd) {
    for (const glm::vec4& b : normal) {
      for (const glm::vec4& c : normal) {
        if (&b == &c) continue;
        for (int rot = 0; rot < 3; ++rot) {
          std::array<ShadedVertex, 3> tri = {sv(a), sv(b), sv(c)};
          std::rotate(tri.begin(), tri.begin() + rot, tri.end());
          const auto out = golden::clip_triangle(tri, gb);
          if (!out.empty()) ++survivors;
          for (const ShadedVertex& v : out) {
            ASSERT_GE(v.clip.w, std::ldexp(1.0f, -32));
            const golden::WindowVertex w = golden::to_window(v, 64, 64);
            ASSERT_TRUE(std::isfinite(w.z));
            ASSERT_LE(std::abs(w.x), (1 << 23) + 64);
            ASSERT_LE(std::abs(w.y), (1 << 23) + 64);
          }
        }
      }
    }
  }
  EXPECT_GT(survivors, 50);

  // Cuts on plane 0 whose w rounds to just below 2^-32 (found by search), so
  // only the rule "w = max(w, 2^-32)" keeps them at 2^-32.
  const glm::vec4 c(0.5f, 0.25f, 0.0f, 1.0f);
  const std::array<glm::vec4, 2> rounding_below[] = {
      {glm::vec4(-0x1.9p-36f, 0, 0, 0x1.8ap-37f), glm::vec4(0x1.2p-3f, 0x1.4p-4f, 0, 0x1.ep+1f)},
      {glm::vec4(0x1.4p-36f, 0, 0, -0x1.ae2p-33f), glm::vec4(-0x1.ap-2f, -0x1p-1f, 0, 0x1.cp+0f)},
      {glm::vec4(-0x1.ep-37f, 0, 0, 0x1p-40f), glm::vec4(-0x1.cp-3f, 0x1.fp-2f, 0, 0x1.cp+0f)},
  };
  for (const auto& ab : rounding_below) {
    for (const ShadedVertex& v : golden::clip_triangle({sv(ab[0]), sv(ab[1]), sv(c)}, gb)) {
      EXPECT_GE(v.clip.w, std::ldexp(1.0f, -32)) << std::hexfloat << v.clip.w;
    }
  }
}

// Guard band: a triangle with one vertex beyond a guard-band plane and two
// vertices at distance g inside it, the outside one at distance -g, so t = 1/2
// and the cut vertices are exact: they lie exactly on the original edges at
// window coordinate -32768 or +32768. The clipped quad is the part of the
// triangle inside the guard band, so inside the 64 x 64 framebuffer it covers
// exactly what the unclipped triangle covers (reference).
TEST(GoldenClip, EachGuardBandPlaneClipsOnlyFarAway) {
  constexpr int W = 64, H = 64;
  const golden::GuardBand gb = golden::guard_band_for(W, H);  // 1025, 1023, 1025, 1023
  struct Case {
    const char* plane;
    int index;
    glm::vec4 in1, in2, out;
    float cut;  // coordinate of the cut vertices on the clipped axis
    bool x_axis;
  };
  const Case cases[] = {
      {"left", 3, {0, -0.5f, 0, 1}, {0, 0.75f, 0, 1}, {-2050, 0.125f, 0, 1}, -1025, true},
      {"right", 4, {0, 0.75f, 0, 1}, {0, -0.5f, 0, 1}, {2046, 0.125f, 0, 1}, 1023, true},
      {"bottom", 5, {0.75f, 0, 0, 1}, {-0.5f, 0, 0, 1}, {0.125f, -2050, 0, 1}, -1025, false},
      {"top", 6, {-0.5f, 0, 0, 1}, {0.75f, 0, 0, 1}, {0.125f, 2046, 0, 1}, 1023, false},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.plane);
    EXPECT_EQ(golden::clip_distance(c.index, c.in1, gb),
              -golden::clip_distance(c.index, c.out, gb));
    const auto out = golden::clip_triangle({sv(c.in1), sv(c.in2), sv(c.out)}, gb);
    // Walk: in1, in2, cut(in2 -> out), cut(in1 -> out), each the midpoint.
    ASSERT_EQ(out.size(), 4u);
    EXPECT_EQ(out[2].clip, (c.in2 + c.out) * 0.5f);
    EXPECT_EQ(out[3].clip, (c.in1 + c.out) * 0.5f);
    EXPECT_EQ(c.x_axis ? out[2].clip.x : out[2].clip.y, c.cut);
    const golden::WindowVertex wv = golden::to_window(out[2], W, H);
    EXPECT_EQ(c.x_axis ? wv.x : wv.y, c.cut < 0 ? -(1 << 23) : (1 << 23));  // +-32768 px

    Scene s = make_scene(W, H);
    s.draws.push_back(draw_of({c.in1, c.in2, c.out}));
    const golden::Result r = golden::render(s);
    EXPECT_EQ(r.stats.triangles_clipped, 1u);
    EXPECT_EQ(r.stats.triangles_after_clip, 2u);
    // Window subpixels of the original vertices: (v + 1) * 32 * 256.
    auto to_pt = [](const glm::vec4& v) {
      return Pt{static_cast<int64_t>((static_cast<double>(v.x) + 1.0) * 8192.0),
                static_cast<int64_t>((static_cast<double>(v.y) + 1.0) * 8192.0)};
    };
    const std::vector<int> want = ref_coverage({to_pt(c.in1), to_pt(c.in2), to_pt(c.out)}, W, H);
    EXPECT_EQ(coverage_of(r), want);
    EXPECT_GT(count(want), 500);
    EXPECT_EQ(r.stats.fragments_generated, static_cast<uint64_t>(count(want)));
  }
}

// A triangle crossing the viewport edges but inside the guard band is not
// clipped, and covers exactly the reference pixels inside the framebuffer.
TEST(GoldenClip, CrossingTheViewportInsideTheGuardBandIsNotClipped) {
  constexpr int W = 64, H = 64;
  // Window (-20, 10.5), (90.25, 30), (30, 100) pixels, in subpixels:
  const std::vector<Pt> tri = {{-5120, 2688}, {23104, 7680}, {7680, 25600}};
  std::vector<glm::vec4> pos;
  for (const Pt& p : tri) {
    pos.push_back({static_cast<float>(p.x) / 8192.0f - 1.0f,
                   static_cast<float>(p.y) / 8192.0f - 1.0f, 0.0f, 1.0f});
  }
  Scene s = make_scene(W, H);
  s.draws.push_back(draw_of(pos));
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_clipped, 0u);
  EXPECT_EQ(r.stats.triangles_clipped_away, 0u);
  EXPECT_EQ(r.stats.triangles_after_clip, 1u);
  const std::vector<int> want = ref_coverage(tri, W, H);
  EXPECT_EQ(coverage_of(r), want);
  EXPECT_GT(count(want), 1000);
  EXPECT_EQ(r.stats.fragments_generated, static_cast<uint64_t>(count(want)));
}

// Flat shading after clipping: every triangle of the fan keeps the original
// provoking colour (the last vertex), even when that vertex was clipped away,
// and the original primitive id.
TEST(GoldenClip, FanTrianglesKeepProvokingColourAndPrimitiveId) {
  constexpr int W = 64, H = 64;
  Scene s = make_scene(W, H);
  // Primitive 0: a visible triangle in the lower left, unclipped.
  Draw first = draw_of({{-0.9f, -0.9f, 0, 1}, {-0.7f, -0.9f, 0, 1}, {-0.9f, -0.7f, 0, 1}});
  s.draws.push_back(first);
  // Primitive 1: near-clipped (the provoking vertex is behind the near plane).
  Draw d = draw_of({{0.5f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.5f, 0.0f, 1.0f}, {0.0f, 0.0f, -2.0f, 1.0f}},
                   {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}});
  d.state.shading = Shading::flat;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_clipped, 1u);
  EXPECT_EQ(r.stats.triangles_after_clip, 3u);  // 1 + a quad's 2
  int pixels = 0;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const size_t p = static_cast<size_t>(y) * W + x;
      if (r.last_writer[p] != 1) continue;
      ++pixels;
      const ColorChannel* c = r.framebuffer.color_at(x, y);
      EXPECT_EQ(c[0], 0);
      EXPECT_EQ(c[1], 0);
      EXPECT_EQ(c[2], 255);
      EXPECT_EQ(c[3], 255);
    }
  }
  // The clipped quad has window corners (48, 32), (32, 48), (32, 40), (40, 32):
  // the band 72 <= x + y <= 80 with x, y >= 32, 96 square pixels.
  EXPECT_GT(pixels, 80);
  EXPECT_LT(pixels, 112);
}

}  // namespace
}  // namespace gpusim
