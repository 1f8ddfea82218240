// `gpusim stats summary` and `stats diff` as a library: the netlist read
// from a stats.json equals the trace's manifest of the same run, the
// bottleneck equals the trace summary's, every figure is the stats.json
// number it is computed from, the memory-bound rule's thresholds, and the
// diff's entries, order and missing keys.
#include <algorithm>
#include <cmath>
#include <string>

#include "hw/netlist_tables.h"
#include "testbench/tests/traces_support.h"
#include "traces/stats_summary.h"
#include "traces/trace_reader.h"
#include "traces/trace_summary.h"

namespace gpusim {
namespace {

using StatsSummaryTest = trace_test::TraceTest;

const std::string kScenes = GPUSIM_SOURCE_DIR "/testbench/scenes/";

// The stages and FIFOs manifest_from_stats() reads from stats.json are
// those the recorder wrote from the elaborated netlist, in the same order.
void expect_same_netlist(const TraceManifest& from_stats, const TraceManifest& traced) {
  ASSERT_EQ(from_stats.stages.size(), traced.stages.size());
  for (size_t i = 0; i < traced.stages.size(); ++i) {
    const TraceStage& a = from_stats.stages[i];
    const TraceStage& b = traced.stages[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.kind, b.kind) << b.name;
    EXPECT_EQ(a.unit, b.unit) << b.name;
    auto sorted = [](std::vector<std::string> v) {
      std::sort(v.begin(), v.end());
      return v;
    };
    EXPECT_EQ(sorted(a.inputs), sorted(b.inputs)) << b.name;
    EXPECT_EQ(sorted(a.outputs), sorted(b.outputs)) << b.name;
  }
  ASSERT_EQ(from_stats.fifos.size(), traced.fifos.size());
  for (const TraceFifo& f : traced.fifos) {
    const TraceFifo* g = from_stats.fifo(f.name);
    ASSERT_NE(g, nullptr) << f.name;
    EXPECT_EQ(g->writer, f.writer) << f.name;
    EXPECT_EQ(g->reader, f.reader) << f.name;
    EXPECT_EQ(g->depth, f.depth) << f.name;
    EXPECT_EQ(g->unit, f.unit) << f.name;
  }
  EXPECT_EQ(from_stats.units, traced.units);
  EXPECT_EQ(from_stats.cycles, traced.cycles);
}

TEST_F(StatsSummaryTest, NetlistAndBottleneckEqualTheTraces) {
  struct Case {
    std::string scene, args;
  };
  for (const Case& c : {Case{"default.json", "--units 1"}, Case{"default.json", "--units 4"},
                        Case{"aa_super2.json", "--units 2"}}) {
    SCOPED_TRACE(c.scene + " " + c.args);
    const std::string dir = trace(kScenes + c.scene, c.args, "t" + std::to_string(c.args.back()));
    const TraceReader reader(dir);
    const nlohmann::json stats = read_stats_file(reader.path("stats.json"), true);
    expect_same_netlist(manifest_from_stats(stats, "stats.json"), reader.manifest());

    const TraceSummary traced(reader);
    const StatsSummary summary(stats, reader.path("stats.json"));
    const Bottleneck& a = summary.bottleneck();
    const Bottleneck& b = traced.bottleneck();
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.busiest, b.busiest);
    EXPECT_EQ(a.bound, b.bound);
    EXPECT_EQ(a.memory_bound, b.memory_bound);
    // The signals and the counters agree within a cycle (the trace
    // summary's cross-check), so the shares within a cycle of the frame.
    const double cycle = 1.0 / static_cast<double>(reader.manifest().cycles);
    EXPECT_NEAR(a.busy, b.busy, cycle);
    ASSERT_EQ(a.stalls.size(), b.stalls.size());
    for (size_t i = 0; i < a.stalls.size(); ++i) {
      EXPECT_EQ(a.stalls[i].kind, b.stalls[i].kind);
      EXPECT_NEAR(a.stalls[i].mean, b.stalls[i].mean, cycle);
    }
    ASSERT_EQ(a.starves.size(), b.starves.size());
    for (size_t i = 0; i < a.starves.size(); ++i) EXPECT_EQ(a.starves[i].kind, b.starves[i].kind);
  }
}

TEST_F(StatsSummaryTest, FiguresAreTheStatsJsonNumbers) {
  const std::string dir = trace(kScenes + "default.json", "--units 4");
  const std::string path = dir + "/stats.json";
  const nlohmann::json stats = read_stats_file(path, true);
  const StatsSummary s(stats, path);
  const nlohmann::json& timing = stats["timing"];
  const double cycles = timing["cycles"].get<double>();
  ASSERT_EQ(s.stages().size(), timing["stages"].size());
  const nlohmann::json j = s.json();
  for (const nlohmann::json& st : j["stages"]) {
    const nlohmann::json& counters = timing["stages"][st["name"].get<std::string>()];
    EXPECT_DOUBLE_EQ(st["busy"].get<double>(), counters["busy_cycles"].get<double>() / cycles);
    EXPECT_DOUBLE_EQ(st["stalled"].get<double>(),
                     counters["stalled_cycles"].get<double>() / cycles);
    EXPECT_DOUBLE_EQ(st["starved"].get<double>(),
                     counters["starved_cycles"].get<double>() / cycles);
  }
  // The bottleneck is the stage with the most busy cycles in stats.json.
  std::string busiest;
  double most = -1.0;
  for (const auto& item : timing["stages"].items()) {
    if (item.value()["busy_cycles"].get<double>() > most) {
      most = item.value()["busy_cycles"].get<double>();
      busiest = item.key();
    }
  }
  EXPECT_EQ(s.bottleneck().busiest, busiest);
  EXPECT_DOUBLE_EQ(s.bottleneck().busy, most / cycles);
  const nlohmann::json& rates = timing["rates"];
  for (const char* r : {"raster_pixels_per_clock", "setup_triangles_per_clock"}) {
    const std::string peak = std::string(r) + "_peak";
    EXPECT_DOUBLE_EQ(j["rates"][r]["achieved"].get<double>(), rates[r].get<double>());
    EXPECT_DOUBLE_EQ(j["rates"][r]["peak"].get<double>(), rates[peak].get<double>());
    EXPECT_DOUBLE_EQ(j["rates"][r]["of_peak"].get<double>(),
                     rates[r].get<double>() / rates[peak].get<double>());
  }
  const nlohmann::json& memory = timing["memory"];
  // The mean channel's utilization: busy cycles summed over the channels.
  EXPECT_NEAR(j["memory"]["utilization"].get<double>(),
              memory["busy_cycles"].get<double>() / (cycles * memory["channels"].size()), 1e-12);
  ASSERT_EQ(j["memory"]["clients"].size(), memory["clients"].size());
  for (const nlohmann::json& c : j["memory"]["clients"]) {
    const nlohmann::json& m = memory["clients"][c["name"].get<std::string>()];
    EXPECT_EQ(c["bytes_read"], m["bytes_read"]);
    EXPECT_EQ(c["bytes_written"], m["bytes_written"]);
    EXPECT_NEAR(c["queued_cycles_mean"].get<double>(),
                m["queued_cycles"].get<double>() / m["requests"].get<double>(), 1e-9);
  }
  ASSERT_EQ(s.units().size(), 4u);
  for (size_t u = 0; u < 4; ++u) {
    EXPECT_EQ(*s.units()[u].tiles, timing["units"][u]["tiles"].get<uint64_t>());
    EXPECT_EQ(
        *s.units()[u].busy[0],
        timing["stages"]["tile_rasterizer_" + std::to_string(u)]["busy_cycles"].get<uint64_t>());
  }
}

// A stats.json of one unit, made up: depth_test_0 busy 900 of 1000 cycles,
// 600 of them memory stalls, the bus `utilization` busy.
nlohmann::json made_up(double utilization) {
  nlohmann::json stages = nlohmann::json::object();
  for (const char* k : {"command_processor", "vertex_fetch", "vertex_shader", "clipper",
                        "primitive_setup", "tile_distributor"}) {
    stages[k] = {{"busy_cycles", 100}, {"stalled_cycles", 800.0}, {"starved_cycles", 100.0}};
  }
  stages["tile_rasterizer_0"] = {
      {"busy_cycles", 100}, {"stalled_cycles", 850.0}, {"starved_cycles", 50.0}};
  stages["depth_test_0"] = {{"busy_cycles", 900},
                            {"stalled_cycles", 0.0},
                            {"starved_cycles", 100.0},
                            {"memory_stall_cycles", 600}};
  stages["interpolator_0"] = {
      {"busy_cycles", 100}, {"stalled_cycles", 0.0}, {"starved_cycles", 900.0}};
  stages["rop_0"] = {{"busy_cycles", 200}, {"stalled_cycles", 0.0}, {"starved_cycles", 800.0}};
  nlohmann::json fifos = nlohmann::json::object();
  // The netlist: a chain, FIFO i from stage i - 1 (the host for the first)
  // to stage i.
  const std::vector<std::string> order = {"command_processor", "vertex_fetch",
                                          "vertex_shader",     "clipper",
                                          "primitive_setup",   "tile_distributor",
                                          "tile_rasterizer_0", "depth_test_0",
                                          "interpolator_0",    "rop_0"};
  const std::vector<std::string> fifo_order = {"commands",
                                               "command_to_fetch",
                                               "fetch_to_shader",
                                               "shader_to_clipper",
                                               "clipper_to_setup",
                                               "setup_to_distributor",
                                               "distributor_to_rasterizer_0",
                                               "rasterizer_to_depth_0",
                                               "depth_to_interpolator_0",
                                               "interpolator_to_rop_0"};
  NetlistTables netlist;
  for (size_t i = 0; i < order.size(); ++i) {
    const bool unit = order[i].back() == '0';
    netlist.stages.push_back(
        {order[i],
         unit ? order[i].substr(0, order[i].size() - 2) : order[i],
         unit ? 0 : -1,
         {static_cast<int>(i)},
         i + 1 < order.size() ? std::vector<int>{static_cast<int>(i + 1)} : std::vector<int>{},
         "primitive",
         {},
         ""});
    const std::string& f = fifo_order[i];
    const bool funit = f.back() == '0';
    netlist.fifos.push_back({f, funit ? f.substr(0, f.size() - 2) : f, 16, static_cast<int>(i) - 1,
                             static_cast<int>(i), funit ? 0 : -1});
    fifos[f] = {{"depth", 16}};
  }
  return {{"stats", nlohmann::json::object()},
          {"config", {{"units", 1}, {"clock_mhz", 1000}}},
          {"timing",
           {{"cycles", 1000},
            {"simulated_seconds", 1e-6},
            {"stages", stages},
            {"fifos", fifos},
            {"netlist", nlohmann::json::parse(to_json(netlist).dump())},
            {"memory", {{"utilization", utilization}, {"busy_cycles", 1000 * utilization}}}}}};
}

TEST(StatsSummary, MemoryBoundFromSeventyPercentOfTheBusAndHalfTheBusyCycles) {
  // 600 / 900 of the depth test's busy cycles are memory stalls: memory-bound
  // from a bus 70% busy.
  const StatsSummary bound(made_up(0.7), "made_up");
  EXPECT_EQ(bound.bottleneck().kind, "depth_test");
  EXPECT_TRUE(bound.bottleneck().memory_bound);
  EXPECT_EQ(bound.bottleneck().bound, "memory");
  EXPECT_DOUBLE_EQ(bound.bottleneck().memory_stall_share, 600.0 / 900.0);
  EXPECT_DOUBLE_EQ(bound.bottleneck().busy, 0.9);
  // Upstream: the rasterizer (85% stalled), then the distributor (80%).
  ASSERT_GE(bound.bottleneck().stalls.size(), 2u);
  EXPECT_EQ(bound.bottleneck().stalls[0].kind, "tile_rasterizer");
  EXPECT_DOUBLE_EQ(bound.bottleneck().stalls[0].mean, 0.85);
  EXPECT_EQ(bound.bottleneck().stalls[1].kind, "tile_distributor");
  ASSERT_EQ(bound.bottleneck().starves.size(), 2u);
  EXPECT_EQ(bound.bottleneck().starves[0].kind, "interpolator");
  EXPECT_DOUBLE_EQ(bound.bottleneck().starves[0].mean, 0.9);
  EXPECT_EQ(bound.bottleneck().starves[1].kind, "rop");

  const StatsSummary not_bound(made_up(0.69), "made_up");
  EXPECT_FALSE(not_bound.bottleneck().memory_bound);
  EXPECT_EQ(not_bound.bottleneck().bound, "depth_test");
  EXPECT_EQ(not_bound.json()["bound"], "depth_test");
  EXPECT_NE(not_bound.text().find("depth_test-bound: memory bus 69.0% utilized"), std::string::npos)
      << not_bound.text();
}

// With several channels the busiest one decides: channels 50%, 80%, 20%
// busy (mean 50%, below the 70% threshold) make the frame memory-bound on
// channel 1; at 69% the busiest is not enough.
TEST(StatsSummary, BusiestMemoryChannelDecidesMemoryBound) {
  nlohmann::json stats = made_up(0.5);
  stats["timing"]["memory"]["channels"] = {
      {{"channel", 0}, {"utilization", 0.5}, {"busy_cycles", 500}},
      {{"channel", 1}, {"utilization", 0.8}, {"busy_cycles", 800}},
      {{"channel", 2}, {"utilization", 0.2}, {"busy_cycles", 200}}};
  const StatsSummary bound(stats, "made_up");
  const Bottleneck& b = bound.bottleneck();
  EXPECT_TRUE(b.memory_bound);
  EXPECT_EQ(b.bound, "memory");
  EXPECT_EQ(b.memory_channel, 1);
  EXPECT_EQ(b.memory_channels, 3u);
  EXPECT_DOUBLE_EQ(*b.memory_utilization, 0.8);
  EXPECT_DOUBLE_EQ(b.memory_mean_utilization, 0.5);
  EXPECT_EQ(bound.json()["bottleneck"]["memory_channel"], 1);
  EXPECT_NE(bound.text().find("memory-bound: memory channel 1 (busiest of 3, mean 50.0%) is 80.0% "
                              "utilized and memory stalls are 66.7% of depth_test's busy cycles"),
            std::string::npos)
      << bound.text();

  stats["timing"]["memory"]["channels"][1]["utilization"] = 0.69;
  const StatsSummary not_bound(stats, "made_up");
  EXPECT_FALSE(not_bound.bottleneck().memory_bound);
  EXPECT_EQ(not_bound.bottleneck().bound, "depth_test");
  EXPECT_NE(not_bound.text().find("depth_test-bound: memory channel 1 (busiest of 3, mean 46.3%) "
                                  "69.0% utilized"),
            std::string::npos)
      << not_bound.text();
}

TEST(StatsDiff, ListsChangesMissingKeysAndSortsByRelativeChange) {
  const nlohmann::json a = {{"stats", {{"same", 5}, {"up", 100}, {"down", 10}, {"zero", 0}}},
                            {"timing", {{"cycles", 1000}, {"units", {{{"tiles", 4}}}}}},
                            {"config", {{"units", 1}, {"name", "x"}, {"gone", 3}}}};
  const nlohmann::json b = {
      {"stats", {{"same", 5}, {"up", 150}, {"down", 9}, {"zero", 2}}},
      {"timing", {{"cycles", 1200}, {"units", {{{"tiles", 4}}, {{"tiles", 2}}}}}},
      {"config", {{"units", 2}, {"name", "y"}}}};
  const StatsDiff d(a, "a", b, "b");
  std::vector<std::string> keys;
  for (const StatsDiff::Entry& e : d.entries()) keys.push_back(e.key);
  // From 0 and missing keys first (no finite relative change), by key; then
  // +100%, +50%, +20%, -10%.
  const std::vector<std::string> expected{"config.gone",  "stats.zero", "timing.units[1].tiles",
                                          "config.units", "stats.up",   "timing.cycles",
                                          "stats.down"};
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(d.compared(), 9u);  // strings are not compared
  const StatsDiff::Entry& cycles = d.entries()[5];
  EXPECT_DOUBLE_EQ(*cycles.relative, 0.2);
  EXPECT_DOUBLE_EQ(cycles.absolute, 200.0);
  EXPECT_FALSE(d.entries()[0].b.has_value());  // config.gone: only in A
  EXPECT_FALSE(d.entries()[2].a.has_value());  // the second unit: only in B
  EXPECT_FALSE(d.entries()[1].relative.has_value());
  const nlohmann::json j = d.json();
  EXPECT_EQ(j["differences"][0]["missing"], "b");
  EXPECT_EQ(j["differences"][2]["missing"], "a");
  EXPECT_FALSE(j["identical"].get<bool>());

  const StatsDiff same(a, "a", a, "a");
  EXPECT_TRUE(same.entries().empty());
  EXPECT_TRUE(same.json()["identical"].get<bool>());
  EXPECT_NE(same.text().find("identical (all 8 numbers equal)"), std::string::npos) << same.text();
}

// A stats.json written before a stage's rename compares with one written
// after: the former name is read as the current one (primitive_setup was
// triangle_setup).
TEST(StatsDiff, ReadsARenamedStageUnderItsCurrentName) {
  const auto file = [](const char* setup_name, uint64_t busy) {
    return nlohmann::json{{"timing", {{"stages", {{setup_name, {{"busy_cycles", busy}}}}}}},
                          {"config", {{"stages", {{setup_name, {{"ii", 4}}}}}}}};
  };
  const StatsDiff same(file("triangle_setup", 7), "old", file("primitive_setup", 7), "new");
  EXPECT_TRUE(same.entries().empty()) << same.text();
  EXPECT_EQ(same.compared(), 2u);
  const StatsDiff changed(file("triangle_setup", 7), "old", file("primitive_setup", 9), "new");
  ASSERT_EQ(changed.entries().size(), 1u);
  EXPECT_EQ(changed.entries()[0].key, "timing.stages.primitive_setup.busy_cycles");
}

}  // namespace
}  // namespace gpusim
