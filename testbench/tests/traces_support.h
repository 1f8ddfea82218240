// Shared by the traces_*_test.cpp files that read real traces: a scratch
// directory per test, scenes and GPU configurations written as JSON, and
// build/gpusim run through a shell so the command line's exit statuses and
// error lines are tested along with the files it writes.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace gpusim {
namespace trace_test {

namespace fs = std::filesystem;

struct CommandResult {
  int status = -1;
  std::string out;  // stdout and stderr together
};

// build/gpusim with `args`, stdout and stderr captured together.
inline CommandResult gpusim(const std::string& args) {
  CommandResult r;
  FILE* p = popen((std::string(GPUSIM_BINARY_DIR "/gpusim ") + args + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// A scratch directory, removed after the test.
class TraceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           ("gpusim_traces_" + std::string(info->name()) + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `j` to dir_/name and returns its path.
  std::string write_json(const std::string& name, const nlohmann::json& j) const {
    const fs::path p = dir_ / name;
    std::ofstream(p) << j.dump(1) << "\n";
    return p.string();
  }

  // `gpusim run SCENE ARGS --trace DIR --out DIR/out`; returns DIR.
  std::string trace(const std::string& scene, const std::string& args = "",
                    const std::string& name = "trace") const {
    const std::string dir = (dir_ / name).string();
    const CommandResult r = gpusim("run " + scene + " " + args + " --trace " + dir + " --out " +
                                   (dir_ / (name + "_out")).string());
    EXPECT_EQ(r.status, 0) << r.out;
    return dir;
  }

  fs::path dir_;
};

// A clip-space vertex (no camera: the scene's matrices are identities) at
// window position (wx, wy) of a width x height framebuffer; z in clip space.
inline nlohmann::json at_window(double wx, double wy, double z, int width, int height) {
  return {wx * 2.0 / width - 1.0, wy * 2.0 / height - 1.0, z, 1.0};
}

}  // namespace trace_test
}  // namespace gpusim
