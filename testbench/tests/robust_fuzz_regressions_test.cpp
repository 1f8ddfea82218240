// The fuzz targets' checks (testbench/fuzz/*_target.h) on every input of their
// seed corpora (testbench/fuzz/corpus/<target>/) and on every input a fuzzing
// run found a problem with (testbench/fuzz/regressions/<target>/, one file
// per finding, named after it; docs/robustness.md lists them). So each
// finding stays fixed, and the normal and sanitizer builds run the harnesses
// without a fuzzing engine.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "testbench/fuzz/gpu_diff_target.h"
#include "testbench/fuzz/scene_target.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> inputs(const std::string& target) {
  std::vector<fs::path> files;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path dir = fs::path(GPUSIM_SOURCE_DIR) / "testbench/fuzz" / kind / target;
    if (!fs::is_directory(dir)) continue;
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.is_regular_file() && e.path().filename().string()[0] != '.') files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<uint8_t> bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(FuzzRegressions, SceneParser) {
  const std::vector<fs::path> files = inputs("scene");
  EXPECT_GE(files.size(), 10u);
  for (const fs::path& f : files) {
    const std::vector<uint8_t> data = bytes_of(f);
    EXPECT_EQ(fuzz::check_scene_input(data.data(), data.size()), "") << f;
  }
}

// One process elaborates the fuzz GPUs once and replays every input through
// them, as the fuzzer does.
TEST(FuzzRegressions, CycleModelAgainstGolden) {
  const std::vector<fs::path> files = inputs("gpu_diff");
  EXPECT_GE(files.size(), 5u);
  for (const fs::path& f : files) {
    const std::vector<uint8_t> data = bytes_of(f);
    EXPECT_EQ(fuzz::check_gpu_diff_input(data.data(), data.size()), "") << f;
  }
  // The same input twice in a row: the instances keep no state that matters.
  const std::vector<uint8_t> first = bytes_of(files.front());
  EXPECT_EQ(fuzz::check_gpu_diff_input(first.data(), first.size()), "");
  EXPECT_EQ(fuzz::check_gpu_diff_input(first.data(), first.size()), "");
}

}  // namespace
}  // namespace gpusim
