// Adding a stage is its own spec and class plus one connection: this test
// declares a pass-through stage here, registers it, puts it in every raster
// unit between the tile rasterizer and the depth test (Interposers, the
// test's one "connect"), and runs whole frames through it. Nothing else in
// the tree knows the stage: the configuration takes its cost key and FIFO
// from its spec, stats.json, the netlist and the conservation ledger list it,
// and the frame stays bit-exact with the golden model.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "hw/pipeline_stage.h"
#include "hw/stage_spec.h"
#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

// Forwards every stamp batch and control token unchanged, ii cycles each.
class PassThrough : public PipelineStage {
 public:
  static const StageSpec& spec() {
    static const StageSpec s{"pass_through",
                             StagePlacement::per_unit,
                             /*optional=*/true,
                             {/*ii=*/1, /*latency=*/3},
                             "stamp batch",
                             "a register stage: forwards what it reads",
                             "stamp batches and control tokens read",
                             "stamp batches and control tokens written",
                             {"rasterizer_to_pass_through"},
                             /*conservation=*/nullptr,
                             StageTrace{TraceItem::stamp_batch, {}, FragmentSite::none},
                             {{"", "`ii` per batch", "Forwards it unchanged."}}};
    return s;
  }

  FifoInPort<StampBatch> in;
  FifoOutPort<StampBatch> out;

  PassThrough(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
              int unit)
      : PipelineStage(name, spec(), unit, config, frame), in("in"), out("out") {
    SC_HAS_PROCESS(PassThrough);
    SC_THREAD(run);
  }

 private:
  void run() {
    StampBatch batch;
    for (;;) {
      receive(in, batch);
      work(m_cost.ii);
      emit(out, std::move(batch));
    }
  }
};
GPUSIM_REGISTER_STAGE(PassThrough);

// The test's connection: a pass-through in the place of every unit's
// rasterizer_to_depth FIFO.
Interposers pass_through_before_depth() {
  Interposers interposers;
  interposers.add<StampBatch>(
      "rasterizer_to_depth", [](int unit, const GpuConfig& config, const FrameState& frame) {
        auto stage = std::make_unique<PassThrough>(
            PipelineStage::instance_name("pass_through", unit).c_str(), config, frame, unit);
        Interposers::Made<StampBatch> made;
        made.in = &stage->in;
        made.out = &stage->out;
        made.stage = std::move(stage);
        return made;
      });
  return interposers;
}

Scene scene(const std::string& name) {
  return load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + name + ".json");
}

TEST(PassThroughStage, ItsSpecIsTheConfigurationsKeysAndDefaults) {
  const std::vector<std::string> stages = GpuConfig::stage_names();
  EXPECT_NE(std::find(stages.begin(), stages.end(), "pass_through"), stages.end());
  const std::vector<std::string> fifos = GpuConfig::fifo_names();
  EXPECT_NE(std::find(fifos.begin(), fifos.end(), "rasterizer_to_pass_through"), fifos.end());
  const GpuConfig config;
  EXPECT_EQ(config.stage("pass_through"), (StageCost{1, 3}));
  EXPECT_EQ(to_json(config)["stages"]["pass_through"]["latency"], 3);
  // A configuration file may set it like any other stage.
  const GpuConfig set = gpu_config_from_json({{"stages", {{"pass_through", {{"ii", 2}}}}},
                                              {"fifo_depths", {{"rasterizer_to_pass_through", 4}}}},
                                             "test");
  EXPECT_EQ(set.stage("pass_through"), (StageCost{2, 3}));
  EXPECT_EQ(set.fifo_depth_of("rasterizer_to_pass_through"), 4u);
}

TEST(PassThroughStage, AFrameRunsThroughItBitExact) {
  const Scene s = scene("default");
  GpuConfig config;
  config.units = 2;
  const GpuRunResult plain = run_gpu(s, config, {});

  GpuRunOptions options;
  const Interposers interposers = pass_through_before_depth();
  options.interposers = &interposers;
  const GpuRunResult r = run_gpu(s, config, options);
  ASSERT_TRUE(r.completed);  // run_gpu also checked the conservation ledger

  EXPECT_EQ(r.framebuffer, golden::render(s).framebuffer);
  EXPECT_EQ(r.framebuffer, plain.framebuffer);
  EXPECT_EQ(r.counts, plain.counts);

  // In the netlist, per unit, between the rasterizer and the depth test.
  for (int unit = 0; unit < 2; ++unit) {
    const std::string u = "_" + std::to_string(unit);
    const auto stage = std::find_if(r.netlist.stages.begin(), r.netlist.stages.end(),
                                    [&](const auto& st) { return st.name == "pass_through" + u; });
    ASSERT_NE(stage, r.netlist.stages.end()) << unit;
    EXPECT_EQ(stage->kind, "pass_through");
    EXPECT_EQ(stage->unit, unit);
    ASSERT_EQ(stage->inputs.size(), 1u);
    ASSERT_EQ(stage->outputs.size(), 1u);
    const auto& fin = r.netlist.fifos[stage->inputs[0]];
    const auto& fout = r.netlist.fifos[stage->outputs[0]];
    EXPECT_EQ(fin.name, "rasterizer_to_pass_through" + u);
    EXPECT_EQ(r.netlist.stages[fin.writer].name, "tile_rasterizer" + u);
    EXPECT_EQ(fout.name, "rasterizer_to_depth" + u);
    EXPECT_EQ(r.netlist.stages[fout.reader].name, "depth_test" + u);

    // Its statistics: every batch and token the rasterizer wrote, ii each.
    const auto& stats = r.timing["stages"]["pass_through" + u];
    const uint64_t emitted = r.timing["stages"]["tile_rasterizer" + u]["tokens_out"];
    EXPECT_GT(emitted, 0u);
    EXPECT_EQ(stats["tokens_in"], emitted);
    EXPECT_EQ(stats["tokens_out"], emitted);
    EXPECT_EQ(stats["busy_cycles"], emitted);
    EXPECT_EQ(r.timing["stages"]["depth_test" + u]["tokens_in"], emitted);
  }
  // Its counters are described like every stage's.
  EXPECT_EQ(r.timing["descriptions"]["stages"]["pass_through"]["tokens_in"]["description"],
            "stamp batches and control tokens read");
  // Three more cycles of latency on the path to every depth test: the frame
  // cannot be shorter.
  EXPECT_GE(r.cycles, plain.cycles);
}

// Random stalls are seeded by each FIFO's name: adding a stage (two FIFOs
// in the place of one) leaves every other FIFO's stall stream as it was.
TEST(PassThroughStage, AddingItKeepsTheOtherFifosStallStreams) {
  const Scene s = scene("default");
  GpuConfig config;
  config.units = 2;
  GpuRunOptions options;
  options.stall_probability = 0.2;
  options.stall_seed = 5;
  const GpuRunResult plain = run_gpu(s, config, options);
  const Interposers interposers = pass_through_before_depth();
  options.interposers = &interposers;
  const GpuRunResult r = run_gpu(s, config, options);
  ASSERT_TRUE(plain.completed && r.completed);
  EXPECT_EQ(r.framebuffer, plain.framebuffer);
  // The front end's FIFOs carry the same items either way; their draws of
  // the same streams delay the same reads and writes.
  for (const char* fifo : {"commands", "command_to_fetch", "fetch_to_shader", "shader_to_clipper",
                           "clipper_to_setup", "setup_to_distributor"}) {
    const auto& a = plain.timing["fifos"][fifo];
    const auto& b = r.timing["fifos"][fifo];
    EXPECT_GT(a["injected_stalls"].get<uint64_t>(), 0u) << fifo;
    EXPECT_EQ(a["injected_stalls"], b["injected_stalls"]) << fifo;
    EXPECT_EQ(a["injected_stall_cycles"], b["injected_stall_cycles"]) << fifo;
  }
  EXPECT_NE(stall_seed_of("commands", 5), stall_seed_of("command_to_fetch", 5));
  EXPECT_NE(stall_seed_of("commands", 5), stall_seed_of("commands", 6));
}

}  // namespace
}  // namespace gpusim
