// Degenerate geometry (docs/robustness.md, "Degenerate geometry"): NaN and
// infinite coordinates, w = 0 and negative w, coordinates far beyond the guard
// band, zero-area and collinear triangles, out-of-range indices, empty draws,
// 1x1 and 8192x8192 framebuffers. The behaviour is the spec's (dropped and
// counted, or clipped) and must be identical in the cycle model and the golden
// model: frame, counters and per-pixel last writer, under the default
// configuration and an unusual one. run_gpu itself checks conservation and
// throws on a hang. Scenes are built in C++: the scene loader refuses
// non-finite numbers, so this is the only way NaN and Inf reach the pipeline.
// The sanitizer build (scripts/sanitize) runs these to show there is no
// undefined behaviour on any of these paths.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kMax = std::numeric_limits<float>::max();
constexpr float kDenorm = std::numeric_limits<float>::denorm_min();

Scene scene_of(int width, int height, std::vector<Draw> draws) {
  Scene s;
  s.path = "robust_degenerate_test";
  s.framebuffer.width = width;
  s.framebuffer.height = height;
  s.framebuffer.clear_color = glm::vec4(0.1f, 0.2f, 0.3f, 1.0f);
  s.draws = std::move(draws);
  return s;
}

// A raw draw in clip space (mvp = identity), one colour per vertex.
Draw draw_of(std::vector<glm::vec4> positions, PrimitiveType type = PrimitiveType::triangles,
             std::vector<uint32_t> indices = {}) {
  Draw d;
  d.name = "draw";
  d.primitive = type;
  for (size_t i = 0; i < positions.size(); ++i) {
    d.colors.push_back(glm::vec4(0.25f * static_cast<float>(i % 4), 0.5f,
                                 1.0f - 0.125f * static_cast<float>(i % 8), 1.0f));
  }
  d.positions = std::move(positions);
  d.indices = std::move(indices);
  d.state.depth_test = true;
  d.state.depth_func = CompareFunc::lequal;
  return d;
}

// A triangle well inside the screen, to show the frame goes on around the
// degenerate ones.
std::vector<glm::vec4> good_triangle() {
  return {{-0.5f, -0.5f, 0.2f, 1.0f}, {0.5f, -0.5f, 0.2f, 1.0f}, {0.0f, 0.6f, 0.2f, 1.0f}};
}

std::vector<glm::vec4> with_good(std::vector<glm::vec4> v) {
  for (const glm::vec4& p : good_triangle()) v.push_back(p);
  return v;
}

GpuConfig unusual_config() {
  GpuConfig c;
  c.units = 3;
  c.tile_size = 8;
  c.stamp = {2, 2};
  c.fifo_depth = 1;
  c.vertex_cache_entries = 3;
  c.tile_cache_entries = 1;
  return c;
}

// Hierarchical Z must not change a frame or a count (it may only cull tiles
// whose every fragment fails the depth test), so every degenerate scene also
// runs with it on.
GpuConfig hz_config(GpuConfig c) {
  c.hierarchical_z.enabled = true;
  return c;
}

std::string first_difference(const Framebuffer& got, const Framebuffer& want) {
  for (int y = 0; y < got.height; ++y) {
    for (int x = 0; x < got.width; ++x) {
      const size_t p = got.pixel_index(x, y);
      if (std::equal(got.color_at(x, y), got.color_at(x, y) + 4, want.color_at(x, y)) &&
          got.depth[p] == want.depth[p]) {
        continue;
      }
      std::ostringstream os;
      os << "first difference at x=" << x << " y=" << y << ": depth " << got.depth[p] << " vs "
         << want.depth[p];
      return os.str();
    }
  }
  return "";
}

// Runs both models under both configurations; returns the golden counters.
nlohmann::json expect_models_agree(const Scene& scene) {
  const golden::Result want = golden::render(scene);
  for (const GpuConfig& config :
       {GpuConfig{}, unusual_config(), hz_config(GpuConfig{}), hz_config(unusual_config())}) {
    SCOPED_TRACE("units " + std::to_string(config.units) +
                 (config.hierarchical_z.enabled ? ", hierarchical Z" : ""));
    GpuRunOptions options;
    options.record_last_writer = true;
    const GpuRunResult got = run_gpu(scene, config, options);
    EXPECT_TRUE(got.completed);
    EXPECT_TRUE(got.framebuffer == want.framebuffer)
        << first_difference(got.framebuffer, want.framebuffer);
    EXPECT_EQ(got.counts, want.stats);
    EXPECT_TRUE(got.last_writer == want.last_writer);
  }
  return want.stats.to_json();
}

uint64_t count(const nlohmann::json& s, const char* k) {
  return s.at(k).get<uint64_t>();
}

TEST(Degenerate, NaNCoordinatesAreInvalid) {
  std::vector<glm::vec4> v;
  for (int k = 0; k < 4; ++k) {
    glm::vec4 bad(0.1f, 0.1f, 0.1f, 1.0f);
    bad[k] = kNaN;
    v.push_back({-0.9f, -0.9f, 0.0f, 1.0f});
    v.push_back(bad);
    v.push_back({0.9f, 0.9f, 0.0f, 1.0f});
  }
  const nlohmann::json s = expect_models_agree(scene_of(64, 48, {draw_of(with_good(v))}));
  EXPECT_EQ(count(s, "triangles_in"), 5u);
  EXPECT_EQ(count(s, "triangles_invalid"), 4u);
  EXPECT_EQ(count(s, "triangles_rasterized"), 1u);
}

TEST(Degenerate, InfiniteCoordinatesAreInvalid) {
  std::vector<glm::vec4> v;
  for (float inf : {kInf, -kInf}) {
    for (int k = 0; k < 4; ++k) {
      glm::vec4 bad(0.1f, 0.1f, 0.1f, 1.0f);
      bad[k] = inf;
      v.push_back({-0.9f, -0.9f, 0.0f, 1.0f});
      v.push_back({0.9f, -0.9f, 0.0f, 1.0f});
      v.push_back(bad);
    }
  }
  const nlohmann::json s = expect_models_agree(scene_of(64, 48, {draw_of(with_good(v))}));
  EXPECT_EQ(count(s, "triangles_invalid"), 8u);
  EXPECT_EQ(count(s, "triangles_rasterized"), 1u);
}

// Finite positions and a finite matrix whose product overflows to infinity
// (or gives NaN from inf - inf): invalid too, in both models.
TEST(Degenerate, MatrixOverflowIsInvalid) {
  Draw d = draw_of(with_good(
      {{3e38f, 0.0f, 0.0f, 1.0f}, {-3e38f, 0.5f, 0.0f, 1.0f}, {0.0f, 3e38f, 0.0f, 1.0f}}));
  Draw big = d;
  big.mvp = glm::mat4(4.0f);  // x, y, z scaled by 4: 1.2e39 overflows
  big.mvp[3][3] = 1.0f;
  big.model_view = big.mvp;
  Draw mixed = d;
  mixed.mvp = glm::mat4(1.0f);
  mixed.mvp[1][0] = kMax;  // x += FLT_MAX * y: inf for y > 0
  mixed.mvp[0][1] = -kMax;
  mixed.model_view = mixed.mvp;
  const nlohmann::json s = expect_models_agree(scene_of(64, 64, {big, mixed}));
  EXPECT_GE(count(s, "triangles_invalid"), 2u);
}

TEST(Degenerate, NonFiniteColoursClampToZero) {
  Draw d = draw_of(good_triangle());
  d.colors = {{kNaN, 1.0f, kInf, -kInf}, {1.0f, kNaN, 0.5f, kNaN}, {-kInf, kInf, kNaN, 1.0f}};
  Draw flat = d;
  flat.state.shading = Shading::flat;
  flat.positions = {{-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}, {-1, 1, 0.5f, 1}};
  Draw blended = d;
  blended.state.blend = true;
  blended.state.blend_src = BlendFactor::src_alpha;
  blended.state.blend_dst = BlendFactor::one_minus_src_alpha;
  blended.positions = {{-1, 1, 0.1f, 1}, {1, -1, 0.1f, 1}, {1, 1, 0.1f, 1}};
  for (ColorFormat format : {ColorFormat::rgba8, ColorFormat::rgba16f}) {
    Scene s = scene_of(32, 32, {d, flat, blended});
    s.framebuffer.color_format = format;
    const nlohmann::json c = expect_models_agree(s);
    EXPECT_EQ(count(c, "triangles_rasterized"), 3u);
  }
}

TEST(Degenerate, ZeroAndNegativeW) {
  const std::vector<glm::vec4> v = {
      // One vertex at w = 0 (at infinity): clipped by the w plane.
      {-0.5f, -0.5f, 0.0f, 1.0f},
      {0.5f, -0.5f, 0.0f, 1.0f},
      {0.2f, 0.9f, 0.0f, 0.0f},
      // All three at w = 0, and all at the origin: clipped away.
      {1.0f, 0.0f, 0.0f, 0.0f},
      {0.0f, 1.0f, 0.0f, 0.0f},
      {-1.0f, -1.0f, 0.0f, 0.0f},
      {0.0f, 0.0f, 0.0f, 0.0f},
      {0.0f, 0.0f, 0.0f, 0.0f},
      {0.0f, 0.0f, 0.0f, 0.0f},
      // Negative zero.
      {-0.5f, -0.5f, 0.0f, -0.0f},
      {0.5f, -0.5f, 0.0f, 1.0f},
      {0.2f, 0.9f, 0.0f, 1.0f},
      // All behind the eye (w < 0): clipped away, even though x/w, y/w land
      // on screen.
      {0.5f, 0.5f, -0.5f, -1.0f},
      {-0.5f, 0.5f, -0.5f, -1.0f},
      {0.0f, -0.5f, -0.5f, -1.0f},
      // Crossing w = 0: a part kept.
      {-0.5f, -0.5f, 0.1f, 1.0f},
      {0.5f, -0.5f, 0.1f, -1.0f},
      {0.0f, 0.5f, 0.1f, 1.0f},
      {-0.5f, -0.5f, 0.1f, -2.0f},
      {0.5f, 0.5f, 0.1f, 0.5f},
      {0.9f, -0.8f, 0.1f, -0.001f},
      // w just above 0: enormous x/w, within the guard band only after clipping.
      {-0.5f, -0.5f, 0.0f, 1e-30f},
      {0.5f, -0.5f, 0.0f, 1.0f},
      {0.0f, 0.5f, 0.0f, kDenorm},
  };
  const nlohmann::json s = expect_models_agree(scene_of(64, 48, {draw_of(v)}));
  EXPECT_EQ(count(s, "triangles_in"), 8u);
  EXPECT_EQ(count(s, "triangles_invalid"), 0u);
  EXPECT_GE(count(s, "triangles_clipped_away"), 3u);
  EXPECT_GE(count(s, "triangles_clipped"), 3u);
}

TEST(Degenerate, FarBeyondTheGuardBand) {
  std::vector<glm::vec4> v;
  for (float far : {1e5f, 1e6f, 1e10f, 1e20f, 1e30f, 1e38f, 3e38f, kMax}) {
    // A vertex far away beside two on screen, in x and in y, both signs.
    v.insert(v.end(),
             {{-0.5f, -0.5f, 0.3f, 1.0f}, {0.5f, -0.5f, 0.3f, 1.0f}, {far, 0.2f, 0.3f, 1.0f}});
    v.insert(v.end(),
             {{-0.5f, -0.5f, 0.3f, 1.0f}, {-far, 0.5f, 0.3f, 1.0f}, {0.5f, 0.5f, 0.3f, 1.0f}});
    v.insert(v.end(),
             {{-0.5f, 0.5f, 0.3f, 1.0f}, {0.5f, -0.5f, 0.3f, 1.0f}, {0.1f, far, 0.3f, 1.0f}});
    v.insert(v.end(),
             {{-0.5f, 0.5f, 0.3f, 1.0f}, {0.1f, -far, 0.3f, 1.0f}, {0.5f, 0.5f, 0.3f, 1.0f}});
    // Far on both sides at once, and far in depth.
    v.insert(v.end(), {{-far, -far, 0.3f, 1.0f}, {far, -far, 0.3f, 1.0f}, {0.0f, far, 0.3f, 1.0f}});
    v.insert(v.end(),
             {{-0.5f, -0.5f, far, 1.0f}, {0.5f, -0.5f, -far, 1.0f}, {0.0f, 0.5f, 0.0f, 1.0f}});
    // Huge w with huge x: on screen.
    v.insert(
        v.end(),
        {{-far, -far, 0.0f, far}, {far * 0.5f, -far, 0.0f, far}, {0.0f, far * 0.5f, 0.0f, far}});
  }
  Draw lines = draw_of(v);
  Draw culled = draw_of(v);
  culled.state.cull = CullMode::back;
  culled.state.offset_factor = 2.0f;
  culled.state.offset_units = 1.0f;
  const nlohmann::json s = expect_models_agree(scene_of(97, 61, {lines, culled}));
  EXPECT_EQ(count(s, "triangles_invalid"), 0u);
  EXPECT_GT(count(s, "triangles_clipped"), 0u);
}

// Float rounding in the clipper on extreme inputs lands cut vertices far
// outside the guard band or at infinity: the b - a of a cut overflows near
// the float range, and a cut next to w = 0 divides a rounding error of large
// coordinates by w = 2^-32. Snapping saturates (docs/pipeline-spec.md,
// section 6); before it did, the conversion to int overflowed (undefined
// behaviour, caught by the sanitizer build) and the models disagreed.
TEST(Degenerate, ClipRoundingOnExtremeInputs) {
  std::vector<glm::vec4> v;
  for (float x : {1e4f, 1e6f, 3.3e7f, 1e8f, 3e10f, 1e20f}) {
    for (float w : {-1e-3f, -0.7f, -3.0f}) {
      v.insert(v.end(),
               {{x, 0.3f * x, 0.1f, 1.0f}, {-0.7f * x, x, 0.2f, w}, {0.1f, -x, 0.3f, 1.0f}});
      v.insert(v.end(), {{0.25f, 0.5f, 0.0f, 1.0f}, {x, -x, 0.0f, w}, {-x, 0.75f, 0.0f, 0.5f}});
    }
  }
  for (float big : {kMax, -kMax, 3e38f}) {
    v.insert(v.end(), {{big, -big, 0.0f, 1.0f}, {-big, big, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f, 1.0f}});
    v.insert(v.end(), {{big, big, big, big}, {-big, -big, 0.5f, big}, {0.1f, 0.2f, 0.0f, -big}});
  }
  const nlohmann::json s = expect_models_agree(scene_of(8192, 2, {draw_of(v)}));
  EXPECT_EQ(count(s, "triangles_invalid"), 0u);
  EXPECT_GT(count(s, "triangles_clipped"), 0u);

  // The same vertices as lines, strips, loops and points, and as triangles
  // drawn as lines or points: cuts and polygon-mode vertices far outside,
  // where snapping and the point's corner saturate (spec sections 6, 8c).
  std::vector<Draw> draws;
  for (const PrimitiveType type : {PrimitiveType::lines, PrimitiveType::line_strip,
                                   PrimitiveType::line_loop, PrimitiveType::points}) {
    for (const LineRasterization rule :
         {LineRasterization::diamond_exit, LineRasterization::bresenham}) {
      Draw d = draw_of(v, type);
      d.state.line_rasterization = rule;
      d.state.line_width = rule == LineRasterization::bresenham ? 3.0f : 2.0f;
      d.state.point_size = 5.5f;
      draws.push_back(d);
    }
  }
  for (const PolygonMode mode : {PolygonMode::line, PolygonMode::point}) {
    Draw d = draw_of(v);
    d.state.polygon_mode = mode;
    d.state.point_size = 9.0f;
    draws.push_back(d);
  }
  const nlohmann::json lp = expect_models_agree(scene_of(8192, 2, draws));
  EXPECT_GT(count(lp, "lines_clipped"), 0u);
  EXPECT_GT(count(lp, "points_clipped_away"), 0u);
  EXPECT_GT(count(lp, "triangles_unfilled"), 0u);
}

TEST(Degenerate, ZeroAreaAndCollinear) {
  const float e = 1.0f / 65536.0f;  // 1/8 subpixel on a 64-pixel screen
  const std::vector<glm::vec4> v = {
      // All three vertices equal.
      {0.1f, 0.1f, 0.0f, 1.0f},
      {0.1f, 0.1f, 0.0f, 1.0f},
      {0.1f, 0.1f, 0.0f, 1.0f},
      // Collinear, along a diagonal and along an axis.
      {-0.5f, -0.5f, 0.0f, 1.0f},
      {0.0f, 0.0f, 0.0f, 1.0f},
      {0.5f, 0.5f, 0.0f, 1.0f},
      {-0.5f, 0.25f, 0.0f, 1.0f},
      {0.5f, 0.25f, 0.0f, 1.0f},
      {0.0f, 0.25f, 0.0f, 1.0f},
      // Distinct, but collinear once snapped to 1/256 pixel.
      {-0.5f, -0.5f, 0.0f, 1.0f},
      {0.5f, 0.5f, 0.0f, 1.0f},
      {0.0f, e, 0.0f, 1.0f},
      // A sliver one subpixel wide, exactly through pixel centres.
      {-1.0f, 0.015625f, 0.0f, 1.0f},
      {1.0f, 0.015625f, 0.0f, 1.0f},
      {1.0f, 0.015625f + 1.0f / 8192.0f, 0.0f, 1.0f},
      // Two vertices equal.
      {-0.5f, -0.5f, 0.0f, 1.0f},
      {-0.5f, -0.5f, 0.0f, 1.0f},
      {0.5f, 0.5f, 0.0f, 1.0f},
  };
  for (PrimitiveType type :
       {PrimitiveType::triangles, PrimitiveType::triangle_strip, PrimitiveType::triangle_fan}) {
    Draw d = draw_of(with_good(v), type);
    d.state.offset_factor = 1.0f;
    d.state.offset_units = 4.0f;
    const nlohmann::json s = expect_models_agree(scene_of(64, 64, {d}));
    if (type == PrimitiveType::triangles) {
      EXPECT_GE(count(s, "triangles_degenerate"), 5u);
      EXPECT_GE(count(s, "triangles_rasterized"), 1u);
    }
  }
}

TEST(Degenerate, OutOfRangeIndices) {
  const std::vector<glm::vec4> v = good_triangle();
  const uint32_t big = std::numeric_limits<uint32_t>::max();
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 1, 3, big, 1, 2, 2, 1, 0, 0, big - 1, 2, 1};
  std::vector<Draw> draws;
  for (PrimitiveType type :
       {PrimitiveType::triangles, PrimitiveType::triangle_strip, PrimitiveType::triangle_fan}) {
    draws.push_back(draw_of(v, type, indices));
  }
  // Indexed, but no positions at all: every triangle invalid.
  Draw none = draw_of({}, PrimitiveType::triangles, {0, 1, 2, 2, 1, 0});
  draws.push_back(none);
  const nlohmann::json s = expect_models_agree(scene_of(40, 30, draws));
  // Lists: 5 triangles, 2 with a bad index (3, big), 1 with big - 1.
  EXPECT_GE(count(s, "triangles_invalid"), 3u + 2u);
  EXPECT_GE(count(s, "triangles_rasterized"), 3u);
}

TEST(Degenerate, EmptyAndShortDraws) {
  std::vector<Draw> draws;
  draws.push_back(draw_of({}));              // nothing
  draws.push_back(draw_of({{0, 0, 0, 1}}));  // one vertex
  draws.push_back(draw_of({{0, 0, 0, 1}, {1, 0, 0, 1}}, PrimitiveType::triangle_strip));
  draws.push_back(draw_of({{0, 0, 0, 1}, {1, 0, 0, 1}}, PrimitiveType::triangle_fan));
  draws.push_back(draw_of(good_triangle(), PrimitiveType::triangles, {0, 1}));    // 2 indices
  draws.push_back(draw_of(with_good({{0, 0, 0, 1}}), PrimitiveType::triangles));  // 4: partial
  draws.push_back(draw_of(good_triangle(), PrimitiveType::triangles, {}));
  const nlohmann::json s = expect_models_agree(scene_of(16, 16, draws));
  EXPECT_EQ(count(s, "triangles_in"), 2u);
  // No draws at all: just the clear.
  const nlohmann::json empty = expect_models_agree(scene_of(16, 16, {}));
  EXPECT_EQ(count(empty, "triangles_in"), 0u);
  EXPECT_EQ(count(empty, "fragments_generated"), 0u);
}

TEST(Degenerate, TinyFramebuffers) {
  // Triangles that cover a pixel's centre, miss it, and have an edge exactly
  // through it (fill rule), on 1x1, 1xN, Nx1 and 2x3 framebuffers.
  const std::vector<glm::vec4> v = {
      {-1, -1, 0.5f, 1}, {3, -1, 0.5f, 1},     {-1, 3, 0.5f, 1},      // covers everything
      {-1, -1, 0.2f, 1}, {-0.5f, -1, 0.2f, 1}, {-1, -0.5f, 0.2f, 1},  // misses the centre
      {0, -1, 0.1f, 1},  {1, -1, 0.1f, 1},     {0, 1, 0.1f, 1},       // edge through x = 0
      {-1, 0, 0.0f, 1},  {1, 0, 0.0f, 1},      {0, 1, 0.0f, 1},       // edge through y = 0
      {-2, -2, 0.3f, 1}, {2, -2, 0.3f, 1},     {0, 2, 0.3f, 1},       // beyond the screen
  };
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {1, 7}, {7, 1}, {2, 3}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    for (DepthFormat depth : {DepthFormat::unorm16, DepthFormat::unorm24, DepthFormat::float32}) {
      Scene s = scene_of(w, h, {draw_of(v), draw_of(v, PrimitiveType::triangle_strip)});
      s.framebuffer.depth_format = depth;
      expect_models_agree(s);
    }
  }
}

// The largest framebuffer the scene format allows: small triangles in the
// far corners, one across the middle, one beyond the edges. About 2.5 GiB.
TEST(Degenerate, LargestFramebuffer) {
  const float p = 2.0f / 8192.0f;  // one pixel in NDC
  const std::vector<glm::vec4> v = {
      {1 - 3 * p, 1 - 3 * p, 0.5f, 1},
      {1, 1 - 3 * p, 0.5f, 1},
      {1, 1, 0.5f, 1},  // top right
      {-1, -1, 0.5f, 1},
      {-1 + 3 * p, -1, 0.5f, 1},
      {-1, -1 + 3 * p, 0.5f, 1},  // bottom left
      {-0.01f, -0.01f, 0.4f, 1},
      {0.01f, -0.01f, 0.4f, 1},
      {0.0f, 0.01f, 0.4f, 1},  // middle
      {0.99f, -2.0f, 0.3f, 1},
      {3.0f, -2.0f, 0.3f, 1},
      {0.99f, -0.99f, 0.3f, 1},  // edges
  };
  const nlohmann::json s = expect_models_agree(scene_of(8192, 8192, {draw_of(v)}));
  EXPECT_EQ(count(s, "triangles_rasterized"), 4u);
}

// A seeded soup of every kind of value above, in every primitive type and
// several render states: the models must agree on all of it.
TEST(Degenerate, RandomSoupOfSpecialValues) {
  uint64_t state = 0x9E3779B97F4A7C15ull;
  const auto next = [&] {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  };
  const float specials[] = {0.0f,  -0.0f,   1.0f,   -1.0f, 0.5f,  kNaN,   kInf, -kInf, kMax,
                            -kMax, kDenorm, 1e-30f, 1e30f, 3e38f, -3e38f, 1e6f, 2.0f,  1e-7f};
  const auto value = [&] {
    const uint64_t r = next();
    if (r % 4 == 0) return specials[(r >> 8) % (sizeof specials / sizeof specials[0])];
    // Mostly ordinary: -2..2 on a fine grid.
    return static_cast<float>(static_cast<int64_t>((r >> 8) % 4097) - 2048) / 1024.0f;
  };
  std::vector<Draw> draws;
  for (int d = 0; d < 12; ++d) {
    std::vector<glm::vec4> v;
    const int n = static_cast<int>(next() % 40);
    for (int i = 0; i < n; ++i) {
      glm::vec4 p(value(), value(), value(), value());
      if (next() % 3 != 0) p.w = std::fabs(p.w) + 0.5f;  // most in front of the eye
      v.push_back(p);
    }
    std::vector<uint32_t> indices;
    if (d % 3 == 1) {
      for (int i = 0; i < n + 3; ++i) indices.push_back(static_cast<uint32_t>(next() % (n + 2)));
    }
    Draw draw = draw_of(v, static_cast<PrimitiveType>(d % 3), indices);
    draw.state.cull = static_cast<CullMode>(next() % 3);
    draw.state.depth_func = static_cast<CompareFunc>(next() % 8);
    draw.state.blend = next() % 2 == 0;
    draw.state.blend_src = static_cast<BlendFactor>(next() % 11);
    draw.state.blend_dst = static_cast<BlendFactor>(next() % 11);
    draw.state.shading = next() % 2 ? Shading::flat : Shading::gouraud;
    draw.state.blend_equation = static_cast<BlendEquation>(next() % 3);
    draw.state.front_face = next() % 2 ? FrontFace::ccw : FrontFace::cw;
    draw.state.depth_test = next() % 4 != 0;
    draw.state.depth_write = next() % 3 != 0;
    for (bool& m : draw.state.color_mask) m = next() % 5 != 0;
    const bool offset = next() % 2 == 0;
    draw.state.offset_factor = offset ? value() : 0.0f;
    draw.state.offset_units = offset ? value() : 0.0f;
    if (!std::isfinite(draw.state.offset_factor)) draw.state.offset_factor = 1.0f;
    if (!std::isfinite(draw.state.offset_units)) draw.state.offset_units = -1.0f;
    draws.push_back(draw);
  }
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {33, 17}, {128, 96}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    Scene s = scene_of(w, h, draws);
    s.framebuffer.color_format = w == 33 ? ColorFormat::rgba16f : ColorFormat::rgba8;
    s.framebuffer.depth_format = w == 33 ? DepthFormat::float32 : DepthFormat::unorm24;
    expect_models_agree(s);
  }
}

}  // namespace
}  // namespace gpusim
