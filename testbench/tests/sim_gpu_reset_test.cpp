// A GPU reset between frames (Gpu::reset, GpuRunner) must leave nothing of
// the frames before: each frame run on one reused GPU gives, byte for byte,
// the cycles, statistics, pipeline counts and frame of the same frame on a
// freshly elaborated GPU. The sequences repeat scenes and mix ones that warm
// every cache and buffer a stage keeps (vertex and tile caches, hierarchical
// Z, the lighting registers of draw 0, clears, lines and points), under
// configurations that keep state in other places (decoupled stages and
// their stamped FIFOs, random stalls, compression and tiled surfaces).
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "testbench/scene/scene.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/sim/progress.h"
#include "testbench/tests/json_difference.h"

namespace gpusim {
namespace {

Scene scene(const std::string& name) {
  return load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + name + ".json");
}

nlohmann::json figures(const GpuRunResult& r) {
  return {{"cycles", r.cycles}, {"timing", r.timing}, {"counts", r.counts.to_json()}};
}

struct ResetCase {
  const char* name;
  GpuConfig config;
  GpuRunOptions options;
};

std::vector<ResetCase> cases() {
  std::vector<ResetCase> out;
  out.push_back({"default", GpuConfig{}, {}});
  GpuConfig hz;
  hz.units = 3;
  hz.hierarchical_z.enabled = true;
  hz.surfaces.tiled = true;
  hz.compression.depth = true;
  hz.compression.colour = true;
  out.push_back({"3 units, hierarchical Z, compressed tiled surfaces", hz, {}});
  GpuConfig tight = GpuConfig::baseline();
  tight.units = 2;
  tight.fifo_depth = 1;
  tight.fifo_depths.clear();
  GpuRunOptions stalled;
  stalled.stall_probability = 0.3;
  stalled.stall_max_cycles = 5;
  out.push_back({"baseline, 2 units, depth 1, random stalls", tight, stalled});
  GpuRunOptions lockstep;
  lockstep.temporal_decoupling = false;
  lockstep.watchdog = false;
  out.push_back({"lockstep, no watchdog", GpuConfig{}, lockstep});
  return out;
}

// "<scene>" with modifiers "+first": its first draw alone; "+relit": that
// draw with the lights and its material in other colours (one after the
// other, the lighting units hold draw 0's registers from the frame before,
// which must be loaded again); "+plain": without its textures (a textured
// frame elaborates texture units, another netlist).
Scene named(const std::string& name) {
  std::vector<std::string> parts;
  for (size_t at = 0;;) {
    const size_t plus = name.find('+', at);
    parts.push_back(name.substr(at, plus == std::string::npos ? std::string::npos : plus - at));
    if (plus == std::string::npos) break;
    at = plus + 1;
  }
  Scene s = scene(parts[0]);
  for (size_t i = 1; i < parts.size(); ++i) {
    if (parts[i] == "plain") {
      s.textures.clear();
      for (Draw& d : s.draws) {
        d.texture = -1;
        d.texcoords.clear();
      }
      continue;
    }
    s.draws.resize(1);
    if (parts[i] == "relit") {
      for (Light& l : s.lights) l.diffuse = glm::vec4(0.9f, 0.3f, 0.1f, 1.0f);
      s.draws[0].material.diffuse = glm::vec4(0.2f, 0.8f, 0.4f, 1.0f);
    }
  }
  return s;
}

// Runs `names` in order on one GpuRunner and each on its own GPU; returns
// the runner's elaborations.
unsigned expect_fresh_results(const ResetCase& c, const std::vector<std::string>& names) {
  GpuRunner runner(c.config, c.options);
  for (size_t i = 0; i < names.size(); ++i) {
    const Scene s = named(names[i]);
    const GpuRunResult reused = runner.run(s);
    const GpuRunResult fresh = run_gpu(s, c.config, c.options);
    const std::string where =
        std::string(c.name) + ", frame " + std::to_string(i) + " (" + names[i] + ")";
    EXPECT_EQ(reused.cycles, fresh.cycles) << where;
    EXPECT_EQ(json_difference(figures(reused), figures(fresh)), "") << where;
    EXPECT_EQ(json_difference(reused.timing, fresh.timing), "") << where;
    EXPECT_TRUE(reused.framebuffer == fresh.framebuffer) << where;
    EXPECT_EQ(reused.decoupled_stages, fresh.decoupled_stages) << where;
  }
  return runner.elaborations();
}

TEST(GpuReset, ReusedGpuGivesEachFrameTheFreshResult) {
  // No resolve stage in any of them: one GPU for the whole sequence.
  // Lit draws 0 of other lights and materials one after the other, scenes
  // of every kind of primitive and clear, a scene twice with others in
  // between.
  const std::vector<std::string> names = {"spider+plain+first", "spider+plain+relit", "phong",
                                          "hiz_funcs",          "lines_points",       "clears",
                                          "spider+plain",       "hiz_funcs",          "states"};
  for (const ResetCase& c : cases()) EXPECT_EQ(expect_fresh_results(c, names), 1u) << c.name;
}

TEST(GpuReset, TexturedFramesShareTheirTextureUnits) {
  // The texture units' caches and fragment FIFOs start empty each frame:
  // other textures, mipmapped and not, and the same frame again.
  const std::vector<std::string> names = {"textured", "spider", "textured+first", "textured"};
  for (const ResetCase& c : cases()) EXPECT_EQ(expect_fresh_results(c, names), 1u) << c.name;
}

TEST(GpuReset, MultisampledFramesShareTheirResolveStage) {
  // Per-pixel lighting (the interpolator's lighting unit), and other sample
  // counts (each reaches its own distance beyond a pixel).
  const std::vector<std::string> names = {"aa_phong_samples4+first",
                                          "aa_phong_samples4+relit",
                                          "aa_samples8",
                                          "hiz_funcs_samples4",
                                          "aa_samples2",
                                          "clears_samples4",
                                          "aa_phong_samples4"};
  EXPECT_EQ(expect_fresh_results(cases()[1], names), 1u);
}

TEST(GpuReset, AnotherNetlistElaboratesAnotherGpu) {
  // A resolve stage, none, then one again: three GPUs, the results still
  // the fresh ones.
  const std::vector<std::string> names = {"clears_samples4", "clears", "clears", "aa_super2"};
  EXPECT_EQ(expect_fresh_results(cases()[0], names), 3u);
  // Texture units, none, then again.
  EXPECT_EQ(expect_fresh_results(cases()[0], {"textured", "states", "textured+first"}), 3u);
}

// The testbench's own threads start over with each frame: the progress
// display reports each frame's figures from its first cycle. Neither it
// nor the watchdog (on in every run here) moves a cycle.
TEST(GpuReset, ProgressStartsOverWithEachFrame) {
  std::ostringstream lines;
  Progress shown(Progress::Mode::lines, lines, 0.0);
  GpuRunOptions options;
  options.progress = &shown;
  GpuConfig config;
  GpuRunner runner(config, options);
  const std::vector<std::string> names = {"clears", "phong", "clears"};
  std::vector<uint64_t> cycles;
  for (const std::string& name : names) {
    const Scene s = scene(name);
    const GpuRunResult reused = runner.run(s);
    const GpuRunResult fresh = run_gpu(s, config, {});
    EXPECT_EQ(json_difference(figures(reused), figures(fresh)), "") << name;
    cycles.push_back(reused.cycles);
  }
  EXPECT_EQ(runner.elaborations(), 1u);
  // Each frame's simulate phase ("simulate: N primitives in D draws")
  // ends with a state line of that frame's cycles.
  std::vector<uint64_t> reported;
  std::istringstream in(lines.str());
  for (std::string line; std::getline(in, line);) {
    if (line.find(" primitives in ") != std::string::npos) reported.push_back(0);
    const size_t at = line.find(" cycles, ");
    if (reported.empty() || line.find("simulate: ") != 0 || at == std::string::npos) continue;
    const size_t from = line.rfind(", ", at) + 2;
    reported.back() = std::stoull(line.substr(from, at - from));
  }
  EXPECT_EQ(reported, cycles) << lines.str();
}

// A lost end of frame leaves the model broken: each run elaborates anew,
// and each reports the watchdog's hang.
TEST(GpuReset, RunsWithAnInjectedFaultAreElaboratedEachTime) {
  GpuConfig config;
  config.watchdog_cycles = 200;
  GpuRunOptions options;
  options.fault_withhold_end_of_frame = true;
  GpuRunner runner(config, options);
  const Scene s = scene("clears");
  EXPECT_THROW(runner.run(s), SimulationError);
  EXPECT_THROW(runner.run(s), SimulationError);
  EXPECT_EQ(runner.elaborations(), 2u);
}

}  // namespace
}  // namespace gpusim
