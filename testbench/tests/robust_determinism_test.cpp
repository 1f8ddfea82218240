// Determinism (docs/robustness.md, "Determinism"): the same input gives the
// same output bytes (frame.exr, frame.png, stats.json with every statistic)
// run after run, for gpusim golden and gpusim run, and the same results when
// a process runs the same frame twice.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

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
      const std::string a = slurp(dir_ / "a" / f), b = slurp(dir_ / "b" / f);
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
                                           "zfight_offset", "shared_edges"));

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
  EXPECT_EQ(g1.stats.to_json(), g2.stats.to_json());
  EXPECT_TRUE(a.framebuffer == g1.framebuffer);
}

}  // namespace
}  // namespace gpusim
