// Nothing outside the modelled GPU may move a cycle count: the testbench's
// own processes (progress line, watchdog) and the order in which SystemC
// first runs the stages' processes (the units elaborated the other way
// round) must leave every byte of the statistics unchanged. The command
// line's cases (a terminal vs a pipe, --trace, --check) are in
// cli_gpusim_test.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/sim/progress.h"
#include "testbench/tests/json_difference.h"

namespace gpusim {
namespace {

Scene scene(const char* name) {
  return load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + name + ".json");
}

nlohmann::json run(const Scene& s, const GpuConfig& config, const GpuRunOptions& options) {
  const GpuRunResult r = run_gpu(s, config, options);
  return {{"timing", r.timing}, {"counts", r.counts.to_json()}};
}

class Determinism : public ::testing::TestWithParam<const char*> {};

TEST_P(Determinism, StatsDoNotDependOnTestbenchProcessesOrElaborationOrder) {
  const Scene s = scene(GetParam());
  for (unsigned units : {1u, 4u, 7u}) {
    GpuConfig config;
    config.units = units;
    const nlohmann::json plain = run(s, config, {});
    // The progress thread, waking every 100k cycles, showing every wake.
    std::ostringstream lines;
    Progress shown(Progress::Mode::lines, lines, 0.0);
    GpuRunOptions progress;
    progress.progress = &shown;
    EXPECT_EQ(json_difference(run(s, config, progress), plain), "")
        << units << " units, progress line";
    EXPECT_NE(lines.str().find("simulate: "), std::string::npos) << lines.str();
    GpuRunOptions no_watchdog;
    no_watchdog.watchdog = false;
    EXPECT_EQ(json_difference(run(s, config, no_watchdog), plain), "")
        << units << " units, no watchdog";
    GpuRunOptions reversed;
    reversed.unit_order = Gpu::UnitOrder::descending;
    EXPECT_EQ(json_difference(run(s, config, reversed), plain), "")
        << units << " units, reversed elaboration";
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Determinism, ::testing::Values("default", "spider"));

// Hierarchical Z's updates cross from each depth test to its rasterizer
// outside the FIFOs; their visibility rule (hw/hierarchical_z.h) must make
// the result independent of the order SystemC runs processes in. Random
// stalls at every FIFO move the depth tests ahead of and behind their
// rasterizers; with the same stalls, both elaboration orders give the same
// statistics byte for byte, and the frame stays the golden model's. Update
// latency 0, the rule's edge. (The reversed order reverses the units, not
// the rasterizer and depth test within one: the same-time case itself is
// tested in hw_hierarchical_z_test, HzUpdateLink.*.)
TEST(HierarchicalZ, StatsDoNotDependOnProcessOrderUnderRandomStalls) {
  for (const char* name : {"hiz_funcs", "default"}) {
    const Scene s = scene(name);
    GpuConfig config;
    config.units = 3;
    config.fifo_depth = 2;
    config.hierarchical_z.enabled = true;
    config.hierarchical_z.update_latency = 0;
    for (uint64_t seed : {1u, 7u}) {
      GpuRunOptions stalled;
      stalled.stall_probability = 0.3;
      stalled.stall_max_cycles = 7;
      stalled.stall_seed = seed;
      const GpuRunResult a = run_gpu(s, config, stalled);
      stalled.unit_order = Gpu::UnitOrder::descending;
      const GpuRunResult b = run_gpu(s, config, stalled);
      ASSERT_TRUE(a.completed && b.completed) << name;
      const nlohmann::json ja = {{"timing", a.timing}, {"counts", a.counts.to_json()}};
      const nlohmann::json jb = {{"timing", b.timing}, {"counts", b.counts.to_json()}};
      EXPECT_EQ(json_difference(ja, jb), "") << name << ", seed " << seed;
      EXPECT_TRUE(a.framebuffer == golden::render(s).framebuffer) << name;
      // Updates were applied and tiles culled: the rule was exercised.
      uint64_t applied = 0, culled = 0;
      for (const auto& [stage, c] : a.timing.at("stages").items()) {
        applied += c.value("hz_updates_applied", uint64_t{0});
        culled += c.value("hz_tiles_culled", uint64_t{0});
      }
      EXPECT_GT(applied, 0u) << name;
      EXPECT_GT(culled, 0u) << name;
    }
  }
}

// Temporal decoupling (hw/pipeline_stage.h, hw/fifo.h's stamped mode) must
// not move a cycle: every scene, under configurations that stress its
// timing (one unit and seven, FIFOs of one and two slots that keep the
// decoupled stages blocked on each other and on vertex fetch, zero latencies
// where an item is readable in the delta after its write, ii of 1 and 3,
// the baseline's single bus, random stalls at every FIFO), gives the same
// statistics byte for byte and the same frame as the lockstep run, in which
// every stage waits in the kernel.
struct DecouplingCase {
  const char* name;
  GpuConfig config;
  double stall_probability = 0.0;
};

std::vector<DecouplingCase> decoupling_cases() {
  std::vector<DecouplingCase> cases;
  cases.push_back({"default", GpuConfig{}});
  cases.push_back({"baseline, 1 unit", GpuConfig::baseline()});
  cases.back().config.units = 1;
  GpuConfig tight;
  tight.units = 7;
  tight.fifo_depth = 1;
  tight.fifo_depths.clear();
  cases.push_back({"7 units, depth 1", tight});
  GpuConfig zero = GpuConfig::baseline();
  zero.units = 3;
  zero.fifo_depth = 2;
  zero.fifo_depths.clear();
  for (auto& [kind, cost] : zero.stages) {
    cost.latency = 0;
    cost.ii = kind == "clipper" || kind == "interpolator" ? 3 : 1;
  }
  cases.push_back({"3 units, depth 2, latency 0", zero});
  GpuConfig stalled;
  stalled.units = 2;
  stalled.fifo_depth = 2;
  stalled.fifo_depths.clear();
  cases.push_back({"2 units, depth 2, random stalls", stalled, 0.3});
  return cases;
}

class TemporalDecoupling : public ::testing::TestWithParam<const char*> {};

TEST_P(TemporalDecoupling, SameStatsAndFrameAsLockstep) {
  const Scene s = scene(GetParam());
  for (const DecouplingCase& c : decoupling_cases()) {
    GpuRunOptions options;
    options.stall_probability = c.stall_probability;
    options.stall_max_cycles = 7;
    const GpuRunResult decoupled = run_gpu(s, c.config, options);
    options.temporal_decoupling = false;
    const GpuRunResult lockstep = run_gpu(s, c.config, options);
    // Every stage but vertex fetch and the resolve ran decoupled (the
    // shader, clipper, setup and distributor, and each unit's rasterizer,
    // depth test, interpolator, texture unit in a textured frame, and ROP),
    // or none.
    const bool textured =
        std::any_of(s.draws.begin(), s.draws.end(), [](const Draw& d) { return d.texture >= 0; });
    EXPECT_EQ(decoupled.decoupled_stages, 4u + (textured ? 5u : 4u) * c.config.units) << c.name;
    EXPECT_EQ(lockstep.decoupled_stages, 0u) << c.name;
    EXPECT_EQ(decoupled.cycles, lockstep.cycles) << c.name;
    const nlohmann::json a = {{"timing", decoupled.timing}, {"counts", decoupled.counts.to_json()}};
    const nlohmann::json b = {{"timing", lockstep.timing}, {"counts", lockstep.counts.to_json()}};
    EXPECT_EQ(json_difference(a, b), "") << c.name;
    EXPECT_TRUE(decoupled.framebuffer == lockstep.framebuffer) << c.name;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, TemporalDecoupling,
                         ::testing::Values("default", "spider", "lines_points", "clears",
                                           "clipping", "states", "tiny_triangles", "phong",
                                           "aa_samples2", "viewport_scissor", "clears_samples4",
                                           "textured", "textured_samples4"));

}  // namespace
}  // namespace gpusim
