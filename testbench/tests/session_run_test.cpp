// The run and golden sessions as libraries (testbench/session/): what
// `gpusim run` and `gpusim golden` do, returned as results a test can read,
// with the files they write.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "hw/input_error.h"
#include "testbench/golden/golden_model.h"
#include "testbench/session/golden_session.h"
#include "testbench/session/run_session.h"
#include "testbench/session/session_steps.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

const std::string kScenes = GPUSIM_SOURCE_DIR "/testbench/scenes/";

class SessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("gpusim_session_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static nlohmann::json read_json(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
  }
  // A session's progress, shown nowhere.
  Progress quiet_{Progress::Mode::quiet, std::cerr};
  fs::path dir_;
};

// A scene written here: one triangle behind the camera's back face, so
// culling removes it.
std::string write_culled_scene(const fs::path& dir) {
  fs::create_directories(dir);
  const fs::path p = dir / "culled.json";
  std::ofstream(p) << R"({"framebuffer": {"width": 32, "height": 32},
    "draws": [{"primitive": "triangles",
               "positions": [[-0.5, -0.5, 0.5], [-0.5, 0.5, 0.5], [0.5, -0.5, 0.5]],
               "state": {"cull": "back"}}]})";
  return p.string();
}

TEST_F(SessionTest, RunWithCheckIsBitExactAndWritesWhatItReturns) {
  RunRequest request;
  request.scene = kScenes + "quad_clipspace.json";
  request.config.units = 2;
  request.out_dir = (dir_ / "out").string();
  request.check = true;
  const RunOutcome outcome = run_session(request, quiet_);

  ASSERT_TRUE(outcome.check.has_value());
  EXPECT_TRUE(outcome.check->ok());
  EXPECT_FALSE(outcome.check->pixel.has_value());
  EXPECT_TRUE(outcome.check->counts.empty());
  // The counts, against the golden model rendered here on its own.
  const golden::Result golden = golden::render(load_scene(request.scene));
  EXPECT_EQ(outcome.result.counts, golden.stats);
  EXPECT_GT(outcome.result.counts.fragments_written, 0u);
  // stats.json on disk is the one returned, with the run's configuration.
  const nlohmann::json stats = read_json(dir_ / "out" / "stats.json");
  EXPECT_EQ(stats, outcome.stats);
  EXPECT_EQ(stats["model"], "cycle");
  EXPECT_EQ(stats["config"]["units"], 2);
  EXPECT_EQ(stats["stats"], golden.stats.to_json());
  EXPECT_EQ(stats["timing"]["cycles"], outcome.result.cycles);
  EXPECT_TRUE(fs::exists(dir_ / "out" / "frame.exr"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "frame.png"));
  EXPECT_TRUE(outcome.warnings.empty());
  EXPECT_TRUE(outcome.trace_files.empty());
}

TEST_F(SessionTest, CompareWithGoldenNamesThePixelAndTheCounters) {
  RunRequest request;
  request.scene = kScenes + "quad_clipspace.json";
  request.out_dir = (dir_ / "out").string();
  request.check = true;
  RunOutcome outcome = run_session(request, quiet_);
  golden::Result golden = golden::render(outcome.scene);
  // One pixel's colour and one counter changed in the golden model's copy.
  const int x = 40, y = 50;
  ColorChannel* c = golden.framebuffer.color_at(x, y);
  c[0] = encode_color(golden.framebuffer.color_format, 0.25f);
  golden.last_writer[golden.framebuffer.pixel_index(x, y)] = 77;
  golden.stats.fragments_written += 3;
  const CheckReport report = compare_with_golden(golden, outcome.result, 1);
  EXPECT_FALSE(report.ok());
  ASSERT_TRUE(report.pixel.has_value());
  EXPECT_EQ(report.pixel->x, x);
  EXPECT_EQ(report.pixel->y, y);
  EXPECT_EQ(report.pixel->golden_writer, 77);
  EXPECT_NE(report.pixel->cycle, report.pixel->golden);
  EXPECT_EQ(report.pixel->golden.rfind("colour (0.25", 0), 0u) << report.pixel->golden;
  ASSERT_EQ(report.counts.size(), 1u);
  EXPECT_EQ(report.counts[0].name, "fragments_written");
  EXPECT_EQ(report.counts[0].a + 3, report.counts[0].b);
}

TEST_F(SessionTest, AFrameWithNothingDrawnIsWarnedAbout) {
  RunRequest request;
  request.scene = write_culled_scene(dir_);
  request.out_dir = (dir_ / "out").string();
  const RunOutcome outcome = run_session(request, quiet_);
  EXPECT_EQ(outcome.result.counts.triangles_culled, 1u);
  ASSERT_EQ(outcome.warnings.size(), 2u);
  EXPECT_EQ(
      outcome.warnings[0].rfind("warning: none of the 1 triangles reaches the frame (1 culled)", 0),
      0u)
      << outcome.warnings[0];
  EXPECT_EQ(outcome.warnings[1].rfind("warning: the frame has no fragments", 0), 0u);
}

TEST_F(SessionTest, BadInputThrowsAndWritesNothing) {
  RunRequest request;
  request.scene = (dir_ / "missing.json").string();
  request.out_dir = (dir_ / "out").string();
  EXPECT_THROW(run_session(request, quiet_), InputError);
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(SessionTest, GoldenWritesTheGoldenModelsFrameAndCounts) {
  GoldenRequest request;
  request.scene = kScenes + "quad_clipspace.json";
  request.out_dir = (dir_ / "golden").string();
  const GoldenOutcome outcome = golden_session(request, quiet_);
  const golden::Result direct = golden::render(load_scene(request.scene));
  EXPECT_EQ(outcome.result.stats, direct.stats);
  EXPECT_TRUE(outcome.result.framebuffer == direct.framebuffer);
  EXPECT_TRUE(outcome.result.last_writer.empty());  // nothing compares it
  const nlohmann::json stats = read_json(dir_ / "golden" / "stats.json");
  EXPECT_EQ(stats, outcome.stats);
  EXPECT_EQ(stats["model"], "golden");
  EXPECT_EQ(stats["stats"], direct.stats.to_json());
  EXPECT_FALSE(stats.contains("timing"));
}

}  // namespace
}  // namespace gpusim
