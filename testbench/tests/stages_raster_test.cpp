// The raster core as a chain: PrimitiveSetup -> TileDistributor -> N
// TileRasterizers (testbench/tests/raster_bench.h), with triangles; lines and
// points are in stages_lines_test.cpp, primitive setup's own tests in
// stages_primitive_setup_test.cpp.
//
// Expected values come from the golden model's free functions (snapped
// vertices, signed_area2, edge_function, edge_owns_boundary) applied per
// pixel, from golden::render() of whole scenes (counts, last writer, depth
// bits), or from hand derivations written out in the comments. Costs are
// checked against the documented formulas evaluated by brute force (every
// pixel centre of every tile classified one by one), not by re-running the
// stages' algorithms. A SystemC model elaborates once per process: ctest runs
// each TEST (and each parameter instance) alone; several independent
// testbenches may share one sc_start().
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "hw/fifo.h"
#include "hw/fixed_point.h"
#include "hw/pixel_formats.h"
#include "stages/primitive_setup.h"
#include "stages/tile_distributor.h"
#include "stages/tile_rasterizer.h"
#include "testbench/golden/golden_model.h"
#include "testbench/tests/raster_bench.h"

namespace gpusim {
namespace {

using namespace test;

using golden::WindowVertex;

// splitmix64: the same sequence with every standard library.
struct Rng {
  uint64_t s;
  uint64_t next() {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  int64_t range(int64_t lo, int64_t hi) {  // inclusive
    return lo + static_cast<int64_t>(next() % static_cast<uint64_t>(hi - lo + 1));
  }
  bool coin() { return next() & 1; }
};

// ---------------------------------------------------------------------------
// Expectations from the golden rules.

enum class Fate { degenerate, culled, rasterized };

struct Expect {
  Fate fate = Fate::rasterized;
  std::array<WindowVertex, 3> v;     // counter-clockwise, snapped
  std::array<int, 3> from{0, 1, 2};  // source vertex of each CCW vertex
  EdgeValue area2 = 0;
  std::array<EdgeValue, 3> bias{};
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
  std::vector<uint32_t> pixels;  // covered, index y * W + x, ascending
  bool has_offset = false;

  bool box_empty() const { return x0 > x1 || y0 > y1; }
  EdgeValue e(int k, int64_t px, int64_t py) const {
    return golden::edge_function(v[(k + 1) % 3], v[(k + 2) % 3], static_cast<Subpixel>(px),
                                 static_cast<Subpixel>(py));
  }
  bool covers(int64_t px, int64_t py) const {
    for (int k = 0; k < 3; ++k) {
      if (e(k, px, py) - bias[k] < 0) return false;
    }
    return true;
  }
};

Expect expect_for(const ClippedPrimitive& t, const RenderState& st, int W, int H) {
  Expect x;
  std::array<WindowVertex, 3> w;
  for (int i = 0; i < 3; ++i) {
    w[i].x = snap_to_subpixel(t.v[i].x);
    w[i].y = snap_to_subpixel(t.v[i].y);
  }
  const EdgeValue area2 = golden::signed_area2(w[0], w[1], w[2]);
  if (area2 == 0) {
    x.fate = Fate::degenerate;
    return x;
  }
  const bool ccw = area2 > 0;
  const bool front = (st.front_face == FrontFace::ccw) == ccw;
  if ((st.cull == CullMode::back && !front) || (st.cull == CullMode::front && front)) {
    x.fate = Fate::culled;
    return x;
  }
  if (!ccw) x.from = {0, 2, 1};
  for (int i = 0; i < 3; ++i) x.v[i] = w[x.from[i]];
  x.area2 = ccw ? area2 : -area2;
  for (int k = 0; k < 3; ++k) {
    x.bias[k] = golden::edge_owns_boundary(x.v[(k + 1) % 3], x.v[(k + 2) % 3]) ? 0 : 1;
  }
  x.has_offset = st.offset_factor != 0.0f || st.offset_units != 0.0f;
  // Pixel centres (256 i + 128) within the vertices' box, clamped (spec 8).
  double lo_x = 1e18, hi_x = -1e18, lo_y = 1e18, hi_y = -1e18;
  for (const WindowVertex& p : x.v) {
    lo_x = std::min(lo_x, double(p.x)), hi_x = std::max(hi_x, double(p.x));
    lo_y = std::min(lo_y, double(p.y)), hi_y = std::max(hi_y, double(p.y));
  }
  x.x0 = std::max(0, static_cast<int>(std::ceil((lo_x - 128) / 256)));
  x.x1 = std::min(W - 1, static_cast<int>(std::floor((hi_x - 128) / 256)));
  x.y0 = std::max(0, static_cast<int>(std::ceil((lo_y - 128) / 256)));
  x.y1 = std::min(H - 1, static_cast<int>(std::floor((hi_y - 128) / 256)));
  for (int py = x.y0; py <= x.y1; ++py) {
    for (int px = x.x0; px <= x.x1; ++px) {
      if (x.covers(int64_t{px} * 256 + 128, int64_t{py} * 256 + 128)) {
        x.pixels.push_back(static_cast<uint32_t>(py * W + px));
      }
    }
  }
  return x;
}

// The documented rasterizer cost of one triangle on one unit, by brute force:
// a tile is rejected when some edge fails at every pixel centre of the tile,
// accepted when every centre is covered; stamps are those of the tile that
// intersect the box.
struct UnitWork {
  uint64_t tiles = 0, rejected = 0, accepted = 0, stamps_evaluated = 0, stamps_accepted = 0;
  uint64_t cycles(unsigned ii) const { return tiles + ii * (stamps_evaluated + stamps_accepted); }
};

UnitWork unit_work(const Expect& x, const GpuConfig& c, unsigned unit) {
  UnitWork w;
  if (x.fate != Fate::rasterized || x.box_empty()) return w;
  const int ts = static_cast<int>(c.tile_size);
  const int sw = static_cast<int>(c.stamp[0]), sh = static_cast<int>(c.stamp[1]);
  for (int ty = x.y0 / ts; ty <= x.y1 / ts; ++ty) {
    for (int tx = x.x0 / ts; tx <= x.x1 / ts; ++tx) {
      if (tile_owner(tx, ty, c.units) != unit) continue;
      ++w.tiles;
      std::array<bool, 3> passes_somewhere{};
      bool all_covered = true;
      for (int j = 0; j < ts; ++j) {
        for (int i = 0; i < ts; ++i) {
          const int64_t px = int64_t{tx * ts + i} * 256 + 128;
          const int64_t py = int64_t{ty * ts + j} * 256 + 128;
          bool cov = true;
          for (int k = 0; k < 3; ++k) {
            const bool pass = x.e(k, px, py) - x.bias[k] >= 0;
            passes_somewhere[k] = passes_somewhere[k] || pass;
            cov = cov && pass;
          }
          all_covered = all_covered && cov;
        }
      }
      uint64_t stamps = 0;
      for (int sy = ty * ts; sy < (ty + 1) * ts; sy += sh) {
        for (int sx = tx * ts; sx < (tx + 1) * ts; sx += sw) {
          if (sx + sw - 1 >= x.x0 && sx <= x.x1 && sy + sh - 1 >= x.y0 && sy <= x.y1) ++stamps;
        }
      }
      if (!(passes_somewhere[0] && passes_somewhere[1] && passes_somewhere[2])) {
        ++w.rejected;
      } else if (all_covered) {
        ++w.accepted;
        w.stamps_accepted += stamps;
      } else {
        w.stamps_evaluated += stamps;
      }
    }
  }
  return w;
}

// Units owning a tile of the box, by looking at every tile.
std::set<unsigned> owners(const Expect& x, const GpuConfig& c) {
  std::set<unsigned> s;
  if (x.fate != Fate::rasterized || x.box_empty()) return s;
  const int ts = static_cast<int>(c.tile_size);
  for (int ty = x.y0 / ts; ty <= x.y1 / ts; ++ty) {
    for (int tx = x.x0 / ts; tx <= x.x1 / ts; ++tx) s.insert(tile_owner(tx, ty, c.units));
  }
  return s;
}

// ---------------------------------------------------------------------------
// Checking the outputs of a bench against the expectations, triangle by
// triangle and pixel by pixel.

struct Totals {
  uint64_t degenerate = 0, culled = 0, rasterized = 0, fragments = 0;
};

// Per triangle (primitive id = index), the covered pixels the units emitted.
void check_outputs(const RasterBench& b, const std::vector<ClippedPrimitive>& tokens,
                   const std::vector<Expect>& ex) {
  const GpuConfig& c = b.config;
  const int W = b.frame.framebuffer.width, H = b.frame.framebuffer.height;
  const int ts = static_cast<int>(c.tile_size);
  const int sw = static_cast<int>(c.stamp[0]), sh = static_cast<int>(c.stamp[1]);
  const uint64_t full = sw * sh == 64 ? ~uint64_t{0} : (uint64_t{1} << (sw * sh)) - 1;
  std::vector<std::vector<uint32_t>> got(ex.size());

  // Per triangle, how many control tokens precede it in the input: no
  // triangle may overtake a control token or fall behind one.
  std::vector<PacketKind> controls_in;
  std::vector<size_t> epoch(tokens.size(), 0);
  for (size_t i = 0; i < tokens.size(); ++i) {
    if (tokens[i].kind != PacketKind::work) controls_in.push_back(tokens[i].kind);
    epoch[i] = controls_in.size();
  }

  for (unsigned u = 0; u < c.units; ++u) {
    std::vector<PacketKind> controls_out;
    int64_t last_prim = -1, last_tile_key = -1;
    for (const StampBatch& batch : b.out[u]) {
      if (batch.kind != PacketKind::work) {
        controls_out.push_back(batch.kind);
        EXPECT_TRUE(batch.stamps.empty());
        EXPECT_FALSE(batch.primitive);
        continue;
      }
      ASSERT_TRUE(batch.primitive);
      const int64_t prim = batch.primitive->primitive_id;
      ASSERT_GE(prim, 0);
      ASSERT_LT(prim, static_cast<int64_t>(ex.size()));
      EXPECT_EQ(epoch[prim], controls_out.size()) << "prim " << prim << " crossed a control token";
      const Expect& x = ex[prim];
      ASSERT_EQ(x.fate, Fate::rasterized) << "prim " << prim;
      ASSERT_FALSE(batch.stamps.empty());
      EXPECT_TRUE(batch.samples.empty());
      const int tx = batch.stamps[0].x / ts, ty = batch.stamps[0].y / ts;
      EXPECT_EQ(tile_owner(tx, ty, c.units), u);
      // Walk order: triangles in input order, tiles bottom-up, left to right.
      const int64_t tile_key = int64_t{ty} * 100000 + tx;
      if (prim == last_prim) {
        EXPECT_GT(tile_key, last_tile_key) << "prim " << prim;
      } else {
        EXPECT_GT(prim, last_prim);
      }
      last_prim = prim;
      last_tile_key = tile_key;
      int64_t last_stamp_key = -1;
      for (const Stamp& s : batch.stamps) {
        EXPECT_EQ(s.x / ts, tx);
        EXPECT_EQ(s.y / ts, ty);
        EXPECT_EQ(s.x % sw, 0);
        EXPECT_EQ(s.y % sh, 0);
        const int64_t key = int64_t{s.y} * 100000 + s.x;
        EXPECT_GT(key, last_stamp_key);
        last_stamp_key = key;
        EXPECT_NE(s.mask, 0u);
        EXPECT_EQ(s.mask & ~full, 0u);
        const int64_t ox = int64_t{s.x} * 256 + 128, oy = int64_t{s.y} * 256 + 128;
        for (int k = 0; k < 3; ++k) {
          ASSERT_EQ(s.e[k], x.e(k, ox, oy)) << "prim " << prim << " stamp " << s.x << "," << s.y;
        }
        for (int bit = 0; bit < sw * sh; ++bit) {
          if (!(s.mask >> bit & 1)) continue;
          const int i = bit % sw, j = bit / sw;
          const int px = s.x + i, py = s.y + j;
          ASSERT_TRUE(px >= 0 && px < W && py >= 0 && py < H) << px << "," << py;
          // The back end's stepping from the stamp's e, with the golden
          // vertices' deltas: a = -(Yb - Ya), b = Xb - Xa.
          for (int k = 0; k < 3; ++k) {
            const WindowVertex &va = x.v[(k + 1) % 3], &vb = x.v[(k + 2) % 3];
            const EdgeValue a = -(EdgeValue{vb.y} - va.y), bb = EdgeValue{vb.x} - va.x;
            EXPECT_EQ(s.e[k] + i * a * 256 + j * bb * 256,
                      x.e(k, int64_t{px} * 256 + 128, int64_t{py} * 256 + 128));
          }
          got[prim].push_back(static_cast<uint32_t>(py * W + px));
        }
      }
    }
    EXPECT_EQ(controls_out, controls_in) << "unit " << u;
  }

  uint64_t fragments = 0;
  for (size_t p = 0; p < ex.size(); ++p) {
    if (tokens[p].kind != PacketKind::work) continue;
    std::sort(got[p].begin(), got[p].end());
    // Equal sorted lists: the same pixels, each exactly once.
    EXPECT_EQ(got[p], ex[p].pixels) << "prim " << p << ": " << tokens[p];
    fragments += ex[p].pixels.size();
  }
  uint64_t unit_fragments = 0;
  for (unsigned u = 0; u < c.units; ++u)
    unit_fragments += counter(b.units[u]->stats(), "fragments");
  EXPECT_EQ(unit_fragments, fragments);
}

// Spec section 10, transcribed from its text: with the CCW vertices, in
// float, in the written order.
float spec_polygon_offset(const Expect& x, const ClippedPrimitive& t, const RenderState& st,
                          DepthFormat fmt) {
  const float s = 1.0f / 256.0f;
  const float dx1 = static_cast<float>(x.v[1].x - x.v[0].x) * s;
  const float dy1 = static_cast<float>(x.v[1].y - x.v[0].y) * s;
  const float dx2 = static_cast<float>(x.v[2].x - x.v[0].x) * s;
  const float dy2 = static_cast<float>(x.v[2].y - x.v[0].y) * s;
  const float z0 = t.v[x.from[0]].z, z1 = t.v[x.from[1]].z, z2 = t.v[x.from[2]].z;
  const float dz1 = z1 - z0;
  const float dz2 = z2 - z0;
  const float a = static_cast<float>(x.area2) * (s * s);
  const float dzdx = (dz1 * dy2 - dz2 * dy1) / a;
  const float dzdy = (dz2 * dx1 - dz1 * dx2) / a;
  const float m = std::max(std::fabs(dzdx), std::fabs(dzdy));
  const float r =
      min_resolvable_depth(fmt, std::max({std::fabs(z0), std::fabs(z1), std::fabs(z2)}));
  return st.offset_factor * m + st.offset_units * r;
}

// Setup's packets (through the tap) against the golden setup.
void check_setup(const RasterBench& b, const std::vector<ClippedPrimitive>& tokens,
                 const std::vector<Expect>& ex) {
  std::vector<int64_t> expected_ids, got_ids;
  for (size_t i = 0; i < tokens.size(); ++i) {
    if (tokens[i].kind != PacketKind::work) {
      expected_ids.push_back(-1 - static_cast<int>(tokens[i].kind));
    } else if (ex[i].fate == Fate::rasterized && !ex[i].box_empty()) {
      expected_ids.push_back(static_cast<int64_t>(i));
    }
  }
  const int64_t probes[][2] = {
      {0, 0},          {128, 128}, {-8388608, 8388608}, {8388608, 8388608}, {-8388608, -8388608},
      {123457, -98765}};
  for (const SetupPacket& p : b.setup_packets) {
    if (p.kind != PacketKind::work) {
      got_ids.push_back(-1 - static_cast<int>(p.kind));
      EXPECT_FALSE(p.primitive);
      continue;
    }
    ASSERT_TRUE(p.primitive);
    const RasterPrimitive& r = *p.primitive;
    got_ids.push_back(r.primitive_id);
    const Expect& x = ex.at(r.primitive_id);
    const ClippedPrimitive& t = tokens.at(r.primitive_id);
    EXPECT_EQ(r.draw_id, t.draw_id);
    EXPECT_EQ(r.area2, x.area2);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(r.x[i], x.v[i].x);
      EXPECT_EQ(r.y[i], x.v[i].y);
      const ClippedVertex& src = t.v[x.from[i]];
      EXPECT_EQ(r.z[i], src.z);
      EXPECT_EQ(r.inv_w[i], src.inv_w);
      EXPECT_EQ(r.varyings_over_w[i], src.varyings_over_w);
    }
    EXPECT_EQ(r.flat_varyings, t.flat_varyings);
    EXPECT_EQ(r.primitive_kind, PrimitiveKind::triangle);
    EXPECT_EQ(r.vertex_count, 3);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(r.edge[k].bias, x.bias[k]);
      for (const auto& pr : probes) {
        EXPECT_EQ(r.edge[k].at(static_cast<Subpixel>(pr[0]), static_cast<Subpixel>(pr[1])),
                  x.e(k, pr[0], pr[1]));
      }
    }
    EXPECT_EQ(std::tie(r.x0, r.x1, r.y0, r.y1), std::tie(x.x0, x.x1, x.y0, x.y1));
    EXPECT_EQ(r.has_depth_offset, x.has_offset);
    const RenderState& st = b.frame.draws.at(t.draw_id).state;
    const float offset =
        x.has_offset ? spec_polygon_offset(x, t, st, b.frame.framebuffer.depth_format) : 0.0f;
    EXPECT_EQ(r.depth_offset, offset) << "prim " << r.primitive_id;
  }
  EXPECT_EQ(got_ids, expected_ids);
}

// ---------------------------------------------------------------------------
// Triangles (window_triangle and control are raster_bench.h's).

// On the subpixel grid: X / 256 is exact in float for |X| < 2^24.
float sub(int64_t X) {
  return static_cast<float>(X) / 256.0f;
}

// Draw states the random triangles pick from: every cull / front-face
// combination, and polygon offsets.
FrameState raster_frame(int W, int H) {
  FrameState f;
  f.framebuffer.width = W;
  f.framebuffer.height = H;
  f.framebuffer.depth_format = DepthFormat::float32;  // offset units depend on max |z|
  const std::array<std::tuple<CullMode, FrontFace, float, float>, 6> states{{
      {CullMode::none, FrontFace::ccw, 0.0f, 0.0f},
      {CullMode::back, FrontFace::ccw, 0.0f, 0.0f},
      {CullMode::front, FrontFace::ccw, 1.0f, 0.0f},
      {CullMode::back, FrontFace::cw, 0.0f, 2.0f},
      {CullMode::front, FrontFace::cw, -0.5f, 1.0f},
      {CullMode::none, FrontFace::cw, 0.0f, 0.0f},
  }};
  for (const auto& [cull, face, factor, units] : states) {
    DrawState d;
    d.state.cull = cull;
    d.state.front_face = face;
    d.state.offset_factor = factor;
    d.state.offset_units = units;
    f.draws.push_back(d);
  }
  return f;
}

// Hundreds of triangles of every kind the brief lists, with control tokens
// at the start, in the middle and at the end. primitive_id = token index.
std::vector<ClippedPrimitive> random_tokens(uint64_t seed, int W, int H, size_t draws) {
  Rng rng{seed};
  std::vector<ClippedPrimitive> out;
  auto next_draw = [&] { return static_cast<uint32_t>(rng.range(0, int64_t(draws) - 1)); };
  auto add = [&](std::array<int64_t, 6> v) {
    if (rng.coin()) {  // either winding
      std::swap(v[2], v[4]);
      std::swap(v[3], v[5]);
    }
    std::array<float, 6> f;
    for (int i = 0; i < 6; ++i) f[i] = sub(v[i]);
    out.push_back(window_triangle(static_cast<int64_t>(out.size()), next_draw(), f));
  };
  const int64_t Ws = int64_t{W} * 256, Hs = int64_t{H} * 256;
  const int64_t L = int64_t{32768} * 256;  // the guard band, in subpixels

  out.push_back(control_primitive(PacketKind::clear));
  // Sizes 2^0 .. 2^8 pixels anywhere on and around the screen.
  for (int n = 0; n < 150; ++n) {
    const int64_t size = int64_t{256} << rng.range(0, 8);
    const int64_t cx = rng.range(-16 * 256, Ws + 16 * 256),
                  cy = rng.range(-16 * 256, Hs + 16 * 256);
    std::array<int64_t, 6> v;
    for (int i = 0; i < 3; ++i) {
      v[2 * i] = cx + rng.range(-size, size);
      v[2 * i + 1] = cy + rng.range(-size, size);
    }
    add(v);
  }
  // Tiny triangles with an edge exactly through a pixel centre, then shifted
  // by -1 / 0 / +1 subpixel: the fill rule decides.
  for (int n = 0; n < 120; ++n) {
    const int64_t px = rng.range(-1, W) * 256 + 128, py = rng.range(-1, H) * 256 + 128;
    const int64_t dx = rng.range(-3, 3), dy = rng.range(-3, 3);
    const int64_t m = rng.range(1, 120), k = rng.range(1, 120);
    const int64_t sx = rng.range(-1, 1), sy = rng.range(-1, 1);
    std::array<int64_t, 6> v{px - m * dx,
                             py - m * dy,
                             px + k * dx,
                             py + k * dy,
                             px + rng.range(-300, 300),
                             py + rng.range(-300, 300)};
    for (int i = 0; i < 3; ++i) v[2 * i] += sx, v[2 * i + 1] += sy;
    add(v);
  }
  // Axis-aligned right triangles on pixel centres and corners (horizontal
  // and vertical edges through rows and columns of centres).
  for (int n = 0; n < 40; ++n) {
    const int64_t x = rng.range(-2, W + 1) * 256 + (rng.coin() ? 128 : 0);
    const int64_t y = rng.range(-2, H + 1) * 256 + (rng.coin() ? 128 : 0);
    const int64_t a = rng.range(-12, 12) * 128, b = rng.range(-12, 12) * 128;
    add({x, y, x + a, y, x, y + b});
  }
  // Big right triangles whose legs run along a row and a column of pixel
  // centres at a tile corner (a multiple of every tile size): the tile test's
  // extreme centres lie exactly on the edges, owned or not.
  for (int n = 0; n < 16; ++n) {
    const int64_t x = rng.range(0, W / 64) * 64 * 256 + 128,
                  y = rng.range(0, H / 64) * 64 * 256 + 128;
    const int64_t lx = (n & 1 ? 1 : -1) * rng.range(64, 150) * 256;
    const int64_t ly = (n & 2 ? 1 : -1) * rng.range(64, 150) * 256;
    add({x, y, x + lx, y, x, y + ly});
  }
  // Quads split along a diagonal: two triangles sharing an edge.
  for (int n = 0; n < 30; ++n) {
    const int64_t x = rng.range(0, Ws), y = rng.range(0, Hs), r = int64_t{256} << rng.range(0, 6);
    const std::array<int64_t, 8> q{x - r + rng.range(-99, 99), y - r + rng.range(-99, 99),
                                   x + r + rng.range(-99, 99), y - r + rng.range(-99, 99),
                                   x + r + rng.range(-99, 99), y + r + rng.range(-99, 99),
                                   x - r + rng.range(-99, 99), y + r + rng.range(-99, 99)};
    add({q[0], q[1], q[2], q[3], q[4], q[5]});
    add({q[0], q[1], q[4], q[5], q[6], q[7]});
  }
  out.push_back(control_primitive(PacketKind::clear));
  // Huge: vertices anywhere in the guard band, and at its corners.
  for (int n = 0; n < 30; ++n) {
    std::array<int64_t, 6> v;
    for (int i = 0; i < 6; ++i) v[i] = rng.range(-L, L);
    if (n % 5 == 0) v = {-L, -L, L, -L, rng.range(-L, L), L};
    add(v);
  }
  // Straddling the framebuffer's edges and corners.
  for (int n = 0; n < 40; ++n) {
    const std::array<int64_t, 2> ex{0, Ws}, ey{0, Hs};
    const int64_t x = rng.coin() ? ex[rng.range(0, 1)] : rng.range(0, Ws);
    const int64_t y = rng.coin() ? ey[rng.range(0, 1)] : rng.range(0, Hs);
    std::array<int64_t, 6> v;
    for (int i = 0; i < 3; ++i) {
      v[2 * i] = x + rng.range(-1000, 1000);
      v[2 * i + 1] = y + rng.range(-1000, 1000);
    }
    add(v);
  }
  // Degenerate: collinear, repeated vertices, and sub-subpixel slivers that
  // snap to a line (off-grid floats: snapping rounds them).
  for (int n = 0; n < 20; ++n) {
    const int64_t x = rng.range(0, Ws), y = rng.range(0, Hs);
    const int64_t dx = rng.range(-500, 500), dy = rng.range(-500, 500), t = rng.range(-3, 3);
    add({x, y, x + dx, y + dy, x + t * dx, y + t * dy});
  }
  for (int n = 0; n < 40; ++n) {
    // Off the grid: floats anywhere, so snapping (ties to even) matters.
    const float x = static_cast<float>(rng.range(-8, W + 8)) + 0.001f * rng.range(0, 999);
    const float y = static_cast<float>(rng.range(-8, H + 8)) + 0.001f * rng.range(0, 999);
    const float s = n < 10 ? 0.0007f : static_cast<float>(rng.range(1, 40));
    std::array<float, 6> f{x,
                           y,
                           x + s * 0.001f * rng.range(0, 999),
                           y + s * 0.001f * rng.range(0, 999),
                           x - s * 0.001f * rng.range(0, 999),
                           y + s * 0.001f * rng.range(0, 999)};
    if (n % 4 == 1) {
      // Every coordinate halfway between two subpixels: ties to even.
      for (int i = 0; i < 6; ++i) {
        f[i] = sub(rng.range(-4 * 256, (i % 2 ? H : W) * 256 + 4 * 256)) + 1.0f / 512.0f;
      }
    }
    out.push_back(window_triangle(static_cast<int64_t>(out.size()), next_draw(), f));
  }
  out.push_back(control_primitive(PacketKind::end_of_frame));
  return out;
}

std::vector<Expect> expectations(const std::vector<ClippedPrimitive>& tokens, const FrameState& f) {
  std::vector<Expect> ex(tokens.size());
  for (size_t i = 0; i < tokens.size(); ++i) {
    if (tokens[i].kind == PacketKind::work) {
      ex[i] = expect_for(tokens[i], f.draws.at(tokens[i].draw_id).state, f.framebuffer.width,
                         f.framebuffer.height);
    }
  }
  return ex;
}

// The documented costs of every stage over a token stream.
void check_costs(const RasterBench& b, const std::vector<ClippedPrimitive>& tokens,
                 const std::vector<Expect>& ex) {
  const GpuConfig& c = b.config;
  const unsigned setup_ii = c.stage("primitive_setup").ii;
  const unsigned dist_ii = c.stage("tile_distributor").ii;
  const unsigned rast_ii = c.stage("tile_rasterizer").ii;
  uint64_t controls = 0, dist_cycles = 0;
  std::vector<UnitWork> work(c.units);
  std::vector<uint64_t> sent(c.units, 0);
  Totals tot;
  for (size_t i = 0; i < tokens.size(); ++i) {
    if (tokens[i].kind != PacketKind::work) {
      ++controls;
      dist_cycles += dist_ii;
      continue;
    }
    const Expect& x = ex[i];
    if (x.fate == Fate::degenerate) ++tot.degenerate;
    if (x.fate == Fate::culled) ++tot.culled;
    if (x.fate != Fate::rasterized) continue;
    ++tot.rasterized;
    if (x.box_empty()) continue;
    const std::set<unsigned> to = owners(x, c);
    dist_cycles += dist_ii * std::max<uint64_t>(1, to.size());
    for (unsigned u : to) ++sent[u];
    for (unsigned u = 0; u < c.units; ++u) {
      const UnitWork w = unit_work(x, c, u);
      EXPECT_EQ(w.tiles > 0, to.count(u) > 0);
      work[u].tiles += w.tiles;
      work[u].rejected += w.rejected;
      work[u].accepted += w.accepted;
      work[u].stamps_evaluated += w.stamps_evaluated;
      work[u].stamps_accepted += w.stamps_accepted;
    }
  }
  const StatGroup& s = b.setup.stats();
  EXPECT_EQ(counter(s, "busy_cycles"), setup_ii * tokens.size());
  EXPECT_EQ(counter(s, "tokens_in"), tokens.size());
  EXPECT_EQ(counter(s, "triangles_degenerate"), tot.degenerate);
  EXPECT_EQ(counter(s, "triangles_culled"), tot.culled);
  EXPECT_EQ(counter(s, "triangles_rasterized"), tot.rasterized);
  EXPECT_GT(tot.degenerate, 0u);
  EXPECT_GT(tot.culled, 0u);
  EXPECT_EQ(counter(b.distributor.stats(), "busy_cycles"), dist_cycles);
  for (unsigned u = 0; u < c.units; ++u) {
    EXPECT_EQ(counter(b.distributor.stats(), "triangles_sent_unit" + std::to_string(u)), sent[u]);
    const StatGroup& r = b.units[u]->stats();
    EXPECT_EQ(counter(r, "tiles_visited"), work[u].tiles) << "unit " << u;
    EXPECT_EQ(counter(r, "tiles_rejected"), work[u].rejected) << "unit " << u;
    EXPECT_EQ(counter(r, "tiles_accepted"), work[u].accepted) << "unit " << u;
    EXPECT_EQ(counter(r, "stamps_evaluated"), work[u].stamps_evaluated) << "unit " << u;
    EXPECT_EQ(counter(r, "stamps_accepted"), work[u].stamps_accepted) << "unit " << u;
    EXPECT_EQ(counter(r, "busy_cycles"), work[u].cycles(rast_ii) + rast_ii * controls)
        << "unit " << u;
    uint64_t stamps = 0;
    for (const StampBatch& sb : b.out[u]) stamps += sb.stamps.size();
    EXPECT_EQ(counter(r, "stamps_emitted"), stamps);
    EXPECT_EQ(counter(r, "tokens_out"), b.out[u].size());
  }
}

// ---------------------------------------------------------------------------
// Coverage, e values, setup fields, costs and stall insensitivity over every
// unit count, tile size and stamp size of the brief.

using RasterParam = std::tuple<unsigned, unsigned, std::array<unsigned, 2>>;

class RasterCore : public ::testing::TestWithParam<RasterParam> {};

TEST_P(RasterCore, MatchesGoldenRuleAndCosts) {
  const auto [units, tile, stamp] = GetParam();
  GpuConfig cfg = GpuConfig::baseline();
  cfg.units = units;
  cfg.tile_size = tile;
  cfg.stamp = stamp;
  cfg.fifo_depth = 2;
  // Distinct costs so every term of each formula is visible.
  cfg.stages["primitive_setup"] = {5, 7};
  cfg.stages["tile_distributor"] = {2, 3};
  cfg.stages["tile_rasterizer"] = {3, 4};
  const int W = 203, H = 157;  // no multiple of any tile or stamp size
  const FrameState frame = raster_frame(W, H);
  const std::vector<ClippedPrimitive> tokens =
      random_tokens(0x5EED + units * 131 + tile, W, H, frame.draws.size());
  auto plain = std::make_unique<RasterBench>("plain", cfg, frame, true);
  auto stalled = std::make_unique<RasterBench>("stalled", cfg, frame, false);
  stalled->stall_everything(77 + units + tile);
  plain->feed(tokens);
  stalled->feed(tokens);
  sc_core::sc_start();

  const std::vector<Expect> ex = expectations(tokens, frame);
  check_setup(*plain, tokens, ex);
  check_outputs(*plain, tokens, ex);
  check_costs(*plain, tokens, ex);
  // Random stalls change the timing, not a bit of the outputs or the work.
  for (unsigned u = 0; u < units; ++u) {
    ASSERT_EQ(stalled->out[u].size(), plain->out[u].size()) << "unit " << u;
    for (size_t i = 0; i < plain->out[u].size(); ++i) {
      ASSERT_EQ(stalled->out[u][i], plain->out[u][i]) << "unit " << u << " batch " << i;
    }
    EXPECT_EQ(stalled->units[u]->stats().to_json(), plain->units[u]->stats().to_json());
  }
  EXPECT_EQ(stalled->setup.stats().to_json(), plain->setup.stats().to_json());
  EXPECT_EQ(stalled->distributor.stats().to_json(), plain->distributor.stats().to_json());
  uint64_t injected = 0;
  for (unsigned u = 0; u < units; ++u) injected += stalled->stamps[u]->stats().injected_stalls;
  EXPECT_GT(injected, 0u);
}

std::string raster_param_name(const ::testing::TestParamInfo<RasterParam>& info) {
  const auto& [units, tile, stamp] = info.param;
  return "units" + std::to_string(units) + "_tile" + std::to_string(tile) + "_stamp" +
         std::to_string(stamp[0]) + "x" + std::to_string(stamp[1]);
}

INSTANTIATE_TEST_SUITE_P(Configs, RasterCore,
                         ::testing::Combine(::testing::Values(1u, 3u, 4u),
                                            ::testing::Values(8u, 16u, 64u),
                                            ::testing::Values(std::array<unsigned, 2>{2, 2},
                                                              std::array<unsigned, 2>{4, 4},
                                                              std::array<unsigned, 2>{8, 8},
                                                              std::array<unsigned, 2>{8, 2})),
                         raster_param_name);

// ---------------------------------------------------------------------------
// Against golden::render() of whole scenes: counts, the last writer of every
// pixel and its depth bits (which carry the polygon offset), for each depth
// format. Clip-space positions with identity matrices; every triangle stays
// inside the clip volume, so the clipper would pass it unchanged and the
// window coordinates below are the spec's viewport transform (section 5).

using SceneParam = std::tuple<DepthFormat, unsigned, unsigned, std::array<unsigned, 2>>;
class RasterVsRender : public ::testing::TestWithParam<SceneParam> {};

TEST_P(RasterVsRender, CountsLastWriterAndDepthEqualGolden) {
  const auto [depth_format, units, tile, stamp] = GetParam();
  const int W = 160, H = 120;
  Scene scene;
  scene.framebuffer.width = W;
  scene.framebuffer.height = H;
  scene.framebuffer.depth_format = depth_format;
  FrameState frame;
  frame.framebuffer = scene.framebuffer;
  const std::array<std::tuple<CullMode, FrontFace, float, float>, 4> states{{
      {CullMode::none, FrontFace::ccw, 0.0f, 0.0f},
      {CullMode::back, FrontFace::ccw, 1.0f, 1.0f},
      {CullMode::front, FrontFace::cw, -0.5f, 2.0f},
      {CullMode::back, FrontFace::cw, 0.0f, -1.0f},
  }};
  Rng rng{0xD00D + static_cast<uint64_t>(depth_format)};
  auto rnd = [&](float lo, float hi) {
    return lo + (hi - lo) * static_cast<float>(rng.next() >> 40) / 16777216.0f;
  };
  std::vector<ClippedPrimitive> tokens;
  int64_t id = 0;
  for (size_t d = 0; d < states.size(); ++d) {
    Draw draw;
    const auto& [cull, face, factor, units_off] = states[d];
    draw.state.cull = cull;
    draw.state.front_face = face;
    draw.state.offset_factor = factor;
    draw.state.offset_units = units_off;
    draw.state.depth_test = true;
    draw.state.depth_func = CompareFunc::always;
    draw.state.depth_write = true;
    for (int n = 0; n < 120; ++n) {
      const float cx = rnd(-1.2f, 1.2f), cy = rnd(-1.2f, 1.2f);
      const float r =
          n % 10 == 0 ? rnd(1.0f, 30.0f) : std::ldexp(1.0f, static_cast<int>(rng.range(-7, 0)));
      for (int i = 0; i < 3; ++i) {
        const float w = n % 3 == 0 ? rnd(0.5f, 2.0f) : 1.0f;
        const glm::vec4 p(cx + rnd(-r, r), cy + rnd(-r, r), rnd(-0.9f, 0.9f), 1.0f);
        draw.positions.push_back(glm::vec4(p.x * w, p.y * w, p.z * w, w));
        draw.colors.push_back(glm::vec4(rnd(0, 1), rnd(0, 1), rnd(0, 1), 1.0f));
      }
    }
    // The clipper's output for these triangles (spec section 5).
    const float half_w = 0.5f * static_cast<float>(W), half_h = 0.5f * static_cast<float>(H);
    for (size_t t = 0; t + 2 < draw.positions.size(); t += 3) {
      ClippedPrimitive ct;
      ct.draw_id = static_cast<uint32_t>(d);
      ct.primitive_id = id++;
      for (int i = 0; i < 3; ++i) {
        const glm::vec4& c = draw.positions[t + i];
        ClippedVertex& v = ct.v[i];
        v.inv_w = 1.0f / c.w;
        v.x = (c.x * v.inv_w + 1.0f) * half_w;
        v.y = (c.y * v.inv_w + 1.0f) * half_h;
        v.z = (c.z * v.inv_w + 1.0f) * 0.5f;
        for (int k = 0; k < 4; ++k) v.varyings_over_w[k] = draw.colors[t + i][k] * v.inv_w;
      }
      for (int k = 0; k < 4; ++k) ct.flat_varyings[k] = draw.colors[t + 2][k];
      tokens.push_back(ct);
    }
    DrawState ds;
    ds.state = draw.state;
    frame.draws.push_back(ds);
    scene.draws.push_back(std::move(draw));
  }
  tokens.push_back(control_primitive(PacketKind::end_of_frame));

  GpuConfig cfg = GpuConfig::baseline();
  cfg.units = units;
  cfg.tile_size = tile;
  cfg.stamp = stamp;
  auto bench = std::make_unique<RasterBench>("scene", cfg, frame, false);
  bench->feed(tokens);
  sc_core::sc_start();

  const golden::Result g = golden::render(scene);
  const StatGroup& s = bench->setup.stats();
  EXPECT_EQ(counter(s, "triangles_degenerate"), g.stats.triangles_degenerate);
  EXPECT_EQ(counter(s, "triangles_culled"), g.stats.triangles_culled);
  EXPECT_EQ(counter(s, "triangles_rasterized"), g.stats.triangles_rasterized);
  EXPECT_EQ(g.stats.triangles_clipped, 0u);  // the premise of the window coordinates
  EXPECT_GT(g.stats.triangles_culled, 0u);
  uint64_t fragments = 0;
  for (unsigned u = 0; u < units; ++u) fragments += counter(bench->units[u]->stats(), "fragments");
  EXPECT_EQ(fragments, g.stats.fragments_generated);

  // Last writer per pixel (API order = primitive id) and its depth, from the
  // stamps' e values with the spec's interpolation (section 9) and offset.
  std::vector<int64_t> last(static_cast<size_t>(W) * H, -1);
  std::vector<DepthValue> depth(last.size(), encode_depth(depth_format, 1.0f));
  const int sw = static_cast<int>(stamp[0]);
  std::vector<std::tuple<int64_t, size_t, DepthValue>> writes;
  for (unsigned u = 0; u < units; ++u) {
    for (const StampBatch& b : bench->out[u]) {
      if (b.kind != PacketKind::work) continue;
      const RasterPrimitive& t = *b.primitive;
      for (const Stamp& st : b.stamps) {
        for (int bit = 0; bit < 64; ++bit) {
          if (!(st.mask >> bit & 1)) continue;
          const int i = bit % sw, j = bit / sw;
          std::array<float, 3> f;
          for (int k = 0; k < 3; ++k) {
            f[k] = static_cast<float>(st.e[k] + int64_t{i} * t.edge[k].a * 256 +
                                      int64_t{j} * t.edge[k].b * 256);
          }
          float z = t.z[0] + (f[1] * (t.z[1] - t.z[0]) + f[2] * (t.z[2] - t.z[0])) /
                                 static_cast<float>(t.area2);
          if (t.has_depth_offset) z = z + t.depth_offset;
          writes.emplace_back(t.primitive_id, static_cast<size_t>(st.y + j) * W + st.x + i,
                              encode_depth(depth_format, z));
        }
      }
    }
  }
  std::sort(writes.begin(), writes.end());  // API order
  for (const auto& [prim, p, z] : writes) {
    last[p] = prim;
    depth[p] = z;
  }
  EXPECT_EQ(last, g.last_writer);
  size_t depth_mismatch = 0;
  for (size_t p = 0; p < last.size(); ++p) depth_mismatch += depth[p] != g.framebuffer.depth[p];
  EXPECT_EQ(depth_mismatch, 0u);
}

INSTANTIATE_TEST_SUITE_P(Formats, RasterVsRender,
                         ::testing::Values(SceneParam{DepthFormat::float32, 3u, 16u, {4, 4}},
                                           SceneParam{DepthFormat::unorm16, 4u, 8u, {2, 2}},
                                           SceneParam{DepthFormat::unorm24, 1u, 64u, {8, 8}}),
                         [](const ::testing::TestParamInfo<SceneParam>& info) {
                           return std::string(to_string(std::get<0>(info.param))) + "_units" +
                                  std::to_string(std::get<1>(info.param));
                         });

// ---------------------------------------------------------------------------
// Timing of a full-screen quad, 256 x 256, 16 x 16 tiles, 4 x 4 stamps,
// default costs (setup ii 4 / latency 16, distributor 1 / 2, rasterizer 1 / 2).
//
// A = (0,0) (256,0) (256,256) covers y <= x; B = (0,0) (256,256) (0,256)
// covers y > x (the diagonal, edge v2 -> v0 of A, runs downwards: A owns
// it). Both boxes are the whole screen, 16 x 16 tiles. For A: tiles with
// tx > ty are accepted (120), tx < ty rejected (120), the 16 diagonal tiles
// partial; B the other way round. Per triangle on one unit:
//   256 tile tests + 120 * 16 accepted stamps + 16 * 16 evaluated stamps
//   = 256 + 1920 + 256 = 2432 cycles; the frame 4864.

std::vector<ClippedPrimitive> quad_tokens() {
  return {window_triangle(0, 0, {0, 0, 256, 0, 256, 256}),
          window_triangle(1, 0, {0, 0, 256, 256, 0, 256})};
}

FrameState quad_frame() {
  FrameState f;
  f.framebuffer.width = 256;
  f.framebuffer.height = 256;
  f.draws.push_back(DrawState{});
  return f;
}

// The quad tests' configuration: 16-pixel tiles, 4 x 4 stamps, FIFOs of 16.
GpuConfig quad_config(unsigned units) {
  GpuConfig cfg = GpuConfig::baseline();
  cfg.units = units;
  cfg.tile_size = 16;
  cfg.stamp = {4, 4};
  cfg.fifo_depth = 16;
  return cfg;
}

TEST(RasterTiming, FullScreenQuadOneUnit) {
  const GpuConfig cfg = quad_config(1);
  auto bench = std::make_unique<RasterBench>("quad", cfg, quad_frame(), false);
  bench->feed(quad_tokens());
  sc_core::sc_start();

  const StatGroup& r = bench->units[0]->stats();
  EXPECT_EQ(counter(r, "busy_cycles"), 4864u);
  EXPECT_EQ(counter(r, "tiles_visited"), 512u);
  EXPECT_EQ(counter(r, "tiles_accepted"), 240u);
  EXPECT_EQ(counter(r, "tiles_rejected"), 240u);
  EXPECT_EQ(counter(r, "stamps_accepted"), 3840u);
  EXPECT_EQ(counter(r, "stamps_evaluated"), 512u);
  EXPECT_EQ(counter(r, "fragments"), 65536u);
  // 136 tiles with coverage per triangle, one batch each.
  ASSERT_EQ(bench->out[0].size(), 272u);
  // Timeline: setup reads A at 0, writes it at 4, readable at 4 + 16 = 20
  // (B: 8, 24). The distributor reads A at 20, writes at 21, readable at 23
  // (B: 24, 25, 27). The rasterizer reads A at 23; tile (0, 0) is partial:
  // 1 + 16 cycles, written at 40, readable at 42. A's last tile, (15, 15),
  // ends at 23 + 2432 = 2455, readable 2457; B is read at 2455 and its last
  // batch is written at 2455 + 2432 = 4887, readable at 4889.
  EXPECT_EQ(bench->out_cycle[0].front(), 42u);
  EXPECT_EQ(bench->out_cycle[0][135], 2457u);
  EXPECT_EQ(bench->out_cycle[0].back(), 4889u);
  EXPECT_EQ(counter(bench->setup.stats(), "busy_cycles"), 8u);
  EXPECT_EQ(counter(bench->distributor.stats(), "busy_cycles"), 2u);
  // Every pixel exactly once.
  std::vector<int> hits(256 * 256, 0);
  for (const StampBatch& b : bench->out[0]) {
    for (const Stamp& s : b.stamps) {
      for (int bit = 0; bit < 16; ++bit) {
        if (s.mask >> bit & 1) ++hits[(s.y + bit / 4) * 256 + s.x + bit % 4];
      }
    }
  }
  EXPECT_EQ(std::count(hits.begin(), hits.end(), 1), 256 * 256);
}

// Four units: unit u owns the 64 tiles with (tx + ty) % 4 == u, 16384 pixels,
// and for each triangle visits those 64 tiles. The diagonal tiles (tx == ty,
// 2 tx % 4) go to units 0 and 2, 8 each; the rest split evenly above and
// below the diagonal. Per triangle: units 0, 2: 64 + 28 * 16 + 8 * 16 = 640
// cycles; units 1, 3: 64 + 32 * 16 = 576. The distributor sends each
// triangle to all 4 units: 4 cycles each, so A is readable by every unit at
// 20 + 4 + 2 = 26, B at 24 + 4 + 2 = 30 (already there when a unit is done
// with A). Unit u's last batch (its last tile in walk order has coverage
// for B) is readable at 26 + 2 * cost + 2.
TEST(RasterTiming, FullScreenQuadFourUnitsSplitEvenly) {
  const GpuConfig cfg = quad_config(4);
  auto bench = std::make_unique<RasterBench>("quad4", cfg, quad_frame(), false);
  bench->feed(quad_tokens());
  sc_core::sc_start();

  const std::array<uint64_t, 4> cost{640, 576, 640, 576};
  for (unsigned u = 0; u < 4; ++u) {
    const StatGroup& r = bench->units[u]->stats();
    EXPECT_EQ(counter(r, "fragments"), 16384u) << u;
    EXPECT_EQ(counter(r, "tiles_visited"), 128u) << u;
    EXPECT_EQ(counter(r, "busy_cycles"), 2 * cost[u]) << u;
    ASSERT_FALSE(bench->out_cycle[u].empty());
    EXPECT_EQ(bench->out_cycle[u].back(), 26 + 2 * cost[u] + 2) << u;
    EXPECT_EQ(counter(bench->distributor.stats(), "triangles_sent_unit" + std::to_string(u)), 2u);
  }
  EXPECT_EQ(counter(bench->distributor.stats(), "busy_cycles"), 8u);
}

}  // namespace
}  // namespace gpusim
