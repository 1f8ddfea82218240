#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "hw/gpu_config.h"
#include "hw/stage_spec.h"

namespace gpusim {
namespace {

using nlohmann::json;

std::string error_of(const json& j) {
  try {
    gpu_config_from_json(j, "gpu.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// Writes `text` to a file in the build tree and returns its path.
std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = std::string(GPUSIM_BINARY_DIR) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string load_error(const std::string& path) {
  try {
    load_gpu_config(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GpuConfig, Defaults) {
  const GpuConfig c;
  EXPECT_EQ(c.clock_mhz, 1000.0);
  EXPECT_EQ(c.cycle(), sc_core::sc_time(1, sc_core::SC_NS));
  EXPECT_EQ(c.cycles(7), sc_core::sc_time(7, sc_core::SC_NS));
  EXPECT_EQ(c.units, 4u);
  EXPECT_EQ(c.tile_size, 16u);
  EXPECT_EQ(c.stamp[0], 4u);
  EXPECT_EQ(c.stamp[1], 4u);
  EXPECT_EQ(c.fifo_depth, 16u);
  EXPECT_EQ(c.memory.latency, 20u);
  EXPECT_EQ(c.memory.bytes_per_cycle, 32u);
  EXPECT_EQ(c.memory.channels, 4u);
  EXPECT_EQ(c.memory.interleave_bytes, 1024u);
  EXPECT_EQ(c.surfaces, (SurfaceConfig{true, 1024, true}));
  EXPECT_EQ(c.compression, (CompressionConfig{true, true, 8, 8}));
  EXPECT_EQ(c.vertex_cache_entries, 32u);
  EXPECT_EQ(c.tile_cache_entries, 16u);
  EXPECT_EQ(c.hierarchical_z, (HierarchicalZConfig{true, 5, 4}));
  EXPECT_EQ(c.samples_per_pass, 4u);
  EXPECT_TRUE(c.tile_test_overlap);
  // The baseline: every mechanism of issue #11 off, the rest the defaults.
  const GpuConfig b = GpuConfig::baseline();
  EXPECT_EQ(b.memory, (MemoryConfig{20, 32, 1, 256}));
  EXPECT_EQ(b.surfaces, (SurfaceConfig{false, 1024, false}));
  EXPECT_FALSE(b.compression.depth || b.compression.colour);
  EXPECT_FALSE(b.hierarchical_z.enabled);
  EXPECT_FALSE(b.tile_test_overlap);
  GpuConfig b2 = b;
  b2.memory = c.memory;
  b2.surfaces = c.surfaces;
  b2.compression = c.compression;
  b2.tile_test_overlap = true;
  b2.hierarchical_z.enabled = true;
  EXPECT_EQ(b2, c);
  EXPECT_EQ(c.sample_passes(1), 1u);
  EXPECT_EQ(c.sample_passes(4), 1u);
  EXPECT_EQ(c.sample_passes(16), 4u);
  EXPECT_EQ(c.lighting_cycles_per_pixel, 1u);
  EXPECT_EQ(c.lighting_cycles_per_light, 2u);
  EXPECT_EQ(c.watchdog_cycles, 1000000u);

  // The registered stages' kinds (hw/stage_spec.h), by name.
  EXPECT_EQ(GpuConfig::stage_names(),
            (std::vector<std::string>{"clipper", "command_processor", "depth_test", "interpolator",
                                      "primitive_setup", "resolve", "rop", "texture_unit",
                                      "tile_distributor", "tile_rasterizer", "vertex_fetch",
                                      "vertex_shader"}));
  EXPECT_EQ(GpuConfig::fifo_names(),
            (std::vector<std::string>{
                "clipper_to_setup", "command_to_fetch", "commands", "depth_to_interpolator",
                "distributor_to_rasterizer", "fetch_to_shader", "interpolator_to_rop",
                "interpolator_to_texture", "rasterizer_to_depth", "rop_to_resolve",
                "setup_to_distributor", "shader_to_clipper"}));
  for (const auto& n : GpuConfig::fifo_names()) EXPECT_EQ(c.fifo_depth_of(n), 16u) << n;
  EXPECT_EQ(c.stages.size(), 12u);
  for (const auto& n : GpuConfig::stage_names()) EXPECT_GE(c.stage(n).ii, 1u) << n;
  EXPECT_EQ(c.stage("tile_rasterizer"), (StageCost{1, 2}));
  EXPECT_EQ(c.stage("vertex_shader"), (StageCost{4, 24}));
  EXPECT_EQ(c.stage("primitive_setup"), (StageCost{4, 16}));

  EXPECT_THROW(c.stage("rasterizr"), std::invalid_argument);
  EXPECT_THROW(c.fifo_depth_of("nowhere"), std::invalid_argument);

  EXPECT_EQ(gpu_config_from_json(json::object(), "gpu.json"), c);
}

TEST(GpuConfig, CycleFollowsClock) {
  GpuConfig c;
  c.clock_mhz = 250;
  EXPECT_EQ(c.cycle(), sc_core::sc_time(4, sc_core::SC_NS));
  EXPECT_EQ(c.cycles(3), sc_core::sc_time(12, sc_core::SC_NS));
  c.clock_mhz = 400;
  EXPECT_EQ(c.cycle(), sc_core::sc_time(2500, sc_core::SC_PS));
}

TEST(GpuConfig, PartialOverridesKeepOtherDefaults) {
  const GpuConfig c = gpu_config_from_json(
      json::parse(R"({"fifo_depth": 8, "fifo_depths": {"interpolator_to_rop": 2},
                      "stages": {"clipper": {"latency": 30}},
                      "memory": {"bytes_per_cycle": 16}})"),
      "gpu.json");
  EXPECT_EQ(c.fifo_depth_of("interpolator_to_rop"), 2u);
  EXPECT_EQ(c.fifo_depth_of("fetch_to_shader"), 8u);
  EXPECT_EQ(c.stage("clipper"), (StageCost{2, 30}));  // ii keeps its default 2
  EXPECT_EQ(c.stage("rop"), GpuConfig().stage("rop"));
  EXPECT_EQ(c.memory.bytes_per_cycle, 16u);
  EXPECT_EQ(c.memory.latency, 20u);
  EXPECT_EQ(c.units, 4u);
}

TEST(GpuConfig, RoundTrip) {
  GpuConfig c;
  c.clock_mhz = 533.5;
  c.units = 16;
  c.tile_size = 64;
  c.stamp = {8, 2};
  c.fifo_depth = 3;
  c.fifo_depths["shader_to_clipper"] = 7;
  c.stages["tile_rasterizer"] = {2, 9};
  c.stages["command_processor"] = {5, 0};
  c.memory = {100, 8, 4, 1024};
  c.vertex_cache_entries = 0;
  c.tile_cache_entries = 18;
  c.lighting_cycles_per_pixel = 0;
  c.lighting_cycles_per_light = 7;
  c.watchdog_cycles = 5000;
  c.surfaces = {true, 256, true};
  c.compression = {true, false, 3, 5};
  c.hierarchical_z = {true, 0, 17};
  c.tile_test_overlap = true;

  const json j = to_json(c);
  // Every value resolved.
  EXPECT_EQ(j["fifo_depths"].size(), GpuConfig::fifo_names().size());
  EXPECT_EQ(j["fifo_depths"]["shader_to_clipper"], 7);
  EXPECT_EQ(j["fifo_depths"]["interpolator_to_rop"], 3);
  EXPECT_EQ(j["stages"].size(), GpuConfig::stage_names().size());
  EXPECT_EQ(j["stages"]["tile_rasterizer"], json({{"ii", 2}, {"latency", 9}}));
  EXPECT_EQ(j["stamp"], json({8, 2}));

  const GpuConfig back = gpu_config_from_json(j, "dump");
  EXPECT_EQ(back, c);
  // Through text as well, as stats.json is written and read.
  EXPECT_EQ(gpu_config_from_json(json::parse(j.dump(2)), "dump"), c);
  EXPECT_EQ(to_json(back), j);

  // Equality sees every field.
  GpuConfig d = c;
  d.fifo_depths["interpolator_to_rop"] = 4;
  EXPECT_NE(d, c);
  d = c;
  d.stages["rop"].latency += 1;
  EXPECT_NE(d, c);
  d = c;
  d.memory.latency = 99;
  EXPECT_NE(d, c);
  d = c;
  d.hierarchical_z.update_latency = 3;
  EXPECT_NE(d, c);
  d = c;
  d.stamp = {2, 8};
  EXPECT_NE(d, c);
  d = c;
  d.tile_cache_entries = 1;
  EXPECT_NE(d, c);
  d = c;
  d.lighting_cycles_per_pixel = 3;
  EXPECT_NE(d, c);
  d = c;
  d.lighting_cycles_per_light = 3;
  EXPECT_NE(d, c);
  // An override equal to the default depth is the same resolved config.
  d = c;
  d.fifo_depths["interpolator_to_rop"] = 3;
  EXPECT_EQ(d, c);
}

TEST(GpuConfig, UnknownKeysNameTheirPathAndTheAllowedKeys) {
  EXPECT_EQ(error_of(json{{"unitz", 4}}),
            "gpu.json: unitz: unknown key (allowed: clock_mhz, units, tile_size, stamp, "
            "fifo_depth, fifo_depths, stages, memory, surfaces, compression, hierarchical_z, "
            "texture, vertex_cache_entries, "
            "tile_cache_entries, samples_per_pass, tile_test_overlap, lighting_cycles_per_pixel, "
            "lighting_cycles_per_light, watchdog_cycles)");
  // The old name of the tile rasterizer is refused with the list of stages.
  EXPECT_EQ(
      error_of(json::parse(R"({"stages": {"rasterizer": {"ii": 1}}})")),
      "gpu.json: stages.rasterizer: unknown key (allowed: clipper, command_processor, "
      "depth_test, interpolator, primitive_setup, resolve, rop, texture_unit, tile_distributor, "
      "tile_rasterizer, vertex_fetch, vertex_shader)");
  EXPECT_EQ(error_of(json::parse(R"({"stages": {"tile_rasterizer": {"iii": 1}}})")),
            "gpu.json: stages.tile_rasterizer.iii: unknown key (allowed: ii, latency)");
  EXPECT_EQ(error_of(json::parse(R"({"fifo_depths": {"fetch_to_shadr": 4}})")),
            "gpu.json: fifo_depths.fetch_to_shadr: unknown key (allowed: clipper_to_setup, "
            "command_to_fetch, commands, depth_to_interpolator, distributor_to_rasterizer, "
            "fetch_to_shader, interpolator_to_rop, interpolator_to_texture, rasterizer_to_depth, "
            "rop_to_resolve, "
            "setup_to_distributor, shader_to_clipper)");
  EXPECT_EQ(error_of(json::parse(R"({"texture": {"cache_sets": 3}})")),
            "gpu.json: texture.cache_sets: 3 is not a power of two");
  EXPECT_EQ(error_of(json::parse(R"({"texture": {"cache_line_bytes": 2048}})")),
            "gpu.json: texture.cache_line_bytes: 2048 is out of range 16..1024");
  EXPECT_EQ(error_of(json::parse(R"({"memory": {"latancy": 4}})")),
            "gpu.json: memory.latancy: unknown key (allowed: latency, bytes_per_cycle, channels, "
            "interleave_bytes)");
  // The host's command queue is configurable like every other FIFO.
  EXPECT_EQ(gpu_config_from_json(json::parse(R"({"fifo_depths": {"commands": 3}})"), "g")
                .fifo_depth_of("commands"),
            3u);
}

TEST(GpuConfig, WrongTypes) {
  EXPECT_EQ(error_of(json::array()), "gpu.json: (root): expected an object, got array");
  EXPECT_EQ(error_of(json{{"units", "4"}}), "gpu.json: units: expected an integer, got string");
  EXPECT_EQ(error_of(json{{"units", 4.5}}), "gpu.json: units: expected an integer, got 4.5");
  EXPECT_EQ(error_of(json{{"units", true}}), "gpu.json: units: expected an integer, got boolean");
  EXPECT_EQ(error_of(json{{"clock_mhz", "fast"}}),
            "gpu.json: clock_mhz: expected a number, got string");
  EXPECT_EQ(error_of(json{{"stamp", 4}}), "gpu.json: stamp: expected an array of 2 integers");
  EXPECT_EQ(error_of(json{{"stamp", {4, 4, 4}}}),
            "gpu.json: stamp: expected an array of 2 integers");
  EXPECT_EQ(error_of(json{{"stamp", {4, nullptr}}}),
            "gpu.json: stamp[1]: expected an integer, got null");
  EXPECT_EQ(error_of(json{{"stages", json::array()}}),
            "gpu.json: stages: expected an object, got array");
  EXPECT_EQ(error_of(json::parse(R"({"stages": {"rop": 3}})")),
            "gpu.json: stages.rop: expected an object, got number");
  EXPECT_EQ(error_of(json::parse(R"({"stages": {"rop": {"latency": "2"}}})")),
            "gpu.json: stages.rop.latency: expected an integer, got string");
  EXPECT_EQ(error_of(json{{"fifo_depths", 4}}),
            "gpu.json: fifo_depths: expected an object, got number");
  EXPECT_EQ(error_of(json{{"memory", nullptr}}), "gpu.json: memory: expected an object, got null");
  EXPECT_EQ(error_of(json::parse(R"({"hierarchical_z": {"enabled": 1}})")),
            "gpu.json: hierarchical_z.enabled: expected true or false, got 1");
  EXPECT_EQ(error_of(json::parse(R"({"hierarchical_z": {"update_latency": 1.5}})")),
            "gpu.json: hierarchical_z.update_latency: expected an integer, got 1.5");
  EXPECT_EQ(error_of(json::parse(R"({"hierarchical_z": {"on": true}})")),
            "gpu.json: hierarchical_z.on: unknown key (allowed: enabled, access_latency, "
            "update_latency)");
}

TEST(GpuConfig, OutOfRangeValues) {
  EXPECT_EQ(error_of(json{{"units", 0}}), "gpu.json: units: 0 is out of range 1..64");
  EXPECT_EQ(error_of(json{{"units", 65}}), "gpu.json: units: 65 is out of range 1..64");
  EXPECT_EQ(error_of(json{{"units", -1}}), "gpu.json: units: -1 is out of range 1..64");
  EXPECT_EQ(error_of(json{{"clock_mhz", 0}}), "gpu.json: clock_mhz: 0 is out of range (0, 10000]");
  EXPECT_EQ(error_of(json{{"clock_mhz", -5.5}}),
            "gpu.json: clock_mhz: -5.5 is out of range (0, 10000]");
  EXPECT_EQ(error_of(json{{"tile_size", 24}}), "gpu.json: tile_size: 24 is not a power of two");
  EXPECT_EQ(error_of(json{{"tile_size", 4}}), "gpu.json: tile_size: 4 is out of range 8..256");
  EXPECT_EQ(error_of(json{{"tile_size", 512}}), "gpu.json: tile_size: 512 is out of range 8..256");
  EXPECT_EQ(error_of(json{{"stamp", {32, 4}}}), "gpu.json: stamp[0]: 32 exceeds tile_size 16");
  EXPECT_EQ(error_of(json{{"tile_size", 8}, {"stamp", {4, 16}}}),
            "gpu.json: stamp[1]: 16 exceeds tile_size 8");
  EXPECT_EQ(error_of(json{{"stamp", {4, 3}}}), "gpu.json: stamp[1]: 3 is not a power of two");
  EXPECT_EQ(error_of(json{{"stamp", {16, 8}}}), "gpu.json: stamp: 16x8 has more than 64 pixels");
  EXPECT_EQ(error_of(json{{"stamp", {0, 4}}}), "gpu.json: stamp[0]: 0 is out of range 1..256");
  EXPECT_EQ(error_of(json{{"fifo_depth", 0}}), "gpu.json: fifo_depth: 0 is out of range 1..65536");
  EXPECT_EQ(error_of(json::parse(R"({"hierarchical_z": {"access_latency": 1000001}})")),
            "gpu.json: hierarchical_z.access_latency: 1000001 is out of range 0..1000000");
  EXPECT_EQ(error_of(json::parse(R"({"fifo_depths": {"interpolator_to_rop": 0}})")),
            "gpu.json: fifo_depths.interpolator_to_rop: 0 is out of range 1..65536");
  EXPECT_EQ(error_of(json::parse(R"({"stages": {"tile_rasterizer": {"ii": 0}}})")),
            "gpu.json: stages.tile_rasterizer.ii: 0 is out of range 1..1000000");
  EXPECT_EQ(error_of(json::parse(R"({"stages": {"tile_rasterizer": {"latency": -1}}})")),
            "gpu.json: stages.tile_rasterizer.latency: -1 is out of range 0..1000000");
  EXPECT_EQ(error_of(json::parse(R"({"memory": {"bytes_per_cycle": 0}})")),
            "gpu.json: memory.bytes_per_cycle: 0 is out of range 1..65536");
  EXPECT_EQ(error_of(json::parse(R"({"memory": {"channels": 0}})")),
            "gpu.json: memory.channels: 0 is out of range 1..64");
  EXPECT_EQ(error_of(json::parse(R"({"memory": {"interleave_bytes": 16}})")),
            "gpu.json: memory.interleave_bytes: 16 is out of range 32..1048576");
  EXPECT_EQ(error_of(json::parse(R"({"memory": {"interleave_bytes": 96}})")),
            "gpu.json: memory.interleave_bytes: must be a power of two, got 96");
  EXPECT_EQ(error_of(json{{"watchdog_cycles", 0}}),
            "gpu.json: watchdog_cycles: 0 is out of range 1..1000000000000");
  EXPECT_EQ(error_of(json{{"vertex_cache_entries", 70000}}),
            "gpu.json: vertex_cache_entries: 70000 is out of range 0..65536");
  EXPECT_EQ(error_of(json{{"lighting_cycles_per_light", 1025}}),
            "gpu.json: lighting_cycles_per_light: 1025 is out of range 0..1024");
  EXPECT_EQ(error_of(json{{"lighting_cycles_per_pixel", -1}}),
            "gpu.json: lighting_cycles_per_pixel: -1 is out of range 0..1024");
  EXPECT_EQ(error_of(json{{"tile_cache_entries", 0}}),
            "gpu.json: tile_cache_entries: 0 is out of range 1..1024");
  EXPECT_EQ(error_of(json{{"tile_cache_entries", 1025}}),
            "gpu.json: tile_cache_entries: 1025 is out of range 1..1024");

  // Limits themselves are accepted.
  const GpuConfig c = gpu_config_from_json(
      json::parse(R"({"units": 64, "tile_size": 256, "stamp": [64, 1], "fifo_depth": 1,
                      "stages": {"rop": {"ii": 1, "latency": 0}},
                      "memory": {"latency": 0, "bytes_per_cycle": 1},
                      "vertex_cache_entries": 0, "tile_cache_entries": 1024,
                      "lighting_cycles_per_pixel": 0, "lighting_cycles_per_light": 1024,
                      "watchdog_cycles": 1})"),
      "gpu.json");
  EXPECT_EQ(c.units, 64u);
  EXPECT_EQ(c.lighting_cycles_per_pixel, 0u);
  EXPECT_EQ(c.lighting_cycles_per_light, 1024u);
  EXPECT_EQ(c.stamp[0], 64u);
  EXPECT_EQ(c.vertex_cache_entries, 0u);
  EXPECT_EQ(c.tile_cache_entries, 1024u);
}

TEST(GpuConfig, MalformedJsonGivesLineAndColumn) {
  const std::string path = write_file("hw_gpu_config_test_bad.json", "{\n  \"units\": 4,\n}\n");
  const std::string e = load_error(path);
  const std::string expected_start = path + ": line 3, column 1: syntax error";
  EXPECT_EQ(e.substr(0, expected_start.size()), expected_start) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos);
  EXPECT_EQ(e.find("json.exception"), std::string::npos) << e;
  std::remove(path.c_str());
}

TEST(GpuConfig, FileErrorsAndComments) {
  const std::string missing = std::string(GPUSIM_BINARY_DIR) + "/no_such_gpu.json";
  EXPECT_EQ(load_error(missing), missing + ": cannot open file");

  const std::string bad = write_file("hw_gpu_config_test_range.json", "{\"units\": 0}");
  EXPECT_EQ(load_error(bad), bad + ": units: 0 is out of range 1..64");
  std::remove(bad.c_str());

  const std::string commented =
      write_file("hw_gpu_config_test_comments.json",
                 "{\n  // two units\n  \"units\": 2, /* wide bus */ \"memory\": "
                 "{\"bytes_per_cycle\": 64}\n}\n");
  const GpuConfig c = load_gpu_config(commented);
  EXPECT_EQ(c.units, 2u);
  EXPECT_EQ(c.memory.bytes_per_cycle, 64u);
  std::remove(commented.c_str());
}

TEST(GpuConfig, DefaultFileHoldsEveryDefault) {
  const std::string path = std::string(GPUSIM_SOURCE_DIR) + "/testbench/configs/default.json";
  EXPECT_EQ(load_gpu_config(path), GpuConfig());
  // Not only equal once loaded: the file spells out every value (with
  // comments, which the loader skips).
  std::ifstream in(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(json::parse(in, nullptr, true, /*ignore_comments=*/true), to_json(GpuConfig()));
}

// --set KEY=VALUE: each override as "--set <assignment>".
std::vector<ConfigOverride> sets(const std::vector<std::string>& assignments) {
  std::vector<ConfigOverride> o;
  for (const std::string& a : assignments) o.push_back({"--set " + a, a});
  return o;
}

std::string override_error(const json& base, const std::vector<ConfigOverride>& overrides) {
  try {
    gpu_config_with_overrides(base, overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GpuConfig, SurfacesAndCompression) {
  const GpuConfig c = gpu_config_from_json(json::parse(R"({"surfaces": {"tiled": true,
      "max_burst_bytes": 64, "skip_overwritten_fill": false}, "compression": {"colour": true,
      "depth": false, "decompressor_latency": 0}})"),
                                           "gpu.json");
  EXPECT_TRUE(c.surfaces.tiled);
  EXPECT_EQ(c.surfaces.max_burst_bytes, 64u);
  EXPECT_FALSE(c.surfaces.skip_overwritten_fill);
  EXPECT_TRUE(c.compression.colour);
  EXPECT_FALSE(c.compression.depth);
  EXPECT_EQ(c.compression.compressor_latency, 8u);
  EXPECT_EQ(c.compression.decompressor_latency, 0u);
  // A compressed tile is one block of variable size: only tiled surfaces have one.
  EXPECT_EQ(error_of(json::parse(R"({"surfaces": {"tiled": false},
                                     "compression": {"depth": true}})")),
            "gpu.json: compression.depth: compression needs surfaces.tiled true");
  EXPECT_EQ(error_of(json::parse(R"({"surfaces": {"tiled": false}})")),
            "gpu.json: surfaces.tiled: false needs compression.depth and compression.colour false "
            "(compression needs tiled surfaces)");
  EXPECT_FALSE(gpu_config_from_json(json::parse(R"({"surfaces": {"tiled": false},
      "compression": {"depth": false, "colour": false}})"),
                                    "gpu.json")
                   .surfaces.tiled);
  EXPECT_EQ(error_of(json::parse(R"({"surfaces": {"tiled": false},
                                     "compression": {"colour": true}})")),
            "gpu.json: compression.colour: compression needs surfaces.tiled true");
  EXPECT_EQ(error_of(json::parse(R"({"surfaces": {"tiled": 1}})")),
            "gpu.json: surfaces.tiled: expected true or false, got number");
  EXPECT_EQ(error_of(json::parse(R"({"surfaces": {"max_burst_bytes": 0}})")),
            "gpu.json: surfaces.max_burst_bytes: 0 is out of range 1..16777216");
  EXPECT_EQ(error_of(json::parse(R"({"compression": {"color": true}})")),
            "gpu.json: compression.color: unknown key (allowed: depth, colour, "
            "compressor_latency, decompressor_latency)");
  EXPECT_EQ(override_error(to_json(GpuConfig::baseline()), sets({"compression.depth=true"})),
            "--set compression.depth=true: compression.depth: compression needs surfaces.tiled "
            "true");
  EXPECT_EQ(gpu_config_with_overrides(to_json(GpuConfig::baseline()),
                                      sets({"surfaces.tiled=true", "compression.depth=true"}))
                .compression.depth,
            true);
}

TEST(GpuConfigOverrides, SetNestedKeysOnTheDefaults) {
  const GpuConfig c = gpu_config_with_overrides(
      json::object(),
      sets({"units=8", "stages.primitive_setup.ii=1", "fifo_depths.clipper_to_setup=4",
            "memory.bytes_per_cycle=64", "stamp=[8,8]"}));
  // Expected: the defaults with exactly these five values changed.
  GpuConfig want;
  want.units = 8;
  want.stages["primitive_setup"].ii = 1;  // latency keeps its default, 16
  want.fifo_depths["clipper_to_setup"] = 4;
  want.memory.bytes_per_cycle = 64;
  want.stamp = {8, 8};
  EXPECT_EQ(c, want);
  EXPECT_EQ(c.stage("primitive_setup").latency, 16u);
  EXPECT_EQ(c.fifo_depth_of("clipper_to_setup"), 4u);
  EXPECT_EQ(c.fifo_depth_of("setup_to_distributor"), 16u);
}

TEST(GpuConfigOverrides, AppliedOnTheFileInOrder) {
  // The file's values stay unless set; a later --set wins over an earlier.
  const json file = json::parse(R"({"units": 2, "fifo_depth": 8,
                                    "stages": {"clipper": {"ii": 3, "latency": 11}}})");
  const GpuConfig c = gpu_config_with_overrides(
      file, sets({"stages.clipper.ii=5", "units=3", "units=6", "fifo_depth=32"}));
  EXPECT_EQ(c.units, 6u);
  EXPECT_EQ(c.stage("clipper").ii, 5u);
  EXPECT_EQ(c.stage("clipper").latency, 11u);  // the file's, not the default 8
  // fifo_depth applies to every FIFO without its own depth, as in a file.
  EXPECT_EQ(c.fifo_depth_of("rasterizer_to_depth"), 32u);
  // A whole object replaces the file's: its absent keys take the defaults.
  const GpuConfig m =
      gpu_config_with_overrides(json::parse(R"({"memory": {"latency": 7, "bytes_per_cycle": 8}})"),
                                sets({R"(memory={"latency":5})"}));
  EXPECT_EQ(m.memory.latency, 5u);
  EXPECT_EQ(m.memory.bytes_per_cycle, 32u);
  // A value that is not JSON is a string.
  nlohmann::json j = json::object();
  apply_config_override(j, "units=eight", "--set units=eight");
  EXPECT_EQ(j, json::parse(R"({"units": "eight"})"));
  apply_config_override(j, "a.b.c=true", "s");
  EXPECT_EQ(j["a"], json::parse(R"({"b": {"c": true}})"));
}

TEST(GpuConfigOverrides, ErrorsNameTheOverride) {
  EXPECT_EQ(override_error(json::object(), sets({"units=4", "stages.primitive_setup.ii=0"})),
            "--set stages.primitive_setup.ii=0: stages.primitive_setup.ii: 0 is out of range "
            "1..1000000");
  EXPECT_EQ(override_error(json::object(), sets({"units=eight"})),
            "--set units=eight: units: expected an integer, got string");
  EXPECT_EQ(override_error(json::object(), sets({"unitz=4"})),
            "--set unitz=4: unitz: unknown key (allowed: clock_mhz, units, tile_size, stamp, "
            "fifo_depth, fifo_depths, stages, memory, surfaces, compression, hierarchical_z, "
            "texture, vertex_cache_entries, "
            "tile_cache_entries, samples_per_pass, tile_test_overlap, lighting_cycles_per_pixel, "
            "lighting_cycles_per_light, watchdog_cycles)");
  // A renamed stage's former names: the kind, and a unit's instance of it.
  EXPECT_EQ(StageRegistry::current_name("triangle_setup"), "primitive_setup");
  EXPECT_EQ(StageRegistry::current_name("triangle_setup_12"), "primitive_setup_12");
  for (const char* other : {"triangle_setup_", "triangle_setup_x", "triangle_setupx",
                            "triangle_set", "primitive_setup", "rop_0"}) {
    EXPECT_EQ(StageRegistry::current_name(other), "") << other;
  }
  // A renamed stage's former key is read as the new one, with one warning;
  // both at once is an error.
  testing::internal::CaptureStderr();
  const GpuConfig renamed =
      gpu_config_with_overrides(json::object(), sets({"stages.triangle_setup.ii=2"}));
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_EQ(renamed.stage("primitive_setup").ii, 2u);
  EXPECT_EQ(renamed.stage("primitive_setup").latency, 16u);
  EXPECT_NE(warned.find("warning: overrides: stages: 'triangle_setup' is deprecated, read as "
                        "'primitive_setup'"),
            std::string::npos)
      << warned;
  EXPECT_EQ(std::count(warned.begin(), warned.end(), '\n'), 1) << warned;
  EXPECT_EQ(override_error(json::object(),
                           sets({"stages.triangle_setup.ii=2", "stages.primitive_setup.ii=3"})),
            "--set stages.triangle_setup.ii=2: stages.triangle_setup: given together with "
            "stages.primitive_setup, its new name");
  // An unknown stage is reported at the stage, which the key leads through.
  EXPECT_EQ(override_error(json::object(), sets({"stages.setup.ii=1"})),
            "--set stages.setup.ii=1: stages.setup: unknown key (allowed: clipper, "
            "command_processor, depth_test, interpolator, primitive_setup, resolve, rop, "
            "texture_unit, tile_distributor, tile_rasterizer, vertex_fetch, vertex_shader)");
  // A key below a value that is not an object.
  EXPECT_EQ(override_error(json::object(), sets({"units.x=1"})),
            "--set units.x=1: units: expected an integer, got object");
  // Inside a whole array set.
  EXPECT_EQ(override_error(json::object(), sets({"stamp=[32,2]"})),
            "--set stamp=[32,2]: stamp[0]: 32 exceeds tile_size 16");
  // A constraint between keys, at a path no override leads to: all named.
  EXPECT_EQ(override_error(json::parse(R"({"tile_size": 32, "stamp": [32, 2]})"),
                           sets({"tile_size=16", "units=2"})),
            "--set tile_size=16 --set units=2: stamp[0]: 32 exceeds tile_size 16");
  // The --units shorthand, named as given.
  EXPECT_EQ(
      override_error(json::object(), {{"--set units=2", "units=2"}, {"--units 0", "units=0"}}),
      "--units 0: units: 0 is out of range 1..64");
  // Malformed assignments.
  EXPECT_EQ(override_error(json::object(), sets({"units"})),
            "--set units: expected KEY=VALUE, e.g. stages.primitive_setup.ii=2");
  EXPECT_EQ(override_error(json::object(), sets({"=4"})),
            "--set =4: expected KEY=VALUE with KEY a dotted configuration key, e.g. "
            "stages.primitive_setup.ii=2");
  EXPECT_EQ(override_error(json::object(), sets({"stages..ii=4"})),
            "--set stages..ii=4: expected KEY=VALUE with KEY a dotted configuration key, e.g. "
            "stages.primitive_setup.ii=2");
}

}  // namespace
}  // namespace gpusim
