#include <gtest/gtest.h>

#include "hw/stats.h"

namespace gpusim {
namespace {

using nlohmann::json;

TEST(StatGroup, CountersAreStableReferences) {
  StatGroup g("raster0");
  uint64_t& stamps = g.counter("stamps", "stamps", "stamps evaluated");
  uint64_t& pixels = g.counter("pixels", "fragments", "pixels covered");
  // Many more counters must not move the first ones.
  for (int i = 0; i < 1000; ++i) g.counter("extra" + std::to_string(i), "items", "filler");
  stamps += 5;
  ++stamps;
  pixels += 70;
  const json j = g.to_json();
  EXPECT_EQ(j["stamps"], 6);
  EXPECT_EQ(j["pixels"], 70);
  EXPECT_EQ(j["extra999"], 0);
  EXPECT_EQ(j.size(), 1002u);
  EXPECT_EQ(g.descriptions()["pixels"],
            json({{"unit", "fragments"}, {"description", "pixels covered"}}));
  EXPECT_EQ(g.name(), "raster0");
}

TEST(StatGroup, FormulasEvaluateAtDumpTime) {
  StatGroup g("raster0");
  uint64_t& stamps = g.counter("stamps", "stamps", "stamps evaluated");
  uint64_t& pixels = g.counter("pixels", "fragments", "pixels covered");
  g.formula("coverage", "ratio", "covered pixels per stamp pixel",
            [&] { return static_cast<double>(pixels) / (16.0 * static_cast<double>(stamps)); });
  EXPECT_TRUE(g.to_json()["coverage"].is_null());  // 0/0
  stamps = 4;
  pixels = 16;
  EXPECT_EQ(g.to_json()["coverage"], 0.25);
  pixels = 32;
  EXPECT_EQ(g.to_json()["coverage"], 0.5);
  EXPECT_EQ(g.descriptions()["coverage"]["unit"], "ratio");
  g.reset();
  EXPECT_EQ(stamps, 0u);
  EXPECT_EQ(pixels, 0u);
  EXPECT_TRUE(g.to_json()["coverage"].is_null());
}

TEST(StatGroup, DuplicateNamesAreRejected) {
  StatGroup g("g");
  g.counter("a", "items", "first");
  EXPECT_THROW(g.counter("a", "items", "again"), std::invalid_argument);
  EXPECT_THROW(g.formula("a", "ratio", "again", [] { return 1.0; }), std::invalid_argument);
  EXPECT_THROW(g.formula("b", "ratio", "empty", {}), std::invalid_argument);
}

TEST(StatGroup, GaugesDumpIntegersReadAtDumpTime) {
  StatGroup g("fifo");
  uint64_t held = 3;
  g.gauge("depth", "items", "slots", [&] { return held; });
  EXPECT_TRUE(g.to_json()["depth"].is_number_unsigned());
  EXPECT_EQ(g.to_json().dump(), R"({"depth":3})");
  held = 7;
  EXPECT_EQ(g.to_json()["depth"], 7);
  g.reset();  // a gauge is not the group's to reset
  EXPECT_EQ(g.to_json()["depth"], 7);
  EXPECT_EQ(g.descriptions()["depth"]["unit"], "items");
  EXPECT_THROW(g.gauge("empty", "items", "no reader", {}), std::invalid_argument);
}

TEST(StatGroup, NestedGroupsAndCollections) {
  StatGroup root("timing");
  StatGroup& rates = root.group("rates");
  rates.formula("per_clock", "items/cycle", "items per cycle", [] { return 0.5; });

  // Members owned elsewhere, described by kind: two units of one kind whose
  // statistics differ are described together.
  StatGroup r0("rop_0", "rop"), r1("rop_1", "rop"), setup("primitive_setup");
  r0.counter("stamps", "stamps", "stamps blended") = 4;
  r1.counter("stamps", "stamps", "stamps blended") = 6;
  r1.counter("clears", "commands", "clears");
  setup.counter("culled", "primitives", "back faces");
  StatCollection& stages =
      root.collection("stages", StatGroup::Layout::object, StatGroup::Describe::by_kind);
  stages.add(setup);
  stages.add(r0);
  stages.add(r1);

  // Members of its own, dumped as a list and described once.
  StatCollection& channels =
      root.collection("channels", StatGroup::Layout::array, StatGroup::Describe::merged);
  for (uint64_t i = 0; i < 3; ++i) {
    StatGroup& c = channels.make("channel" + std::to_string(i));
    c.gauge("channel", "index", "which", [i] { return i; });
    c.counter("bytes", "bytes", "moved") = 10 * i;
  }

  const json j = root.to_json();
  EXPECT_EQ(j["rates"]["per_clock"], 0.5);
  EXPECT_EQ(j["stages"]["rop_0"]["stamps"], 4);
  EXPECT_EQ(j["stages"]["rop_1"]["stamps"], 6);
  EXPECT_EQ(j["stages"]["primitive_setup"]["culled"], 0);
  ASSERT_TRUE(j["channels"].is_array());
  ASSERT_EQ(j["channels"].size(), 3u);
  EXPECT_EQ(j["channels"][2], json({{"channel", 2}, {"bytes", 20}}));

  const json d = root.descriptions();
  EXPECT_EQ(d["rates"]["per_clock"]["unit"], "items/cycle");
  EXPECT_EQ(d["stages"].size(), 2u);  // by kind: rop, primitive_setup
  EXPECT_TRUE(d["stages"]["rop"].contains("stamps"));
  EXPECT_TRUE(d["stages"]["rop"].contains("clears"));
  EXPECT_TRUE(d["stages"]["primitive_setup"].contains("culled"));
  EXPECT_EQ(d["channels"], json({{"channel", {{"unit", "index"}, {"description", "which"}}},
                                 {"bytes", {{"unit", "bytes"}, {"description", "moved"}}}}));

  // reset() reaches the collection's own members, not other parts' groups.
  root.reset();
  EXPECT_EQ(root.to_json()["channels"][2]["bytes"], 0);
  EXPECT_EQ(root.to_json()["stages"]["rop_1"]["stamps"], 6);
  EXPECT_THROW(root.group("rates"), std::invalid_argument);
}

}  // namespace
}  // namespace gpusim
