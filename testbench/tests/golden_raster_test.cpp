// Golden model: snapping, edge functions, the fill rule and coverage
// (docs/pipeline-spec.md sections 5-8).
//
// Every expected value here is derived independently of the code under test:
// by hand (the numbers are worked out in the comments), or by the reference
// point-in-triangle test below, written from the spec text with a different
// formulation of the tie rule (a symbolic perturbation of the sample point).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "hw/fixed_point.h"
#include "testbench/golden/golden_model.h"
#include "testbench/tests/golden_support.h"

namespace gpusim {
namespace {

using namespace golden_support;

// ---------------------------------------------------------------------------
// Scene helpers. With identity matrices, positions are clip space. For a
// framebuffer of power-of-two width W, the window point X/256 (X in
// subpixels) has clip x = X / (128 W) - 1 with w = 1: both operations are
// exact in float for the magnitudes used here, and the model's viewport
// transform (x*1 + 1) * (W/2) maps it back exactly, so the snapped vertex is X.

glm::vec4 at_subpixel(int64_t X, int64_t Y, int W, int H, float z = 0.0f) {
  return {static_cast<float>(X) / (128.0f * static_cast<float>(W)) - 1.0f,
          static_cast<float>(Y) / (128.0f * static_cast<float>(H)) - 1.0f, z, 1.0f};
}

Draw triangle_draw(const std::vector<Pt>& v, int W, int H) {
  Draw d;
  d.primitive = PrimitiveType::triangles;
  for (const Pt& p : v) d.positions.push_back(at_subpixel(p.x, p.y, W, H));
  d.colors.assign(v.size(), glm::vec4(1.0f));
  d.state.depth_test = false;
  return d;
}

// Coverage of one rendered scene: pixel index -> covered by some triangle.
std::vector<int> coverage_of(const golden::Result& r) {
  std::vector<int> c(r.last_writer.size());
  for (size_t i = 0; i < c.size(); ++i) c[i] = r.last_writer[i] >= 0 ? 1 : 0;
  return c;
}

// Renders one triangle alone in a W x H framebuffer; returns its coverage.
std::vector<int> render_one(const std::vector<Pt>& tri, int W, int H,
                            golden::Stats* stats = nullptr) {
  Scene s = make_scene(W, H);
  s.draws.push_back(triangle_draw(tri, W, H));
  const golden::Result r = golden::render(s);
  if (stats) *stats = r.stats;
  return coverage_of(r);
}

// ---------------------------------------------------------------------------
// Reference coverage, from the spec text (sections 7-8), in exact integers.
//
// A pixel centre p lying exactly on an edge belongs to the triangle when the
// edge is a left edge (going down in a CCW triangle) or a bottom edge
// (horizontal, going +x). For a CCW triangle the interior is left of each
// edge; a left edge has the interior on its +x side and a bottom edge on its
// +y side. So the rule is the same as asking whether p + (e, e^2), for an
// infinitesimal e > 0, is strictly inside: first order in e decides unless
// the edge is horizontal, then second order. This formulation needs neither
// the CW -> CCW swap nor the owner table, so it is an independent check.

// perturbed_side() (golden_support.h) is that test.

int64_t twice_area(const std::vector<Pt>& poly) {
  int64_t s = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Pt& a = poly[i];
    const Pt& b = poly[(i + 1) % poly.size()];
    s += a.x * b.y - b.x * a.y;
  }
  return s;
}

// Convex polygon (either orientation, no three consecutive collinear vertices).
bool ref_covers(const std::vector<Pt>& poly, Pt p) {
  const int orientation = sgn(twice_area(poly));
  if (orientation == 0) return false;
  for (size_t i = 0; i < poly.size(); ++i) {
    if (perturbed_side(poly[i], poly[(i + 1) % poly.size()], p) != orientation) return false;
  }
  return true;
}

std::vector<int> ref_coverage(const std::vector<Pt>& poly, int W, int H) {
  std::vector<int> c(static_cast<size_t>(W) * H, 0);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      c[static_cast<size_t>(y) * W + x] = ref_covers(poly, {256 * x + 128, 256 * y + 128}) ? 1 : 0;
    }
  }
  return c;
}

// Pixel centres of the framebuffer lying exactly on a side of the polygon
// (where the tie rule decides).
int centres_on_edges(const std::vector<Pt>& poly, int W, int H) {
  int n = 0;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const Pt p{256 * x + 128, 256 * y + 128};
      for (size_t i = 0; i < poly.size(); ++i) {
        const Pt a = poly[i], b = poly[(i + 1) % poly.size()];
        const int64_t cross = (a.x - p.x) * (b.y - p.y) - (a.y - p.y) * (b.x - p.x);
        const bool between = std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
                             std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
        if (cross == 0 && between) {
          ++n;
          break;
        }
      }
    }
  }
  return n;
}

int count(const std::vector<int>& c) {
  int n = 0;
  for (int v : c) n += v;
  return n;
}

// Human-readable first difference, for failure messages.
std::string first_difference(const std::vector<int>& got, const std::vector<int>& want, int W) {
  for (size_t i = 0; i < got.size(); ++i) {
    if (got[i] != want[i]) {
      return "pixel (" + std::to_string(i % W) + ", " + std::to_string(i / W) + "): got " +
             std::to_string(got[i]) + ", want " + std::to_string(want[i]);
    }
  }
  return "identical";
}

constexpr int64_t px(double pixels) {
  return static_cast<int64_t>(pixels * 256.0);
}

// ---------------------------------------------------------------------------
// Section 6: snapping.

TEST(GoldenSnap, SnapToSubpixelRoundsTiesToEven) {
  // x * 256 = k + 1/2: round to the even neighbour.
  EXPECT_EQ(snap_to_subpixel(100.5f / 256.0f), 100);
  EXPECT_EQ(snap_to_subpixel(101.5f / 256.0f), 102);
  EXPECT_EQ(snap_to_subpixel(0.5f / 256.0f), 0);
  EXPECT_EQ(snap_to_subpixel(1.5f / 256.0f), 2);
  EXPECT_EQ(snap_to_subpixel(-100.5f / 256.0f), -100);
  EXPECT_EQ(snap_to_subpixel(-101.5f / 256.0f), -102);
  EXPECT_EQ(snap_to_subpixel(-0.5f / 256.0f), 0);
  // Not ties: nearest.
  EXPECT_EQ(snap_to_subpixel(100.25f / 256.0f), 100);
  EXPECT_EQ(snap_to_subpixel(100.75f / 256.0f), 101);
  EXPECT_EQ(snap_to_subpixel(-100.25f / 256.0f), -100);
  EXPECT_EQ(snap_to_subpixel(-100.75f / 256.0f), -101);
  // Exact grid values are unchanged, up to the guard band (2^23 subpixels).
  EXPECT_EQ(snap_to_subpixel(12345.0f / 256.0f), 12345);
  EXPECT_EQ(snap_to_subpixel(-777.0f / 256.0f), -777);
  EXPECT_EQ(snap_to_subpixel(32768.0f), 1 << 23);
  EXPECT_EQ(snap_to_subpixel(-32768.0f), -(1 << 23));
  EXPECT_EQ(snap_to_subpixel(-32767.99609375f), -(1 << 23) + 1);
}

// The same through the viewport transform of to_window (section 5). W = 64,
// H = 32: x_w = (x + 1) * 32, y_w = (y + 1) * 16. A clip x of
// v / 8192 - 1 (exact) gives x_w * 256 = v.
TEST(GoldenSnap, ToWindowSnapsTiesToEvenIncludingNegatives) {
  struct Case {
    double v;      // x_w * 256 (and y_w * 256)
    int32_t want;  // hand-rounded, ties to even
  };
  const Case cases[] = {{100.5, 100},   {101.5, 102},     {-100.5, -100},  {-101.5, -102},
                        {2.5, 2},       {3.5, 4},         {-2.5, -2},      {-3.5, -4},
                        {100.25, 100},  {100.75, 101},    {-100.25, -100}, {-100.75, -101},
                        {4097.0, 4097}, {-4097.0, -4097}, {8191.5, 8192},  {8190.5, 8190}};
  for (const Case& c : cases) {
    golden::ShadedVertex sv;
    sv.clip = {static_cast<float>(c.v / 8192.0 - 1.0), static_cast<float>(c.v / 4096.0 - 1.0), 0.0f,
               1.0f};
    ASSERT_EQ(static_cast<double>(sv.clip.x), c.v / 8192.0 - 1.0) << "test input not exact";
    ASSERT_EQ(static_cast<double>(sv.clip.y), c.v / 4096.0 - 1.0) << "test input not exact";
    const golden::WindowVertex w = golden::to_window(sv, 64, 32);
    EXPECT_EQ(w.x, c.want) << "x_w*256 = " << c.v;
    EXPECT_EQ(w.y, c.want) << "y_w*256 = " << c.v;
  }
}

// Section 5 with a viewport and a depth range: clip (1, -0.5, 0.5, 2),
// viewport (10, 20, 64, 32), depth range (0.25, 0.75): q = 0.5;
// x_w = (0.5 + 1) * 32 + 10 = 58 -> 14848; y_w = (-0.25 + 1) * 16 + 20 = 32
// -> 8192; z_w = (0.25 + 1) * 0.5 * 0.5 + 0.25 = 0.5625. Every step exact.
TEST(GoldenSnap, ToWindowAppliesViewportOffsetAndDepthRange) {
  golden::ShadedVertex sv;
  sv.clip = {1.0f, -0.5f, 0.5f, 2.0f};
  sv.color = {1.0f, 0.5f, 0.25f, 1.0f};
  const golden::ViewportTransform vp{PixelRect{10, 20, 64, 32}, 0.25f, 0.75f};
  const golden::WindowVertex w = golden::to_window(sv, vp);
  EXPECT_EQ(w.x, 14848);
  EXPECT_EQ(w.y, 8192);
  EXPECT_EQ(w.z, 0.5625f);
  EXPECT_EQ(w.inv_w, 0.5f);
  EXPECT_EQ(golden::window_xy(sv, vp.rect), glm::vec2(58.0f, 32.0f));
  // A reversed range maps NDC z = -1 to 1 and +1 to 0:
  // z_w = (0.25 + 1) * 0.5 * (0 - 1) + 1 = 0.375.
  EXPECT_EQ(golden::to_window(sv, {PixelRect{10, 20, 64, 32}, 1.0f, 0.0f}).z, 0.375f);
  // A negative origin: x_w = 1.5 * 32 - 7 = 41.
  EXPECT_EQ(golden::to_window(sv, {PixelRect{-7, 0, 64, 32}, 0.0f, 1.0f}).x, 41 * 256);
}

TEST(GoldenSnap, ToWindowDividesByW) {
  // clip (1, -0.5, 0.5, 2), colour (1, 0.5, 0.25, 1), 64 x 32:
  // q = 0.5; x_w = (0.5 + 1) * 32 = 48 -> 12288; y_w = (-0.25 + 1) * 16 = 12 -> 3072;
  // z_w = (0.25 + 1) * 0.5 = 0.625; colour / w = (0.5, 0.25, 0.125, 0.5).
  golden::ShadedVertex sv;
  sv.clip = {1.0f, -0.5f, 0.5f, 2.0f};
  sv.color = {1.0f, 0.5f, 0.25f, 1.0f};
  const golden::WindowVertex w = golden::to_window(sv, 64, 32);
  EXPECT_EQ(w.x, 12288);
  EXPECT_EQ(w.y, 3072);
  EXPECT_EQ(w.z, 0.625f);
  EXPECT_EQ(w.inv_w, 0.5f);
  EXPECT_EQ(w.color_over_w, glm::vec4(0.5f, 0.25f, 0.125f, 0.5f));
}

// A rectangle x in [L, R] px, y in [2, 4] px in a 16 x 16 framebuffer, with R
// or L a tie between two subpixels. Pixel column c has its centre at
// 256 c + 128 subpixels. The right edge goes up (not owned), the left edge
// goes down (owned).
TEST(GoldenSnap, TieRoundingDecidesCoverage) {
  struct Case {
    double left, right;  // subpixels * 1 (window * 256), may be .5
    int columns;         // covered columns, by hand
  };
  const Case cases[] = {
      // right = 1408.5 -> 1408 = centre of column 5, on the unowned right edge: 2..4.
      {512, 1408.5, 3},
      // right = 1409.5 -> 1410, just right of centre 5: 2..5.
      {512, 1409.5, 4},
      // right = 1407.5 -> 1408 (even): 2..4, not 1407 (which would also give 3,
      // so the next two distinguish rounding up from ties-to-even).
      {512, 1407.5, 3},
      // right = 1152.5 -> 1152 = centre of column 4: 2..3 (round-half-up: 1153 -> 2..4).
      {512, 1152.5, 2},
      // right = 1153.5 -> 1154: 2..4.
      {512, 1153.5, 3},
      // left = 640.5 -> 640 = centre of column 2 on the owned left edge: 2..4.
      // (round-half-up: 641 -> 3..4).
      {640.5, 1280, 3},
      // left = 641.5 -> 642: 3..4.
      {641.5, 1280, 2},
  };
  constexpr int W = 16, H = 16;
  for (const Case& c : cases) {
    const float l = static_cast<float>(c.left / 2048.0 - 1.0);
    const float r = static_cast<float>(c.right / 2048.0 - 1.0);
    ASSERT_EQ(static_cast<double>(r), c.right / 2048.0 - 1.0);
    ASSERT_EQ(static_cast<double>(l), c.left / 2048.0 - 1.0);
    const float b = 512.0f / 2048.0f - 1.0f, t = 1024.0f / 2048.0f - 1.0f;
    Scene s = make_scene(W, H);
    Draw d;
    d.positions = {{l, b, 0, 1}, {r, b, 0, 1}, {r, t, 0, 1},
                   {l, b, 0, 1}, {r, t, 0, 1}, {l, t, 0, 1}};
    d.state.depth_test = false;
    s.draws.push_back(d);
    const golden::Result res = golden::render(s);
    std::vector<int> want(W * H, 0);
    const int first = c.left == 641.5 ? 3 : 2;
    for (int y = 2; y <= 3; ++y) {
      for (int x = first; x < first + c.columns; ++x) want[y * W + x] = 1;
    }
    const std::vector<int> got = coverage_of(res);
    EXPECT_EQ(got, want) << "left " << c.left << " right " << c.right << ": "
                         << first_difference(got, want, W);
  }
}

// ---------------------------------------------------------------------------
// Section 7: edge functions, area, ownership.

golden::WindowVertex wv(Subpixel x, Subpixel y) {
  golden::WindowVertex v;
  v.x = x;
  v.y = y;
  return v;
}

TEST(GoldenEdge, EdgeFunctionAndAreaByHand) {
  // v0 = (0, 0), v1 = (512, 0), v2 = (0, 256), p = (128, 128).
  const auto v0 = wv(0, 0), v1 = wv(512, 0), v2 = wv(0, 256);
  // area2 = 512 * 256 - 0 * 0.
  EXPECT_EQ(golden::signed_area2(v0, v1, v2), 131072);
  // Clockwise order negates it.
  EXPECT_EQ(golden::signed_area2(v0, v2, v1), -131072);
  // E_{v1 v2} = (-512)(128 - 0) - (256)(128 - 512) = -65536 + 98304.
  EXPECT_EQ(golden::edge_function(v1, v2, 128, 128), 32768);
  // E_{v2 v0} = (0)(128 - 256) - (-256)(128 - 0).
  EXPECT_EQ(golden::edge_function(v2, v0, 128, 128), 32768);
  // E_{v0 v1} = 512 * 128 - 0.
  EXPECT_EQ(golden::edge_function(v0, v1, 128, 128), 65536);
  // Outside across v1 -> v2: p = (512, 256): (-512)(256) - (256)(0).
  EXPECT_EQ(golden::edge_function(v1, v2, 512, 256), -131072);
  // On the edge.
  EXPECT_EQ(golden::edge_function(v1, v2, 256, 128), 0);
}

TEST(GoldenEdge, EdgeFunctionNeedsSixtyFourBits) {
  // Corners of the guard band: +-(2^23) subpixels, a right triangle with legs
  // D = 2^24: area2 = D * D = 2^48, far beyond int32.
  const Subpixel m = 1 << 23;
  const auto a = wv(-m, -m), b = wv(m, -m), c = wv(-m, m);
  const int64_t D = int64_t{1} << 24;
  EXPECT_EQ(golden::signed_area2(a, b, c), D * D);
  // Point (m, m) is outside b -> c by the full area:
  // E = (-m - m)(m - (-m)) - (m - (-m))(m - m) = -D * D.
  EXPECT_EQ(golden::edge_function(b, c, m, m), -D * D);
  // A few ulps beyond the guard band still works (spec: int32 absorbs them).
  const auto d = wv(-m - 7, -m), e = wv(m + 9, -m - 3);
  // (m+9 - (-m-7)) * (py - (-m)) - (-3) * (px - (-m-7)) at p = (0, 0):
  // (D + 16) * m + 3 * (m + 7).
  EXPECT_EQ(golden::edge_function(d, e, 0, 0), (D + 16) * m + 3 * (m + 7));
}

TEST(GoldenEdge, OwnershipIsLeftAndBottomEdges) {
  const auto o = wv(1000, 1000);
  // dy < 0: left edge of a CCW triangle, owned whatever dx.
  EXPECT_TRUE(golden::edge_owns_boundary(o, wv(1000, 0)));
  EXPECT_TRUE(golden::edge_owns_boundary(o, wv(0, 999)));
  EXPECT_TRUE(golden::edge_owns_boundary(o, wv(2000, 999)));
  // dy > 0: right edges, not owned.
  EXPECT_FALSE(golden::edge_owns_boundary(o, wv(1000, 2000)));
  EXPECT_FALSE(golden::edge_owns_boundary(o, wv(0, 1001)));
  EXPECT_FALSE(golden::edge_owns_boundary(o, wv(2000, 1001)));
  // Horizontal: bottom (+x) owned, top (-x) not.
  EXPECT_TRUE(golden::edge_owns_boundary(o, wv(1001, 1000)));
  EXPECT_FALSE(golden::edge_owns_boundary(o, wv(999, 1000)));
}

// ---------------------------------------------------------------------------
// Section 8: shared edges.

// Renders each triangle alone; returns per-pixel coverage counts and, per
// triangle, its coverage.
std::vector<int> coverage_counts(const std::vector<std::vector<Pt>>& tris, int W, int H,
                                 std::vector<std::vector<int>>* each = nullptr) {
  std::vector<int> counts(static_cast<size_t>(W) * H, 0);
  for (const auto& t : tris) {
    const std::vector<int> c = render_one(t, W, H);
    for (size_t i = 0; i < c.size(); ++i) counts[i] += c[i];
    if (each) each->push_back(c);
  }
  return counts;
}

TEST(GoldenFillRule, SharedDiagonalEdgeSquareOnPixelCentres) {
  // Square with corners on pixel centres (2.5, 2.5) .. (10.5, 10.5), split by
  // the diagonal A -> C, which passes through the centres (k.5, k.5).
  // Left and bottom sides are owned, right and top are not: the square covers
  // columns and rows 2..9, 64 pixels. In T1 = (A, B, C) (lower right) the
  // diagonal runs C -> A, downwards: owned; in T2 = (A, C, D) it runs A -> C,
  // upwards: not owned. So T1 covers {2 <= y <= x <= 9}: 8 * 9 / 2 = 36 pixels,
  // T2 the remaining 28.
  constexpr int W = 16, H = 16;
  const Pt A{px(2.5), px(2.5)}, B{px(10.5), px(2.5)}, C{px(10.5), px(10.5)}, D{px(2.5), px(10.5)};
  std::vector<std::vector<int>> each;
  const std::vector<int> counts = coverage_counts({{A, B, C}, {A, C, D}}, W, H, &each);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const bool in_square = x >= 2 && x <= 9 && y >= 2 && y <= 9;
      EXPECT_EQ(counts[y * W + x], in_square ? 1 : 0) << "pixel " << x << ", " << y;
      EXPECT_EQ(each[0][y * W + x], in_square && y <= x ? 1 : 0) << "T1 pixel " << x << ", " << y;
    }
  }
  EXPECT_EQ(count(each[0]), 36);
  EXPECT_EQ(count(each[1]), 28);
}

TEST(GoldenFillRule, SharedVerticalEdge) {
  // Diamond L (1.5, 7), P (6.5, 1.5), R (11.5, 7), Q (6.5, 12.5) split along
  // the vertical P - Q through the centres of column 6. In T1 = (L, P, Q) the
  // edge runs up (right edge, not owned); in T2 = (P, R, Q) it runs Q -> P,
  // down (left edge, owned). So column 6 belongs to T2, except its two ends:
  // P (6, 1): T2's edge P -> R (up) also passes through it, not owned; T1's
  // P -> Q not owned: uncovered. Q (6, 12): T2's R -> Q goes up: uncovered;
  // T1's P -> Q: uncovered. Column 6 covered for y = 2..11 by T2 only.
  constexpr int W = 16, H = 16;
  const Pt L{px(1.5), px(7)}, P{px(6.5), px(1.5)}, R{px(11.5), px(7)}, Q{px(6.5), px(12.5)};
  std::vector<std::vector<int>> each;
  const std::vector<int> counts = coverage_counts({{L, P, Q}, {P, R, Q}}, W, H, &each);
  const std::vector<int> diamond = ref_coverage({L, P, R, Q}, W, H);
  EXPECT_EQ(counts, diamond) << first_difference(counts, diamond, W);
  for (int y = 0; y < H; ++y) {
    EXPECT_EQ(each[0][y * W + 6], 0) << "T1 must not own column 6, y " << y;
    EXPECT_EQ(each[1][y * W + 6], y >= 2 && y <= 11 ? 1 : 0) << "T2 column 6, y " << y;
  }
}

TEST(GoldenFillRule, SharedHorizontalEdge) {
  // Diamond P (1.5, 6.5), B (7, 1.5), Q (12.5, 6.5), T (7, 11.5) split along
  // the horizontal P - Q through the centres of row 6. In T1 = (P, B, Q)
  // (lower) it runs Q -> P (-x, top edge, not owned); in T2 = (Q, T, P)
  // (upper) it runs P -> Q (+x, bottom edge, owned). At P (1, 6) T2's other
  // edge T -> P runs down (owned): covered by T2. At Q (12, 6) T2's Q -> T runs
  // up: uncovered. Row 6: x = 1..11, by T2.
  constexpr int W = 16, H = 16;
  const Pt P{px(1.5), px(6.5)}, B{px(7), px(1.5)}, Q{px(12.5), px(6.5)}, T{px(7), px(11.5)};
  std::vector<std::vector<int>> each;
  const std::vector<int> counts = coverage_counts({{P, B, Q}, {Q, T, P}}, W, H, &each);
  const std::vector<int> diamond = ref_coverage({P, B, Q, T}, W, H);
  EXPECT_EQ(counts, diamond) << first_difference(counts, diamond, W);
  for (int x = 0; x < W; ++x) {
    EXPECT_EQ(each[0][6 * W + x], 0) << "T1 must not own row 6, x " << x;
    EXPECT_EQ(each[1][6 * W + x], x >= 1 && x <= 11 ? 1 : 0) << "T2 row 6, x " << x;
  }
}

TEST(GoldenFillRule, QuadSplitEitherWayCoversTheSamePixels) {
  // A general quad on the grid, split along either diagonal: each pixel at
  // most once, union = the quad.
  constexpr int W = 32, H = 32;
  const Pt a{px(3.25), px(2.5)}, b{px(27.5), px(5.5)}, c{px(25.0), px(28.5)}, d{px(4.5), px(20.0)};
  const std::vector<int> quad = ref_coverage({a, b, c, d}, W, H);
  const std::vector<int> split1 = coverage_counts({{a, b, c}, {a, c, d}}, W, H);
  const std::vector<int> split2 = coverage_counts({{a, b, d}, {b, c, d}}, W, H);
  EXPECT_EQ(split1, quad) << first_difference(split1, quad, W);
  EXPECT_EQ(split2, quad) << first_difference(split2, quad, W);
  EXPECT_GT(count(quad), 400);
}

// A fan of 8 triangles around the centre of pixel (16, 16), its spokes along
// rows, columns and diagonals of pixel centres, all rendered separately.
TEST(GoldenFillRule, FanOnPixelCentresCoversEveryPixelOnce) {
  constexpr int W = 32, H = 32;
  const Pt c{px(16.5), px(16.5)};
  const int off[8][2] = {{10, 0}, {7, 7}, {0, 10}, {-7, 7}, {-10, 0}, {-7, -7}, {0, -10}, {7, -7}};
  std::vector<Pt> rim;
  for (const auto& o : off) rim.push_back({c.x + 256 * o[0], c.y + 256 * o[1]});
  std::vector<std::vector<Pt>> tris;
  for (size_t i = 0; i < rim.size(); ++i) tris.push_back({c, rim[i], rim[(i + 1) % rim.size()]});
  std::vector<std::vector<int>> each;
  const std::vector<int> counts = coverage_counts(tris, W, H, &each);
  const std::vector<int> octagon = ref_coverage(rim, W, H);
  EXPECT_EQ(counts, octagon) << first_difference(counts, octagon, W);
  // The centre pixel is the apex of every triangle: exactly one owns it, the
  // one containing c + (e, e^2), i.e. the first (spokes (10,0) and (7,7)).
  EXPECT_EQ(each[0][16 * W + 16], 1);

  // The same fan as one triangle_fan draw: the last writer of every covered
  // pixel is the triangle that covers it alone.
  Scene s = make_scene(W, H);
  Draw d;
  d.primitive = PrimitiveType::triangle_fan;
  d.positions.push_back(at_subpixel(c.x, c.y, W, H));
  for (size_t i = 0; i <= rim.size(); ++i) {
    const Pt& p = rim[i % rim.size()];
    d.positions.push_back(at_subpixel(p.x, p.y, W, H));
  }
  d.state.depth_test = false;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_rasterized, 8u);
  EXPECT_EQ(r.stats.fragments_generated, static_cast<uint64_t>(count(octagon)));
  for (size_t p = 0; p < counts.size(); ++p) {
    int64_t want = -1;
    for (size_t t = 0; t < each.size(); ++t) {
      if (each[t][p]) want = static_cast<int64_t>(t);
    }
    EXPECT_EQ(r.last_writer[p], want) << "pixel " << p % W << ", " << p / W;
  }
}

// A fan of 13 triangles around an off-grid centre, rim on a circle (rounded to
// the subpixel grid, so edges have awkward slopes).
TEST(GoldenFillRule, IrregularFanCoversEveryPixelOnce) {
  constexpr int W = 32, H = 32;
  const Pt c{px(15.0) + 77, px(16.0) + 201};
  std::vector<Pt> rim;
  for (int i = 0; i < 13; ++i) {
    const double a = 2.0 * M_PI * (i + 0.3) / 13.0;
    rim.push_back({c.x + std::llround(13.7 * 256.0 * std::cos(a)),
                   c.y + std::llround(13.7 * 256.0 * std::sin(a))});
  }
  std::vector<std::vector<Pt>> tris;
  for (size_t i = 0; i < rim.size(); ++i) tris.push_back({c, rim[i], rim[(i + 1) % rim.size()]});
  const std::vector<int> counts = coverage_counts(tris, W, H);
  const std::vector<int> polygon = ref_coverage(rim, W, H);
  EXPECT_EQ(counts, polygon) << first_difference(counts, polygon, W);
  EXPECT_GT(count(polygon), 500);
}

// Tiny triangles (16 subpixels across) with an edge through the centre of
// pixel (5, 5), shifted by -1, 0, +1 subpixel across that edge. Which of them
// cover the pixel follows from the rule by hand (see each case).
TEST(GoldenFillRule, TinyTrianglesAroundAPixelCentre) {
  constexpr int W = 16, H = 16;
  const Pt c{px(5.5), px(5.5)};
  struct Case {
    const char* what;
    Pt v[3];          // relative to the centre, CCW
    int sx, sy;       // shift direction
    bool covered[3];  // for shifts -1, 0, +1
  };
  const Case cases[] = {
      // Vertical left edge (2 -> 0 runs down: owned), interior to its right.
      // Shift -1 moves the centre inside; 0 on the owned edge; +1 outside.
      {"left edge", {{0, -8}, {8, 0}, {0, 8}}, 1, 0, {true, true, false}},
      // Vertical right edge (0 -> 1 runs up: not owned), interior to its left.
      // Shift -1 moves the triangle left: centre outside; 0 on the edge: no;
      // +1 inside.
      {"right edge", {{0, -8}, {0, 8}, {-8, 0}}, 1, 0, {false, false, true}},
      // Horizontal bottom edge (0 -> 1 runs +x: owned), interior above.
      {"bottom edge", {{-8, 0}, {8, 0}, {0, 8}}, 0, 1, {true, true, false}},
      // Horizontal top edge (2 -> 0 runs -x: not owned), interior below.
      {"top edge", {{-8, 0}, {0, -8}, {8, 0}}, 0, 1, {false, false, true}},
      // Diagonal edge 1 -> 2 from (8, -8) to (-8, 8): runs up-left, dy > 0,
      // not owned; interior below-left of it. Shifting along +x moves the
      // triangle right, bringing the centre inside.
      {"diagonal right edge", {{-8, -8}, {8, -8}, {-8, 8}}, 1, 0, {false, false, true}},
      // Diagonal edge 2 -> 0 from (8, 8) to (-8, -8): runs down-left, dy < 0,
      // owned; interior below-right of it.
      {"diagonal left edge", {{-8, -8}, {8, -8}, {8, 8}}, 1, 0, {true, true, false}},
  };
  for (const Case& k : cases) {
    for (int s = -1; s <= 1; ++s) {
      std::vector<Pt> tri;
      for (const Pt& v : k.v) tri.push_back({c.x + v.x + s * k.sx, c.y + v.y + s * k.sy});
      const std::vector<int> cov = render_one(tri, W, H);
      EXPECT_EQ(cov[5 * W + 5], k.covered[s + 1] ? 1 : 0) << k.what << ", shift " << s;
      // Nothing else: the triangle is 16 subpixels across.
      EXPECT_EQ(count(cov), k.covered[s + 1] ? 1 : 0) << k.what << ", shift " << s;
    }
  }
}

TEST(GoldenFillRule, FourTrianglesMeetingAtAPixelCentre) {
  // Right-angled triangles in the four quadrants around the centre of pixel
  // (5, 5), each with its right-angle vertex on the centre. Only the
  // upper-right one covers it: its edges through the centre are its bottom
  // edge (+x, owned) and its left edge (down, owned). The upper-left one has
  // the centre on its right edge (up); the lower ones on their top edges.
  constexpr int W = 16, H = 16;
  const Pt c{px(5.5), px(5.5)};
  const int quad[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  for (int q = 0; q < 4; ++q) {
    const int sx = quad[q][0], sy = quad[q][1];
    const std::vector<Pt> tri = {c, {c.x + 12 * sx, c.y}, {c.x, c.y + 12 * sy}};
    const std::vector<int> cov = render_one(tri, W, H);
    EXPECT_EQ(cov[5 * W + 5], q == 0 ? 1 : 0) << "quadrant " << sx << ", " << sy;
    EXPECT_EQ(count(cov), q == 0 ? 1 : 0) << "quadrant " << sx << ", " << sy;
  }
}

TEST(GoldenFillRule, PixelCentreOnVerticesOfALargeTriangle) {
  // Triangle (2.5, 2.5), (12.5, 2.5), (2.5, 12.5): its three vertices are
  // pixel centres. (2,2): bottom and left edge meet, both owned -> covered.
  // (12,2): on the bottom edge (owned) and the hypotenuse (12,2) -> (2,12),
  // which runs up: not owned -> uncovered. (2,12): on the left edge (owned)
  // and the hypotenuse -> uncovered. The hypotenuse passes through the centres
  // (x.5, y.5) with x + y = 14: uncovered; the covered set is x, y >= 2 and
  // x + y <= 13: rows y = 2..11 hold 12 - y columns (x = 2 .. 13 - y),
  // summing 10 + 9 + ... + 1 = 55.
  constexpr int W = 16, H = 16;
  const std::vector<Pt> tri = {{px(2.5), px(2.5)}, {px(12.5), px(2.5)}, {px(2.5), px(12.5)}};
  const std::vector<int> cov = render_one(tri, W, H);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const bool want = x >= 2 && y >= 2 && x + y <= 13;
      EXPECT_EQ(cov[y * W + x], want ? 1 : 0) << "pixel " << x << ", " << y;
    }
  }
  EXPECT_EQ(count(cov), 55);
}

// ---------------------------------------------------------------------------
// Piglit-style: random triangles on the subpixel grid against the reference.

struct RandomTriangles {
  explicit RandomTriangles(uint32_t seed) : rng(seed) {}
  std::mt19937 rng;
  int64_t uniform(int64_t lo, int64_t hi) {  // inclusive
    return lo + static_cast<int64_t>(rng() % static_cast<uint32_t>(hi - lo + 1));
  }
  // Grid of a triangle: anywhere (1 subpixel), the half-pixel lattice of
  // pixel centres and pixel corners (128), or pixel centres only (256 + 128).
  // Vertices on the coarse lattices put many pixel centres exactly on edges.
  int64_t coord(int64_t base, int64_t extent, int mode) {
    const int64_t v = base + uniform(-extent, extent);
    if (mode == 0) return v;
    const int64_t step = mode == 1 ? 128 : 256;
    const int64_t q = (v >= 0 ? v : v - step + 1) / step * step;
    return mode == 1 ? q : q + 128;
  }
  std::vector<Pt> next(int W, int H) {
    // Size classes: tiny, small, large (crossing the framebuffer edges).
    static const int64_t kExtent[3] = {3 * 256, 10 * 256, 40 * 256};
    const int64_t e = kExtent[uniform(0, 2)];
    const int mode = static_cast<int>(uniform(0, 2));
    const int64_t cx = uniform(-2 * 256, (W + 2) * 256), cy = uniform(-2 * 256, (H + 2) * 256);
    std::vector<Pt> t;
    for (int i = 0; i < 3; ++i) t.push_back({coord(cx, e, mode), coord(cy, e, mode)});
    if (uniform(0, 19) == 0) {
      // Collinear on purpose: v2 = v0 + k (v1 - v0).
      const int64_t k = uniform(-2, 2);
      t[2] = {t[0].x + k * (t[1].x - t[0].x), t[0].y + k * (t[1].y - t[0].y)};
    }
    return t;
  }
};

TEST(GoldenPiglit, RandomTrianglesMatchExactReference) {
  constexpr int W = 64, H = 32;
  RandomTriangles gen(20240611u);
  int degenerate = 0, mismatches = 0, ties = 0;
  uint64_t total_fragments = 0;
  for (int i = 0; i < 600; ++i) {
    const std::vector<Pt> tri = gen.next(W, H);
    golden::Stats st;
    const std::vector<int> got = render_one(tri, W, H, &st);
    const std::vector<int> want = ref_coverage(tri, W, H);
    const bool zero_area = twice_area(tri) == 0;
    degenerate += zero_area;
    if (!zero_area) ties += centres_on_edges(tri, W, H);
    EXPECT_EQ(st.triangles_degenerate, zero_area ? 1u : 0u);
    EXPECT_EQ(st.triangles_clipped, 0u);  // all well inside the guard band
    EXPECT_EQ(st.fragments_generated, static_cast<uint64_t>(count(want)));
    total_fragments += st.fragments_generated;
    if (got != want && ++mismatches <= 5) {
      ADD_FAILURE() << "triangle " << i << " (" << tri[0].x << "," << tri[0].y << ") (" << tri[1].x
                    << "," << tri[1].y << ") (" << tri[2].x << "," << tri[2].y
                    << "): " << first_difference(got, want, W);
    }
  }
  EXPECT_EQ(mismatches, 0);
  // The generator must have exercised something.
  EXPECT_GT(total_fragments, 20000u);
  EXPECT_GT(ties, 300);  // pixel centres exactly on an edge, decided by the tie rule
  EXPECT_GT(degenerate, 0);
  std::printf("random triangles: %d degenerate, %d centres on edges, %llu fragments\n", degenerate,
              ties, static_cast<unsigned long long>(total_fragments));
}

// Degenerate cases forced: collinear vertices, repeated vertices, and vertices
// that are distinct in float but equal after snapping.
TEST(GoldenPiglit, ZeroAreaTrianglesProduceNothing) {
  constexpr int W = 16, H = 16;
  const std::vector<std::vector<Pt>> tris = {
      {{px(1), px(1)}, {px(5), px(5)}, {px(9), px(9)}},               // collinear diagonal
      {{px(1.5), px(4.5)}, {px(8.5), px(4.5)}, {px(14.5), px(4.5)}},  // along centres
      {{px(2), px(2)}, {px(2), px(2)}, {px(9), px(3)}},               // repeated vertex
  };
  for (const auto& t : tris) {
    golden::Stats st;
    const std::vector<int> cov = render_one(t, W, H, &st);
    EXPECT_EQ(count(cov), 0);
    EXPECT_EQ(st.triangles_degenerate, 1u);
    EXPECT_EQ(st.triangles_rasterized, 0u);
    EXPECT_EQ(st.fragments_generated, 0u);
  }
  // Three vertices within 1/1024 pixel of (4, 4): they snap to one subpixel.
  Scene s = make_scene(W, H);
  Draw d;
  const float e = 1.0f / 1024.0f / 8.0f;  // 1/1024 px in clip units (8 px per unit)
  const float x = 4.0f / 8.0f - 1.0f;
  d.positions = {{x, x, 0, 1}, {x + e, x, 0, 1}, {x, x + e, 0, 1}};
  d.state.depth_test = false;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_degenerate, 1u);
  EXPECT_EQ(r.stats.fragments_generated, 0u);
}

TEST(GoldenPiglit, WindingDoesNotChangeCoverage) {
  constexpr int W = 64, H = 32;
  RandomTriangles gen(777u);
  for (int i = 0; i < 200; ++i) {
    std::vector<Pt> tri = gen.next(W, H);
    const std::vector<int> a = render_one(tri, W, H);
    std::swap(tri[1], tri[2]);
    const std::vector<int> b = render_one(tri, W, H);
    EXPECT_EQ(a, b) << "triangle " << i << ": " << first_difference(a, b, W);
    const std::vector<int> want = ref_coverage(tri, W, H);
    EXPECT_EQ(b, want) << "triangle " << i << ": " << first_difference(b, want, W);
  }
}

// ---------------------------------------------------------------------------
// The draw rectangle (spec section 8d): the framebuffer intersected with the
// viewport and the scissor, per pixel, for every kind of primitive.

// The pixels a render wrote, as a set of (x, y), from its last-writer map.
std::vector<std::pair<int, int>> written(const golden::Result& r, int W) {
  std::vector<std::pair<int, int>> out;
  for (size_t i = 0; i < r.last_writer.size(); ++i) {
    if (r.last_writer[i] >= 0) out.push_back({static_cast<int>(i) % W, static_cast<int>(i) / W});
  }
  return out;
}
// Every pixel of [x0, x1] x [y0, y1] in the same order (rows bottom-up).
std::vector<std::pair<int, int>> rect_pixels(int x0, int y0, int x1, int y1) {
  std::vector<std::pair<int, int>> out;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) out.push_back({x, y});
  }
  return out;
}
// A triangle holding the whole clip square: window corners far outside any
// viewport's edge, inside the guard band.
Draw giant_draw() {
  Draw d;
  d.positions = {{-1, -1, 0.5f, 1}, {3, -1, 0.5f, 1}, {-1, 3, 0.5f, 1}};
  d.state.depth_test = false;
  return d;
}

TEST(GoldenDrawRectangle, ScissorKeepsExactlyItsPixels) {
  Scene s = make_scene(64, 32);
  s.draws.push_back(giant_draw());
  s.draws.back().state.scissor = PixelRect{7, 5, 13, 11};
  golden::Result r = golden::render(s);
  EXPECT_EQ(written(r, 64), rect_pixels(7, 5, 19, 15));
  EXPECT_EQ(r.stats.fragments_generated, 13u * 11u);
  EXPECT_EQ(r.stats.triangles_offscreen, 0u);
  // Partly outside the framebuffer: only the intersection.
  s.draws.back().state.scissor = PixelRect{60, 28, 10, 10};
  r = golden::render(s);
  EXPECT_EQ(written(r, 64), rect_pixels(60, 28, 63, 31));
  // Multisampled: all samples of a pixel inside, none outside.
  s.framebuffer.samples = 4;
  s.draws.back().state.scissor = PixelRect{7, 5, 13, 11};
  r = golden::render(s);
  EXPECT_EQ(r.stats.fragments_generated, 143u);
  EXPECT_EQ(r.stats.samples_generated, 4u * 143u);
}

TEST(GoldenDrawRectangle, ViewportPlacesAndBoundsTheDraw) {
  // The clip square [-1, 1]^2 through viewport (5, 7, 20, 11) covers its
  // 20 x 11 pixels; the giant triangle, which crosses every viewport edge
  // inside the guard band, is cut at the same pixels.
  Scene s = make_scene(64, 32);
  Draw quad;
  quad.primitive = PrimitiveType::triangle_strip;
  quad.positions = {{-1, -1, 0, 1}, {1, -1, 0, 1}, {-1, 1, 0, 1}, {1, 1, 0, 1}};
  quad.state.depth_test = false;
  quad.state.viewport = PixelRect{5, 7, 20, 11};
  s.draws.push_back(quad);
  EXPECT_EQ(written(golden::render(s), 64), rect_pixels(5, 7, 24, 17));
  s.draws[0] = giant_draw();
  s.draws[0].state.viewport = PixelRect{5, 7, 20, 11};
  const golden::Result r = golden::render(s);
  EXPECT_EQ(written(r, 64), rect_pixels(5, 7, 24, 17));
  EXPECT_EQ(r.stats.triangles_clipped, 0u);  // bounded, not cut
}

TEST(GoldenDrawRectangle, DepthRangeMapsStoredDepth) {
  // NDC z = 0 with depth range (0.25, 0.75): z_w = 1 * 0.5 * 0.5 + 0.25 =
  // 0.5, stored in unorm24 as nearbyint(0.5 * 16777215) = 8388608 (the
  // half rounds to even).
  Scene s = make_scene(64, 32);
  s.draws.push_back(giant_draw());
  s.draws[0].positions = {{-1, -1, 0, 1}, {3, -1, 0, 1}, {-1, 3, 0, 1}};
  s.draws[0].state.depth_test = true;
  s.draws[0].state.depth_func = CompareFunc::always;
  s.draws[0].state.depth_near = 0.25f;
  s.draws[0].state.depth_far = 0.75f;
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.framebuffer.depth[r.framebuffer.pixel_index(3, 3)], 8388608u);
}

TEST(GoldenDrawRectangle, ScissorCutsLinesAndPoints) {
  const int W = 64, H = 32;
  Scene s = make_scene(W, H);
  // A horizontal line through the centres of row 10 from x_w = -5 to 69:
  // every pixel of the row, of which the scissor keeps x = 3..6.
  Draw line;
  line.primitive = PrimitiveType::lines;
  line.positions = {at_subpixel(-5 * 256, 10 * 256 + 128, W, H),
                    at_subpixel(69 * 256, 10 * 256 + 128, W, H)};
  line.state.depth_test = false;
  line.state.scissor = PixelRect{3, 0, 4, 32};
  s.draws.push_back(line);
  golden::Result r = golden::render(s);
  EXPECT_EQ(written(r, W), rect_pixels(3, 10, 6, 10));
  EXPECT_EQ(r.stats.lines_rasterized, 1u);
  // A point of size 8 at window (10.5, 10.5): X0 = 2560 - 1024, so the
  // square covers x, y = 6..13; the scissor from x = 8 keeps 6 x 8 pixels.
  Draw point;
  point.primitive = PrimitiveType::points;
  point.positions = {at_subpixel(2688, 2688, W, H)};
  point.state.depth_test = false;
  point.state.point_size = 8.0f;
  point.state.scissor = PixelRect{8, 0, 100, 100};
  s.draws[0] = point;
  r = golden::render(s);
  EXPECT_EQ(written(r, W), rect_pixels(8, 6, 13, 13));
}

TEST(GoldenDrawRectangle, TriangleMissingTheScissorIsOffscreen) {
  Scene s = make_scene(64, 32);
  s.draws.push_back(triangle_draw({{256, 256}, {1024, 256}, {256, 1024}}, 64, 32));
  s.draws[0].state.scissor = PixelRect{20, 20, 5, 5};
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_rasterized, 1u);
  EXPECT_EQ(r.stats.triangles_offscreen, 1u);
  EXPECT_EQ(r.stats.fragments_generated, 0u);
}

}  // namespace
}  // namespace gpusim
