// Hierarchical Z through the whole GPU (stages/tile_rasterizer.h,
// "Hierarchical Z"): the cycles and counters of a culled layer, derived from
// the documented cost model, and an update's latency.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

Draw quad(float z) {
  Draw d;
  d.name = "layer";
  d.primitive = PrimitiveType::triangles;
  d.positions = {{-1, -1, z, 1}, {1, -1, z, 1}, {-1, 1, z, 1},
                 {1, -1, z, 1},  {1, 1, z, 1},  {-1, 1, z, 1}};
  d.state.depth_test = true;
  d.state.depth_func = CompareFunc::less;
  return d;
}

// 256x256: a near full-screen layer (clip z -0.5, window 0.25), `gap`
// triangles wholly outside the view volume (the front end's work only, so
// the depth test finishes the near layer before the far one reaches the
// rasterizer), then the same layer behind it (clip z 0.5).
Scene occluded_layer(int gap) {
  Scene s;
  s.path = "hiz_test";
  s.framebuffer.width = 256;
  s.framebuffer.height = 256;
  s.draws.push_back(quad(-0.5f));
  Draw away;
  away.name = "outside";
  away.primitive = PrimitiveType::triangles;
  for (int i = 0; i < gap; ++i) {
    away.positions.insert(away.positions.end(), {{3, 3, 0, 1}, {4, 3, 0, 1}, {3, 4, 0, 1}});
  }
  if (gap > 0) s.draws.push_back(away);
  s.draws.push_back(quad(0.5f));
  return s;
}

// One unit, 16x16 tiles, 4x4 stamps, a memory that never stalls.
GpuConfig config(bool hz, unsigned update_latency = 4) {
  GpuConfig c = GpuConfig::baseline();
  c.units = 1;
  c.tile_size = 16;
  c.stamp = {4, 4};
  c.memory.latency = 0;
  c.memory.bytes_per_cycle = 65536;
  c.tile_cache_entries = 1024;
  c.hierarchical_z.enabled = hz;
  c.hierarchical_z.update_latency = update_latency;
  return c;
}

GpuRunResult run(const Scene& scene, const GpuConfig& c) {
  GpuRunResult r = run_gpu(scene, c, {});
  EXPECT_TRUE(r.completed);
  EXPECT_EQ(r.framebuffer, golden::render(scene).framebuffer);
  return r;
}

uint64_t counter(const GpuRunResult& r, const char* stage, const char* name) {
  return r.timing.at("stages").at(stage).at(name).get<uint64_t>();
}

// Each triangle of a full-screen layer keeps 136 of the 256 tiles after the
// coverage test (120 accepted, 16 on the diagonal; sim_cycles_test's
// FullScreenQuadOnOneUnit) and emits 2080 stamps, 16 per kept tile
// (accepted or evaluated), so ii = 1 costs 2176 stamp cycles. Culled, the far
// layer's 272 kept tiles cost only their tile tests: the rasterizer saves
// 2 * 2176 cycles, its 65536 pixels never leave it, and the depth test sees
// only the near layer's 4160 stamps.
TEST(HierarchicalZ, OccludedFullScreenLayerIsCulledEntirely) {
  const Scene s = occluded_layer(3000);
  const GpuRunResult off = run(s, config(false));
  const GpuRunResult on = run(s, config(true));
  const char* ras = "tile_rasterizer_0";
  const char* dt = "depth_test_0";
  EXPECT_EQ(counter(off, dt, "stamps"), 2u * 4160u);
  EXPECT_EQ(counter(on, ras, "hz_tests"), 4u * 136u);
  EXPECT_EQ(counter(on, ras, "hz_tiles_culled"), 2u * 136u);
  EXPECT_EQ(counter(on, ras, "hz_fragments_culled"), 65536u);
  EXPECT_EQ(counter(on, ras, "stamps_emitted"), 4160u);
  EXPECT_EQ(counter(on, dt, "stamps"), 4160u);
  EXPECT_EQ(counter(on, dt, "fragments_in"), 65536u);
  EXPECT_EQ(counter(off, ras, "busy_cycles") - counter(on, ras, "busy_cycles"), 2u * 2176u);
  // Every near-layer batch wrote depth: one update each, all applied. A
  // diagonal tile gets two, and the first is applied too: the second
  // triangle reaches the tile a whole triangle walk (2432 cycles) after the
  // first, when the depth test, at most a FIFO (16 batches) behind, has long
  // sent its update.
  EXPECT_EQ(counter(on, dt, "hz_updates_sent"), 2u * 136u);
  EXPECT_EQ(counter(on, ras, "hz_updates_applied"), 2u * 136u);
  EXPECT_EQ(counter(on, ras, "hz_updates_dropped"), 0u);
  // The golden model's fragment count includes the culled pixels.
  EXPECT_EQ(on.counts, off.counts);
}

// The same frame with the updates slower than the whole frame: the far
// layer is tested before any update is visible, and the widening alone
// (less: the near layer lowers a block's min, never its max, which stays
// the clear value 1.0) culls nothing.
TEST(HierarchicalZ, TileTestedBeforeTheUpdateIsVisibleIsNotCulled) {
  const Scene s = occluded_layer(3000);
  const GpuRunResult off = run(s, config(false));
  const GpuRunResult late = run(s, config(true, 1000000));
  ASSERT_LT(late.cycles, 1000000u);
  const char* ras = "tile_rasterizer_0";
  EXPECT_EQ(counter(late, ras, "hz_tests"), 4u * 136u);
  EXPECT_EQ(counter(late, ras, "hz_tiles_culled"), 0u);
  EXPECT_EQ(counter(late, ras, "hz_updates_applied"), 0u);
  EXPECT_EQ(counter(late, "depth_test_0", "stamps"), counter(off, "depth_test_0", "stamps"));
  EXPECT_EQ(counter(late, ras, "busy_cycles"), counter(off, ras, "busy_cycles"));
}

// The far layer right behind the near one: the rasterizer reaches the far
// layer's first tiles before the depth test has finished the near layer's,
// so culling needs the updates: fewer tiles are culled with a longer update
// latency, never more, and frames stay exact.
TEST(HierarchicalZ, LongerUpdateLatencyNeverCullsMore) {
  const Scene s = occluded_layer(0);
  uint64_t previous = ~uint64_t{0};
  for (unsigned latency : {0u, 64u, 512u, 2048u, 1000000u}) {
    const GpuRunResult r = run(s, config(true, latency));
    const uint64_t culled = counter(r, "tile_rasterizer_0", "hz_tiles_culled");
    EXPECT_LE(culled, previous) << latency;
    previous = culled;
  }
  EXPECT_EQ(previous, 0u);
}

}  // namespace
}  // namespace gpusim
