// Conservation (docs/robustness.md, "Conservation"): at the end of every run,
// each stage's items in equal its items out plus the items it dropped (culled,
// clipped, failed the depth test, ...), and every FIFO delivered what it took.
// run_gpu checks it and throws SimulationError on a mismatch. Here: the check
// passes on every example scene (under two configurations and with random
// stalls), and the checker itself catches every kind of doctored counter.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "stages/gpu.h"
#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> scene_names() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(GPUSIM_SOURCE_DIR "/testbench/scenes")) {
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

Scene load(const std::string& name) {
  return load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + name + ".json");
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

class EveryScene : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryScene, CountersBalance) {
  const Scene scene = load(GetParam());
  const LoadedFrame frame = load_frame(scene);
  GpuConfig odd;
  odd.units = 3;
  odd.tile_size = 8;
  odd.stamp = {2, 4};
  odd.fifo_depth = 1;
  odd.vertex_cache_entries = 0;
  odd.tile_cache_entries = 1;
  GpuRunOptions stalls;
  stalls.stall_probability = 0.2;
  stalls.stall_max_cycles = 5;
  for (const auto& [config, options] :
       std::vector<std::pair<GpuConfig, GpuRunOptions>>{{GpuConfig{}, {}}, {odd, stalls}}) {
    // run_gpu throws SimulationError when the counters do not balance.
    const GpuRunResult r = run_gpu(scene, config, options);
    EXPECT_EQ(joined(conservation_errors(r.timing, r.netlist, frame.frame)), "");
    EXPECT_EQ(joined(pipeline_count_errors(r.counts)), "");
  }
  EXPECT_EQ(joined(pipeline_count_errors(golden::render(scene).stats)), "");
}

INSTANTIATE_TEST_SUITE_P(Scenes, EveryScene, ::testing::ValuesIn(scene_names()));

// A real run's counters, doctored one way at a time: each must be caught,
// and the message must name where.
class Doctored : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Culling, clipping, depth failures, blending: every drop path is used.
    scene_ = new Scene(load("default"));
    frame_ = new LoadedFrame(load_frame(*scene_));
    GpuConfig config;
    config.units = 2;
    result_ = new GpuRunResult(run_gpu(*scene_, config, {}));
  }
  static void TearDownTestSuite() {
    delete result_;
    delete frame_;
    delete scene_;
  }
  static const nlohmann::json& stats() { return result_->timing; }
  static std::string check(const nlohmann::json& s) {
    return joined(conservation_errors(s, result_->netlist, frame_->frame));
  }
  static Scene* scene_;
  static LoadedFrame* frame_;
  static GpuRunResult* result_;
};
Scene* Doctored::scene_ = nullptr;
LoadedFrame* Doctored::frame_ = nullptr;
GpuRunResult* Doctored::result_ = nullptr;

TEST_F(Doctored, TheRealCountersBalance) {
  EXPECT_EQ(check(stats()), "");
  // The scene exercises the drop paths the rules account for.
  const nlohmann::json& st = stats().at("stages");
  EXPECT_GT(st.at("primitive_setup").at("triangles_culled").get<uint64_t>(), 0u);
  EXPECT_GT(st.at("depth_test_0").at("fragments_in").get<uint64_t>(),
            st.at("depth_test_0").at("fragments_passed").get<uint64_t>());
}

struct Doctoring {
  const char* section;  // "stages" or "fifos"
  const char* name;
  const char* counter;
  int64_t delta;
  const char* expect;  // in the report
};

TEST_F(Doctored, EveryMismatchIsCaught) {
  const std::vector<Doctoring> cases = {
      // A FIFO that lost an item, or delivered one twice.
      {"fifos", "clipper_to_setup", "read", -1, "fifo clipper_to_setup"},
      {"fifos", "rasterizer_to_depth_1", "written", +1, "rasterizer_to_depth_1"},
      {"fifos", "commands", "read", +1, "command_processor: tokens_in"},
      // Stages whose counts of items in and out disagree.
      {"stages", "command_processor", "tokens_out", -1, "command_processor: tokens_out"},
      {"stages", "vertex_fetch", "invalid_slots", +1, "vertex_fetch: slots"},
      {"stages", "vertex_fetch", "cache_hits", -1, "vertex_fetch: slots"},
      {"stages", "vertex_shader", "vertices_shaded", -1, "vertex_shader: vertices_shaded"},
      {"stages", "clipper", "triangles_in", +1, "clipper: triangles_in"},
      {"stages", "clipper", "triangles_after_clip", -1, "clipper"},
      // Lines and points the clipper says it wrote, which no FIFO carried.
      {"stages", "clipper", "lines_out", +1, "clipper: lines_out"},
      {"stages", "clipper", "unfilled_points", +1, "clipper: points_out"},
      {"stages", "clipper", "triangles_culled", +1000000, "clipper: polygon-mode triangles"},
      {"stages", "primitive_setup", "triangles_culled", +1,
       "primitive_setup: clipper.triangles_after_clip"},
      {"stages", "primitive_setup", "triangles_degenerate", -1, "primitive_setup"},
      {"stages", "primitive_setup", "tokens_out", -1, "primitive_setup: tokens_out"},
      {"stages", "tile_distributor", "triangles_sent_unit1", +1, "tile_distributor"},
      {"stages", "tile_rasterizer_0", "triangles", -1, "tile_rasterizer_0: triangles"},
      {"stages", "tile_rasterizer_1", "fragments", +1, "depth_test_1: fragments_in"},
      {"stages", "depth_test_0", "fragments_passed", -1, "interpolator_0: fragments"},
      {"stages", "depth_test_1", "fragments_passed", +1000000, "depth_test_1: fragments_passed"},
      {"stages", "interpolator_1", "stamps", +1, "interpolator_1: stamps"},
      {"stages", "rop_0", "fragments_in", -1, "rop_0: fragments_in"},
      {"stages", "rop_1", "fragments_written", +1000000, "rop_1: fragments_written"},
      {"stages", "rop_1", "frames", +1, "rop_1: frames"},
      // A clear lost or executed twice (the frame clear is the scene's only one).
      {"stages", "command_processor", "clears", +1, "command_processor: clears"},
      {"stages", "depth_test_1", "depth_clears", -1, "depth_test_1: depth_clears"},
      {"stages", "rop_0", "color_clears", +1, "rop_0: color_clears"},
  };
  for (const Doctoring& d : cases) {
    SCOPED_TRACE(std::string(d.section) + "." + d.name + "." + d.counter);
    nlohmann::json s = stats();
    nlohmann::json& v = s.at(d.section).at(d.name).at(d.counter);
    v = static_cast<uint64_t>(static_cast<int64_t>(v.get<uint64_t>()) + d.delta);
    const std::string report = check(s);
    EXPECT_NE(report, "");
    EXPECT_NE(report.find(d.expect), std::string::npos) << report;
  }
}

TEST_F(Doctored, MissingCountersAndMemoryErrorsAreCaught) {
  nlohmann::json s = stats();
  s["stages"]["clipper"].erase("triangles_invalid");
  EXPECT_NE(check(s).find("stages.clipper.triangles_invalid: missing from the statistics"),
            std::string::npos)
      << check(s);
  s = stats();
  s.erase("fifos");
  EXPECT_NE(check(s).find("fifos: missing"), std::string::npos) << check(s);
  s = stats();
  s["memory"]["clients"].begin().value()["errors"] = 2;
  EXPECT_NE(check(s).find("2 requests answered with an error"), std::string::npos) << check(s);
}

TEST(PipelineCounts, DoctoredGoldenCountsAreCaught) {
  const nlohmann::json good = golden::render(load("clipping")).stats.to_json();
  EXPECT_EQ(joined(pipeline_count_errors(PipelineCounts::from_json(good))), "");
  for (const char* k : {"triangles_culled", "triangles_after_clip", "fragments_passed_depth",
                        "fragments_written", "triangles_invalid"}) {
    nlohmann::json bad = good;
    bad[k] = good[k].get<uint64_t>() + 1000000;
    EXPECT_NE(joined(pipeline_count_errors(PipelineCounts::from_json(bad))), "") << k;
  }
  // Counts read back from a file must have every field.
  nlohmann::json missing = good;
  missing.erase("triangles_in");
  try {
    PipelineCounts::from_json(missing);
    ADD_FAILURE() << "a missing field was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "triangles_in: missing");
  }
}

// Counters of a frame with every kind, made up by hand to satisfy section 13:
// 10 triangles, 1 invalid, 1 clipped away; of the 8 kept, 6 filled (one cut
// in two: 7 after clip; setup: 1 degenerate, 1 culled, 5 rasterized) and 2
// in polygon mode line (1 culled, 1 unfilled drawn as 3 lines). 5 lines, 1
// invalid, 1 clipped away, 1 clipped; 3 kept + 3 = 5 rasterized and 1
// degenerate. 4 points, 2 clipped away, 2 rasterized. 1 of the 5
// rasterized triangles is off-screen.
nlohmann::json every_kind_counts() {
  return {{"triangles_in", 10u},
          {"triangles_invalid", 1u},
          {"triangles_clipped_away", 1u},
          {"triangles_clipped", 1u},
          {"triangles_after_clip", 7u},
          {"triangles_degenerate", 1u},
          {"triangles_culled", 2u},
          {"triangles_rasterized", 5u},
          {"triangles_unfilled", 1u},
          {"triangles_offscreen", 1u},
          {"lines_in", 5u},
          {"lines_invalid", 1u},
          {"lines_clipped_away", 1u},
          {"lines_clipped", 1u},
          {"lines_degenerate", 1u},
          {"lines_rasterized", 5u},
          {"points_in", 4u},
          {"points_invalid", 0u},
          {"points_clipped_away", 2u},
          {"points_rasterized", 2u},
          {"fragments_generated", 100u},
          {"fragments_passed_depth", 90u},
          {"fragments_written", 80u},
          {"color_clears", 1u},
          {"depth_clears", 1u},
          {"samples_generated", 100u},
          {"samples_passed_depth", 90u},
          {"samples_written", 80u}};
}

TEST(PipelineCounts, LinesPointsAndPolygonModeBalance) {
  const nlohmann::json good = every_kind_counts();
  const auto errors = [](const nlohmann::json& j) {
    return joined(pipeline_count_errors(PipelineCounts::from_json(j)));
  };
  EXPECT_EQ(errors(good), "");
  struct Case {
    const char* key;
    int64_t delta;
    const char* expect;
  };
  for (const Case& c : std::vector<Case>{
           {"lines_rasterized", -4, "lines_rasterized + lines_degenerate = 2"},
           {"lines_clipped", +3, "lines_clipped = 4"},
           {"lines_invalid", +5, "lines_invalid + lines_clipped_away = 7"},
           {"points_rasterized", -1, "points_rasterized = 1"},
           {"points_clipped_away", +3, "points_invalid + points_clipped_away = 5"},
           {"triangles_culled", +10, "polygon-mode triangles"},
           {"triangles_unfilled", +7, "polygon-mode triangles"},
           {"triangles_rasterized", -3, "is below triangles_after_clip = 7"},
           {"triangles_in", +5, "triangles_after_clip = 7 is below the 11"},
           {"triangles_offscreen", +5, "triangles_offscreen = 6 exceeds triangles_rasterized = 5"},
       }) {
    nlohmann::json bad = good;
    bad[c.key] = static_cast<uint64_t>(static_cast<int64_t>(good[c.key].get<uint64_t>()) + c.delta);
    const std::string report = errors(bad);
    EXPECT_NE(report.find(c.expect), std::string::npos) << c.key << ": " << report;
  }
  // Without unfilled triangles, lines and points rasterized are exactly the
  // ones kept.
  nlohmann::json filled = good;
  filled["triangles_unfilled"] = 0u;
  filled["triangles_degenerate"] = 2u;  // the unfilled one was degenerate instead
  filled["lines_rasterized"] = 2u;
  EXPECT_EQ(errors(filled), "");
  filled["lines_rasterized"] = 3u;
  EXPECT_NE(errors(filled).find("lines_rasterized"), std::string::npos);
  filled["lines_rasterized"] = 2u;
  filled["points_rasterized"] = 3u;
  EXPECT_NE(errors(filled).find("points_rasterized"), std::string::npos);
}

}  // namespace
}  // namespace gpusim
