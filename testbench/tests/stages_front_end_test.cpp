// The geometry front end as a chain (command processor -> vertex fetch ->
// vertex shader -> clipper, testbench/tests/front_end_bench.h) against the
// golden model's rules: scenes are built here (or loaded), put into a Memory
// and a FrameState as a driver would, run through the four stages, and the
// ClippedPrimitive stream is compared with what golden::shade_vertex,
// assemble_triangles, clip_triangle and to_window give, bit for bit, for
// every vertex cache size and FIFO depth and under random FIFO stalls; and
// the exact timing of simple cases through all four stages. The stages' own
// tests on the same bench are in stages_vertex_fetch_test.cpp (cache and
// memory traffic), stages_vertex_shader_test.cpp and stages_clipper_test.cpp
// (lines, points, polygon mode). One sc_start per TEST (ctest runs each in
// its own process).
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"
#include "testbench/tests/front_end_bench.h"

namespace gpusim {
namespace {

using namespace test;
using sc_core::sc_time;

void expect_clipper_stats(const FrontEndBench& b, const golden::Stats& s) {
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_in"), s.triangles_in);
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_invalid"), s.triangles_invalid);
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_clipped_away"), s.triangles_clipped_away);
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_clipped"), s.triangles_clipped);
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_after_clip"), s.triangles_after_clip);
}

// ---------------------------------------------------------------------------
// Scenes only these tests use.

// Out-of-range indices and non-finite positions, in every primitive type.
Scene invalid_scene() {
  std::mt19937 rng(7);
  Scene s;
  s.framebuffer.width = 200;
  s.framebuffer.height = 100;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (PrimitiveType p :
       {PrimitiveType::triangles, PrimitiveType::triangle_strip, PrimitiveType::triangle_fan}) {
    Draw d = random_draw(rng, p, 40, true, 0);
    d.positions[3] = {nan, 0.0f, 0.0f, 1.0f};
    d.positions[10] = {0.0f, 0.0f, inf, 1.0f};
    d.positions[17] = {0.1f, 0.1f, 0.1f, -inf};
    d.colors[20] = {nan, nan, 2.0f, -1.0f};  // colours clamp: NaN -> 0; harmless
    for (uint32_t i = 0; i < 90; ++i) d.indices.push_back((i * 7 + i / 5) % 40);
    d.indices[5] = 40;            // one past the end
    d.indices[31] = 0xFFFFFFFFu;  // at a batch edge
    d.indices[32] = 1000;
    d.indices[60] = 3;  // NaN vertex through the cache too
    d.indices[61] = 3;
    s.draws.push_back(d);
  }
  // Non-indexed with NaN: every triangle using it is dropped.
  Draw d = random_draw(rng, PrimitiveType::triangle_strip, 20, false, 0);
  d.positions[9] = {0.0f, nan, 0.0f, 1.0f};
  s.draws.push_back(d);
  return s;
}

// Runs `scene` through the front end and checks it against the golden rules.
void run_and_compare(const Scene& scene, GpuConfig config, uint64_t stall_seed = 0) {
  const LoadedFrame frame = load_frame(scene);
  const Expected want = expected_stream(scene);
  FrontEndBench bench("bench", config, frame);
  if (stall_seed != 0) bench.inject_stalls(stall_seed, config);
  sc_core::sc_start();
  if (stall_seed != 0) {
    // The stalls happened, on every boundary.
    EXPECT_GT(bench.command_to_fetch.stats().injected_stalls, 0u);
    EXPECT_GT(bench.fetch_to_shader.stats().injected_stalls, 10u);
    EXPECT_GT(bench.shader_to_clipper.stats().injected_stalls, 10u);
    EXPECT_GT(bench.results.stats().injected_stalls, 100u);
  }
  expect_stream(bench.got, want);
  expect_clipper_stats(bench, want.stats);
  // The golden renderer's own counters agree with the expected stream.
  const golden::Stats g = golden::render(scene).stats;
  EXPECT_EQ(want.stats.triangles_in, g.triangles_in);
  EXPECT_EQ(want.stats.triangles_invalid, g.triangles_invalid);
  EXPECT_EQ(want.stats.triangles_clipped_away, g.triangles_clipped_away);
  EXPECT_EQ(want.stats.triangles_clipped, g.triangles_clipped);
  EXPECT_EQ(want.stats.triangles_after_clip, g.triangles_after_clip);
  // Hits read what misses wrote, one for one.
  EXPECT_EQ(bench.stat(bench.fetch.stats(), "cache_hits"),
            bench.stat(bench.clipper.stats(), "cache_reads"));
  EXPECT_EQ(bench.stat(bench.fetch.stats(), "vertices_fetched"),
            bench.stat(bench.shader.stats(), "vertices_shaded"));
}

// ---------------------------------------------------------------------------
// Golden equivalence.

TEST(FrontEnd, RandomListsStripsFansMatchGolden) {
  const Scene scene = random_scene(1);
  // The scene must exercise what it claims to.
  const Expected e = expected_stream(scene);
  EXPECT_GT(e.stats.triangles_clipped, 50u);
  EXPECT_GT(e.stats.triangles_clipped_away, 30u);
  EXPECT_GT(e.stats.triangles_after_clip,
            e.stats.triangles_in - e.stats.triangles_invalid - e.stats.triangles_clipped_away);
  run_and_compare(scene, GpuConfig{});
}

// Every cache size gives the same stream (and the mirror holds): none, one
// entry (hits only on immediate repeats), odd, default, larger than a draw.
class FrontEndCacheSizes : public ::testing::TestWithParam<unsigned> {};
TEST_P(FrontEndCacheSizes, RandomSceneMatchesGolden) {
  run_and_compare(random_scene(2), config_with(GetParam(), 2));
}
INSTANTIATE_TEST_SUITE_P(Entries, FrontEndCacheSizes, ::testing::Values(0u, 1u, 7u, 32u, 4096u));

TEST(FrontEnd, DepthOneFifosMatchGolden) {
  run_and_compare(random_scene(3), config_with(32, 1));
}

TEST(FrontEnd, InvalidIndicesAndNonFinitePositionsAreDropped) {
  const Scene scene = invalid_scene();
  const Expected e = expected_stream(scene);
  EXPECT_GT(e.stats.triangles_invalid, 20u);
  run_and_compare(scene, config_with(8, 4));
}

TEST(FrontEnd, LitIndexedSphereMatchesGolden) {
  const Scene scene = lit_sphere_scene();
  const Expected e = expected_stream(scene);
  EXPECT_GT(e.stats.triangles_clipped, 0u);  // the near plane cuts the sphere
  run_and_compare(scene, GpuConfig{});
}

TEST(FrontEnd, SpiderMeshMatchesGolden) {
  const Scene scene = spider_scene();
  ASSERT_TRUE(scene.draws.at(0).lighting);
  run_and_compare(scene, GpuConfig{});
}

TEST(FrontEnd, RandomStallsChangeNoOutput) {
  const Scene scene = random_scene(4);
  const GpuConfig config = config_with(16, 2);
  run_and_compare(scene, config, /*stall_seed=*/99);
}

// ---------------------------------------------------------------------------
// Timing, the documented defaults: command processor ii 1 / latency 2, vertex fetch 1 / 2,
// vertex shader 4 / 24, clipper 2 / 8; memory latency 20, 32 bytes/cycle;
// 1 GHz. These benches send only the draw and end_of_frame, both written by
// the source at time 0; the lists are the cycles at which the sink reads each
// result.

// The costs the comments below assume, pinned so that a change of the
// defaults does not silently change what these tests check.
GpuConfig timing_config() {
  GpuConfig c;
  c.clock_mhz = 1000.0;
  c.stages["command_processor"] = {1, 2};
  c.stages["vertex_fetch"] = {1, 2};
  c.stages["vertex_shader"] = {4, 24};
  c.stages["clipper"] = {2, 8};
  c.memory = {20, 32};
  c.fifo_depth = 16;
  c.vertex_cache_entries = 32;
  return c;
}

void run_timing(const Scene& scene, const std::vector<double>& want,
                const GpuConfig& config = timing_config()) {
  const LoadedFrame frame = load_frame(scene);
  FrontEndBench bench("bench", config, frame);
  bench.script = {{PacketKind::work, 0}, {PacketKind::end_of_frame, 0}};
  sc_core::sc_start();
  std::vector<double> cycles;
  for (const sc_time& t : bench.times) cycles.push_back(t / config.cycle());
  EXPECT_EQ(cycles, want);
}

TEST(FrontEndTiming, OneTriangle) {
  // command processor: draw at 0, busy 1, readable at 3; end of frame
  //   read at 1, readable at 4.
  // fetch: draw at 3; 3 positions in one 48-byte burst: bus 2 cycles + 20
  //   = 22 of memory time; busy 3 x 1 -> 6; readable at 3 + max(3, 22) + 2
  //   = 27. End of frame: 6 -> 7, readable 9 (behind the batch).
  // shader: batch at 27, 3 vertices x 4 = 12 -> 39, readable 63; end of
  //   frame 39 -> 43, readable 67.
  // clipper: batch at 63, 1 triangle x 2 -> 65, readable 73; end of frame
  //   67 -> 69, readable 77.
  Scene scene;
  Draw d;
  d.positions = {{-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, 0.0f, 1.0f}};
  scene.draws = {d};
  run_timing(scene, {73, 77});
}

TEST(FrontEndTiming, IndexedWithColorsAndCacheHits) {
  // fetch: draw at 3; 6 indices (24 B) bus [3, 4), back at 4 + 20 = 24;
  //   misses 0 1 2 3 (2 and 1 hit) are one burst: positions 64 B bus
  //   [24, 26), colours 64 B bus [26, 28), done at 28 + 20 = 48: memory time
  //   45; busy 6 x 1 -> 9; readable at 3 + max(6, 45) + 2 = 50. End of
  //   frame 9 -> 10.
  // shader: batch at 50, 4 new vertices x 4 = 16 -> 66, readable 90; end
  //   of frame 66 -> 70, readable 94.
  // clipper: batch at 90, 2 triangles x 2 = 4 -> 94, both readable 102;
  //   end of frame 94 -> 96, readable 104.
  Scene scene;
  Draw d;
  d.positions = {{-0.5f, -0.5f, 0.0f, 1.0f},
                 {0.5f, -0.5f, 0.0f, 1.0f},
                 {0.0f, 0.5f, 0.0f, 1.0f},
                 {0.9f, 0.5f, 0.0f, 1.0f}};
  d.colors.assign(4, glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
  d.indices = {0, 1, 2, 2, 1, 3};
  scene.draws = {d};
  run_timing(scene, {102, 102, 104});
}

TEST(FrontEndTiming, ClippedTrianglePaysPerOutputTriangle) {
  // One triangle with one vertex behind the near plane: a quad, 2 triangles.
  // fetch as in OneTriangle: batch readable 27, shader readable 63.
  // clipper: (1 + 1 extra) x 2 = 4 -> 67, both readable 75; end of frame
  //   (readable 67) read at 67 -> 69, readable 77.
  Scene scene;
  Draw d;
  d.positions = {{-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, -3.0f, 1.0f}};
  scene.draws = {d};
  const Expected e = expected_stream(scene);
  ASSERT_EQ(e.triangles.size(), 2u);
  run_timing(scene, {75, 75, 77});
}

TEST(FrontEndTiming, StageCostsFromConfig) {
  // Same triangle as OneTriangle with other costs and a slow, narrow memory:
  // cp ii 3 lat 1: draw readable 4, end of frame 3 -> 6, readable 7.
  // fetch ii 2 lat 5: draw at 4; 48 B at 8 B/cycle = 6 bus cycles + 50 =
  //   56 of memory time; busy 3 x 2 -> 10; readable 4 + max(6, 56) + 5 =
  //   65; end of frame 10 -> 12, readable 17.
  // shader ii 1 lat 3: 65 -> 68, readable 71; end of frame 68 -> 69,
  //   readable 72.
  // clipper ii 5 lat 0: 71 -> 76, readable 76; end of frame 76 -> 81.
  GpuConfig config = timing_config();
  config.stages["command_processor"] = {3, 1};
  config.stages["vertex_fetch"] = {2, 5};
  config.stages["vertex_shader"] = {1, 3};
  config.stages["clipper"] = {5, 0};
  config.memory = {50, 8};
  Scene scene;
  Draw d;
  d.positions = {{-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, 0.0f, 1.0f}};
  scene.draws = {d};
  run_timing(scene, {76, 81}, config);
}

TEST(FrontEndTiming, LineStripPaysPerLine) {
  // fetch: 4 positions, one 64-byte burst: bus 2 + 20 = 22 of memory time;
  //   busy 4; readable 3 + 22 + 2 = 27; end of frame readable 10.
  // shader: 4 vertices x 4 = 16 -> 43, readable 67; end of frame 43 -> 47,
  //   readable 71.
  // clipper: 3 lines x 2 = 6 -> 73, readable 81; end of frame 73 -> 75,
  //   readable 83.
  Scene scene;
  Draw d;
  d.primitive = PrimitiveType::line_strip;
  for (size_t i = 0; i < 4; ++i) d.positions.push_back(strip_vertex(i));
  scene.draws = {d};
  run_timing(scene, {81, 81, 81, 83});
}

TEST(FrontEndTiming, PolygonModePaysPerEmittedLine) {
  // As OneTriangle to the clipper (batch at 63); the triangle drawn as 3
  // lines costs 1 + 2 extra: 3 x 2 = 6 -> 69, readable 77; end of frame
  // (readable 67) at 69 -> 71, readable 79. Culled, it costs its one: 63 ->
  // 65, and the end of frame 67 -> 69, readable 77.
  Scene scene;
  Draw d;
  d.positions = kCcw;
  d.state.polygon_mode = PolygonMode::line;
  scene.draws = {d};
  run_timing(scene, {77, 77, 77, 79});
}

TEST(FrontEndTiming, CulledPolygonModeTrianglePaysOne) {
  Scene scene;
  Draw d;
  d.positions = kCcw;
  d.state.polygon_mode = PolygonMode::line;
  d.state.cull = CullMode::front;
  scene.draws = {d};
  run_timing(scene, {77});
}

}  // namespace
}  // namespace gpusim
