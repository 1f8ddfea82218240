// The test host around one stage, for the tests of a stage alone
// (stages_<kind>_test.cpp): a source writing a list of tokens into the
// stage's input FIFO, a sink reading its output FIFO and recording each item
// with the cycle it was read at, and the counter lookups the tests read the
// stage's statistics with.
#pragma once

#ifndef SC_INCLUDE_DYNAMIC_PROCESSES
#define SC_INCLUDE_DYNAMIC_PROCESSES  // sc_spawn: <systemc> includes it past its guard
#endif
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <systemc>
#include <utility>
#include <vector>

#include "hw/fifo.h"
#include "hw/stats.h"

namespace gpusim {
namespace test {

// Writes `tokens` into `fifo` in order from time 0, blocking while it is full.
template <typename T>
void feed(Fifo<T>& fifo, std::vector<T> tokens) {
  sc_core::sc_spawn([&fifo, tokens = std::move(tokens)] {
    for (const T& t : tokens) fifo.write(t);
  });
}

// Reads every item `fifo` yields from cycle `from` on, as soon as it is
// readable, and records it with the cycle (of `cycle`) it was read at.
template <typename T>
struct Sink {
  std::vector<T> items;
  std::vector<uint64_t> cycles;

  Sink(Fifo<T>& fifo, sc_core::sc_time cycle, uint64_t from = 0) {
    sc_core::sc_spawn([this, &fifo, cycle, from] {
      if (from > 0) sc_core::wait(cycle * static_cast<double>(from));
      for (;;) {
        items.push_back(fifo.read());
        cycles.push_back(static_cast<uint64_t>(std::llround(sc_core::sc_time_stamp() / cycle)));
      }
    });
  }
  Sink(const Sink&) = delete;  // its thread holds `this`
  Sink& operator=(const Sink&) = delete;
};

// Counter `name` of a stage's statistics; a missing one fails the test.
inline uint64_t counter(const StatGroup& g, const std::string& name) {
  const nlohmann::json j = g.to_json();
  EXPECT_TRUE(j.contains(name)) << g.name() << " has no counter " << name;
  return j.contains(name) ? j.at(name).get<uint64_t>() : 0;
}

// Each named counter of a stage's statistics against its expected value.
inline void expect_counters(const StatGroup& g,
                            const std::vector<std::pair<std::string, uint64_t>>& want) {
  for (const auto& [name, value] : want)
    EXPECT_EQ(counter(g, name), value) << g.name() << "." << name;
}

}  // namespace test
}  // namespace gpusim
