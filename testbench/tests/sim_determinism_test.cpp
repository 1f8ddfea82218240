// Nothing outside the modelled GPU may move a cycle count: the testbench's
// own processes (progress line, watchdog) and the order in which SystemC
// first runs the stages' processes (the units elaborated the other way
// round) must leave every byte of the statistics unchanged. The command
// line's cases (a terminal vs a pipe, --trace, --check) are in
// cli_gpusim_test.
#include <gtest/gtest.h>

#include <sstream>

#include "testbench/scene/scene.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/sim/progress.h"

namespace gpusim {
namespace {

Scene scene(const char* name) {
  return load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + name + ".json");
}

nlohmann::json run(const Scene& s, const GpuConfig& config, const GpuRunOptions& options) {
  const GpuRunResult r = run_gpu(s, config, options);
  return {{"timing", r.timing}, {"counts", r.counts}};
}

// "" when equal, else the path of the first difference and both values.
std::string difference(const nlohmann::json& a, const nlohmann::json& b,
                       const std::string& path = "") {
  if (a == b) return "";
  if (a.is_object() && b.is_object()) {
    for (const auto& item : a.items()) {
      if (!b.contains(item.key())) return path + "." + item.key() + " missing";
      const std::string d = difference(item.value(), b[item.key()], path + "." + item.key());
      if (!d.empty()) return d;
    }
    return path + ": keys differ";
  }
  return path + ": " + a.dump() + " vs " + b.dump();
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
    EXPECT_EQ(difference(run(s, config, progress), plain), "") << units << " units, progress line";
    EXPECT_NE(lines.str().find("simulate: "), std::string::npos) << lines.str();
    GpuRunOptions no_watchdog;
    no_watchdog.watchdog = false;
    EXPECT_EQ(difference(run(s, config, no_watchdog), plain), "") << units << " units, no watchdog";
    GpuRunOptions reversed;
    reversed.unit_order = Gpu::UnitOrder::descending;
    EXPECT_EQ(difference(run(s, config, reversed), plain), "")
        << units << " units, reversed elaboration";
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Determinism, ::testing::Values("default", "spider"));

}  // namespace
}  // namespace gpusim
