// What a raster unit's back end reads, made with the golden model's
// functions, shared by the back end's chain tests (stages_back_end_test.cpp)
// and the tests of the tile rasterizer, the depth test, the interpolator and
// the ROP alone (stages_<kind>_test.cpp): the test plays front end, setting
// triangles up and cutting them into per-unit stamp batches with
// golden::clip_triangle, to_window, edge_function and the fill rule
// (front_end); random scenes of clip-space triangles; the frame's registers
// (frame_state) and configurations (config).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "hw/draw_state.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/pixel_formats.h"
#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"

namespace gpusim {
namespace test {

using golden::WindowVertex;

inline constexpr uint64_t kGuard = 256;  // bytes around each buffer that must stay untouched

// ---------------------------------------------------------------------------
// Front end, from the golden model's functions.

// The spec's polygon offset (section 10), on the counter-clockwise vertices.
inline float polygon_offset(const std::array<WindowVertex, 3>& v, EdgeValue area2,
                            const RenderState& st, DepthFormat fmt) {
  const float s = 1.0f / 256.0f;
  const float dx1 = static_cast<float>(v[1].x - v[0].x) * s;
  const float dy1 = static_cast<float>(v[1].y - v[0].y) * s;
  const float dx2 = static_cast<float>(v[2].x - v[0].x) * s;
  const float dy2 = static_cast<float>(v[2].y - v[0].y) * s;
  const float dz1 = v[1].z - v[0].z;
  const float dz2 = v[2].z - v[0].z;
  const float a = static_cast<float>(area2) * (s * s);
  const float dzdx = (dz1 * dy2 - dz2 * dy1) / a;
  const float dzdy = (dz2 * dx1 - dz1 * dx2) / a;
  const float m = std::max(std::fabs(dzdx), std::fabs(dzdy));
  const float max_z = std::max({std::fabs(v[0].z), std::fabs(v[1].z), std::fabs(v[2].z)});
  return st.offset_factor * m + st.offset_units * min_resolvable_depth(fmt, max_z);
}

// Triangle setup of three window vertices; nullptr when degenerate or culled.
inline std::shared_ptr<RasterPrimitive> setup(std::array<WindowVertex, 3> v, const RenderState& st,
                                              uint32_t draw_id, int64_t id, const glm::vec4& flat,
                                              const FramebufferDesc& fb) {
  EdgeValue area2 = golden::signed_area2(v[0], v[1], v[2]);
  if (area2 == 0) return nullptr;
  const bool ccw = area2 > 0;
  const bool front = (st.front_face == FrontFace::ccw) == ccw;
  if ((st.cull == CullMode::back && !front) || (st.cull == CullMode::front && front)) {
    return nullptr;
  }
  if (!ccw) {
    std::swap(v[1], v[2]);
    area2 = -area2;
  }
  auto t = std::make_shared<RasterPrimitive>();
  t->draw_id = draw_id;
  t->primitive_id = id;
  t->area2 = area2;
  for (int k = 0; k < 3; ++k) {
    t->x[k] = v[k].x;
    t->y[k] = v[k].y;
    t->z[k] = v[k].z;
    t->inv_w[k] = v[k].inv_w;
    // The colour-only layout every draw has (varying_layout_for): 0-3.
    for (int c = 0; c < 4; ++c) t->varyings_over_w[k][c] = v[k].color_over_w[c];
    const WindowVertex& a = v[(k + 1) % 3];
    const WindowVertex& b = v[(k + 2) % 3];
    EdgeEquation& e = t->edge[k];
    e.a = -(EdgeValue{b.y} - a.y);
    e.b = EdgeValue{b.x} - a.x;
    e.c = (EdgeValue{b.y} - a.y) * a.x - (EdgeValue{b.x} - a.x) * a.y;
    e.bias = golden::edge_owns_boundary(a, b) ? 0 : 1;
    t->coverage[k] = e;  // a triangle's coverage edges are its edges
  }
  for (int c = 0; c < 4; ++c) t->flat_varyings[c] = flat[c];
  if (st.offset_factor != 0.0f || st.offset_units != 0.0f) {
    t->has_depth_offset = true;
    t->depth_offset = polygon_offset(v, area2, st, fb.depth_format);
  }
  const Subpixel min_x = std::min({v[0].x, v[1].x, v[2].x});
  const Subpixel max_x = std::max({v[0].x, v[1].x, v[2].x});
  const Subpixel min_y = std::min({v[0].y, v[1].y, v[2].y});
  const Subpixel max_y = std::max({v[0].y, v[1].y, v[2].y});
  t->x0 = std::max(0, -floor_div_subpixel(-(int64_t{min_x} - kSubpixelHalf)));
  t->x1 = std::min(fb.width - 1, floor_div_subpixel(int64_t{max_x} - kSubpixelHalf));
  t->y0 = std::max(0, -floor_div_subpixel(-(int64_t{min_y} - kSubpixelHalf)));
  t->y1 = std::min(fb.height - 1, floor_div_subpixel(int64_t{max_y} - kSubpixelHalf));
  return t;
}

// A triangle at depth z covering every pixel of any framebuffer, whose
// stamps a test places where it likes (draw 0, primitive 0).
inline std::shared_ptr<RasterPrimitive> full_screen_triangle(const FramebufferDesc& fb, float z) {
  std::array<WindowVertex, 3> v;
  const Subpixel big = 1 << 20;
  v[0].x = -big, v[0].y = -big;
  v[1].x = 3 * big, v[1].y = -big;  // hypotenuse x + y = 2 big: beyond any framebuffer
  v[2].x = -big, v[2].y = 3 * big;
  for (auto& w : v) {
    w.z = z;
    w.inv_w = 1.0f;
    w.color_over_w = glm::vec4(0.2f, 0.4f, 0.6f, 1.0f);
  }
  RenderState st;
  return setup(v, st, 0, 0, glm::vec4(1.0f), fb);
}

inline std::array<WindowVertex, 3> window_vertices(const RasterPrimitive& t) {
  std::array<WindowVertex, 3> v;
  for (int k = 0; k < 3; ++k) {
    v[k].x = t.x[k];
    v[k].y = t.y[k];
    v[k].z = t.z[k];
    v[k].inv_w = t.inv_w[k];
    for (int c = 0; c < 4; ++c) v[k].color_over_w[c] = t.varyings_over_w[k][c];
  }
  return v;
}

// The stamp with origin (sx, sy): golden coverage of its pixels inside the
// framebuffer, raw edge values at the origin's centre.
inline Stamp make_stamp(const RasterPrimitive& t, int sx, int sy, const GpuConfig& cfg,
                        const FramebufferDesc& fb) {
  const auto v = window_vertices(t);
  Stamp s;
  s.x = sx;
  s.y = sy;
  for (int k = 0; k < 3; ++k) {
    s.e[k] =
        golden::edge_function(v[(k + 1) % 3], v[(k + 2) % 3], pixel_center(sx), pixel_center(sy));
  }
  for (unsigned j = 0; j < cfg.stamp[1]; ++j) {
    for (unsigned i = 0; i < cfg.stamp[0]; ++i) {
      const int x = sx + static_cast<int>(i), y = sy + static_cast<int>(j);
      if (x >= fb.width || y >= fb.height) continue;
      bool covered = true;
      for (int k = 0; k < 3; ++k) {
        const EdgeValue e =
            golden::edge_function(v[(k + 1) % 3], v[(k + 2) % 3], pixel_center(x), pixel_center(y));
        covered = covered && e - t.edge[k].bias >= 0;
      }
      if (covered) s.mask |= uint64_t{1} << (j * cfg.stamp[0] + i);
    }
  }
  return s;
}

using UnitTokens = std::vector<std::vector<StampBatch>>;

// Per unit, one batch per (triangle, owned tile) with its covered stamps.
inline void rasterize(const std::shared_ptr<RasterPrimitive>& t, const GpuConfig& cfg,
                      const FramebufferDesc& fb, UnitTokens& out) {
  if (t->x0 > t->x1 || t->y0 > t->y1) return;
  const int ts = static_cast<int>(cfg.tile_size);
  for (int ty = t->y0 / ts; ty <= t->y1 / ts; ++ty) {
    for (int tx = t->x0 / ts; tx <= t->x1 / ts; ++tx) {
      StampBatch b;
      b.primitive = t;
      for (int sy = ty * ts; sy < (ty + 1) * ts && sy < fb.height; sy += cfg.stamp[1]) {
        for (int sx = tx * ts; sx < (tx + 1) * ts && sx < fb.width; sx += cfg.stamp[0]) {
          const Stamp s = make_stamp(*t, sx, sy, cfg, fb);
          if (s.mask) b.stamps.push_back(s);
        }
      }
      if (!b.stamps.empty()) out[tile_owner(tx, ty, cfg.units)].push_back(std::move(b));
    }
  }
}

// The scene's work for every unit, framed by clear and end_of_frame.
inline UnitTokens front_end(const Scene& scene, const GpuConfig& cfg) {
  UnitTokens out(cfg.units);
  for (auto& u : out) u.push_back(StampBatch{PacketKind::clear, nullptr, {}, {}});
  const FramebufferDesc& fb = scene.framebuffer;
  const golden::GuardBand gb = golden::guard_band_for(fb.width, fb.height);
  int64_t id = 0;
  for (uint32_t d = 0; d < scene.draws.size(); ++d) {
    const Draw& draw = scene.draws[d];
    for (const auto& slots : golden::assemble_triangles(draw.primitive, draw.vertex_count())) {
      const int64_t prim = id++;
      std::array<golden::ShadedVertex, 3> tri;
      for (int k = 0; k < 3; ++k) tri[k] = golden::shade_vertex(scene, draw, slots[k]);
      const auto poly = golden::clip_triangle(tri, gb);
      if (poly.size() < 3) continue;
      std::vector<WindowVertex> win;
      for (const auto& p : poly) win.push_back(golden::to_window(p, fb.width, fb.height));
      for (size_t i = 1; i + 1 < win.size(); ++i) {
        auto t = setup({win[0], win[i], win[i + 1]}, draw.state, d, prim, tri[2].color, fb);
        if (t) rasterize(t, cfg, fb, out);
      }
    }
  }
  for (auto& u : out) u.push_back(StampBatch{PacketKind::end_of_frame, nullptr, {}, {}});
  return out;
}

// ---------------------------------------------------------------------------
// Scenes.

class Rng {
 public:
  explicit Rng(uint32_t seed) : m_gen(seed) {}
  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(m_gen); }
  int below(int n) { return std::uniform_int_distribution<int>(0, n - 1)(m_gen); }
  bool chance(double p) { return std::bernoulli_distribution(p)(m_gen); }

 private:
  std::mt19937 m_gen;
};

// Triangles in clip space: varied sizes, perspective (w in [0.5, 2]), some
// off screen or crossing the near and far planes; with probability `repeat`
// a triangle repeats an earlier one's positions (equal depths).
inline std::vector<glm::vec4> random_positions(Rng& rng, int triangles, double repeat,
                                               std::vector<glm::vec4>* history) {
  std::vector<glm::vec4> p;
  for (int t = 0; t < triangles; ++t) {
    if (history && history->size() >= 3 && rng.chance(repeat)) {
      const int n = static_cast<int>(history->size() / 3);
      const int k = rng.below(n);
      for (int i = 0; i < 3; ++i) p.push_back((*history)[3 * k + i]);
      continue;
    }
    const float cx = rng.uniform(-1.1f, 1.1f), cy = rng.uniform(-1.1f, 1.1f);
    const float size = rng.chance(0.3) ? rng.uniform(0.02f, 0.2f) : rng.uniform(0.2f, 1.6f);
    for (int i = 0; i < 3; ++i) {
      const float w = rng.uniform(0.5f, 2.0f);
      const float x = cx + size * rng.uniform(-1.0f, 1.0f);
      const float y = cy + size * rng.uniform(-1.0f, 1.0f);
      const float z = rng.uniform(-1.1f, 1.1f);
      p.emplace_back(x * w, y * w, z * w, w);
    }
  }
  if (history) history->insert(history->end(), p.begin(), p.end());
  return p;
}

inline std::vector<glm::vec4> random_colors(Rng& rng, size_t n) {
  std::vector<glm::vec4> c(n);
  for (auto& v : c)
    v = {rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0, 1)};
  return c;
}

inline Draw make_draw(std::vector<glm::vec4> positions, std::vector<glm::vec4> colors,
                      const RenderState& st) {
  Draw d;
  d.positions = std::move(positions);
  d.colors = std::move(colors);
  d.state = st;
  return d;
}

inline Scene make_scene(int w, int h, ColorFormat cf, DepthFormat df) {
  Scene s;
  s.framebuffer.width = w;
  s.framebuffer.height = h;
  s.framebuffer.color_format = cf;
  s.framebuffer.depth_format = df;
  s.framebuffer.clear_color = {0.25f, 0.5f, 0.75f, 0.4f};
  s.framebuffer.clear_depth = 0.75f;
  return s;
}

inline void add_random_draw(Scene& s, Rng& rng, int triangles, const RenderState& st, double repeat,
                            std::vector<glm::vec4>* history) {
  auto p = random_positions(rng, triangles, repeat, history);
  auto c = random_colors(rng, p.size());
  s.draws.push_back(make_draw(std::move(p), std::move(c), st));
}

// The frame's registers: the draws' states and first primitive ids, the
// colour and depth buffers at kGuard bytes from each other and from address 0.
inline FrameState frame_state(const Scene& scene) {
  FrameState f;
  f.framebuffer = scene.framebuffer;
  int64_t first = 0;
  for (const Draw& d : scene.draws) {
    DrawState ds;
    ds.primitive = d.primitive;
    ds.state = d.state;
    ds.first_primitive_id = first;
    first += static_cast<int64_t>(golden::assemble_triangles(d.primitive, d.vertex_count()).size());
    f.draws.push_back(ds);
  }
  const FramebufferDesc& fb = scene.framebuffer;
  const uint64_t pixels = static_cast<uint64_t>(fb.width) * fb.height;
  f.color_address = kGuard;
  f.depth_address = f.color_address + pixels * color_bytes_per_pixel(fb.color_format) + kGuard;
  return f;
}

// GpuConfig::baseline() with these units, tile size, stamp, FIFO depth and
// tile cache entries.
inline GpuConfig config(unsigned units, unsigned tile, unsigned sw, unsigned sh, unsigned fifo,
                        unsigned entries) {
  GpuConfig c = GpuConfig::baseline();
  c.units = units;
  c.tile_size = tile;
  c.stamp = {sw, sh};
  c.fifo_depth = fifo;
  c.tile_cache_entries = entries;
  return c;
}

}  // namespace test
}  // namespace gpusim
