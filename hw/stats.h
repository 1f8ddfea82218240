// gem5-style statistics: each module declares a group of named counters,
// each with its unit and a one-line description, next to the code that counts
// them; the netlist (stages/topology.h) dumps every stage's group together at
// the end of the run (stats.json, next to the configuration, with the
// descriptions).
//
//   StatGroup m_stats{"tile_rasterizer_0"};
//   uint64_t& m_stamps = m_stats.counter("stamps", "stamps", "4x4 stamps evaluated");
//   ...
//   ++m_stamps;  // a plain integer add
//
// Values computed at dump time (ratios, means) are formulas: callbacks
// evaluated by to_json(). Code outside the module reads a counter through the
// module's own typed accessor, never by its name.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace gpusim {

// {"unit": unit, "description": description}: how every statistic is
// described in stats.json, a group's counters and a channel's fields alike.
nlohmann::json stat_description(const std::string& unit, const std::string& description);

class StatGroup {
 public:
  explicit StatGroup(std::string name) : m_name(std::move(name)) {}
  // Counters are handed out by reference: the group must not move.
  StatGroup(const StatGroup&) = delete;
  StatGroup& operator=(const StatGroup&) = delete;

  const std::string& name() const { return m_name; }

  // A zero-initialised counter whose address stays valid for the life of the
  // group. Names are unique within a group (std::invalid_argument otherwise).
  // `unit` says what one count is ("cycles", "stamps", "bytes").
  uint64_t& counter(const std::string& name, const std::string& unit,
                    const std::string& description);

  // A value computed when the group is dumped, e.g. a ratio of two counters.
  // A non-finite result (0/0) dumps as null.
  void formula(const std::string& name, const std::string& unit, const std::string& description,
               std::function<double()> compute);

  // Sets every counter back to 0 (formulas follow their inputs).
  void reset();

  // {name: value}, and {name: {"unit": unit, "description": description}}.
  nlohmann::json to_json() const;
  nlohmann::json descriptions() const;

 private:
  struct Stat {
    std::string name;
    std::string unit;
    std::string description;
    uint64_t value = 0;
    std::function<double()> compute;  // empty for counters
  };
  Stat& add(const std::string& name, const std::string& unit, const std::string& description);

  std::string m_name;
  std::deque<Stat> m_stats;  // a deque never moves its elements on push_back
};

}  // namespace gpusim
