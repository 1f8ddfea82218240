#include <gtest/gtest.h>

#include <sstream>

#include "hw/stats.h"

namespace gpusim {
namespace {

using nlohmann::json;

TEST(StatGroup, CountersAreStableReferences) {
  StatGroup g("raster0");
  uint64_t& stamps = g.counter("stamps", "stamps evaluated");
  uint64_t& pixels = g.counter("pixels", "pixels covered");
  // Many more counters must not move the first ones.
  for (int i = 0; i < 1000; ++i) g.counter("extra" + std::to_string(i), "filler");
  stamps += 5;
  ++stamps;
  pixels += 70;
  const json j = g.to_json();
  EXPECT_EQ(j["stamps"], 6);
  EXPECT_EQ(j["pixels"], 70);
  EXPECT_EQ(j["extra999"], 0);
  EXPECT_EQ(j.size(), 1002u);
  EXPECT_EQ(g.descriptions()["pixels"], "pixels covered");
  EXPECT_EQ(g.name(), "raster0");
}

TEST(StatGroup, FormulasEvaluateAtDumpTime) {
  StatGroup g("raster0");
  uint64_t& stamps = g.counter("stamps", "stamps evaluated");
  uint64_t& pixels = g.counter("pixels", "pixels covered");
  g.formula("coverage", "covered pixels per stamp pixel",
            [&] { return static_cast<double>(pixels) / (16.0 * static_cast<double>(stamps)); });
  EXPECT_TRUE(g.to_json()["coverage"].is_null());  // 0/0
  stamps = 4;
  pixels = 16;
  EXPECT_EQ(g.to_json()["coverage"], 0.25);
  pixels = 32;
  EXPECT_EQ(g.to_json()["coverage"], 0.5);
  g.reset();
  EXPECT_EQ(stamps, 0u);
  EXPECT_EQ(pixels, 0u);
  EXPECT_TRUE(g.to_json()["coverage"].is_null());
}

TEST(StatGroup, DuplicateNamesAreRejected) {
  StatGroup g("g");
  g.counter("a", "first");
  EXPECT_THROW(g.counter("a", "again"), std::invalid_argument);
  EXPECT_THROW(g.formula("a", "again", [] { return 1.0; }), std::invalid_argument);
  EXPECT_THROW(g.formula("b", "empty", {}), std::invalid_argument);
}

TEST(StatRegistry, DumpsEveryGroupAndCallback) {
  StatGroup setup("setup");
  uint64_t& triangles = setup.counter("triangles", "triangles set up");
  uint64_t& culled = setup.counter("culled", "back-facing triangles dropped");
  setup.formula("cull_ratio", "culled / triangles",
                [&] { return static_cast<double>(culled) / static_cast<double>(triangles); });
  StatGroup rop("rop");
  uint64_t& writes = rop.counter("writes", "pixels written");

  StatRegistry reg;
  reg.add(setup);
  reg.add(rop);
  reg.add("fifo.interpolator_to_rop", [] {
    return json{{"max_occupancy", 3}, {"nested", {{"x", 1}}}};
  });
  EXPECT_THROW(reg.add(rop), std::invalid_argument);
  EXPECT_THROW(reg.add("setup", [] { return json(); }), std::invalid_argument);

  triangles = 8;
  culled = 2;
  writes = 1234;
  const json j = reg.to_json();
  EXPECT_EQ(j, json::parse(R"({
    "setup": {"triangles": 8, "culled": 2, "cull_ratio": 0.25},
    "rop": {"writes": 1234},
    "fifo.interpolator_to_rop": {"max_occupancy": 3, "nested": {"x": 1}}
  })"));

  std::ostringstream text;
  reg.dump_text(text);
  EXPECT_EQ(text.str(),
            "setup.triangles 8 # triangles set up\n"
            "setup.culled 2 # back-facing triangles dropped\n"
            "setup.cull_ratio 0.25 # culled / triangles\n"
            "rop.writes 1234 # pixels written\n"
            "fifo.interpolator_to_rop.max_occupancy 3\n"
            "fifo.interpolator_to_rop.nested.x 1\n");

  // The registry reads live values at each dump.
  ++writes;
  EXPECT_EQ(reg.to_json()["rop"]["writes"], 1235);
}

}  // namespace
}  // namespace gpusim
