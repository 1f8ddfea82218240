// Hangs (docs/robustness.md, "Watchdog"): test-only faults make the cycle
// model lose an item, deadlock, or keep a stage busy without end; each run
// must stop with a SimulationError whose report names every stage's state and
// every FIFO's occupancy, instead of hanging. A normal run is not changed by
// the watchdog. The command line turns these into exit status 3.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

// A strip of `n` triangles across a 64x64 screen.
Scene strip_scene(int n) {
  Scene s;
  s.path = "robust_watchdog_test";
  s.framebuffer.width = 64;
  s.framebuffer.height = 64;
  Draw d;
  d.name = "strip";
  d.primitive = PrimitiveType::triangle_strip;
  for (int i = 0; i < n + 2; ++i) {
    const float x = -0.9f + 1.8f * static_cast<float>(i / 2) / static_cast<float>(n / 2 + 1);
    d.positions.push_back({x, i % 2 ? 0.8f : -0.8f, 0.0f, 1.0f});
  }
  s.draws.push_back(d);
  return s;
}

// Runs and returns the SimulationError's report (fails when none is thrown).
std::string failure(const Scene& scene, const GpuConfig& config, const GpuRunOptions& options,
                    SimulationError::Kind kind) {
  const auto start = std::chrono::steady_clock::now();
  try {
    run_gpu(scene, config, options);
  } catch (const SimulationError& e) {
    EXPECT_EQ(static_cast<int>(e.kind()), static_cast<int>(kind)) << e.what();
    // Stopping costs no wall time: the kernel jumps over idle cycles.
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              30.0);
    return e.what();
  }
  ADD_FAILURE() << "the run completed";
  return "";
}

bool has(const std::string& report, const std::string& text) {
  return report.find(text) != std::string::npos;
}

// Every stage and every FIFO has a line in the report.
void expect_complete_report(const std::string& report, unsigned units) {
  for (const char* stage : {"command_processor:", "vertex_fetch:", "vertex_shader:", "clipper:",
                            "primitive_setup:", "tile_distributor:"}) {
    EXPECT_TRUE(has(report, std::string("\n    ") + stage)) << stage << "\n" << report;
  }
  for (const char* fifo : {"commands:", "command_to_fetch:", "fetch_to_shader:",
                           "shader_to_clipper:", "clipper_to_setup:", "setup_to_distributor:"}) {
    EXPECT_TRUE(has(report, std::string("\n    ") + fifo)) << fifo << "\n" << report;
  }
  for (unsigned u = 0; u < units; ++u) {
    const std::string n = std::to_string(u);
    for (const std::string& name :
         {"tile_rasterizer_" + n, "depth_test_" + n, "interpolator_" + n, "rop_" + n,
          "distributor_to_rasterizer_" + n, "rasterizer_to_depth_" + n,
          "depth_to_interpolator_" + n, "interpolator_to_rop_" + n}) {
      EXPECT_TRUE(has(report, "\n    " + name + ":")) << name << "\n" << report;
    }
  }
}

TEST(Watchdog, LostEndOfFrameIsReportedAsALostItem) {
  GpuRunOptions options;
  options.fault_withhold_end_of_frame = true;
  const std::string r =
      failure(strip_scene(20), GpuConfig{}, options, SimulationError::Kind::deadlock);
  EXPECT_EQ(r.rfind("deadlock: every process is blocked and the frame is not complete (seen at "
                    "cycle ",
                    0),
            0u)
      << r;
  EXPECT_TRUE(has(r, "every stage waits for input and every FIFO is empty: an item was lost")) << r;
  EXPECT_TRUE(has(r, "clipper: waiting on input shader_to_clipper (0/16)")) << r;
  EXPECT_TRUE(has(r, "rop_3: waiting on input interpolator_to_rop_3 (0/16)")) << r;
  EXPECT_FALSE(has(r, ": busy")) << r;
  expect_complete_report(r, 4);
}

TEST(Watchdog, DisconnectedFifoIsReportedAsADeadlock) {
  GpuConfig config;
  config.units = 2;
  config.fifo_depth = 2;
  GpuRunOptions options;
  options.fault_disconnected_fifo = "clipper_to_setup";
  const std::string r = failure(strip_scene(60), config, options, SimulationError::Kind::deadlock);
  EXPECT_TRUE(has(r, "a deadlock")) << r;
  // The clipper cannot write into the full FIFO; setup waits on the stand-in
  // that nobody writes; everything after it starves.
  EXPECT_TRUE(has(r, "clipper: waiting on output clipper_to_setup (2/2, withheld)")) << r;
  EXPECT_TRUE(has(r, "primitive_setup: waiting on input clipper_to_setup (2/2, withheld)")) << r;
  EXPECT_TRUE(has(r, "withheld from its reader (test fault)")) << r;
  EXPECT_TRUE(has(r, "rop_1: waiting on input interpolator_to_rop_1 (0/2)")) << r;
  EXPECT_TRUE(has(r, "clipper_to_setup: 2/2; 2 written, 0 read")) << r;
  expect_complete_report(r, 2);
}

TEST(Watchdog, StageBusyWithoutProgressFiresTheWatchdog) {
  GpuConfig config;
  config.watchdog_cycles = 5000;
  GpuRunOptions options;
  options.fault_stalled_fifo = "rasterizer_to_depth_1";
  const std::string r = failure(strip_scene(40), config, options, SimulationError::Kind::watchdog);
  EXPECT_EQ(r.rfind("watchdog: no item moved through any FIFO or the memory for ", 0), 0u) << r;
  EXPECT_TRUE(has(r, "(watchdog_cycles 5000;")) << r;
  // The stalled accesses keep the FIFO's writer (and reader) in a timed wait.
  EXPECT_TRUE(has(r, "busy without moving an item: tile_rasterizer_1")) << r;
  EXPECT_TRUE(has(r, "tile_rasterizer_1: busy")) << r;
  EXPECT_TRUE(has(r, "injected stalls")) << r;
  expect_complete_report(r, 4);
  // It fires within one period (watchdog_cycles / 4) of the limit.
  std::istringstream head(r.substr(r.find("for ") + 4));
  uint64_t idle = 0;
  head >> idle;
  EXPECT_GE(idle, 5000u) << r;
  EXPECT_LE(idle, 5000u + 1250u + 1u) << r;
}

TEST(Watchdog, UnknownFaultFifoIsAnError) {
  GpuRunOptions options;
  options.fault_disconnected_fifo = "no_such_fifo";
  EXPECT_THROW(run_gpu(strip_scene(2), GpuConfig{}, options), std::invalid_argument);
}

// The watchdog only reads state: a run's results, timing statistics
// included, are the same whatever watchdog_cycles is, and a long
// memory-bound flush (an 8192x1024 frame's write-back) does not trip it.
TEST(Watchdog, DoesNotChangeOrStopANormalRun) {
  Scene s = strip_scene(30);
  GpuConfig tight, loose;
  tight.watchdog_cycles = 3000;
  loose.watchdog_cycles = 1000000000000ull;
  const GpuRunResult a = run_gpu(s, tight, {});
  const GpuRunResult b = run_gpu(s, loose, {});
  EXPECT_EQ(a.cycles, b.cycles);
  EXPECT_TRUE(a.framebuffer == b.framebuffer);
  EXPECT_EQ(a.counts, b.counts);
  EXPECT_EQ(a.timing, b.timing);

  Scene wide = strip_scene(4);
  wide.framebuffer.width = 8192;
  wide.framebuffer.height = 1024;
  GpuConfig slow_memory = GpuConfig::baseline();
  slow_memory.watchdog_cycles = 20000;
  slow_memory.memory.bytes_per_cycle = 4;
  const GpuRunResult c = run_gpu(wide, slow_memory, {});
  EXPECT_GT(c.cycles, 20u * slow_memory.watchdog_cycles);
  EXPECT_TRUE(c.framebuffer == golden::render(wide).framebuffer);
}

// End to end: a watchdog far too tight for the stages' costs is a hang as far
// as the watchdog can tell: exit status 3, a multi-line report on stderr that
// names the scene, nothing written.
TEST(Watchdog, CommandLineExitsWithThree) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("gpusim_wd_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "scene.json")
      << R"({"draws": [{"positions": [[-1,-1,0],[1,-1,0],[0,1,0],[0,-1,0],[1,1,0],[-1,1,0]]}]})";
  std::ofstream(dir / "gpu.json") << R"({"watchdog_cycles": 1})";
  const std::string cmd = std::string(GPUSIM_BINARY_DIR) + "/gpusim run " +
                          (dir / "scene.json").string() + " --config " +
                          (dir / "gpu.json").string() + " --out " + (dir / "out").string() + " >" +
                          (dir / "stdout").string() + " 2>" + (dir / "stderr").string();
  const int st = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 3);
  std::ifstream in(dir / "stderr");
  std::stringstream err;
  err << in.rdbuf();
  const std::string r = err.str();
  EXPECT_EQ(r.rfind("gpusim: " + (dir / "scene.json").string() + ": watchdog: ", 0), 0u) << r;
  EXPECT_TRUE(has(r, "busy without moving an item")) << r;
  EXPECT_TRUE(has(r, "\n  stages:\n")) << r;
  EXPECT_TRUE(has(r, "\n  FIFOs (items held/depth; items written, read):\n")) << r;
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace gpusim
