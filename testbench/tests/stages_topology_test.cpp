// The netlist (stages/topology.h) is the one list of the pipeline: the
// configuration (the registered specs), stats.json and the trace tables must
// name the same stages and FIFOs, with the same endpoints, and nothing may
// depend on the order in which the GPU elaborates its units.
#include <gtest/gtest.h>

#include <algorithm>

#include "hw/simulation_context.h"
#include "stages/gpu.h"

namespace gpusim {
namespace {

FrameState small_frame() {
  FrameState f;
  f.framebuffer.width = 64;
  f.framebuffer.height = 48;
  return f;
}

std::vector<std::string> sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  return v;
}

// The configuration's kinds are the registered specs' (hw/stage_spec.h);
// docs/gpu-config.md's tables are generated (sim_config_defaults_test).
TEST(Topology, ConfigurationAndNetlistNameTheSameThings) {
  GpuConfig config;
  config.units = 3;
  // A multisampled frame with a textured draw elaborates every stage, the
  // resolve and the texture units included.
  FrameState frame = small_frame();
  frame.framebuffer.samples = 4;
  frame.draws.emplace_back().texture.levels = {TextureLevel{0, 1, 1}};
  Gpu gpu("gpu", config, frame, 1 << 16);
  const Topology& t = gpu.topology();
  EXPECT_EQ(sorted(t.stage_kinds()), GpuConfig::stage_names());
  EXPECT_EQ(sorted(t.fifo_kinds()), GpuConfig::fifo_names());
  // Each FIFO is an input its reader's spec declares.
  for (const auto& f : t.fifos()) {
    const auto& inputs = t.stages()[f.reader].stage->spec().inputs;
    EXPECT_NE(std::find(inputs.begin(), inputs.end(), f.kind), inputs.end()) << f.name;
  }
  // Each stage's placement is where the netlist put it.
  for (const auto& s : t.stages()) {
    const bool per_unit = s.stage->spec().placement == StagePlacement::per_unit;
    EXPECT_EQ(per_unit, s.stage->unit() >= 0) << s.stage->basename();
  }
}

TEST(Topology, ASingleSampleFrameLeavesOutExactlyTheOptionalKinds) {
  GpuConfig config;
  config.units = 2;
  const FrameState frame = small_frame();
  fresh_simulation_context();
  Gpu gpu("gpu", config, frame, 1 << 16);
  std::vector<std::string> kinds = gpu.topology().stage_kinds();
  for (const std::string& f : gpu.topology().fifo_kinds()) kinds.push_back(f);
  std::vector<std::string> all = GpuConfig::stage_names();
  for (const std::string& f : GpuConfig::fifo_names()) all.push_back(f);
  std::vector<std::string> missing;
  for (const std::string& k : all) {
    if (std::find(kinds.begin(), kinds.end(), k) == kinds.end()) missing.push_back(k);
  }
  EXPECT_EQ(sorted(missing), StageRegistry::optional_kinds());
  // The resolve comes last in pipeline order when present.
  FrameState aa = small_frame();
  aa.framebuffer.supersample = 2;
  fresh_simulation_context();
  Gpu gpu_aa("gpu", config, aa, 1 << 16);
  EXPECT_EQ(gpu_aa.topology().stages().back().stage->stage_kind(), "resolve");
  EXPECT_EQ(gpu_aa.topology().fifos().back().kind, "rop_to_resolve");
}

TEST(Topology, NamesAreKindAndUnitAndStatsUseThem) {
  GpuConfig config;
  config.units = 2;
  const FrameState frame = small_frame();
  Gpu gpu("gpu", config, frame, 1 << 16);
  const Topology& t = gpu.topology();
  // 6 front-end stages and 4 per unit; 6 front-end FIFOs and 4 per unit.
  ASSERT_EQ(t.stages().size(), 6u + 4u * 2u);
  ASSERT_EQ(t.fifos().size(), 6u + 4u * 2u);
  for (const auto& s : t.stages()) {
    EXPECT_EQ(s.stage->basename(),
              PipelineStage::instance_name(s.stage->stage_kind(), s.stage->unit()));
    EXPECT_EQ(s.stage->stats().name(), s.stage->basename());
  }
  for (const auto& f : t.fifos()) {
    EXPECT_EQ(f.name, PipelineStage::instance_name(f.kind, f.unit));
    EXPECT_EQ(f.channel->capacity(), config.fifo_depth_of(f.kind));
    // A unit's FIFOs join that unit's stages (or the distributor).
    if (f.writer != Topology::kHost && t.stages()[f.writer].stage->unit() >= 0) {
      EXPECT_EQ(t.stages()[f.writer].stage->unit(), f.unit) << f.name;
    }
    EXPECT_EQ(t.stages()[f.reader].stage->unit(), f.unit) << f.name;
  }
  // Pipeline order: the front end by distance from the host, then each unit.
  std::vector<std::string> names;
  for (const auto& s : t.stages()) names.push_back(s.stage->basename());
  EXPECT_EQ(names,
            (std::vector<std::string>{
                "command_processor", "vertex_fetch", "vertex_shader", "clipper", "primitive_setup",
                "tile_distributor", "tile_rasterizer_0", "depth_test_0", "interpolator_0", "rop_0",
                "tile_rasterizer_1", "depth_test_1", "interpolator_1", "rop_1"}));

  // stats.json: one entry per stage and FIFO under its name, every counter
  // described with a unit, the stalled / starved figures derived from the
  // FIFOs.
  const nlohmann::json j = gpu.stats_json(0);
  EXPECT_EQ(j["stages"].size(), t.stages().size());
  EXPECT_EQ(j["fifos"].size(), t.fifos().size());
  for (const auto& s : t.stages()) {
    const nlohmann::json& counters = j["stages"][s.stage->basename()];
    const nlohmann::json& described = j["descriptions"]["stages"][s.stage->stage_kind()];
    for (const auto& c : counters.items()) {
      ASSERT_TRUE(described.contains(c.key())) << s.stage->basename() << "." << c.key();
      EXPECT_FALSE(described[c.key()]["unit"].get<std::string>().empty()) << c.key();
      EXPECT_FALSE(described[c.key()]["description"].get<std::string>().empty()) << c.key();
    }
    EXPECT_TRUE(counters.contains("stalled_cycles"));
    EXPECT_TRUE(counters.contains("starved_cycles"));
  }
  for (const auto& f : j["fifos"].items()) {
    for (const auto& field : f.value().items()) {
      EXPECT_TRUE(j["descriptions"]["fifos"].contains(field.key())) << field.key();
    }
  }
}

TEST(Topology, UnitElaborationOrderChangesNothingListed) {
  GpuConfig config;
  config.units = 3;
  const FrameState frame = small_frame();
  Gpu up("up", config, frame, 1 << 16, Gpu::UnitOrder::ascending);
  Gpu down("down", config, frame, 1 << 16, Gpu::UnitOrder::descending);
  const NetlistTables a = up.topology().trace_tables(), b = down.topology().trace_tables();
  ASSERT_EQ(a.stages.size(), b.stages.size());
  ASSERT_EQ(a.fifos.size(), b.fifos.size());
  for (size_t i = 0; i < a.stages.size(); ++i) {
    EXPECT_EQ(a.stages[i].name, b.stages[i].name);
    EXPECT_EQ(a.stages[i].inputs, b.stages[i].inputs);
    EXPECT_EQ(a.stages[i].outputs, b.stages[i].outputs);
  }
  for (size_t i = 0; i < a.fifos.size(); ++i) {
    EXPECT_EQ(a.fifos[i].name, b.fifos[i].name);
    EXPECT_EQ(a.fifos[i].writer, b.fifos[i].writer);
    EXPECT_EQ(a.fifos[i].reader, b.fifos[i].reader);
  }
  // Memory clients, numbered in bind order (their round-robin order at the
  // arbiter), are bound in unit order whatever the elaboration order.
  std::vector<std::string> clients;
  for (unsigned c = 0; c < up.memory().num_clients(); ++c)
    clients.push_back(up.memory().client_name(c));
  EXPECT_EQ(clients, (std::vector<std::string>{"vertex_fetch", "depth_test_0", "rop_0",
                                               "depth_test_1", "rop_1", "depth_test_2", "rop_2"}));
  ASSERT_EQ(down.memory().num_clients(), clients.size());
  for (unsigned c = 0; c < clients.size(); ++c) EXPECT_EQ(down.memory().client_name(c), clients[c]);
}

// Memory ports and the hierarchical-Z links are edges of the netlist: the
// tables name each client's stage in the memory's client order, and each
// unit's link from its depth test to its rasterizer.
TEST(Topology, MemoryClientsAndLinksAreNetlistEdges) {
  GpuConfig config;
  config.units = 2;
  config.hierarchical_z.enabled = true;
  FrameState frame = small_frame();
  frame.framebuffer.samples = 4;  // with the resolve, the last client
  Gpu gpu("gpu", config, frame, 1 << 16, Gpu::UnitOrder::descending);
  const NetlistTables t = gpu.topology().trace_tables();
  ASSERT_EQ(t.memory_clients.size(), gpu.memory().num_clients());
  std::vector<std::string> stages;
  for (size_t c = 0; c < t.memory_clients.size(); ++c) {
    EXPECT_EQ(t.memory_clients[c].name, gpu.memory().client_name(static_cast<unsigned>(c)));
    stages.push_back(t.stages.at(t.memory_clients[c].stage).name);
  }
  EXPECT_EQ(stages, (std::vector<std::string>{"vertex_fetch", "depth_test_0", "rop_0",
                                              "depth_test_1", "rop_1", "resolve"}));
  ASSERT_EQ(t.links.size(), 2u);
  for (int u = 0; u < 2; ++u) {
    const NetlistTables::Link& l = t.links[static_cast<size_t>(u)];
    EXPECT_EQ(l.kind, "hz_update");
    EXPECT_EQ(l.unit, u);  // in unit order, though elaborated in descending order
    EXPECT_EQ(l.name, "hz_update_" + std::to_string(l.unit));
    EXPECT_EQ(t.stages.at(l.writer).name, "depth_test_" + std::to_string(l.unit));
    EXPECT_EQ(t.stages.at(l.reader).name, "tile_rasterizer_" + std::to_string(l.unit));
  }
  const nlohmann::ordered_json j = to_json(t);
  EXPECT_EQ(j["memory_clients"][5]["stage"], "resolve");
  EXPECT_EQ(j["links"][0]["writer"], "depth_test_0");

  // Without hierarchical Z there is no link.
  config.hierarchical_z.enabled = false;
  Gpu plain("plain", config, small_frame(), 1 << 16);
  EXPECT_TRUE(plain.topology().trace_tables().links.empty());
}

}  // namespace
}  // namespace gpusim
