// `gpusim trace summary`: the bottleneck named in scenes built to be limited
// by one stage (setup, the rasterizers, the memory bus), the signals
// agreeing with stats.json, and the histograms adding up to the window.
#include <cmath>
#include <filesystem>
#include <string>

#include "testbench/tests/traces_support.h"
#include "traces/trace_reader.h"
#include "traces/trace_summary.h"

namespace gpusim {
namespace {

using trace_test::at_window;
using trace_test::CommandResult;
using trace_test::gpusim;
using TraceSummaryTest = trace_test::TraceTest;
namespace fs = std::filesystem;

// Checks that hold for any unfiltered trace: the signals' busy, stalled and
// starved cycles equal stats.json's, each stage is in exactly one state at a
// time, and every FIFO's histogram covers the whole frame.
void expect_consistent(const TraceSummary& s, uint64_t cycles) {
  EXPECT_TRUE(s.cross_checked());
  for (const std::string& e : s.cross_check()) ADD_FAILURE() << "cross-check: " << e;
  for (const TraceSummary::Stage& st : s.stages()) {
    EXPECT_EQ(st.busy + st.stalled + st.starved, cycles) << st.name;
  }
  for (const TraceSummary::Fifo& f : s.fifos()) {
    uint64_t total = 0;
    for (const auto& [level, t] : f.cycles_at) {
      EXPECT_LE(level, f.depth) << f.name;
      total += t;
    }
    EXPECT_EQ(total, cycles) << f.name;
  }
}

// The bottleneck is `kind`, not memory-bound; the nearest stage it stalls
// is of kind `stalled` and stalled more than half the frame; the nearest it
// starves is of kind `starved`. Returns the bottleneck for further checks.
const TraceSummary::Bottleneck& expect_bottleneck(const TraceSummary& s, const char* kind,
                                                  const char* stalled, const char* starved) {
  const TraceSummary::Bottleneck& b = s.bottleneck();
  EXPECT_EQ(b.kind, kind);
  EXPECT_GT(b.busy, 0.8);
  EXPECT_FALSE(b.memory_bound);
  EXPECT_TRUE(!b.stalls.empty() && b.stalls[0].kind == stalled && b.stalls[0].mean > 0.5)
      << s.text();
  EXPECT_TRUE(!b.starves.empty() && b.starves[0].kind == starved) << s.text();
  return b;
}

TEST_F(TraceSummaryTest, SetupBoundSceneNamesPrimitiveSetup) {
  // 480 triangles inside pixel (8, 8) of a 64x64 screen, one unit, setup at
  // ii 32 per triangle. Per triangle the other stages need: fetch 3 slots
  // x 1, the shader 3 vertices x 4 = 12, the clipper 2, the distributor 1,
  // the rasterizer 1 tile test + 1 stamp, the back end 1 stamp each; so
  // setup (32) is the slowest by far and busy through most of the frame.
  // Its writer, the clipper, is stalled behind it; its reader, the
  // distributor, starves.
  const int w = 64, h = 64;
  nlohmann::json positions = nlohmann::json::array();
  for (int i = 0; i < 480; ++i) {
    positions.push_back(at_window(8.2, 8.2, 0.0, w, h));
    positions.push_back(at_window(8.9, 8.3, 0.0, w, h));
    positions.push_back(at_window(8.4, 8.9, 0.0, w, h));
  }
  const std::string scene = write_json("tiny.json", {{"framebuffer", {{"width", w}, {"height", h}}},
                                                     {"draws", {{{"positions", positions}}}}});
  const std::string config =
      write_json("setup_bound.json",
                 {{"units", 1}, {"stages", {{"primitive_setup", {{"ii", 32}, {"latency", 40}}}}}});
  const std::string dir = trace(scene, "--config " + config);
  const TraceReader reader(dir);
  const TraceSummary s(reader);
  expect_consistent(s, reader.manifest().cycles);

  // Busy for 480 x 32 cycles of a frame a little longer.
  const TraceSummary::Bottleneck& b =
      expect_bottleneck(s, "primitive_setup", "clipper", "tile_distributor");
  EXPECT_EQ(b.busiest, "primitive_setup");
  ASSERT_FALSE(b.starves.empty());
  EXPECT_GT(b.starves[0].mean, 0.8);

  const CommandResult r = gpusim("trace summary " + dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("Bottleneck: primitive_setup"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("stalls (upstream, blocked writing into its input): clipper"),
            std::string::npos)
      << r.out;
  const CommandResult j = gpusim("trace summary " + dir + " --json");
  ASSERT_EQ(j.status, 0) << j.out;
  const nlohmann::json parsed = nlohmann::json::parse(j.out);
  EXPECT_EQ(parsed["bottleneck"]["kind"], "primitive_setup");
  EXPECT_EQ(parsed["stages"].size(), s.stages().size());
}

TEST_F(TraceSummaryTest, FillBoundSceneNamesTheRasterizers) {
  // 100 triangles each holding the whole 64x64 screen (window (0,0),
  // (128,0), (0,128)), depth test off, 8x8 tiles of 4x4 stamps: every
  // triangle covers all 64 tiles, 16 per unit on 4 units, each accepted
  // whole. Per tile a rasterizer spends 1 test + 4 stamps = 5 cycles, the
  // depth test, interpolator and ROP 4 each: 8000 cycles per rasterizer
  // against 6400 per back-end stage. The memory never holds a tile access up
  // (no latency, 64 KiB a cycle, caches holding every tile); the final
  // write-back, one bus cycle per tile row (64 tiles x 8 rows per buffer),
  // adds at most 512 cycles to a depth test and 1024 to a ROP, which
  // leaves the rasterizers the busiest. (With 16x16 tiles a rasterizer
  // spends 17 cycles per tile against 16, and the write-back would decide.)
  // Setup and the distributor spend 4 cycles per triangle and fill the
  // rasterizers' 16-deep input FIFOs, then wait on them: the distributor is
  // stalled; the depth tests starve 1 cycle in 5.
  // --trace-prims 0:0 keeps fragments.bin small; signals are not filtered.
  const int w = 64, h = 64;
  nlohmann::json draws = nlohmann::json::array();
  for (int i = 0; i < 100; ++i) {
    draws.push_back(
        {{"positions",
          {at_window(0, 0, 0, w, h), at_window(128, 0, 0, w, h), at_window(0, 128, 0, w, h)}},
         {"state", {{"depth_test", "off"}}}});
  }
  const std::string scene =
      write_json("huge.json", {{"framebuffer", {{"width", w}, {"height", h}}}, {"draws", draws}});
  const std::string config =
      write_json("fill_bound.json", {{"units", 4},
                                     {"tile_size", 8},
                                     {"stamp", {4, 4}},
                                     {"memory", {{"latency", 0}, {"bytes_per_cycle", 65536}}},
                                     {"tile_cache_entries", 1024},
                                     // The serial tile test of the cost above.
                                     {"tile_test_overlap", false}});
  const std::string dir = trace(scene, "--config " + config + " --trace-prims 0:0");
  const TraceReader reader(dir);
  const TraceSummary s(reader);
  expect_consistent(s, reader.manifest().cycles);

  const TraceSummary::Bottleneck& b =
      expect_bottleneck(s, "tile_rasterizer", "tile_distributor", "depth_test");
  EXPECT_EQ(b.stages, 4u);
  ASSERT_FALSE(b.starves.empty());
  EXPECT_EQ(b.starves[0].stages.size(), 4u);

  // Load balance: every unit owns 16 of the 64 tiles and visits them once
  // per triangle, 5 cycles each.
  ASSERT_EQ(s.units().size(), 4u);
  for (const TraceSummary::Unit& u : s.units()) {
    ASSERT_TRUE(u.tiles.has_value());
    EXPECT_EQ(*u.tiles, 100u * 16u);
    ASSERT_TRUE(u.fragments.has_value());
    EXPECT_EQ(*u.fragments, 100u * 16u * 64u);
    ASSERT_FALSE(u.busy.empty());
    ASSERT_TRUE(u.busy[0].has_value());
    EXPECT_EQ(*u.busy[0], 100u * 16u * 5u + 2u);  // + clear and end of frame
  }
  const CommandResult r = gpusim("trace summary " + dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("Bottleneck: tile_rasterizer (busiest of 4 units"), std::string::npos)
      << r.out;
}

// The memory system of issue #11 switched off (GpuConfig::baseline()): one
// channel, row-major surfaces, no compression, a serial tile test.
const char* const kBaselineSettings =
    " --set memory.channels=1 --set memory.interleave_bytes=256 --set surfaces.tiled=false"
    " --set surfaces.skip_overwritten_fill=false --set compression.depth=false"
    " --set compression.colour=false --set tile_test_overlap=false";

TEST_F(TraceSummaryTest, DefaultSceneIsMemoryBoundOnOneBus) {
  // Without the memory system (one bus, a request per tile row, every tile
  // read and written whole), the default scene keeps the bus busy 96% of the
  // frame with tile cache fills and the final write-back; the depth tests
  // and ROPs spend most of their busy time waiting for memory.
  const std::string dir = trace(GPUSIM_SOURCE_DIR "/testbench/scenes/default.json",
                                std::string("--trace-prims 0:0") + kBaselineSettings);
  const TraceReader reader(dir);
  const TraceSummary s(reader);
  expect_consistent(s, reader.manifest().cycles);
  const TraceSummary::Bottleneck& b = s.bottleneck();
  EXPECT_TRUE(b.kind == "rop" || b.kind == "depth_test") << b.kind;
  EXPECT_TRUE(b.memory_bound);
  ASSERT_TRUE(b.memory_utilization.has_value());
  EXPECT_GT(*b.memory_utilization, 0.9);
  EXPECT_GT(b.memory_stall_share, 0.5);
  const CommandResult r = gpusim("trace summary " + dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("memory-bound"), std::string::npos) << r.out;
}

TEST_F(TraceSummaryTest, DefaultSceneIsNotBusBoundUnderTheDefaultConfiguration) {
  // Issue #11: with 4 channels, tiled surfaces, compression and no fill for
  // overwritten tiles, no channel is busy 70% of the frame; the depth tests
  // are the busiest stage, still waiting on the fills of the tiles they miss.
  const std::string dir =
      trace(GPUSIM_SOURCE_DIR "/testbench/scenes/default.json", "--trace-prims 0:0");
  const TraceReader reader(dir);
  const TraceSummary s(reader);
  expect_consistent(s, reader.manifest().cycles);
  const TraceSummary::Bottleneck& b = s.bottleneck();
  EXPECT_EQ(b.kind, "depth_test");
  EXPECT_FALSE(b.memory_bound);
  ASSERT_TRUE(b.memory_utilization.has_value());
  EXPECT_LT(*b.memory_utilization, 0.7);
  const CommandResult r = gpusim("trace summary " + dir);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find("memory-bound"), std::string::npos) << r.out;
}

// Issue #16 item 5: `trace summary` on a run's --out directory said only
// "manifest.json: cannot open". Every trace subcommand now says the
// directory is not a trace, how to write one, and, when it holds a run's
// outputs, that it looks like an --out directory; exit 2, one line.
TEST_F(TraceSummaryTest, NotATraceDirectoryIsNamed) {
  const std::string trace_dir =
      trace(GPUSIM_SOURCE_DIR "/testbench/scenes/quad_clipspace.json", "--units 1", "t");
  const std::string out = trace_dir + "_out";  // run --out: stats.json, frame.exr
  ASSERT_TRUE(fs::exists(fs::path(out) / "stats.json"));
  const std::string not_trace =
      ": not a trace directory (no manifest.json; write one with gpusim run SCENE --trace DIR)";
  const std::string hint = " (this looks like a run's --out directory)";
  for (const std::string& cmd :
       {"trace summary " + out, "trace summary --json " + out, "trace follow " + out + " --prim 0",
        "trace follow " + out + " --pixel 1,1"}) {
    const CommandResult r = gpusim(cmd);
    EXPECT_EQ(r.status, 2) << cmd << ": " << r.out;
    EXPECT_EQ(r.out, "gpusim: " + out + not_trace + hint + "\n") << cmd;
  }
  const fs::path empty = dir_ / "empty";
  fs::create_directories(empty);
  CommandResult r = gpusim("trace summary " + empty.string());
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_EQ(r.out, "gpusim: " + empty.string() + not_trace + "\n");
  r = gpusim("trace summary " + (dir_ / "missing").string());
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_EQ(r.out, "gpusim: " + (dir_ / "missing").string() + ": no such directory\n");
  // The trace itself still reads.
  EXPECT_EQ(gpusim("trace summary " + trace_dir).status, 0);
}

}  // namespace
}  // namespace gpusim
