// Golden model: points, lines, wide lines, Bresenham and polygon mode
// (docs/pipeline-spec.md sections 3, 4b, 4c, 4d, 8b, 8c, 9, 13).
//
// Every expected value is derived independently of the code under test: by
// hand (worked out in the comments), from the spec's "Consequences" paragraph
// of section 8b (a second, integer formulation of the diamond-exit rule,
// written here from the spec text), or from a textbook Bresenham loop written
// here octant by octant with an error term.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "hw/fixed_point.h"
#include "testbench/golden/golden_model.h"
#include "testbench/tests/golden_support.h"

namespace gpusim {
namespace {

using namespace golden_support;

using golden::Pixel;
using PixelSet = std::set<Pixel>;

// ---------------------------------------------------------------------------
// Scene helpers. With identity matrices positions are clip space. For a
// power-of-two framebuffer side W, the window point X / 256 (X in subpixels)
// has clip x = X / (128 W) - 1 with w = 1; both operations are exact in float
// for the magnitudes used here, and the viewport transform (x + 1) * (W / 2)
// maps it back exactly, so the snapped vertex is X.

glm::vec4 at_subpixel(int64_t X, int64_t Y, int W, int H, float z = 0.0f) {
  return {static_cast<float>(X) / (128.0f * static_cast<float>(W)) - 1.0f,
          static_cast<float>(Y) / (128.0f * static_cast<float>(H)) - 1.0f, z, 1.0f};
}
// Pixels to subpixels: 2.5 -> 640.
constexpr int64_t sp(double pixels) {
  return static_cast<int64_t>(pixels * 256.0);
}

Draw draw_at(PrimitiveType prim, const std::vector<Pt>& pts, int W, int H) {
  Draw d;
  d.primitive = prim;
  for (const Pt& p : pts) d.positions.push_back(at_subpixel(p.x, p.y, W, H));
  d.colors.assign(pts.size(), glm::vec4(1.0f));
  d.state.depth_test = false;
  return d;
}

PixelSet written_pixels(const golden::Result& r) {
  PixelSet s;
  const int W = r.framebuffer.width;
  for (size_t i = 0; i < r.last_writer.size(); ++i) {
    if (r.last_writer[i] >= 0) s.insert({static_cast<int>(i % W), static_cast<int>(i / W)});
  }
  return s;
}

PixelSet row_of(int y, int x0, int x1) {
  PixelSet s;
  for (int x = x0; x <= x1; ++x) s.insert({x, y});
  return s;
}
PixelSet column_of(int x, int y0, int y1) {
  PixelSet s;
  for (int y = y0; y <= y1; ++y) s.insert({x, y});
  return s;
}
PixelSet unite(PixelSet a, const PixelSet& b) {
  a.insert(b.begin(), b.end());
  return a;
}

// One line (or a strip, loop...) rendered alone in a 32 x 32 framebuffer.
constexpr int kW = 32, kH = 32;
golden::Result render_lines(PrimitiveType prim, const std::vector<Pt>& pts,
                            LineRasterization rule = LineRasterization::diamond_exit,
                            float width = 1.0f) {
  Scene s = make_scene(kW, kH);
  Draw d = draw_at(prim, pts, kW, kH);
  d.state.line_rasterization = rule;
  d.state.line_width = width;
  s.draws.push_back(d);
  return golden::render(s);
}

// ---------------------------------------------------------------------------
// Section 3: assembly.

TEST(GoldenLinesAssembly, LinesStripsLoopsAndPoints) {
  using golden::assemble_lines;
  using L = golden::LineSlots;
  using Ls = std::vector<L>;
  EXPECT_EQ(assemble_lines(PrimitiveType::lines, 0), Ls{});
  EXPECT_EQ(assemble_lines(PrimitiveType::lines, 1), Ls{});
  // 5 slots: two lines, the fifth vertex ignored; every end drawn.
  EXPECT_EQ(assemble_lines(PrimitiveType::lines, 5),
            (Ls{{{0, 1}, true, true}, {{2, 3}, true, true}}));
  EXPECT_EQ(assemble_lines(PrimitiveType::line_strip, 1), Ls{});
  // A strip's shared vertices are drawn by the line they end: later lines
  // clear their first flag.
  EXPECT_EQ(assemble_lines(PrimitiveType::line_strip, 4),
            (Ls{{{0, 1}, true, true}, {{1, 2}, false, true}, {{2, 3}, false, true}}));
  EXPECT_EQ(assemble_lines(PrimitiveType::line_loop, 1), Ls{});
  // A loop closes back to vertex 0 (its provoking vertex), both flags clear.
  EXPECT_EQ(assemble_lines(PrimitiveType::line_loop, 3),
            (Ls{{{0, 1}, true, true}, {{1, 2}, false, true}, {{2, 0}, false, false}}));
  EXPECT_EQ(assemble_lines(PrimitiveType::line_loop, 2),
            (Ls{{{0, 1}, true, true}, {{1, 0}, false, false}}));
  EXPECT_EQ(assemble_lines(PrimitiveType::triangles, 6), Ls{});
  EXPECT_EQ(assemble_lines(PrimitiveType::points, 6), Ls{});

  EXPECT_EQ(golden::assemble_points(PrimitiveType::points, 3), (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(golden::assemble_points(PrimitiveType::lines, 3), std::vector<uint32_t>{});
  EXPECT_TRUE(golden::assemble_triangles(PrimitiveType::line_loop, 6).empty());
  EXPECT_TRUE(golden::assemble_triangles(PrimitiveType::points, 6).empty());
}

// Primitive ids: one counter for every kind, in API order across draws.
TEST(GoldenLinesAssembly, PrimitiveIdsCountEveryKind) {
  Scene s = make_scene(kW, kH);
  // Draw 0: a triangle (id 0) far from the rest, bottom left.
  s.draws.push_back(
      draw_at(PrimitiveType::triangles, {{sp(0), sp(0)}, {sp(3), sp(0)}, {sp(0), sp(3)}}, kW, kH));
  // Draw 1: two points (ids 1, 2), at pixels (10, 10) and (20, 10).
  s.draws.push_back(
      draw_at(PrimitiveType::points, {{sp(10.5), sp(10.5)}, {sp(20.5), sp(10.5)}}, kW, kH));
  // Draw 2: a line strip of two lines (ids 3, 4): row 20, columns 2..5, then
  // column 6, rows 20..23.
  s.draws.push_back(draw_at(PrimitiveType::line_strip,
                            {{sp(2.5), sp(20.5)}, {sp(6.5), sp(20.5)}, {sp(6.5), sp(24.5)}}, kW,
                            kH));
  const golden::Result r = golden::render(s);
  const auto id_at = [&](int x, int y) { return r.last_writer[r.framebuffer.pixel_index(x, y)]; };
  EXPECT_EQ(id_at(0, 0), 0);
  EXPECT_EQ(id_at(10, 10), 1);
  EXPECT_EQ(id_at(20, 10), 2);
  EXPECT_EQ(id_at(2, 20), 3);
  EXPECT_EQ(id_at(5, 20), 3);
  EXPECT_EQ(id_at(6, 20), 4);
  EXPECT_EQ(id_at(6, 23), 4);
  EXPECT_EQ(r.stats.triangles_in, 1u);
  EXPECT_EQ(r.stats.points_in, 2u);
  EXPECT_EQ(r.stats.points_rasterized, 2u);
  EXPECT_EQ(r.stats.lines_in, 2u);
  EXPECT_EQ(r.stats.lines_rasterized, 2u);
}

TEST(GoldenLinesAssembly, InvalidLinesAndPoints) {
  Scene s = make_scene(kW, kH);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Lines: (0, 1) fine, (2, 3) has a NaN, (4, 99) an index out of range.
  Draw lines = draw_at(PrimitiveType::lines,
                       {{sp(1.5), sp(1.5)},
                        {sp(5.5), sp(1.5)},
                        {sp(1.5), sp(3.5)},
                        {sp(5.5), sp(3.5)},
                        {sp(1.5), sp(5.5)}},
                       kW, kH);
  lines.positions[3].x = nan;
  lines.indices = {0, 1, 2, 3, 4, 99};
  s.draws.push_back(lines);
  // Points: one fine, one infinite, one index out of range.
  Draw points =
      draw_at(PrimitiveType::points, {{sp(10.5), sp(10.5)}, {sp(12.5), sp(10.5)}}, kW, kH);
  points.positions[1].w = std::numeric_limits<float>::infinity();
  points.indices = {0, 1, 7};
  s.draws.push_back(points);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.lines_in, 3u);
  EXPECT_EQ(r.stats.lines_invalid, 2u);
  EXPECT_EQ(r.stats.lines_rasterized, 1u);
  EXPECT_EQ(r.stats.points_in, 3u);
  EXPECT_EQ(r.stats.points_invalid, 2u);
  EXPECT_EQ(r.stats.points_rasterized, 1u);
  // Line (1.5, 1.5) -> (5.5, 1.5): columns 1..4 (below); the point: 1 pixel.
  EXPECT_EQ(written_pixels(r), unite(row_of(1, 1, 4), {{10, 10}}));
}

// ---------------------------------------------------------------------------
// Section 8b: diamond exit, worked out by hand.
//
// A line between two pixel centres n pixels apart draws n pixels: the start
// pixel (the segment leaves its diamond) but not the end pixel (it ends
// inside). Perturbed by -(eps, eps^2), a line through centres runs just below
// and left of them, still inside their diamonds.

TEST(GoldenDiamondExit, HorizontalAndVerticalThroughCentres) {
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(1.5), sp(4.5)}, {sp(9.5), sp(4.5)}})),
      row_of(4, 1, 8));
  // Leftwards: starts in pixel 9, ends in pixel 1's diamond.
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(9.5), sp(4.5)}, {sp(1.5), sp(4.5)}})),
      row_of(4, 2, 9));
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(4.5), sp(1.5)}, {sp(4.5), sp(9.5)}})),
      column_of(4, 1, 8));
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(4.5), sp(9.5)}, {sp(4.5), sp(1.5)}})),
      column_of(4, 2, 9));
  const golden::Result r =
      render_lines(PrimitiveType::lines, {{sp(1.5), sp(4.5)}, {sp(9.5), sp(4.5)}});
  EXPECT_EQ(r.stats.fragments_generated, 8u);
  EXPECT_EQ(r.stats.lines_rasterized, 1u);
  EXPECT_EQ(r.stats.lines_degenerate, 0u);
}

// Between two pixel centres (on the boundary of both diamonds): the tie goes
// to the side the perturbation moves the line towards: down for a horizontal
// line (y - eps^2), left for a vertical one (x - eps).
TEST(GoldenDiamondExit, TiesBetweenTwoPixelCentres) {
  // y = 4.0: between rows 3 and 4: row 3. From x = 1.5 to 9.5: columns 1..8
  // (the start on column 1's centre line enters its diamond there).
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(1.5), sp(4)}, {sp(9.5), sp(4)}})),
      row_of(3, 1, 8));
  // x = 4.0: between columns 3 and 4: column 3.
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(4), sp(1.5)}, {sp(4), sp(9.5)}})),
      column_of(3, 1, 8));
}

// End points on pixel corners, a horizontal line through centres' row: from
// x = 2.0 (the corner between columns 1 and 2) to 6.0. Column 1's diamond
// only touches x = 2.0 at its right vertex (y = 4.5); A' = A - (eps, eps^2)
// lies inside it (128 - eps + eps^2 < 128), and the segment leaves it: column
// 1 is drawn. At the other end B = (6.0, 4.5) is column 5's right vertex:
// B' lies inside column 5's diamond, so the line ends there without exiting
// it, and never reaches column 6's: columns 1..4, four pixels for a line
// four pixels long.
TEST(GoldenDiamondExit, EndPointsOnDiamondVertices) {
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(2), sp(4.5)}, {sp(6), sp(4.5)}})),
      row_of(4, 1, 4));
}

// Ending a quarter pixel past column 9's centre (9.75): the centre is passed,
// but B' lies inside column 9's diamond (u = 64 - eps), so the line ends in it
// without exiting: columns 1..8. Ending 0.75 pixel past it (10.25), B' is
// outside (|u| = 192): column 9 is drawn.
TEST(GoldenDiamondExit, EndPastACentreButInsideItsDiamond) {
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(1.5), sp(4.5)}, {sp(9.75), sp(4.5)}})),
      row_of(4, 1, 8));
  EXPECT_EQ(written_pixels(
                render_lines(PrimitiveType::lines, {{sp(1.5), sp(4.5)}, {sp(10.25), sp(4.5)}})),
            row_of(4, 1, 9));
}

// 45 degrees through centres: (i, i) for the n pixels from the start.
TEST(GoldenDiamondExit, FortyFiveDegrees) {
  PixelSet diag;
  for (int i = 1; i <= 8; ++i) diag.insert({i, i});
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(1.5), sp(1.5)}, {sp(9.5), sp(9.5)}})),
      diag);
  // Along diamond edges: y = x + 0.5 runs along the lower-right edge of the
  // diamonds of pixels (i - 1, i) (centre (i - 0.5, i + 0.5)) and the upper-
  // left edge of pixels (i, i). Moved left and down by the perturbation, it
  // enters the former: (i - 1, i) for i = 1..8, from A = (1.0, 1.5), inside
  // pixel (0, 1)'s diamond as perturbed, to B = (9.0, 9.5), which ends in
  // pixel (8, 9)'s.
  PixelSet upper;
  for (int i = 1; i <= 8; ++i) upper.insert({i - 1, i});
  EXPECT_EQ(
      written_pixels(render_lines(PrimitiveType::lines, {{sp(1), sp(1.5)}, {sp(9), sp(9.5)}})),
      upper);
}

TEST(GoldenDiamondExit, ZeroLengthIsDegenerate) {
  const golden::Result r =
      render_lines(PrimitiveType::lines, {{sp(4.5), sp(4.5)}, {sp(4.5), sp(4.5)}});
  EXPECT_EQ(r.stats.lines_in, 1u);
  EXPECT_EQ(r.stats.lines_degenerate, 1u);
  EXPECT_EQ(r.stats.lines_rasterized, 0u);
  EXPECT_EQ(r.stats.fragments_generated, 0u);
  // Bresenham draws it: one pixel, both ends set.
  const golden::Result b = render_lines(
      PrimitiveType::lines, {{sp(4.5), sp(4.5)}, {sp(4.5), sp(4.5)}}, LineRasterization::bresenham);
  EXPECT_EQ(b.stats.lines_degenerate, 0u);
  EXPECT_EQ(b.stats.lines_rasterized, 1u);
  EXPECT_EQ(written_pixels(b), (PixelSet{{4, 4}}));
}

// A strip draws each shared vertex once: row 1 columns 1..8 then column 9
// rows 1..6; the shared vertex (9.5, 1.5) is the second line's start pixel.
TEST(GoldenDiamondExit, StripDrawsSharedVerticesOnce) {
  const golden::Result r = render_lines(
      PrimitiveType::line_strip, {{sp(1.5), sp(1.5)}, {sp(9.5), sp(1.5)}, {sp(9.5), sp(7.5)}});
  EXPECT_EQ(written_pixels(r), unite(row_of(1, 1, 8), column_of(9, 1, 6)));
  EXPECT_EQ(r.stats.fragments_generated, 14u);  // 8 + 6, none twice
  EXPECT_EQ(r.stats.lines_in, 2u);
}

// A loop around the 7 x 7 square of centres (2.5 .. 8.5): its 24 boundary
// pixels, each once.
TEST(GoldenDiamondExit, LoopCloses) {
  const std::vector<Pt> square = {
      {sp(2.5), sp(2.5)}, {sp(8.5), sp(2.5)}, {sp(8.5), sp(8.5)}, {sp(2.5), sp(8.5)}};
  PixelSet ring =
      unite(unite(row_of(2, 2, 8), row_of(8, 2, 8)), unite(column_of(2, 2, 8), column_of(8, 2, 8)));
  ASSERT_EQ(ring.size(), 24u);
  for (const LineRasterization rule :
       {LineRasterization::diamond_exit, LineRasterization::bresenham}) {
    const golden::Result r = render_lines(PrimitiveType::line_loop, square, rule);
    EXPECT_EQ(written_pixels(r), ring);
    EXPECT_EQ(r.stats.fragments_generated, 24u);
    EXPECT_EQ(r.stats.lines_in, 4u);
    // Without the closing line, the left column's rows 3..8 stay empty
    // (diamond exit: 3..8; Bresenham: the strip ends on (2, 8), so 3..7).
    const golden::Result strip = render_lines(PrimitiveType::line_strip, square, rule);
    EXPECT_EQ(strip.stats.fragments_generated, rule == LineRasterization::diamond_exit ? 18u : 19u);
  }
}

// ---------------------------------------------------------------------------
// The spec's "Consequences" paragraph (section 8b) as a second formulation,
// written from its text: a band test on D(C) with its ties, plus the end
// test on the end columns (rows for y-major). It must agree with the
// definition (golden::diamond_exit_covers) everywhere.

int64_t sgn64(int64_t v) {
  return (v > 0) - (v < 0);
}

// P' in R for the pixel centred at (cx, cy): |u| + |v| < 128, or = 128 with u > 0.
bool perturbed_inside(int64_t px, int64_t py, int64_t cx, int64_t cy) {
  const int64_t u = px - cx, v = py - cy;
  const int64_t l1 = std::llabs(u) + std::llabs(v);
  return l1 < 128 || (l1 == 128 && u > 0);
}

// The band of a width-w line (w = 1: the width-1 rule) with its ties.
bool in_band(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t cx, int64_t cy, int w) {
  const int64_t dx = bx - ax, dy = by - ay;
  if (std::llabs(dx) >= std::llabs(dy)) {
    const int64_t sd = sgn64(dx) * ((cy - ay) * dx - (cx - ax) * dy);
    const int64_t band = 128 * w * std::llabs(dx);
    return (-band < sd && sd < band) || (sd == -band && dx * dy <= 0) ||
           (sd == band && dx * dy > 0);
  }
  const int64_t sd = sgn64(dy) * ((cx - ax) * dy - (cy - ay) * dx);
  const int64_t band = 128 * w * std::llabs(dy);
  return (-band < sd && sd < band) || sd == -band;
}

bool consequences_covers(int64_t ax, int64_t ay, int64_t bx, int64_t by, int x, int y) {
  const int64_t cx = 256 * int64_t{x} + 128, cy = 256 * int64_t{y} + 128;
  const int64_t dx = bx - ax, dy = by - ay;
  if (dx == 0 && dy == 0) return false;
  if (!in_band(ax, ay, bx, by, cx, cy, 1)) return false;
  const bool x_major = std::llabs(dx) >= std::llabs(dy);
  const int64_t pa = x_major ? ax : ay, pb = x_major ? bx : by, c = x_major ? cx : cy;
  const bool forward = (x_major ? dx : dy) > 0;
  const bool a_in = perturbed_inside(ax, ay, cx, cy);
  const bool b_in = perturbed_inside(bx, by, cx, cy);
  if (forward) return (pa <= c || a_in) && (pb > c && !b_in);
  return (pa > c || a_in) && (pb <= c && !b_in);
}

// Random end points with the structures that exercise the ties.
struct LineGen {
  std::mt19937_64 rng{12345};
  int64_t uniform(int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  }
  Pt point(int range_px) {
    switch (uniform(0, 3)) {
      case 0:  // anywhere
        return {uniform(0, 256 * range_px), uniform(0, 256 * range_px)};
      case 1:  // a pixel centre
        return {256 * uniform(0, range_px) + 128, 256 * uniform(0, range_px) + 128};
      case 2: {  // on a diamond's boundary: |u| + |v| = 128
        const int64_t u = uniform(-128, 128);
        const int64_t v = (128 - std::llabs(u)) * (uniform(0, 1) ? 1 : -1);
        return {256 * uniform(0, range_px) + 128 + u, 256 * uniform(0, range_px) + 128 + v};
      }
      default:  // a pixel corner or a half-pixel
        return {128 * uniform(0, 2 * range_px), 128 * uniform(0, 2 * range_px)};
    }
  }
  // A line of a random kind: general, horizontal, vertical, 45 degrees, tiny.
  std::pair<Pt, Pt> line(int range_px) {
    const Pt a = point(range_px);
    Pt b = point(range_px);
    switch (uniform(0, 5)) {
      case 0:
        b.y = a.y;
        break;
      case 1:
        b.x = a.x;
        break;
      case 2: {
        const int64_t d = b.x - a.x;
        b.y = a.y + (uniform(0, 1) ? d : -d);
        break;
      }
      case 3:  // tiny: a few subpixels
        b = {a.x + uniform(-3, 3), a.y + uniform(-3, 3)};
        break;
      default:
        break;
    }
    return {a, b};
  }
};

TEST(GoldenDiamondExit, DefinitionAgreesWithTheSpecsIntegerForm) {
  LineGen gen;
  int lines = 0, fragments = 0;
  for (int n = 0; n < 30000; ++n) {
    const auto [a, b] = gen.line(n % 3 == 0 ? 40 : 6);  // long and short
    // Every pixel within two of the end points' box.
    const int64_t x0 = std::min(a.x, b.x) / 256 - 2, x1 = std::max(a.x, b.x) / 256 + 2;
    const int64_t y0 = std::min(a.y, b.y) / 256 - 2, y1 = std::max(a.y, b.y) / 256 + 2;
    for (int64_t y = y0; y <= y1; ++y) {
      for (int64_t x = x0; x <= x1; ++x) {
        const bool def = golden::diamond_exit_covers(a.x, a.y, b.x, b.y, static_cast<int>(x),
                                                     static_cast<int>(y));
        const bool integer =
            consequences_covers(a.x, a.y, b.x, b.y, static_cast<int>(x), static_cast<int>(y));
        fragments += def;
        ASSERT_EQ(def, integer) << "line (" << a.x << ", " << a.y << ") -> (" << b.x << ", " << b.y
                                << "), pixel (" << x << ", " << y << ")";
      }
    }
    ++lines;
  }
  EXPECT_EQ(lines, 30000);
  EXPECT_GT(fragments, 150000);  // the comparison is not vacuous
}

// diamond_exit_pixels scans a window around the line, not the whole box: it
// must find exactly the pixels the definition covers in the framebuffer.
TEST(GoldenDiamondExit, PixelWalkFindsEveryCoveredPixel) {
  LineGen gen;
  constexpr int W = 24, H = 20;
  for (int n = 0; n < 1500; ++n) {
    auto [a, b] = gen.line(28);
    a.x -= 512;  // some lines start or end off-screen
    b.y -= 512;
    PixelSet want;
    for (int y = 0; y < H; ++y) {
      for (int x = 0; x < W; ++x) {
        if (golden::diamond_exit_covers(a.x, a.y, b.x, b.y, x, y)) want.insert({x, y});
      }
    }
    const std::vector<Pixel> got = golden::diamond_exit_pixels(a.x, a.y, b.x, b.y, 1, W, H);
    const PixelSet got_set(got.begin(), got.end());
    ASSERT_EQ(got.size(), got_set.size()) << "a pixel twice";
    ASSERT_EQ(got_set, want) << "line (" << a.x << ", " << a.y << ") -> (" << b.x << ", " << b.y
                             << ")";
  }
}

// ---------------------------------------------------------------------------
// Wide lines (section 8b): w pixels per column (x-major) or row (y-major).

TEST(GoldenWideLines, HorizontalAndVerticalWidthsOneToTen) {
  for (int w = 1; w <= 10; ++w) {
    // Moved down by (w - 1) / 2 pixels, the line at y = 8.5 lies on row
    // 8 - (w - 1) / 2's centre (odd w) or half-way between rows (even w),
    // where the tie takes the lower row: the base row is 8 - floor(w / 2),
    // and the column runs w rows up from it (even widths extend downwards).
    const int base = 8 - w / 2;
    PixelSet want;
    for (int k = 0; k < w; ++k) want = unite(want, row_of(base + k, 2, 11));
    const golden::Result h =
        render_lines(PrimitiveType::lines, {{sp(2.5), sp(8.5)}, {sp(12.5), sp(8.5)}},
                     LineRasterization::diamond_exit, static_cast<float>(w));
    EXPECT_EQ(written_pixels(h), want) << "width " << w;
    EXPECT_EQ(h.stats.fragments_generated, 10u * w);
    // Vertical: the same to the left.
    PixelSet want_v;
    for (int k = 0; k < w; ++k) want_v = unite(want_v, column_of(base + k, 2, 11));
    const golden::Result v =
        render_lines(PrimitiveType::lines, {{sp(8.5), sp(2.5)}, {sp(8.5), sp(12.5)}},
                     LineRasterization::diamond_exit, static_cast<float>(w));
    EXPECT_EQ(written_pixels(v), want_v) << "width " << w;
  }
}

TEST(GoldenWideLines, WidthRoundsHalfAwayFromZero) {
  EXPECT_EQ(golden::line_width_pixels(1.0f), 1);
  EXPECT_EQ(golden::line_width_pixels(1.4f), 1);
  EXPECT_EQ(golden::line_width_pixels(1.5f), 2);
  EXPECT_EQ(golden::line_width_pixels(2.5f), 3);
  EXPECT_EQ(golden::line_width_pixels(3.7f), 4);
  EXPECT_EQ(golden::line_width_pixels(0.25f), 1);
  EXPECT_EQ(golden::line_width_pixels(255.0f), 255);
}

// Any slope: every column more than half a pixel inside both end points
// (x-major; rows for y-major) holds exactly w pixels, those of the spec's band
// -128 w |dx| < s D < 128 w |dx| (with the width-1 ties).
TEST(GoldenWideLines, InteriorColumnsAreTheBandOfWidthW) {
  LineGen gen;
  // Moved into the middle of a framebuffer large enough for every band.
  constexpr int W = 160, H = 160;
  int checked = 0;
  for (int n = 0; n < 3000; ++n) {
    auto [a, b] = gen.line(40);
    a = {a.x + 256 * 56, a.y + 256 * 56};
    b = {b.x + 256 * 56, b.y + 256 * 56};
    if (a.x == b.x && a.y == b.y) continue;
    const int w = 1 + static_cast<int>(n % 10);
    const int64_t dx = b.x - a.x, dy = b.y - a.y;
    const bool x_major = std::llabs(dx) >= std::llabs(dy);
    const std::vector<Pixel> got = golden::diamond_exit_pixels(a.x, a.y, b.x, b.y, w, W, H);
    const PixelSet got_set(got.begin(), got.end());
    ASSERT_EQ(got.size(), got_set.size()) << "a pixel twice";
    const int64_t lo = std::min(x_major ? a.x : a.y, x_major ? b.x : b.y);
    const int64_t hi = std::max(x_major ? a.x : a.y, x_major ? b.x : b.y);
    for (int i = 0; i < (x_major ? W : H); ++i) {
      const int64_t c = 256 * int64_t{i} + 128;
      // End columns have their own test: an end point within half a pixel of
      // the centre can lie in the diamond of a pixel of the band.
      if (!(lo + 128 < c && c + 128 < hi)) continue;
      PixelSet line_pixels, band;
      for (int j = 0; j < (x_major ? H : W); ++j) {
        const Pixel p = x_major ? Pixel{i, j} : Pixel{j, i};
        if (got_set.count(p)) line_pixels.insert(p);
        if (in_band(a.x, a.y, b.x, b.y, 256 * int64_t{p.x} + 128, 256 * int64_t{p.y} + 128, w)) {
          band.insert(p);
        }
      }
      ASSERT_EQ(line_pixels, band) << "line (" << a.x << ", " << a.y << ") -> (" << b.x << ", "
                                   << b.y << ") width " << w << ", line " << i;
      ASSERT_EQ(line_pixels.size(), static_cast<size_t>(w));
      ++checked;
    }
  }
  EXPECT_GT(checked, 20000);
}

// ---------------------------------------------------------------------------
// Bresenham (section 8b) against the textbook loop.

// The classic integer loop on pixel end points: x-major when |dx| >= |dy|,
// error term d = 2 dy - dx, a minor step when d > 0 (so a midpoint exactly on
// the line does not step), written per octant through the step signs.
std::vector<Pixel> textbook_bresenham(int x0, int y0, int x1, int y1) {
  std::vector<Pixel> out;
  const int dx = std::abs(x1 - x0), dy = std::abs(y1 - y0);
  const int sx = x1 >= x0 ? 1 : -1, sy = y1 >= y0 ? 1 : -1;
  if (dx >= dy) {
    int d = 2 * dy - dx, y = y0;
    for (int i = 0, x = x0; i <= dx; ++i, x += sx) {
      out.push_back({x, y});
      if (d > 0) {
        y += sy;
        d -= 2 * dx;
      }
      d += 2 * dy;
    }
  } else {
    int d = 2 * dx - dy, x = x0;
    for (int i = 0, y = y0; i <= dy; ++i, y += sy) {
      out.push_back({x, y});
      if (d > 0) {
        x += sx;
        d -= 2 * dy;
      }
      d += 2 * dx;
    }
  }
  return out;
}

TEST(GoldenBresenham, MatchesTheTextbookLoopInEveryOctant) {
  std::mt19937_64 rng(777);
  constexpr int W = 64, H = 64;
  std::uniform_int_distribution<int64_t> coord(0, 256 * W - 1);
  int octants[8] = {};
  for (int n = 0; n < 20000; ++n) {
    const int64_t ax = coord(rng), ay = coord(rng), bx = coord(rng), by = coord(rng);
    const bool first = n % 4 != 1, last = n % 4 != 2;
    const int x0 = static_cast<int>(ax / 256), y0 = static_cast<int>(ay / 256);
    const int x1 = static_cast<int>(bx / 256), y1 = static_cast<int>(by / 256);
    std::vector<Pixel> want = textbook_bresenham(x0, y0, x1, y1);
    // End flags drop the first and last pixel (a single pixel needs both).
    if (want.size() == 1) {
      if (!(first && last)) want.clear();
    } else {
      if (!last) want.pop_back();
      if (!first) want.erase(want.begin());
    }
    const std::vector<Pixel> got = golden::bresenham_pixels(ax, ay, bx, by, first, last, 1, W, H);
    ASSERT_EQ(got, want) << "line (" << ax << ", " << ay << ") -> (" << bx << ", " << by << ")";
    const int ddx = x1 - x0, ddy = y1 - y0;
    ++octants[(ddx < 0) * 4 + (ddy < 0) * 2 + (std::abs(ddx) < std::abs(ddy))];
  }
  for (int o = 0; o < 8; ++o) EXPECT_GT(octants[o], 1000) << "octant " << o;
}

// Lines starting or ending off-screen: the on-screen part of the textbook line.
TEST(GoldenBresenham, OffScreenPartsAreCut) {
  std::mt19937_64 rng(4242);
  constexpr int W = 40, H = 30;
  std::uniform_int_distribution<int64_t> coord(-256 * 50, 256 * 90);
  for (int n = 0; n < 5000; ++n) {
    const int64_t ax = coord(rng), ay = coord(rng), bx = coord(rng), by = coord(rng);
    const auto pixel = [](int64_t v) { return static_cast<int>(std::floor(v / 256.0)); };
    std::vector<Pixel> want;
    for (const Pixel& p : textbook_bresenham(pixel(ax), pixel(ay), pixel(bx), pixel(by))) {
      if (p.x >= 0 && p.y >= 0 && p.x < W && p.y < H) want.push_back(p);
    }
    ASSERT_EQ(golden::bresenham_pixels(ax, ay, bx, by, true, true, 1, W, H), want)
        << "line (" << ax << ", " << ay << ") -> (" << bx << ", " << by << ")";
  }
}

// Through the renderer: a `lines` draw with both ends, then the same path as
// a strip (shared vertices once).
TEST(GoldenBresenham, LinesAndStripsThroughTheRenderer) {
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<int64_t> coord(0, 256 * kW - 1);
  for (int n = 0; n < 300; ++n) {
    std::vector<Pt> path;
    for (int k = 0; k < 4; ++k) path.push_back({coord(rng), coord(rng)});
    std::vector<Pt> pairs;
    PixelSet want;
    size_t textbook_count = 0;
    for (int k = 0; k + 1 < 4; ++k) {
      pairs.push_back(path[k]);
      pairs.push_back(path[k + 1]);
      const std::vector<Pixel> seg = textbook_bresenham(
          static_cast<int>(path[k].x / 256), static_cast<int>(path[k].y / 256),
          static_cast<int>(path[k + 1].x / 256), static_cast<int>(path[k + 1].y / 256));
      want.insert(seg.begin(), seg.end());
      textbook_count += seg.size();
    }
    const golden::Result l =
        render_lines(PrimitiveType::lines, pairs, LineRasterization::bresenham);
    EXPECT_EQ(written_pixels(l), want);
    EXPECT_EQ(l.stats.fragments_generated, textbook_count);
    const golden::Result s =
        render_lines(PrimitiveType::line_strip, path, LineRasterization::bresenham);
    EXPECT_EQ(written_pixels(s), want);
    // The strip draws its 2 shared vertices once.
    EXPECT_EQ(s.stats.fragments_generated, textbook_count - 2);
  }
}

// Wide Bresenham: each pixel becomes a column starting floor((w - 1) / 2)
// below it (rows for y-major).
TEST(GoldenBresenham, WideLinesReplicateAcrossTheMinorAxis) {
  for (int w = 1; w <= 6; ++w) {
    const int below = (w - 1) / 2;
    PixelSet want_h, want_v;
    for (int k = 0; k < w; ++k) {
      want_h = unite(want_h, row_of(8 - below + k, 2, 12));
      want_v = unite(want_v, column_of(8 - below + k, 2, 12));
    }
    EXPECT_EQ(
        written_pixels(render_lines(PrimitiveType::lines, {{sp(2.5), sp(8.5)}, {sp(12.5), sp(8.5)}},
                                    LineRasterization::bresenham, static_cast<float>(w))),
        want_h)
        << "width " << w;
    EXPECT_EQ(
        written_pixels(render_lines(PrimitiveType::lines, {{sp(8.5), sp(2.5)}, {sp(8.5), sp(12.5)}},
                                    LineRasterization::bresenham, static_cast<float>(w))),
        want_v)
        << "width " << w;
  }
}

// ---------------------------------------------------------------------------
// Points (sections 4c, 8c).

// Window position -> clip (w = 1) in the 32 x 32 framebuffer: x / 16 - 1.
glm::vec4 at_window(float x, float y, float z = 0.0f) {
  return {x / 16.0f - 1.0f, y / 16.0f - 1.0f, z, 1.0f};
}

golden::Result render_point(float x, float y, float size) {
  Scene s = make_scene(kW, kH);
  Draw d;
  d.primitive = PrimitiveType::points;
  d.positions = {at_window(x, y)};
  d.state.depth_test = false;
  d.state.point_size = size;
  s.draws.push_back(d);
  return golden::render(s);
}

PixelSet square(int x0, int y0, int side) {
  PixelSet s;
  for (int k = 0; k < side; ++k) s = unite(s, row_of(y0 + k, x0, x0 + side - 1));
  return s;
}

TEST(GoldenPoints, SquaresOfIntegerAndFractionalSizes) {
  // Centred on pixel (5, 5)'s centre: X0 = 256 * 5 - floor(F / 2).
  // size 1: F = 256, X0 = 1152: 1152 <= 256 x < 1408: x = 5.
  EXPECT_EQ(written_pixels(render_point(5.5f, 5.5f, 1.0f)), square(5, 5, 1));
  // size 2: F = 512, X0 = 1024: x = 4, 5.
  EXPECT_EQ(written_pixels(render_point(5.5f, 5.5f, 2.0f)), square(4, 4, 2));
  // size 3: F = 768, X0 = 896: x = 4, 5, 6.
  EXPECT_EQ(written_pixels(render_point(5.5f, 5.5f, 3.0f)), square(4, 4, 3));
  // size 1.5: F = 384, X0 = 1088: 1088 <= 256 x < 1472: x = 5 only.
  EXPECT_EQ(written_pixels(render_point(5.5f, 5.5f, 1.5f)), square(5, 5, 1));
  // size 1.5 on a pixel corner (6, 6): X0 = 1408 - 192 = 1216, up to 1600:
  // x = 5, 6.
  EXPECT_EQ(written_pixels(render_point(6.0f, 6.0f, 1.5f)), square(5, 5, 2));
  // size 2.5: F = 640, X0 = 960, up to 1600: x = 4, 5, 6.
  EXPECT_EQ(written_pixels(render_point(5.5f, 5.5f, 2.5f)), square(4, 4, 3));
  // size 0.5: at least one pixel (F = 256).
  EXPECT_EQ(written_pixels(render_point(5.5f, 5.5f, 0.5f)), square(5, 5, 1));
  // size 4 on a corner (10, 10): F = 1024, X0 = 2432 - 512 = 1920: x = 8..11.
  EXPECT_EQ(written_pixels(render_point(10.0f, 10.0f, 4.0f)), square(8, 8, 4));
}

TEST(GoldenPoints, SizeSixtyFour) {
  Scene s = make_scene(128, 128);
  Draw d;
  d.primitive = PrimitiveType::points;
  // Window (64.5, 64.5) in 128 x 128: clip x / 64 - 1.
  d.positions = {{64.5f / 64.0f - 1.0f, 64.5f / 64.0f - 1.0f, 0.0f, 1.0f}};
  d.state.depth_test = false;
  d.state.point_size = 64.0f;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  // F = 16384, X0 = 64 * 256 - 8192 = 8192: x = 32..95.
  EXPECT_EQ(written_pixels(r), square(32, 32, 64));
  EXPECT_EQ(r.stats.fragments_generated, 4096u);
}

// iround rounds half away from zero, unlike vertex snapping: x_w =
// 5 + 1/512 gives (x_w - 0.5) * 256 = 1152.5 -> 1153, X0 = 1025, so the
// pixel is x = 5 (1280); half to even (1152) would give x = 4.
TEST(GoldenPoints, SnapRoundsHalfAwayFromZero) {
  EXPECT_EQ(written_pixels(render_point(5.001953125f, 8.5f, 1.0f)), square(5, 8, 1));
  const golden::PointSquare sq = golden::point_square(5.001953125f, 8.5f, 1.0f);
  EXPECT_EQ(sq.x0, 1025);
  EXPECT_EQ(sq.side, 256);
}

TEST(GoldenPoints, CentreOffScreenIsDroppedOnTheEdgeKept) {
  // Centre at x_w = -0.25: outside the view volume, dropped whole although a
  // size-10 square would reach pixels 0..4.
  const golden::Result off = render_point(-0.25f, 8.5f, 10.0f);
  EXPECT_TRUE(written_pixels(off).empty());
  EXPECT_EQ(off.stats.points_in, 1u);
  EXPECT_EQ(off.stats.points_clipped_away, 1u);
  EXPECT_EQ(off.stats.points_rasterized, 0u);
  // Exactly on the left edge (clip x = -w): kept. Size 4: F = 1024,
  // X0 = -128 - 512 = -640: x = -2..1, of which 0 and 1 are on screen;
  // Y0 = 2048 - 512 = 1536: y = 6..9.
  const golden::Result edge = render_point(0.0f, 8.5f, 4.0f);
  EXPECT_EQ(written_pixels(edge), unite(column_of(0, 6, 9), column_of(1, 6, 9)));
  EXPECT_EQ(edge.stats.points_clipped_away, 0u);
  EXPECT_EQ(edge.stats.points_rasterized, 1u);
  // Behind the near plane and w < 0: dropped.
  EXPECT_FALSE(golden::point_in_view_volume({0.0f, 0.0f, -1.5f, 1.0f}));
  EXPECT_FALSE(golden::point_in_view_volume({0.0f, 0.0f, 0.0f, -1.0f}));
  EXPECT_TRUE(golden::point_in_view_volume({1.0f, -1.0f, 1.0f, 1.0f}));
}

// A point takes its vertex's depth and colour, even with Gouraud shading.
TEST(GoldenPoints, DepthAndColourAreTheVertexs) {
  Scene s = make_scene(kW, kH);
  Draw d;
  d.primitive = PrimitiveType::points;
  d.positions = {at_window(5.5f, 5.5f, 0.5f)};
  d.colors = {{0.2f, 0.4f, 0.6f, 1.0f}};
  d.state.point_size = 3.0f;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  // z_w = (0.5 + 1) / 2 = 0.75, stored as unorm24 nearbyint(0.75 * (2^24 - 1)).
  const uint32_t z = static_cast<uint32_t>(std::nearbyint(0.75 * 16777215.0));
  for (const Pixel& p : square(4, 4, 3)) {
    const size_t i = r.framebuffer.pixel_index(p.x, p.y);
    EXPECT_EQ(r.framebuffer.depth[i], z);
    EXPECT_EQ(r.framebuffer.color[4 * i + 0], 51);  // 0.2 * 255
    EXPECT_EQ(r.framebuffer.color[4 * i + 1], 102);
    EXPECT_EQ(r.framebuffer.color[4 * i + 2], 153);
  }
}

// ---------------------------------------------------------------------------
// Line clipping (section 4b).

golden::Result render_clip_line(const glm::vec4& a, const glm::vec4& b) {
  Scene s = make_scene(kW, kH);
  Draw d;
  d.primitive = PrimitiveType::lines;
  d.positions = {a, b};
  d.state.depth_test = false;
  s.draws.push_back(d);
  return golden::render(s);
}

TEST(GoldenLineClip, NearPlane) {
  // From window (16, 8) at z = 0 up to a vertex behind the near plane
  // (z + w = -2). The cut is t = 1 / 3 of the way (d = 1 and -2, from the
  // inside end, the nearer): y = -0.5 + t = -0.16666666 (float), window
  // y = 13.333333 -> 3413 subpixels. The line x = 16.0 is half-way between
  // columns 15 and 16: the tie takes column 15. Rows: 8 (its centre 8.5 is
  // above the start 8.0) to 12; row 13's centre (13.5) is beyond the end.
  const golden::Result r = render_clip_line({0.0f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, -3.0f, 1.0f});
  EXPECT_EQ(written_pixels(r), column_of(15, 8, 12));
  EXPECT_EQ(r.stats.lines_in, 1u);
  EXPECT_EQ(r.stats.lines_clipped, 1u);
  EXPECT_EQ(r.stats.lines_clipped_away, 0u);
  EXPECT_EQ(r.stats.lines_rasterized, 1u);
  // Directly: the end behind the plane moved onto it, z = -w.
  const golden::GuardBand gb = golden::guard_band_for(kW, kH);
  const golden::ClippedLine c =
      golden::clip_line({golden::ShadedVertex{{0.0f, -0.5f, 0.0f, 1.0f}, {}},
                         golden::ShadedVertex{{0.0f, 0.5f, -3.0f, 1.0f}, {}}},
                        gb);
  EXPECT_EQ(c.result, golden::LineClip::clipped);
  EXPECT_EQ(c.v[0].clip, glm::vec4(0.0f, -0.5f, 0.0f, 1.0f));
  EXPECT_FLOAT_EQ(c.v[1].clip.z, -1.0f);
  EXPECT_FLOAT_EQ(c.v[1].clip.w, 1.0f);
}

TEST(GoldenLineClip, EndWithNegativeW) {
  // From the centre (16, 16) towards a vertex with w = -1: clipped at w > 0
  // and then at the guard band; x and y are cut by identical operations, so
  // the kept part is exactly 45 degrees: it runs through the centres of
  // (16, 16) .. (31, 31) and beyond the framebuffer.
  const golden::Result r = render_clip_line({0.0f, 0.0f, 0.0f, 1.0f}, {0.5f, 0.5f, 0.0f, -1.0f});
  PixelSet diag;
  for (int i = 16; i < 32; ++i) diag.insert({i, i});
  EXPECT_EQ(written_pixels(r), diag);
  EXPECT_EQ(r.stats.lines_clipped, 1u);
  EXPECT_EQ(r.stats.lines_rasterized, 1u);
}

TEST(GoldenLineClip, TrivialAcceptAndReject) {
  const golden::GuardBand gb = golden::guard_band_for(kW, kH);
  const golden::ShadedVertex in_a{{-0.5f, 0.0f, 0.0f, 1.0f}, {}};
  const golden::ShadedVertex in_b{{0.5f, 0.25f, 0.5f, 1.0f}, {}};
  const golden::ClippedLine acc = golden::clip_line({in_a, in_b}, gb);
  EXPECT_EQ(acc.result, golden::LineClip::accepted);
  EXPECT_EQ(acc.v[0].clip, in_a.clip);
  EXPECT_EQ(acc.v[1].clip, in_b.clip);
  // Both behind the eye, or both beyond the far plane: clipped away.
  const golden::ShadedVertex back_a{{0.0f, 0.0f, 0.0f, -1.0f}, {}};
  const golden::ShadedVertex back_b{{0.5f, 0.0f, 0.0f, -2.0f}, {}};
  EXPECT_EQ(golden::clip_line({back_a, back_b}, gb).result, golden::LineClip::rejected);
  const golden::ShadedVertex far_a{{0.0f, 0.0f, 2.0f, 1.0f}, {}};
  const golden::ShadedVertex far_b{{0.5f, 0.0f, 3.0f, 1.0f}, {}};
  EXPECT_EQ(golden::clip_line({far_a, far_b}, gb).result, golden::LineClip::rejected);
  const golden::Result r = render_clip_line(back_a.clip, back_b.clip);
  EXPECT_EQ(r.stats.lines_clipped_away, 1u);
  EXPECT_EQ(r.stats.lines_rasterized, 0u);
  EXPECT_EQ(r.stats.fragments_generated, 0u);
  // The cut is the triangle's: a line and a triangle edge on the same two
  // vertices are cut at the same point.
  const golden::ShadedVertex behind{{0.25f, 0.5f, -3.0f, 1.0f}, {0.0f, 1.0f, 0.0f, 1.0f}};
  const golden::ClippedLine line = golden::clip_line({in_a, behind}, gb);
  const std::vector<golden::ShadedVertex> poly = golden::clip_triangle({in_a, in_b, behind}, gb);
  ASSERT_EQ(poly.size(), 4u);
  EXPECT_EQ(line.v[1].clip, poly[3].clip);  // the cut of edge behind -> in_a
  EXPECT_EQ(line.v[1].color, poly[3].color);
}

// ---------------------------------------------------------------------------
// Polygon mode (section 4d).

const std::vector<Pt> kTri = {{sp(2.5), sp(2.5)}, {sp(12.5), sp(2.5)}, {sp(2.5), sp(12.5)}};

golden::Result render_polygon_mode(PolygonMode mode, const std::vector<Pt>& tri,
                                   CullMode cull = CullMode::none,
                                   LineRasterization rule = LineRasterization::diamond_exit) {
  Scene s = make_scene(kW, kH);
  Draw d = draw_at(PrimitiveType::triangles, tri, kW, kH);
  d.state.polygon_mode = mode;
  d.state.cull = cull;
  d.state.line_rasterization = rule;
  s.draws.push_back(d);
  return golden::render(s);
}

// The CCW triangle (2.5, 2.5), (12.5, 2.5), (2.5, 12.5): bottom row 2,
// columns 2..11; the 45-degree hypotenuse through centres (12 - k, 2 + k),
// k = 0..9; the left column 2 downwards, rows 12..3. 30 pixels.
PixelSet triangle_outline() {
  PixelSet diag;
  for (int k = 0; k <= 9; ++k) diag.insert({12 - k, 2 + k});
  return unite(unite(row_of(2, 2, 11), diag), column_of(2, 3, 12));
}

TEST(GoldenPolygonMode, LineDrawsTheThreeEdges) {
  for (const LineRasterization rule :
       {LineRasterization::diamond_exit, LineRasterization::bresenham}) {
    const golden::Result r = render_polygon_mode(PolygonMode::line, kTri, CullMode::none, rule);
    EXPECT_EQ(written_pixels(r), triangle_outline());
    EXPECT_EQ(r.stats.fragments_generated, 30u);  // every vertex once
    EXPECT_EQ(r.stats.triangles_in, 1u);
    EXPECT_EQ(r.stats.triangles_unfilled, 1u);
    EXPECT_EQ(r.stats.triangles_after_clip, 0u);
    EXPECT_EQ(r.stats.triangles_rasterized, 0u);
    EXPECT_EQ(r.stats.lines_in, 0u);
    EXPECT_EQ(r.stats.lines_rasterized, 3u);
    // The same as the loop through its vertices.
    EXPECT_EQ(written_pixels(render_lines(PrimitiveType::line_loop, kTri, rule)),
              triangle_outline());
  }
}

TEST(GoldenPolygonMode, PointDrawsTheThreeVertices) {
  const golden::Result r = render_polygon_mode(PolygonMode::point, kTri);
  EXPECT_EQ(written_pixels(r), (PixelSet{{2, 2}, {12, 2}, {2, 12}}));
  EXPECT_EQ(r.stats.triangles_unfilled, 1u);
  EXPECT_EQ(r.stats.points_in, 0u);
  EXPECT_EQ(r.stats.points_rasterized, 3u);
}

TEST(GoldenPolygonMode, CullingComesFirst) {
  const std::vector<Pt> cw = {kTri[0], kTri[2], kTri[1]};
  for (const PolygonMode mode : {PolygonMode::line, PolygonMode::point}) {
    const golden::Result culled = render_polygon_mode(mode, cw, CullMode::back);
    EXPECT_TRUE(written_pixels(culled).empty());
    EXPECT_EQ(culled.stats.triangles_culled, 1u);
    EXPECT_EQ(culled.stats.triangles_unfilled, 0u);
    EXPECT_EQ(culled.stats.lines_rasterized + culled.stats.points_rasterized, 0u);
    const golden::Result kept = render_polygon_mode(mode, kTri, CullMode::back);
    EXPECT_EQ(kept.stats.triangles_unfilled, 1u);
    EXPECT_FALSE(written_pixels(kept).empty());
  }
  // Degenerate (collinear after snapping): neither culled nor drawn.
  const golden::Result flat = render_polygon_mode(
      PolygonMode::line, {{sp(2.5), sp(2.5)}, {sp(6.5), sp(2.5)}, {sp(12.5), sp(2.5)}});
  EXPECT_EQ(flat.stats.triangles_degenerate, 1u);
  EXPECT_EQ(flat.stats.lines_rasterized, 0u);
}

// A triangle cut by the near plane: the new edge along the plane is not an
// edge of the triangle and is not drawn.
TEST(GoldenPolygonMode, EdgesMadeByTheClipperAreNotDrawn) {
  const golden::ShadedVertex a{{-0.5f, -0.5f, 0.0f, 1.0f}, {}};
  const golden::ShadedVertex b{{0.5f, -0.5f, 0.0f, 1.0f}, {}};
  const golden::ShadedVertex c{{0.0f, 0.5f, -3.0f, 1.0f}, {}};  // behind the near plane
  const golden::FlaggedPolygon p =
      golden::clip_triangle_with_edge_flags({a, b, c}, golden::guard_band_for(kW, kH));
  // a, b, the cut of b -> c (leaving: the edge from it runs along the
  // plane), the cut of c -> a (entering: it continues c -> a).
  ASSERT_EQ(p.v.size(), 4u);
  EXPECT_EQ(p.edge_flag, (std::vector<bool>{true, true, false, true}));
  EXPECT_EQ(p.v[0].clip, a.clip);
  EXPECT_EQ(p.v[1].clip, b.clip);
  // The vertices are clip_triangle's.
  const std::vector<golden::ShadedVertex> q =
      golden::clip_triangle({a, b, c}, golden::guard_band_for(kW, kH));
  ASSERT_EQ(q.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(p.v[i].clip, q[i].clip);

  Scene s = make_scene(kW, kH);
  Draw d;
  d.primitive = PrimitiveType::triangles;
  d.positions = {a.clip, b.clip, c.clip};
  d.state.depth_test = false;
  d.state.polygon_mode = PolygonMode::line;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_clipped, 1u);
  EXPECT_EQ(r.stats.triangles_unfilled, 1u);
  EXPECT_EQ(r.stats.lines_rasterized, 3u);
}

// ---------------------------------------------------------------------------
// Attributes (section 9).

TEST(GoldenLineAttributes, FlatTakesTheProvokingVertex) {
  const glm::vec4 red{1, 0, 0, 1}, green{0, 1, 0, 1}, blue{0, 0, 1, 1};
  const auto colour_at = [](const golden::Result& r, int x, int y) {
    const ColorChannel* c = r.framebuffer.color_at(x, y);
    return glm::ivec3(c[0], c[1], c[2]);
  };
  // A loop red -> green -> blue: its lines take green, blue, and (closing,
  // ending on vertex 0) red.
  Scene s = make_scene(kW, kH);
  Draw d = draw_at(PrimitiveType::line_loop, kTri, kW, kH);
  d.colors = {red, green, blue};
  d.state.shading = Shading::flat;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(colour_at(r, 5, 2), glm::ivec3(0, 255, 0));   // bottom: 0 -> 1
  EXPECT_EQ(colour_at(r, 8, 6), glm::ivec3(0, 0, 255));   // hypotenuse: 1 -> 2
  EXPECT_EQ(colour_at(r, 2, 8), glm::ivec3(255, 0, 0));   // left: 2 -> 0
  EXPECT_EQ(colour_at(r, 12, 2), glm::ivec3(0, 0, 255));  // vertex 1 starts line 1 -> 2
  // Polygon mode: every edge and point takes the triangle's last vertex.
  for (const PolygonMode mode : {PolygonMode::line, PolygonMode::point}) {
    Scene t = make_scene(kW, kH);
    Draw e = draw_at(PrimitiveType::triangles, kTri, kW, kH);
    e.colors = {red, green, blue};
    e.state.shading = Shading::flat;
    e.state.polygon_mode = mode;
    t.draws.push_back(e);
    const golden::Result u = golden::render(t);
    for (const Pixel& p : written_pixels(u))
      EXPECT_EQ(colour_at(u, p.x, p.y), glm::ivec3(0, 0, 255));
  }
  // Gouraud polygon-mode points take their own vertex's colour.
  Scene g = make_scene(kW, kH);
  Draw e = draw_at(PrimitiveType::triangles, kTri, kW, kH);
  e.colors = {red, green, blue};
  e.state.polygon_mode = PolygonMode::point;
  g.draws.push_back(e);
  const golden::Result u = golden::render(g);
  EXPECT_EQ(colour_at(u, 2, 2), glm::ivec3(255, 0, 0));
  EXPECT_EQ(colour_at(u, 12, 2), glm::ivec3(0, 255, 0));
  EXPECT_EQ(colour_at(u, 2, 12), glm::ivec3(0, 0, 255));
}

// A line from window (2.5, 4.5), w = 1, red, z_w = 0.2, to (12.5, 4.5),
// w = 3, black, z_w = 0.6. At the pixel centre x + 0.5 the parameter is
// t = (x + 0.5 - 2.5) / 10; depth is linear in window space, 0.2 + 0.4 t;
// colour perspective-correct: red = ((1 - t) / 1) / ((1 - t) / 1 + t / 3).
// At t = 0.5 that is 0.75 (191), not the window-linear 0.5 (128).
TEST(GoldenLineAttributes, PerspectiveCorrectColourLinearDepth) {
  Scene s = make_scene(kW, kH);
  Draw d;
  d.primitive = PrimitiveType::lines;
  const float y = 4.5f / 16.0f - 1.0f;
  d.positions = {{2.5f / 16.0f - 1.0f, y, -0.6f, 1.0f},
                 {(12.5f / 16.0f - 1.0f) * 3.0f, y * 3.0f, 0.6f, 3.0f}};
  d.colors = {{1, 0, 0, 1}, {0, 0, 0, 1}};
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(written_pixels(r), row_of(4, 2, 11));
  for (int x = 2; x <= 11; ++x) {
    const double t = (x + 0.5 - 2.5) / 10.0;
    const double red = (1.0 - t) / ((1.0 - t) + t / 3.0);
    const int got = r.framebuffer.color_at(x, 4)[0];
    EXPECT_NEAR(got, red * 255.0, 1.0) << "x " << x;
    const double z = 0.2 + 0.4 * t;
    EXPECT_NEAR(static_cast<double>(r.framebuffer.depth[r.framebuffer.pixel_index(x, 4)]),
                z * 16777215.0, 8.0)
        << "x " << x;
  }
  EXPECT_EQ(r.framebuffer.color_at(7, 4)[0], 191);
}

// Lines are not offset: polygon offset changes filled triangles only.
TEST(GoldenLineAttributes, NoPolygonOffset) {
  const auto depth_row = [](float units) {
    Scene s = make_scene(kW, kH);
    Draw d = draw_at(PrimitiveType::lines, {{sp(2.5), sp(4.5)}, {sp(12.5), sp(4.5)}}, kW, kH);
    d.state.depth_test = true;
    d.state.offset_units = units;
    d.state.offset_factor = units;
    s.draws.push_back(d);
    const golden::Result r = golden::render(s);
    return r.framebuffer.depth[r.framebuffer.pixel_index(5, 4)];
  };
  EXPECT_EQ(depth_row(0.0f), depth_row(100.0f));
}

// Section 13's identities on a mixed scene.
TEST(GoldenLinesStats, CountersBalance) {
  Scene s = make_scene(kW, kH);
  // 3 lines: one inside, one zero-length, one behind the eye.
  Draw l;
  l.primitive = PrimitiveType::lines;
  l.positions = {at_window(2.5f, 2.5f), at_window(8.5f, 2.5f),     at_window(4.5f, 4.5f),
                 at_window(4.5f, 4.5f), {0.0f, 0.0f, 0.0f, -1.0f}, {0.5f, 0.0f, 0.0f, -1.0f}};
  l.state.depth_test = false;
  s.draws.push_back(l);
  // 3 points: inside, outside, on the edge.
  Draw p;
  p.primitive = PrimitiveType::points;
  p.positions = {at_window(20.5f, 20.5f), at_window(-3.0f, 4.0f), at_window(32.0f, 5.0f)};
  p.state.depth_test = false;
  s.draws.push_back(p);
  const golden::Result r = golden::render(s);
  const golden::Stats& st = r.stats;
  EXPECT_EQ(st.lines_in, 3u);
  EXPECT_EQ(st.lines_clipped_away, 1u);
  EXPECT_EQ(st.lines_degenerate, 1u);
  EXPECT_EQ(st.lines_rasterized, 1u);
  EXPECT_EQ(st.lines_in,
            st.lines_invalid + st.lines_clipped_away + st.lines_degenerate + st.lines_rasterized);
  EXPECT_EQ(st.points_in, 3u);
  EXPECT_EQ(st.points_clipped_away, 1u);
  EXPECT_EQ(st.points_rasterized, 2u);
  // 6 fragments of the line, 1 for each kept point: the one on the right
  // edge, x_w = 32, covers [31.5, 32.5) in x, so pixel 31 (X0 = 8064 - 128 =
  // 7936 = 256 * 31), whose centre is inside the square.
  EXPECT_EQ(st.fragments_generated, 8u);
  const nlohmann::json j = st.to_json();
  EXPECT_EQ(j.at("lines_rasterized").get<uint64_t>(), 1u);
  EXPECT_EQ(j.at("points_clipped_away").get<uint64_t>(), 1u);
}

}  // namespace
}  // namespace gpusim

namespace gpusim {
namespace {

// Extreme clip coordinates (near w = 0, near the float range): every line,
// point and wireframe triangle is accounted for once (section 13), and
// nothing is drawn outside the framebuffer or takes long.
TEST(GoldenLinesStats, ExtremeInputsBalance) {
  std::mt19937_64 rng(2024);
  const float values[] = {0.0f,   1e-30f, -1e-30f, 0.5f,   -0.5f,  1.0f,   -1.0f,
                          2.0f,   -3.0f,  1e5f,    -1e5f,  1e30f,  -1e30f, 3e38f,
                          -3e38f, 1e-8f,  -1e-8f,  0.999f, 1.001f, 4.0e4f, -4.0e4f};
  std::uniform_int_distribution<size_t> pick(0, std::size(values) - 1);
  Scene s = make_scene(kW, kH);
  for (int n = 0; n < 60; ++n) {
    Draw d;
    d.primitive = n % 3 == 0   ? PrimitiveType::line_loop
                  : n % 3 == 1 ? PrimitiveType::points
                               : PrimitiveType::triangles;
    for (int k = 0; k < 30; ++k) {
      d.positions.push_back(
          {values[pick(rng)], values[pick(rng)], values[pick(rng)], values[pick(rng)]});
    }
    d.state.depth_test = false;
    d.state.line_width = static_cast<float>(1 + n % 7);
    d.state.point_size = static_cast<float>(1 + n % 5) * 3.0f;
    d.state.line_rasterization =
        n % 2 ? LineRasterization::bresenham : LineRasterization::diamond_exit;
    d.state.polygon_mode = n % 4 == 2 ? PolygonMode::line : PolygonMode::point;
    s.draws.push_back(d);
  }
  const golden::Result r = golden::render(s);
  const golden::Stats& st = r.stats;
  EXPECT_EQ(st.lines_in, 20u * 30u);
  EXPECT_EQ(st.points_in, 20u * 30u);
  EXPECT_EQ(st.triangles_in, 20u * 10u);
  const uint64_t line_survivors = st.lines_in - st.lines_invalid - st.lines_clipped_away;
  const uint64_t triangle_survivors =
      st.triangles_in - st.triangles_invalid - st.triangles_clipped_away;
  // Every surviving wireframe triangle is degenerate, culled or unfilled;
  // they draw up to one line or point per polygon vertex (at most 9).
  EXPECT_EQ(triangle_survivors,
            st.triangles_degenerate + st.triangles_culled + st.triangles_unfilled);
  EXPECT_EQ(st.triangles_after_clip, 0u);
  EXPECT_GE(st.lines_rasterized + st.lines_degenerate, line_survivors);
  EXPECT_LE(st.lines_rasterized + st.lines_degenerate, line_survivors + 9 * st.triangles_unfilled);
  EXPECT_GE(st.points_rasterized, st.points_in - st.points_invalid - st.points_clipped_away);
  EXPECT_GT(st.lines_clipped, 0u);
  EXPECT_GT(st.points_clipped_away, 0u);
  EXPECT_GT(st.triangles_unfilled, 0u);
  EXPECT_GT(st.fragments_generated, 0u);
}

}  // namespace
}  // namespace gpusim
