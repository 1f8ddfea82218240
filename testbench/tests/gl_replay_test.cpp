// `gpusim replay` end to end on a real program: glxgears is recorded under
// Xvfb with apitrace, llvmpipe renders frame 1 of the trace (apitrace
// dump-images), the cycle model replays the same frame, and at least 99.5% of
// the pixels must be within 2/255 per channel. xvfb-run, apitrace and glxgears
// come from scripts/setup; when one is missing the test fails.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "testbench/io/image_files.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

const std::string kGpusim = std::string(GPUSIM_BINARY_DIR) + "/gpusim";
const std::string kXvfb = "xvfb-run -a -s '-screen 0 640x480x24' ";

// Exit status of a shell command (-1 when it did not exit normally).
int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool have(const std::string& tool) {
  return run("command -v " + tool + " > /dev/null") == 0;
}

class GlReplay : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* tool : {"xvfb-run", "apitrace", "glxgears", "timeout"}) {
      ASSERT_TRUE(have(tool)) << tool << " is missing: scripts/setup installs it";
    }
    dir = fs::path(GPUSIM_BINARY_DIR) / "gl_replay_test.work";
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  fs::path dir;
};

TEST_F(GlReplay, GlxgearsFrameMatchesLlvmpipe) {
  const fs::path trace = dir / "gears.trace";
  // glxgears runs until killed: a second of it is dozens of frames.
  run(kXvfb + "timeout 1 apitrace trace -o " + trace.string() + " glxgears -geometry 300x300 > " +
      (dir / "record.log").string() + " 2>&1");
  ASSERT_TRUE(fs::exists(trace) && fs::file_size(trace) > 0) << read_text(dir / "record.log");

  const fs::path out = dir / "out";
  ASSERT_EQ(run(kGpusim + " replay " + trace.string() + " --frame 1 --out " + out.string() +
                " --quiet > " + (dir / "replay.log").string() + " 2>&1"),
            0)
      << read_text(dir / "replay.log");
  const nlohmann::json stats = nlohmann::json::parse(read_text(out / "stats_1.json"));
  const nlohmann::json& driver = stats.at("driver");
  EXPECT_FALSE(driver.at("unsupported_used").get<bool>()) << driver.dump();
  EXPECT_LE(driver.at("draws").get<int>(), 12)
      << "glxgears' geometry should batch into a handful of draws";
  EXPECT_GT(stats.at("stats").at("triangles_rasterized").get<int>(), 100);

  // apitrace dump-images names each image by the call number of its swap.
  const unsigned swap = driver.at("swap_call").get<unsigned>();
  ASSERT_EQ(run("LIBGL_ALWAYS_SOFTWARE=1 " + kXvfb + "apitrace dump-images --calls=" +
                std::to_string(swap) + " -o " + (dir / "ref_").string() + " " + trace.string() +
                " > " + (dir / "dump.log").string() + " 2>&1"),
            0)
      << read_text(dir / "dump.log");
  char name[32];
  std::snprintf(name, sizeof name, "ref_%010u.png", swap);
  const Image ref = read_png((dir / name).string());
  const Image got = read_png((out / "frame_1.png").string());
  ASSERT_EQ(ref.width, got.width);
  ASSERT_EQ(ref.height, got.height);
  long long close = 0;
  const long long pixels = static_cast<long long>(ref.width) * ref.height;
  for (long long p = 0; p < pixels; ++p) {
    float worst = 0.0f;
    for (size_t c = 0; c < 3; ++c) {
      worst = std::max(worst, std::fabs(ref.channels[c][static_cast<size_t>(p)] -
                                        got.channels[c][static_cast<size_t>(p)]));
    }
    if (worst <= 2.0f / 255.0f + 1e-6f) ++close;
  }
  const double share = static_cast<double>(close) / static_cast<double>(pixels);
  std::printf("glxgears frame 1 (swap call %u): %.4f%% of %lld pixels within 2/255 of llvmpipe\n",
              swap, 100.0 * share, pixels);
  EXPECT_GE(share, 0.995);

  // --strict passes a frame without unsupported features (glxgears uses none).
  EXPECT_EQ(run(kGpusim + " replay " + trace.string() + " --frame 2 --strict --quiet --out " +
                (dir / "strict").string() + " > /dev/null"),
            0);

  // Bad input: one line, exit 2.
  EXPECT_EQ(run(kGpusim + " replay " + (dir / "missing.trace").string() + " 2> " +
                (dir / "err.log").string()),
            2);
  const std::string err = read_text(dir / "err.log");
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("missing.trace"), std::string::npos) << err;
  EXPECT_EQ(run(kGpusim + " replay " + trace.string() + " --frame 1000000 --quiet --out " +
                (dir / "none").string() + " > /dev/null 2> " + (dir / "err2.log").string()),
            2);
  // The recording was cut by `timeout`: reading on past its last frame meets
  // either the end of the file ("only N complete frames") or, when apitrace
  // was killed in the middle of writing an event, that event's truncation.
  const std::string err2 = read_text(dir / "err2.log");
  EXPECT_EQ(std::count(err2.begin(), err2.end(), '\n'), 1) << err2;
  EXPECT_TRUE(err2.find("complete frames") != std::string::npos ||
              err2.find("truncated trace: the data ends inside an event") != std::string::npos)
      << err2;
  EXPECT_EQ(run(kGpusim + " replay " + trace.string() + " --frames 3:1 2> /dev/null"), 2);
  // A trace with no swap (its first calls, cut by apitrace trim) says why
  // it has no frame, and how to record one, not what --frames asks.
  ASSERT_EQ(run("apitrace trim --calls=0-10 -o " + (dir / "noswap.trace").string() + " " +
                trace.string() + " > /dev/null 2>&1"),
            0);
  EXPECT_EQ(run(kGpusim + " replay " + (dir / "noswap.trace").string() + " --quiet --out " +
                (dir / "noswap").string() + " > /dev/null 2> " + (dir / "err3.log").string()),
            2);
  const std::string err3 = read_text(dir / "err3.log");
  EXPECT_EQ(std::count(err3.begin(), err3.end(), '\n'), 1) << err3;
  EXPECT_NE(err3.find("has no complete frame: no glXSwapBuffers or eglSwapBuffers ends one"),
            std::string::npos)
      << err3;
  EXPECT_EQ(err3.find("--frames"), std::string::npos) << err3;
  EXPECT_FALSE(fs::exists(dir / "noswap"));
  // A replay that rendered nothing leaves no folder, nested ones included.
  EXPECT_FALSE(fs::exists(dir / "none"));
  EXPECT_EQ(run(kGpusim + " replay " + trace.string() + " --frame 1000000 --quiet --out " +
                (dir / "nested" / "deeper").string() + " > /dev/null 2>&1"),
            2);
  EXPECT_FALSE(fs::exists(dir / "nested"));
}

}  // namespace
}  // namespace gpusim
