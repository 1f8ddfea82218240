// Lines and points through chains of stages: the raster core,
// PrimitiveSetup -> TileDistributor -> N TileRasterizers
// (testbench/tests/raster_bench.h), and one unit from setup to the depth
// test and the interpolator.
//
// Expected pixels come from rules written out here from
// docs/pipeline-spec.md, evaluated by brute force: diamond exit by its
// integer form (section 8b, "Consequences"), scanning every row of a column
// for the band pixel instead of setup's end-column formulas; Bresenham by the
// closed formula P_i of section 8b (ceil of a quotient, where the walker
// steps a decision variable); points by section 8c's inequalities per pixel.
// Cycle counts are derived by hand from the cost models in
// stages/tile_rasterizer.h and stages/primitive_setup.h, in the comments.
// A SystemC model elaborates once per process: ctest runs each TEST alone.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "hw/fifo.h"
#include "hw/fixed_point.h"
#include "hw/memory.h"
#include "hw/pixel_formats.h"
#include "hw/trace_probe.h"
#include "stages/depth_test.h"
#include "stages/interpolator.h"
#include "stages/primitive_setup.h"
#include "stages/tile_distributor.h"
#include "stages/tile_rasterizer.h"
#include "testbench/tests/raster_bench.h"

namespace gpusim {
namespace {

using namespace test;

// splitmix64.
struct Rng {
  uint64_t s;
  uint64_t next() {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  int64_t range(int64_t lo, int64_t hi) {
    return lo + static_cast<int64_t>(next() % static_cast<uint64_t>(hi - lo + 1));
  }
};

FrameState frame_with(int W, int H, std::vector<RenderState> states) {
  FrameState f;
  f.framebuffer.width = W;
  f.framebuffer.height = H;
  for (const RenderState& st : states) {
    DrawState d;
    d.state = st;
    f.draws.push_back(d);
  }
  return f;
}

// A primitive of `kind` with its vertices' 1/w at 1.
ClippedPrimitive primitive(PrimitiveKind kind, int64_t id, uint32_t draw) {
  ClippedPrimitive p;
  p.primitive_kind = kind;
  p.vertex_count = vertex_count_of(kind);
  p.draw_id = draw;
  p.primitive_id = id;
  for (unsigned i = 0; i < p.vertex_count; ++i) p.v[i].inv_w = 1.0f;
  return p;
}

ClippedPrimitive line(int64_t id, uint32_t draw, float xa, float ya, float xb, float yb,
                      bool first = true, bool last = true) {
  ClippedPrimitive p = primitive(PrimitiveKind::line, id, draw);
  p.v[0].x = xa;
  p.v[0].y = ya;
  p.v[1].x = xb;
  p.v[1].y = yb;
  p.v[0].z = 0.25f;
  p.v[1].z = 0.75f;
  p.draw_first = first;
  p.draw_last = last;
  return p;
}

ClippedPrimitive point(int64_t id, uint32_t draw, float x, float y) {
  ClippedPrimitive p = primitive(PrimitiveKind::point, id, draw);
  p.v[0].x = x;
  p.v[0].y = y;
  p.v[0].z = 0.5f;
  return p;
}

int64_t floor_div(int64_t a, int64_t b) {  // b > 0
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// ---------------------------------------------------------------------------
// The spec's rules, by brute force.

// Diamond exit, the integer form of section 8b, for snapped end points and
// width w, on a W x H framebuffer. Per major column: every row is tried for
// the offset line's width-1 band pixel C; the column produces iff C passes
// the end test; the fragment becomes w pixels.
std::set<std::pair<int, int>> diamond_exit(int64_t xa, int64_t ya, int64_t xb, int64_t yb, int w,
                                           int W, int H) {
  std::set<std::pair<int, int>> px;
  const int64_t dx = xb - xa, dy = yb - ya;
  if (dx == 0 && dy == 0) return px;
  const bool xmaj = std::llabs(dx) >= std::llabs(dy);
  const int64_t off = -128 * (w - 1);
  // Offset end points.
  const int64_t oxa = xmaj ? xa : xa + off, oya = xmaj ? ya + off : ya;
  const int64_t oxb = xmaj ? xb : xb + off, oyb = xmaj ? yb + off : yb;
  const auto in_diamond = [](int64_t px_, int64_t py_, int64_t cx, int64_t cy) {
    const int64_t u = px_ - cx, v = py_ - cy, d = std::llabs(u) + std::llabs(v);
    return d < 128 || (d == 128 && u > 0);
  };
  const int major_n = xmaj ? W : H, minor_n = xmaj ? H : W;
  for (int m = -2; m < major_n + 2; ++m) {
    for (int nn = -300; nn < minor_n + 300; ++nn) {
      const int64_t cx = 256 * (xmaj ? m : nn) + 128, cy = 256 * (xmaj ? nn : m) + 128;
      bool band;
      if (xmaj) {
        const int64_t s = dx > 0 ? 1 : -1;
        const int64_t sd = s * ((cy - oya) * dx - (cx - oxa) * dy), h = 128 * std::llabs(dx);
        band = (sd > -h && sd < h) || (sd == -h && dx * dy <= 0) || (sd == h && dx * dy > 0);
      } else {
        const int64_t s = dy > 0 ? 1 : -1;
        const int64_t sd = s * ((cx - oxa) * dy - (cy - oya) * dx), h = 128 * std::llabs(dy);
        band = (sd > -h && sd < h) || sd == -h;
      }
      if (!band) continue;
      const int64_t cm = xmaj ? cx : cy, ma = xmaj ? oxa : oya, mb = xmaj ? oxb : oyb;
      const bool a_in = in_diamond(oxa, oya, cx, cy), b_in = in_diamond(oxb, oyb, cx, cy);
      const bool plus = (xmaj ? dx : dy) > 0;
      const bool ok = plus ? (ma <= cm || a_in) && (mb > cm && !b_in)
                           : (ma > cm || a_in) && (mb <= cm && !b_in);
      if (!ok) continue;
      for (int k = 0; k < w; ++k) {
        const int x = xmaj ? m : nn + k, y = xmaj ? nn + k : m;
        if (x >= 0 && x < W && y >= 0 && y < H) px.insert({x, y});
      }
    }
  }
  return px;
}

// Bresenham by section 8b's closed formula.
std::set<std::pair<int, int>> bresenham(int64_t xa, int64_t ya, int64_t xb, int64_t yb, int w,
                                        bool first, bool last, int W, int H) {
  std::set<std::pair<int, int>> px;
  const int64_t ax = floor_div(xa, 256), ay = floor_div(ya, 256);
  const int64_t bx = floor_div(xb, 256), by = floor_div(yb, 256);
  const int64_t ddx = bx - ax, ddy = by - ay;
  const bool xmaj = std::llabs(ddx) >= std::llabs(ddy);
  const int64_t M = std::max(std::llabs(ddx), std::llabs(ddy));
  const int64_t big = xmaj ? std::llabs(ddx) : std::llabs(ddy);
  const int64_t small = xmaj ? std::llabs(ddy) : std::llabs(ddx);
  const auto sgn = [](int64_t v) { return v < 0 ? -1 : v > 0 ? 1 : 0; };
  for (int64_t i = 0; i <= M; ++i) {
    const bool drawn = M == 0 ? first && last : (i > 0 || first) && (i < M || last);
    if (!drawn) continue;
    int64_t k = 0;
    if (big > 0) {
      const double q = static_cast<double>(2 * i * small - big) / static_cast<double>(2 * big);
      k = static_cast<int64_t>(std::ceil(q));  // exact: numerator and denominator < 2^40
    }
    const int64_t x = xmaj ? ax + i * sgn(ddx) : ax + sgn(ddx) * k;
    const int64_t y = xmaj ? ay + sgn(ddy) * k : ay + i * sgn(ddy);
    for (int64_t j = 0; j < w; ++j) {
      const int64_t rx = xmaj ? x : x - (w - 1) / 2 + j;
      const int64_t ry = xmaj ? y - (w - 1) / 2 + j : y;
      if (rx >= 0 && rx < W && ry >= 0 && ry < H)
        px.insert({static_cast<int>(rx), static_cast<int>(ry)});
    }
  }
  return px;
}

std::set<std::pair<int, int>> keys(const std::map<std::pair<int, int>, int>& m) {
  std::set<std::pair<int, int>> s;
  for (const auto& [p, n] : m) s.insert(p);
  return s;
}

int max_count(const std::map<std::pair<int, int>, int>& m) {
  int c = 0;
  for (const auto& [p, n] : m) c = std::max(c, n);
  return c;
}

// A subpixel coordinate from a list of awkward offsets (pixel centres,
// diamond vertices, edges, near misses) or at random.
int64_t coordinate(Rng& r, int pixels) {
  static const std::array<int64_t, 8> frac{0, 128, 64, 192, 1, 127, 129, 255};
  const int64_t base = r.range(-3, pixels + 2) * 256;
  return r.range(0, 2) == 0 ? base + r.range(0, 255) : base + frac[r.range(0, 7)];
}

float sub(int64_t X) {
  return static_cast<float>(X) / 256.0f;
}

struct LineCase {
  int64_t xa, ya, xb, yb;
  int w;
  bool first, last;
};

std::vector<LineCase> random_lines(uint64_t seed, int W, int H, size_t n) {
  Rng r{seed};
  std::vector<LineCase> v;
  // Hand-picked: every octant of a short line, axis-aligned and 45 degree
  // lines through pixel centres and along diamond edges.
  const std::array<std::array<int64_t, 2>, 8> dirs{
      {{5, 2}, {2, 5}, {-2, 5}, {-5, 2}, {-5, -2}, {-2, -5}, {2, -5}, {5, -2}}};
  for (const auto& d : dirs) {
    v.push_back({10 * 256 + 128, 10 * 256 + 128, (10 + d[0]) * 256 + 128, (10 + d[1]) * 256 + 128,
                 1, true, true});
  }
  v.push_back({2 * 256 + 128, 5 * 256 + 128, 20 * 256 + 128, 5 * 256 + 128, 1, true, true});
  v.push_back({5 * 256, 3 * 256, 5 * 256, 20 * 256, 1, true, true});
  v.push_back({3 * 256, 3 * 256, 20 * 256, 20 * 256, 1, true, true});
  v.push_back({3 * 256 + 128, 3 * 256, 20 * 256 + 128, 20 * 256, 1, true, true});
  v.push_back({20 * 256, 3 * 256 + 128, 3 * 256, 20 * 256 + 128, 2, true, true});
  // Long lines from far outside (up to the guard band, 2^15 pixels) across
  // the framebuffer: only their middle is walked.
  for (int i = 0; i < 12; ++i) {
    const int64_t far = 256 * 30000;
    const int64_t ya = r.range(-far, far), yb = r.range(-far, far) / 4000;
    if (i % 2 == 0) {
      v.push_back({-far + r.range(0, 255), (H / 2) * 256 + yb, far, ya / 3000 + 256 * (H / 2),
                   static_cast<int>(1 + i % 3), true, true});
    } else {
      v.push_back({(W / 2) * 256 + yb, -far, ya / 3000 + 256 * (W / 2), far - r.range(0, 255),
                   static_cast<int>(1 + i % 3), true, true});
    }
  }
  while (v.size() < n) {
    LineCase c{coordinate(r, W), coordinate(r, H), 0, 0, 1, true, true};
    if (r.range(0, 3) == 0) {  // short
      c.xb = c.xa + r.range(-700, 700);
      c.yb = c.ya + r.range(-700, 700);
    } else {
      c.xb = coordinate(r, W);
      c.yb = coordinate(r, H);
    }
    c.w = static_cast<int>(r.range(0, 3) == 0 ? r.range(2, 7) : 1);
    c.first = r.range(0, 3) != 0;
    c.last = r.range(0, 3) != 0;
    v.push_back(c);
  }
  return v;
}

std::vector<RenderState> width_states(LineRasterization rule) {
  std::vector<RenderState> s;
  for (int w = 1; w <= 7; ++w) {
    RenderState st;
    st.line_rasterization = rule;
    st.line_width = static_cast<float>(w);
    s.push_back(st);
  }
  return s;
}

std::vector<ClippedPrimitive> tokens_for(const std::vector<LineCase>& cases) {
  std::vector<ClippedPrimitive> t;
  for (size_t i = 0; i < cases.size(); ++i) {
    const LineCase& c = cases[i];
    t.push_back(line(static_cast<int64_t>(i), static_cast<uint32_t>(c.w - 1), sub(c.xa), sub(c.ya),
                     sub(c.xb), sub(c.yb), c.first, c.last));
  }
  return t;
}

GpuConfig config_with(unsigned units, unsigned tile, unsigned sw, unsigned sh) {
  GpuConfig c = GpuConfig::baseline();
  c.units = units;
  c.tile_size = tile;
  c.stamp = {sw, sh};
  c.fifo_depth = 4;
  return c;
}

// ---------------------------------------------------------------------------

// Setup's parallelogram (two band edges, a box from the end tests) and the
// tile walk give exactly the pixels of the spec's integer form, each once,
// whatever the units, tiles and stamps; and every stamp carries the
// interpolation function T = (px - Xa) dx + (py - Ya) dy at its origin.
TEST(Lines, DiamondExitEqualsIntegerForm) {
  const int W = 40, H = 33;
  const std::vector<LineCase> cases = random_lines(7, W, H, 260);
  const FrameState frame = frame_with(W, H, width_states(LineRasterization::diamond_exit));
  const std::array<GpuConfig, 3> configs{config_with(1, 8, 2, 2), config_with(2, 16, 4, 4),
                                         config_with(4, 8, 8, 8)};
  std::vector<std::unique_ptr<RasterBench>> benches;
  for (size_t c = 0; c < configs.size(); ++c) {
    benches.push_back(
        std::make_unique<RasterBench>("de" + std::to_string(c), configs[c], frame, false));
    benches.back()->feed(tokens_for(cases));
  }
  sc_core::sc_start();

  size_t degenerate = 0, drawn = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const LineCase& c = cases[i];
    if (c.xa == c.xb && c.ya == c.yb) ++degenerate;
    const auto want = diamond_exit(c.xa, c.ya, c.xb, c.yb, c.w, W, H);
    if (!want.empty()) ++drawn;
    for (const auto& b : benches) {
      const auto got = b->pixels(static_cast<int64_t>(i));
      EXPECT_EQ(keys(got), want) << "line " << i << " (" << c.xa << ", " << c.ya << ") - (" << c.xb
                                 << ", " << c.yb << ") w " << c.w << " units " << b->config.units;
      EXPECT_LE(max_count(got), 1) << "line " << i;
    }
  }
  EXPECT_GT(drawn, 150u);  // the cases exercise the rule
  for (const auto& b : benches) {
    EXPECT_EQ(counter(b->setup.stats(), "lines_degenerate"), degenerate);
    EXPECT_EQ(counter(b->setup.stats(), "lines_rasterized"), cases.size() - degenerate);
    for (const auto& unit : b->out) {
      for (const StampBatch& batch : unit) {
        const RasterPrimitive& t = *batch.primitive;
        const int64_t dx = int64_t{t.x[1]} - t.x[0], dy = int64_t{t.y[1]} - t.y[0];
        EXPECT_EQ(t.area2, dx * dx + dy * dy);
        for (const Stamp& s : batch.stamps) {
          const int64_t T =
              (256 * int64_t{s.x} + 128 - t.x[0]) * dx + (256 * int64_t{s.y} + 128 - t.y[0]) * dy;
          EXPECT_EQ(s.e[1], T);
          EXPECT_EQ(s.e[0], t.area2 - T);
          EXPECT_EQ(s.e[2], 0);
        }
      }
    }
  }
}

// The line walker in 1, 2 and 4 units (different tiles and stamps) gives
// the pixels of the closed formula, each once, end flags and widths included.
TEST(Lines, BresenhamWalkerEqualsClosedFormAcrossUnits) {
  const int W = 70, H = 45;
  const std::vector<LineCase> cases = random_lines(11, W, H, 300);
  const FrameState frame = frame_with(W, H, width_states(LineRasterization::bresenham));
  const std::array<GpuConfig, 4> configs{config_with(1, 16, 4, 4), config_with(2, 8, 2, 2),
                                         config_with(4, 8, 4, 2), config_with(3, 16, 8, 8)};
  std::vector<std::unique_ptr<RasterBench>> benches;
  for (size_t c = 0; c < configs.size(); ++c) {
    benches.push_back(
        std::make_unique<RasterBench>("br" + std::to_string(c), configs[c], frame, false));
    benches.back()->feed(tokens_for(cases));
  }
  sc_core::sc_start();
  size_t drawn = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const LineCase& c = cases[i];
    const auto want = bresenham(c.xa, c.ya, c.xb, c.yb, c.w, c.first, c.last, W, H);
    if (!want.empty()) ++drawn;
    for (const auto& b : benches) {
      const auto got = b->pixels(static_cast<int64_t>(i));
      EXPECT_EQ(keys(got), want) << "line " << i << " (" << c.xa << ", " << c.ya << ") - (" << c.xb
                                 << ", " << c.yb << ") w " << c.w << " ends " << c.first << c.last
                                 << " units " << b->config.units;
      EXPECT_LE(max_count(got), 1) << "line " << i;
    }
  }
  EXPECT_GT(drawn, 150u);
  for (const auto& b : benches) {
    EXPECT_EQ(counter(b->setup.stats(), "lines_rasterized"), cases.size());
    EXPECT_EQ(counter(b->setup.stats(), "lines_degenerate"), 0u);
  }
}

// Points of sizes 1 to 12 in quarter steps at random positions: the pixels
// of section 8c's inequalities, each once, interpolation E0 = 1, area2 = 1.
TEST(Points, SquareEqualsSpecInequalities) {
  const int W = 37, H = 29;
  std::vector<RenderState> states;
  for (int q = 1; q <= 48; ++q) {
    RenderState st;
    st.point_size = 0.25f * static_cast<float>(q);
    states.push_back(st);
  }
  const FrameState frame = frame_with(W, H, states);
  Rng r{5};
  std::vector<ClippedPrimitive> tokens;
  for (int i = 0; i < 300; ++i) {
    const float x = static_cast<float>(r.range(-4 * 64, (W + 4) * 64)) / 64.0f;
    const float y = static_cast<float>(r.range(-4 * 64, (H + 4) * 64)) / 64.0f;
    tokens.push_back(point(i, static_cast<uint32_t>(r.range(0, 47)), x, y));
  }
  RasterBench b("pt", config_with(3, 8, 4, 2), frame, false);
  b.feed(tokens);
  sc_core::sc_start();
  for (const ClippedPrimitive& p : tokens) {
    const float size = states[p.draw_id].point_size;
    const int64_t F = std::max<int64_t>(256, std::lround(size * 256.0f));
    const int64_t X0 = std::lround((p.v[0].x - 0.5f) * 256.0f) - F / 2;
    const int64_t Y0 = std::lround((p.v[0].y - 0.5f) * 256.0f) - F / 2;
    std::set<std::pair<int, int>> want;
    for (int y = 0; y < H; ++y) {
      for (int x = 0; x < W; ++x) {
        if (X0 <= 256 * x && 256 * x < X0 + F && Y0 <= 256 * y && 256 * y < Y0 + F)
          want.insert({x, y});
      }
    }
    const auto got = b.pixels(p.primitive_id);
    EXPECT_EQ(keys(got), want) << "point " << p.primitive_id << " size " << size;
    EXPECT_LE(max_count(got), 1);
  }
  EXPECT_EQ(counter(b.setup.stats(), "points_rasterized"), tokens.size());
  for (const auto& unit : b.out) {
    for (const StampBatch& batch : unit) {
      EXPECT_EQ(batch.primitive->area2, 1);
      for (const Stamp& s : batch.stamps) EXPECT_EQ(s.e, (std::array<EdgeValue, 3>{1, 0, 0}));
    }
  }
}

// ---------------------------------------------------------------------------
// Cycles (stages/tile_rasterizer.h): tile 16, stamp 4x4, ii(tile_rasterizer)
// = 1 by default.

// A horizontal diamond-exit line from (2, 5.25) to (42, 5.25) covers x = 2
// .. 41 of row 5 (the row whose centre 5.5 is within half a pixel; column 1's
// diamond is not reached, column 41's is left at x = 41.75 < 42, and 42's
// centre is not before the end): 40 fragments. Its box is x 2..41, y 5: one
// unit walks tiles (0, 0), (1, 0), (2, 0), partial each (the band cuts them),
// and evaluates the stamps meeting the box: x 0-15 (4), 16-31 (4), 32-43 (3).
// Busy: 3 tile tests + 11 stamps = 14 cycles; 3 batches.
TEST(LineTiming, HorizontalDiamondExitOneUnit) {
  GpuConfig cfg = config_with(1, 16, 4, 4);
  RasterBench b("h", cfg, frame_with(64, 64, {RenderState{}}), false);
  b.feed({line(0, 0, 2.0f, 5.25f, 42.0f, 5.25f)});
  sc_core::sc_start();
  const StatGroup& r = b.units[0]->stats();
  EXPECT_EQ(counter(r, "fragments"), 40u);
  EXPECT_EQ(counter(r, "tiles_visited"), 3u);
  EXPECT_EQ(counter(r, "stamps_evaluated"), 11u);
  EXPECT_EQ(counter(r, "busy_cycles"), 14u);
  EXPECT_EQ(b.out[0].size(), 3u);
  EXPECT_EQ(counter(r, "lines"), 1u);
  EXPECT_EQ(counter(r, "triangles"), 0u);
}

// The same line with Bresenham: end pixels (2, 5) and (42, 5), 41 steps,
// both ends drawn: 41 fragments. Walker: 1 cycle to enter, 3 spans (tile
// columns 0, 1, 2: steps x 2-15, 16-31, 32-42) at 1 cycle each, 41 steps at
// 1 cycle, 11 stamps (x 0-43) at ii = 1: 56 cycles. Without its last pixel
// (a strip's line): 40 fragments, the walk stops at x = 41: 1 + 3 + 40 +
// 11 stamps (x 41 is still in stamp 40-43) = 55.
TEST(LineTiming, HorizontalBresenhamOneUnit) {
  GpuConfig cfg = config_with(1, 16, 4, 4);
  RenderState st;
  st.line_rasterization = LineRasterization::bresenham;
  RasterBench b("hb", cfg, frame_with(64, 64, {st}), false);
  b.feed({line(0, 0, 2.0f, 5.25f, 42.0f, 5.25f)});
  sc_core::sc_start();
  const StatGroup& r = b.units[0]->stats();
  EXPECT_EQ(counter(r, "fragments"), 41u);
  EXPECT_EQ(counter(r, "line_steps"), 41u);
  EXPECT_EQ(counter(r, "line_spans"), 3u);
  EXPECT_EQ(counter(r, "stamps_emitted"), 11u);
  EXPECT_EQ(counter(r, "busy_cycles"), 56u);
  EXPECT_EQ(b.out[0].size(), 3u);
}

TEST(LineTiming, HorizontalBresenhamWithoutLastPixel) {
  GpuConfig cfg = config_with(1, 16, 4, 4);
  RenderState st;
  st.line_rasterization = LineRasterization::bresenham;
  RasterBench b("hb2", cfg, frame_with(64, 64, {st}), false);
  b.feed({line(0, 0, 2.0f, 5.25f, 42.0f, 5.25f, true, false)});
  sc_core::sc_start();
  const StatGroup& r = b.units[0]->stats();
  EXPECT_EQ(counter(r, "fragments"), 40u);
  EXPECT_EQ(counter(r, "busy_cycles"), 55u);
}

// A vertical diamond-exit line from (5.25, 2) to (5.25, 42): y-major, column
// 5, rows 2 .. 41 (40 fragments) across tiles (0, 0), (0, 1), (0, 2). Two
// units: tiles 0 and 2 are unit 0's, tile 1 unit 1's. Unit 0: 2 tile tests,
// stamps rows 0-15 (4) and 32-43 (3): 9 cycles, 14 + 10 fragments; unit 1:
// 1 + 4 = 5 cycles, 16 fragments. The distributor sends it to both (2
// cycles).
TEST(LineTiming, VerticalDiamondExitAcrossTilesTwoUnits) {
  GpuConfig cfg = config_with(2, 16, 4, 4);
  RasterBench b("v", cfg, frame_with(64, 64, {RenderState{}}), false);
  b.feed({line(0, 0, 5.25f, 2.0f, 5.25f, 42.0f)});
  sc_core::sc_start();
  EXPECT_EQ(counter(b.units[0]->stats(), "fragments"), 24u);
  EXPECT_EQ(counter(b.units[0]->stats(), "busy_cycles"), 9u);
  EXPECT_EQ(counter(b.units[1]->stats(), "fragments"), 16u);
  EXPECT_EQ(counter(b.units[1]->stats(), "busy_cycles"), 5u);
  EXPECT_EQ(counter(b.distributor.stats(), "busy_cycles"), 2u);
  std::set<std::pair<int, int>> want;
  for (int y = 2; y <= 41; ++y) want.insert({5, y});
  EXPECT_EQ(keys(b.pixels(0)), want);
}

// A Bresenham vertical line x = 5, rows 2 .. 42, in 2 units: spans are tile
// rows. Unit 0 owns tiles (0, 0) and (0, 2), unit 1 (0, 1). Unit 0: enter
// 1, spans 3 (one jumped, unit 1's), steps 14 + 11 = 25, stamps 4 + 3 = 7:
// 36 cycles. Unit 1: enter 1, spans 3 (two jumped), steps 16, stamps 4: 24.
TEST(LineTiming, VerticalBresenhamSkipsOtherUnitsSpans) {
  GpuConfig cfg = config_with(2, 16, 4, 4);
  RenderState st;
  st.line_rasterization = LineRasterization::bresenham;
  RasterBench b("vb", cfg, frame_with(64, 64, {st}), false);
  b.feed({line(0, 0, 5.25f, 2.0f, 5.25f, 42.0f)});
  sc_core::sc_start();
  EXPECT_EQ(counter(b.units[0]->stats(), "line_spans_skipped"), 1u);
  EXPECT_EQ(counter(b.units[0]->stats(), "busy_cycles"), 36u);
  EXPECT_EQ(counter(b.units[1]->stats(), "line_spans_skipped"), 2u);
  EXPECT_EQ(counter(b.units[1]->stats(), "busy_cycles"), 24u);
  EXPECT_EQ(counter(b.units[0]->stats(), "fragments") + counter(b.units[1]->stats(), "fragments"),
            41u);
}

// A point of size 8 at (20, 20): F = 2048, X0 = Y0 = 4992 - 1024 = 3968
// (15.5 pixels), so x, y in 16 .. 23: 64 fragments, all in tile (1, 1). The
// box is the square: the tile is accepted (no coverage edge) and its 4
// stamps are emitted without tests: 1 + 4 = 5 cycles. Setup: ii = 4.
TEST(PointTiming, SixtyFourPixelPoint) {
  GpuConfig cfg = config_with(1, 16, 4, 4);
  RenderState st;
  st.point_size = 8.0f;
  RasterBench b("p", cfg, frame_with(64, 64, {st}), false);
  b.feed({point(0, 0, 20.0f, 20.0f)});
  sc_core::sc_start();
  const StatGroup& r = b.units[0]->stats();
  EXPECT_EQ(counter(r, "fragments"), 64u);
  EXPECT_EQ(counter(r, "tiles_accepted"), 1u);
  EXPECT_EQ(counter(r, "stamps_accepted"), 4u);
  EXPECT_EQ(counter(r, "busy_cycles"), 5u);
  EXPECT_EQ(counter(r, "points"), 1u);
  EXPECT_EQ(counter(b.setup.stats(), "busy_cycles"), 4u);
  const auto got = b.pixels(0);
  ASSERT_EQ(got.size(), 64u);
  EXPECT_EQ(got.begin()->first, std::make_pair(16, 16));
  EXPECT_EQ(got.rbegin()->first, std::make_pair(23, 23));
}

// ---------------------------------------------------------------------------
// The back end: setup -> distributor -> one unit's rasterizer -> depth test
// -> interpolator. Depth (float32, func always, so every fragment's z is
// computed, reported through the fragment probe) and colour per pixel
// against section 9's formulas written out here: a line as the triangle
// (a, b, a) with E0 = L2 - T, E1 = T, E2 = 0; a point its vertex's z and
// flat colour, also with smooth shading.

struct DepthRecorder : FragmentProbe {
  std::map<std::pair<int, int>, float> depth;
  void depth_tested(unsigned, const DepthFragment& f) override { depth[{f.x, f.y}] = f.depth; }
  void rop_wrote(unsigned, const RopFragment&) override {}
};

struct BackBench {
  GpuConfig config = GpuConfig::baseline();
  FrameState frame;
  Memory memory;
  Fifo<ClippedPrimitive> input;
  PrimitiveSetup setup;
  Fifo<SetupPacket> setup_out;
  TileDistributor distributor;
  Fifo<SetupPacket> jobs;
  TileRasterizer rasterizer;
  Fifo<StampBatch> stamps;
  DepthTest depth;
  Fifo<StampBatch> visible;
  Interpolator interpolator;
  Fifo<ShadedStampBatch> shaded;
  DepthRecorder probe;
  std::map<std::pair<int, int>, glm::vec4> color;

  static uint64_t memory_size(const FrameState& f) {
    return f.depth_address + uint64_t{4} * f.framebuffer.width * f.framebuffer.height + 64;
  }

  BackBench(const GpuConfig& c, const FrameState& f)
      : config(c),
        frame(f),
        memory("bb_memory", memory_size(frame), 20, 32, config.cycle()),
        input("bb_input", 4),
        setup("bb_setup", config, frame),
        setup_out("bb_setup_out", 4),
        distributor("bb_distributor", config, frame),
        jobs("bb_jobs", 4),
        rasterizer("bb_rasterizer", config, frame, 0),
        stamps("bb_stamps", 4),
        depth("bb_depth", config, frame, 0),
        visible("bb_visible", 4),
        interpolator("bb_interpolator", config, frame, 0),
        shaded("bb_shaded", 4) {
    setup.in(input);
    setup.out(setup_out);
    distributor.in(setup_out);
    distributor.out[0](jobs);
    rasterizer.in(jobs);
    rasterizer.out(stamps);
    depth.in(stamps);
    depth.out(visible);
    depth.mem.bind(memory);
    depth.set_fragment_probe(&probe);
    interpolator.in(visible);
    interpolator.out(shaded);
    sc_core::sc_spawn([this] {
      const int sw = static_cast<int>(config.stamp[0]);
      for (;;) {
        const ShadedStampBatch b = shaded.read();
        size_t n = 0;
        for (const Stamp& s : b.stamps) {
          for (int bit = 0; bit < 64; ++bit) {
            if (s.mask >> bit & 1) color[{s.x + bit % sw, s.y + bit / sw}] = b.colors.at(n++);
          }
        }
      }
    });
  }
};

// It reads the depth test's fragment probe: a build without trace hooks
// (GPUSIM_TRACE_HOOKS=0) has no probe, and no such test rather than a
// skipped one.
#if GPUSIM_TRACE_HOOKS
TEST(LinesBackEnd, DepthAndColourFollowTheLineParameter) {
  const int W = 48, H = 40;
  FrameState f = frame_with(W, H, {});
  f.framebuffer.depth_format = DepthFormat::float32;
  f.depth_address = uint64_t{4} * W * H;
  for (LineRasterization rule : {LineRasterization::diamond_exit, LineRasterization::bresenham}) {
    DrawState d;
    d.state.depth_func = CompareFunc::always;
    d.state.line_rasterization = rule;
    d.state.line_width = 2.0f;
    d.state.point_size = 3.0f;
    f.draws.push_back(d);
  }
  // Perspective: 1/w differs at the ends; colours over w.
  const auto make = [](int64_t id, uint32_t draw, float xa, float ya, float xb, float yb) {
    ClippedPrimitive p = line(id, draw, xa, ya, xb, yb);
    p.v[0].z = 0.2f;
    p.v[1].z = 0.9f;
    p.v[0].inv_w = 1.0f;
    p.v[1].inv_w = 0.25f;
    const std::array<glm::vec4, 2> c{glm::vec4(1.0f, 0.0f, 0.5f, 1.0f),
                                     glm::vec4(0.0f, 1.0f, 0.25f, 0.5f)};
    for (int v = 0; v < 2; ++v) {
      for (int k = 0; k < 4; ++k) p.v[v].varyings_over_w[k] = c[v][k] * p.v[v].inv_w;
    }
    return p;
  };
  // Separate lines (no pixel shared), one per rule, and a point.
  std::vector<ClippedPrimitive> tokens{make(0, 0, 1.3f, 2.7f, 45.1f, 17.2f),
                                       make(1, 1, 3.6f, 38.2f, 20.9f, 22.4f)};
  ClippedPrimitive pt = point(2, 0, 40.25f, 33.5f);
  pt.v[0].z = 0.375f;
  pt.v[0].varyings_over_w = {0.9f, 0.9f, 0.9f, 0.9f};  // not what the point shows
  pt.flat_varyings = {0.125f, 0.25f, 0.5f, 1.0f};
  tokens.push_back(pt);

  BackBench b(config_with(1, 16, 4, 4), f);
  sc_core::sc_spawn([&b, tokens] {
    for (const ClippedPrimitive& t : tokens) b.input.write(t);
  });
  sc_core::sc_start();

  size_t line_pixels = 0, point_pixels = 0;
  for (const ClippedPrimitive& p : tokens) {
    std::set<std::pair<int, int>> pixels;
    if (p.primitive_kind == PrimitiveKind::point) {
      // Size 3 at (40.25, 33.5): F = 768, X0 = 10176 - 384 = 9792 (38.25
      // pixels), Y0 = 8448 - 384 = 8064 (31.5): 256 x in [9792, 10560),
      // x 39 .. 41; 256 y in [8064, 8832), y 32 .. 34.
      for (int y = 32; y <= 34; ++y) {
        for (int x = 39; x <= 41; ++x) pixels.insert({x, y});
      }
      for (const auto& px : pixels) {
        ASSERT_TRUE(b.probe.depth.count(px)) << px.first << ", " << px.second;
        EXPECT_EQ(b.probe.depth.at(px), 0.375f);
        EXPECT_EQ(b.color.at(px), glm::vec4(0.125f, 0.25f, 0.5f, 1.0f));
        ++point_pixels;
      }
      continue;
    }
    const int64_t xa = snap_to_subpixel(p.v[0].x), ya = snap_to_subpixel(p.v[0].y);
    const int64_t xb = snap_to_subpixel(p.v[1].x), yb = snap_to_subpixel(p.v[1].y);
    pixels = p.draw_id == 0 ? diamond_exit(xa, ya, xb, yb, 2, W, H)
                            : bresenham(xa, ya, xb, yb, 2, true, true, W, H);
    ASSERT_GT(pixels.size(), 20u);
    const int64_t dx = xb - xa, dy = yb - ya, l2 = dx * dx + dy * dy;
    for (const auto& px : pixels) {
      const int64_t T =
          (256 * int64_t{px.first} + 128 - xa) * dx + (256 * int64_t{px.second} + 128 - ya) * dy;
      const float f0 = static_cast<float>(l2 - T), f1 = static_cast<float>(T), f2 = 0.0f;
      const float A = static_cast<float>(l2);
      const float za = p.v[0].z, zb = p.v[1].z;
      const float d1 = zb - za, d2 = za - za;
      const float z = za + (f1 * d1 + f2 * d2) / A;
      ASSERT_TRUE(b.probe.depth.count(px)) << px.first << ", " << px.second;
      EXPECT_EQ(b.probe.depth.at(px), clamp01(z)) << px.first << ", " << px.second;
      const float qa = p.v[0].inv_w, qb = p.v[1].inv_w;
      const float den = f0 * qa + f1 * qb + f2 * qa;
      glm::vec4 want;
      for (int k = 0; k < 4; ++k) {
        const float ca = p.v[0].varyings_over_w[k], cb = p.v[1].varyings_over_w[k];
        want[k] = clamp01((f0 * ca + f1 * cb + f2 * ca) / den);
      }
      EXPECT_EQ(b.color.at(px), want) << px.first << ", " << px.second;
      ++line_pixels;
    }
  }
  EXPECT_EQ(b.probe.depth.size(), line_pixels + point_pixels);
  EXPECT_EQ(b.color.size(), line_pixels + point_pixels);
  EXPECT_EQ(point_pixels, 9u);
}
#endif  // GPUSIM_TRACE_HOOKS

}  // namespace
}  // namespace gpusim
