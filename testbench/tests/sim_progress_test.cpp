// The progress display (testbench/sim/progress.h) on its own: what each mode
// writes, its rate limit, and the phases it times. Through the command line
// and run_gpu: cli_gpusim_test (phases, the simulation's state) and the
// determinism tests (nothing it does moves a cycle).
#include <gtest/gtest.h>

#include <regex>
#include <sstream>
#include <string>
#include <utility>

#include "testbench/scene/scene.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/sim/progress.h"

namespace gpusim {
namespace {

TEST(Progress, LinesModeShowsPhasesAndRateLimitsTheState) {
  std::ostringstream out;
  {
    // An interval no test outlasts: only the forced state is shown.
    Progress p(Progress::Mode::lines, out, 1e6);
    p.begin("load", "reading a.json");
    p.update("importing a.obj", true);
    p.begin("simulate", "3 primitives");
    p.update("1 of 3");  // not shown: the phase's start line was just now
    p.update("2 of 3", true);
    p.end();
    p.end();  // nothing open: no effect
  }
  const std::regex expected(
      "load: reading a\\.json \\.\\.\\.\n"
      "load: importing a\\.obj\n"
      "load: done in [0-9]+\\.[0-9]{3} s\n"
      "simulate: 3 primitives \\.\\.\\.\n"
      "simulate: 2 of 3\n"
      "simulate: done in [0-9]+\\.[0-9]{3} s\n");
  EXPECT_TRUE(std::regex_match(out.str(), expected)) << out.str();
}

TEST(Progress, IntervalZeroShowsEveryState) {
  std::ostringstream out;
  Progress p(Progress::Mode::lines, out, 0.0);
  p.begin("simulate", "x");
  p.update("1");
  p.update("2");
  EXPECT_EQ(out.str(), "simulate: x ...\nsimulate: 1\nsimulate: 2\n");
}

TEST(Progress, QuietShowsNothingButTimesEveryPhase) {
  std::ostringstream out;
  Progress p(Progress::Mode::quiet, out);
  p.begin("load", "reading");
  p.update("importing", true);
  p.begin("write", "files");
  p.begin("write", "more files");
  p.end();
  EXPECT_EQ(out.str(), "");
  ASSERT_EQ(p.phases().size(), 3u);
  EXPECT_EQ(p.phases()[0].first, "load");
  EXPECT_EQ(p.phases()[2].first, "write");
  EXPECT_TRUE(std::regex_match(
      p.wall_summary(),
      std::regex("load [0-9.]+ s, write [0-9.]+ s, write [0-9.]+ s; total [0-9.]+ s")))
      << p.wall_summary();
  // The total covers the phases.
  double sum = 0;
  for (const auto& phase : p.phases()) sum += phase.second;
  const std::string summary = p.wall_summary();
  EXPECT_GE(std::stod(summary.substr(summary.find("total ") + 6)) + 0.0005, sum);
}

// One line redrawn in place: \r, then spaces over a longer earlier line; the
// line is cleared when a phase ends and when the display goes away before an
// error message (an interrupted phase is not timed).
TEST(Progress, TerminalModeRedrawsOneLineAndClearsIt) {
  std::ostringstream out;
  {
    Progress p(Progress::Mode::terminal, out);
    p.begin("load", "reading a.json");  // "load: reading a.json ..." is 24 characters
    p.update("x", true);
    EXPECT_EQ(out.str(), "\rload: reading a.json ...\rload: x" + std::string(17, ' '));
    out.str("");
    p.end();
    EXPECT_EQ(out.str(), "\r" + std::string(7, ' ') + "\r");
    out.str("");
    p.begin("simulate", "y");
    out.str("");
  }
  EXPECT_EQ(out.str(), "\r" + std::string(15, ' ') + "\r");
  EXPECT_EQ(out.str().find('\n'), std::string::npos);
}

TEST(Progress, InterruptedPhaseIsNotTimed) {
  std::ostringstream out;
  Progress p(Progress::Mode::lines, out);
  p.begin("load", "reading");
  p.end();
  p.begin("simulate", "frame");
  p.interrupt();
  p.end();
  ASSERT_EQ(p.phases().size(), 1u);
  EXPECT_EQ(p.phases()[0].first, "load");
  EXPECT_EQ(out.str().find("simulate: done"), std::string::npos) << out.str();
}

TEST(Progress, ModeFromFlagsAndTerminal) {
  using M = Progress::Mode;
  EXPECT_EQ(Progress::mode_for(false, false, true), M::terminal);
  EXPECT_EQ(Progress::mode_for(false, false, false), M::quiet);
  EXPECT_EQ(Progress::mode_for(true, false, false), M::lines);
  EXPECT_EQ(Progress::mode_for(true, false, true), M::terminal);
  EXPECT_EQ(Progress::mode_for(false, true, true), M::quiet);
}

// run_gpu's phases, and the simulation's final figures shown however long
// the interval: the frame's cycles and fragments as the result gives them;
// and the same frame and timing as without the display.
// (The reporting thread once waited for an item to move after the frame was
// done, and the final line never came when the frame ended in a write-back
// longer than its 100k-cycle period: a slow bus here.)
TEST(Progress, RunGpuShowsItsPhasesAndTheFinalFigures) {
  GpuConfig slow_bus;
  slow_bus.memory.bytes_per_cycle = 1;
  for (const auto& [name, config] : {std::pair{"default", GpuConfig{}},
                                     {"lines_points", GpuConfig{}},
                                     {"quad_clipspace", slow_bus}}) {
    SCOPED_TRACE(name);
    const Scene scene = load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" +
                                   std::string(name) + ".json");
    std::ostringstream out;
    Progress p(Progress::Mode::lines, out, 1e6);
    GpuRunOptions options;
    options.progress = &p;
    const GpuRunResult r = run_gpu(scene, config, options);
    ASSERT_EQ(p.phases().size(), 3u);
    EXPECT_EQ(p.phases()[0].first, "build");
    EXPECT_EQ(p.phases()[1].first, "simulate");
    EXPECT_EQ(p.phases()[2].first, "read back");
    // Every primitive assembled, as the pipeline counters count them.
    const uint64_t primitives = r.counts.triangles_in + r.counts.lines_in + r.counts.points_in;
    const std::string final_state = "\nsimulate: " + std::to_string(primitives) + " of " +
                                    std::to_string(primitives) + " primitives assembled, " +
                                    std::to_string(r.cycles) + " cycles, " +
                                    std::to_string(r.counts.fragments_generated) + " fragments, ";
    EXPECT_NE(out.str().find(final_state), std::string::npos) << final_state << "\n" << out.str();
    // Its thread wakes through the write-back as well: no cycle moves.
    const GpuRunResult plain = run_gpu(scene, config, GpuRunOptions{});
    EXPECT_EQ(r.cycles, plain.cycles);
    EXPECT_EQ(r.timing, plain.timing);
    EXPECT_TRUE(r.framebuffer == plain.framebuffer);
  }
}

}  // namespace
}  // namespace gpusim
