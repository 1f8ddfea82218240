// gem5-style statistics: each module declares a group of named, described
// counters next to the code that counts them, and a registry dumps every group
// together at the end of the run (stats.json, next to the configuration).
//
//   StatGroup m_stats{"rasterizer0"};
//   uint64_t& m_stamps = m_stats.counter("stamps", "4x4 stamps evaluated");
//   ...
//   ++m_stamps;  // a plain integer add
//
// Values computed at dump time (ratios, means) are formulas: callbacks
// evaluated by to_json(). Channels with structured statistics (Fifo, Memory)
// join the registry through a callback returning their JSON.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace gpusim {

class StatGroup {
 public:
  explicit StatGroup(std::string name) : m_name(std::move(name)) {}
  // Counters are handed out by reference: the group must not move.
  StatGroup(const StatGroup&) = delete;
  StatGroup& operator=(const StatGroup&) = delete;

  const std::string& name() const { return m_name; }

  // A zero-initialised counter whose address stays valid for the life of the
  // group. Names are unique within a group (std::invalid_argument otherwise).
  uint64_t& counter(const std::string& name, const std::string& description);

  // A value computed when the group is dumped, e.g. a ratio of two counters.
  // A non-finite result (0/0) dumps as null.
  void formula(const std::string& name, const std::string& description,
               std::function<double()> compute);

  // Sets every counter back to 0 (formulas follow their inputs).
  void reset();

  // {name: value}, and {name: description}.
  nlohmann::json to_json() const;
  nlohmann::json descriptions() const;

  // "<prefix><name> <value> # <description>" lines in declaration order.
  void dump_text(std::ostream& os, const std::string& prefix) const;

 private:
  struct Stat {
    std::string name;
    std::string description;
    uint64_t value = 0;
    std::function<double()> compute;  // empty for counters
  };
  Stat& add(const std::string& name, const std::string& description);

  std::string m_name;
  std::deque<Stat> m_stats;  // a deque never moves its elements on push_back
};

// Collects groups (and JSON-producing callbacks) from every module. It does
// not own them: each must outlive the dumps, which the module tree does when
// stats are dumped at the end of sc_main.
class StatRegistry {
 public:
  // Names are unique across the registry (std::invalid_argument otherwise).
  void add(const StatGroup& group);
  void add(const std::string& name, std::function<nlohmann::json()> dump);

  // {name: group or callback json}.
  nlohmann::json to_json() const;

  // gem5's stats.txt layout: one "<group>.<stat> <value> # <description>"
  // line per value, groups in registration order, a group's stats in
  // declaration order; a callback's nested objects flattened with dots.
  void dump_text(std::ostream& os) const;

 private:
  struct Entry {
    std::string name;
    const StatGroup* group = nullptr;      // either a group
    std::function<nlohmann::json()> dump;  // or a callback
  };
  void check_unique(const std::string& name) const;

  std::vector<Entry> m_entries;
};

}  // namespace gpusim
