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

}  // namespace
}  // namespace gpusim
