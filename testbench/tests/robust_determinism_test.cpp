// Determinism (docs/robustness.md, "Determinism"): the same input gives the
// same output bytes (frame.exr, frame.png, stats.json with every statistic)
// run after run, for gpusim golden and gpusim run, and the same results when
// a process runs the same frame twice; and the cycle model's statistics do
// not change when something outside the modelled GPU adds processes to the
// simulation (a progress line, tracing, --check, the watchdog).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>

#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/tests/file_bytes.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

class SameBytes : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("gpusim_det_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "gpu.json")
        << R"({"units": 3, "tile_size": 8, "stamp": [2, 2], "fifo_depth": 2})";
  }
  void TearDown() override { fs::remove_all(dir_); }

  void expect_same_bytes(const std::string& args) {
    SCOPED_TRACE(args);
    for (const char* out : {"a", "b"}) {
      const std::string cmd = std::string(GPUSIM_BINARY_DIR) + "/gpusim " + args + " --out " +
                              (dir_ / out).string() + " >/dev/null";
      const int st = std::system(cmd.c_str());
      ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << cmd;
    }
    for (const char* f : {"frame.exr", "frame.png", "stats.json"}) {
      const std::string a = file_bytes(dir_ / "a" / f), b = file_bytes(dir_ / "b" / f);
      EXPECT_FALSE(a.empty()) << f;
      EXPECT_TRUE(a == b) << f << " differs between two runs";
    }
    fs::remove_all(dir_ / "a");
    fs::remove_all(dir_ / "b");
  }
  fs::path dir_;
};

TEST_P(SameBytes, GoldenAndCycleModel) {
  const std::string scene =
      std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + GetParam() + ".json";
  expect_same_bytes("golden " + scene);
  expect_same_bytes("run " + scene + " --check");
  expect_same_bytes("run " + scene + " --config " + (dir_ / "gpu.json").string());
}

INSTANTIATE_TEST_SUITE_P(Scenes, SameBytes,
                         ::testing::Values("default", "spider", "clipping", "states",
                                           "zfight_offset", "shared_edges", "phong"));

// Pairs of `gpusim run` on the default scene that differ only in something
// outside the modelled GPU: stats.json must be the same bytes. Each of these
// adds or drops SystemC processes or waits, which changes the order in which
// the kernel runs the processes of one delta; the memory's arbiter must not
// let that order reach the timing (hw/memory.h).
class SameStats : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("gpusim_obs_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // `gpusim run default.json --out DIR/out <args>`, under `wrapper` (a
  // shell prefix taking the command as its last argument, or empty); returns
  // stats.json.
  std::string run(const std::string& out, const std::string& args,
                  const std::string& wrapper = "") {
    const std::string gpusim = std::string(GPUSIM_BINARY_DIR) + "/gpusim run " + GPUSIM_SOURCE_DIR +
                               "/testbench/scenes/default.json --out " + (dir_ / out).string() +
                               " " + args;
    const std::string cmd =
        (wrapper.empty() ? gpusim : wrapper + " '" + gpusim + "' /dev/null") + " >/dev/null 2>&1";
    const int st = std::system(cmd.c_str());
    EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << cmd;
    const std::string stats = file_bytes(dir_ / out / "stats.json");
    EXPECT_FALSE(stats.empty()) << cmd;
    return stats;
  }
  fs::path dir_;
};

// Progress (testbench/sim/progress.h) adds a thread waking every 100,000
// cycles and on FIFO activity when it is shown: on a terminal (script(1),
// from bsdutils, which scripts/setup installs, runs gpusim on a
// pseudo-terminal), forced off one with every state printed, or not at all
// (--quiet, or a pipe). One unit: three wakes in this frame. frame.exr and
// stats.json must be the same bytes every way.
TEST_F(SameStats, ProgressOnATerminalForcedOrQuiet) {
  ASSERT_EQ(std::system("command -v script >/dev/null"), 0)
      << "script(1) is missing: scripts/setup installs it (package bsdutils)";
  const std::string args = "--units 1 --progress-interval 0";
  const std::string quiet = run("quiet", args + " --quiet");
  const std::string piped = run("piped", args);
  const std::string forced = run("forced", args + " --progress");
  const std::string terminal = run("terminal", args, "script -qec");
  const std::string terminal_quiet = run("terminal_quiet", args + " --quiet", "script -qec");
  for (const auto& [name, stats] : {std::pair{"piped", piped},
                                    {"forced", forced},
                                    {"terminal", terminal},
                                    {"terminal_quiet", terminal_quiet}}) {
    EXPECT_TRUE(stats == quiet) << "stats.json differs between --quiet and " << name;
    EXPECT_TRUE(file_bytes(dir_ / name / "frame.exr") == file_bytes(dir_ / "quiet" / "frame.exr"))
        << "frame.exr differs between --quiet and " << name;
  }
}

TEST_F(SameStats, TracedOrNot) {
  const std::string plain = run("plain", "");
  const std::string traced = run("traced", "--trace " + (dir_ / "trace").string());
  EXPECT_TRUE(plain == traced) << "stats.json differs with --trace";
}

TEST_F(SameStats, CheckedOrNot) {
  const std::string plain = run("plain", "");
  const std::string checked = run("checked", "--check");
  EXPECT_TRUE(plain == checked) << "stats.json differs with --check";
}

// The watchdog cannot be turned off from the command line; at its maximum,
// 10^12 cycles, it wakes every 2.5 * 10^11 cycles, never during this frame,
// and at 1000 every 250 cycles. stats.json records the setting itself, so
// that one field is left out of the comparison.
TEST_F(SameStats, WatchdogOftenOrNever) {
  std::ofstream(dir_ / "often.json") << R"({"watchdog_cycles": 1000})";
  std::ofstream(dir_ / "never.json") << R"({"watchdog_cycles": 1000000000000})";
  const auto without_setting = [](const std::string& text) {
    nlohmann::json j = nlohmann::json::parse(text);
    j.at("config").erase("watchdog_cycles");
    return j.dump(2);
  };
  const std::string often = run("often", "--config " + (dir_ / "often.json").string());
  const std::string never = run("never", "--config " + (dir_ / "never.json").string());
  EXPECT_TRUE(without_setting(often) == without_setting(never))
      << "stats.json differs with the watchdog waking every 250 cycles";
}

// Twice in one process (a fresh SystemC context each time), with random
// stalls at every FIFO: identical frames, counters and timing statistics.
TEST(SameResults, TwiceInOneProcess) {
  const Scene scene = load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/default.json");
  GpuRunOptions options;
  options.record_last_writer = true;
  options.stall_probability = 0.1;
  options.stall_seed = 42;
  const GpuRunResult a = run_gpu(scene, GpuConfig{}, options);
  const GpuRunResult b = run_gpu(scene, GpuConfig{}, options);
  EXPECT_EQ(a.cycles, b.cycles);
  EXPECT_TRUE(a.framebuffer == b.framebuffer);
  EXPECT_TRUE(a.last_writer == b.last_writer);
  EXPECT_EQ(a.counts, b.counts);
  EXPECT_EQ(a.timing, b.timing);
  const golden::Result g1 = golden::render(scene), g2 = golden::render(scene);
  EXPECT_TRUE(g1.framebuffer == g2.framebuffer);
  EXPECT_EQ(g1.stats, g2.stats);
  EXPECT_TRUE(a.framebuffer == g1.framebuffer);
}

}  // namespace
}  // namespace gpusim
