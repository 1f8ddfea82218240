// gem5-style statistics: each part of the model declares a group of named
// statistics, each with its unit and a one-line description, next to the
// code that counts them; stats.json is the tree of groups dumped at the end
// of the run, with the descriptions from the same declarations.
//
//   StatGroup m_stats{"tile_rasterizer_0"};
//   uint64_t& m_stamps = m_stats.counter("stamps", "stamps", "4x4 stamps evaluated");
//   ...
//   ++m_stamps;  // a plain integer add
//
// Four kinds of statistic, one mechanism:
//   counter  an integer the owner adds to (handed out by reference);
//   gauge    an integer read when dumped (a FIFO's depth, a count kept elsewhere);
//   formula  a real number computed when dumped (ratios, means, cycles from
//            times); a non-finite result (0/0) dumps as null;
//   group    a nested group: owned (group()), another part's (attach()), or a
//            collection of groups with the same statistics (collection()):
//            the stages, the FIFOs, the memory's clients and channels.
// Code outside a part reads its counters through the part's own typed
// accessor, never by name.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace gpusim {

// {"unit": unit, "description": description}: how every statistic is
// described in stats.json.
nlohmann::json stat_description(const std::string& unit, const std::string& description);

class StatCollection;

class StatGroup {
 public:
  // `kind`: what a collection describing its members by kind files this
  // group's descriptions under (a stage's kind: "depth_test" for
  // "depth_test_0"); empty: its name.
  explicit StatGroup(std::string name, std::string kind = {})
      : m_name(std::move(name)), m_kind(std::move(kind)) {}
  // Counters are handed out by reference: the group must not move.
  StatGroup(const StatGroup&) = delete;
  StatGroup& operator=(const StatGroup&) = delete;
  ~StatGroup();

  const std::string& name() const { return m_name; }
  const std::string& kind() const { return m_kind.empty() ? m_name : m_kind; }

  // A zero-initialised counter whose address stays valid for the life of the
  // group. Names are unique within a group (std::invalid_argument otherwise).
  // `unit` says what one count is ("cycles", "stamps", "bytes").
  uint64_t& counter(const std::string& name, const std::string& unit,
                    const std::string& description);

  // An integer read when the group is dumped.
  void gauge(const std::string& name, const std::string& unit, const std::string& description,
             std::function<uint64_t()> read);

  // A real number computed when the group is dumped, e.g. a ratio of two
  // counters.
  void formula(const std::string& name, const std::string& unit, const std::string& description,
               std::function<double()> compute);

  // A nested group owned by this one, dumped under `name`.
  StatGroup& group(const std::string& name);
  // Another part's group, dumped under its name; it must outlive this one.
  void attach(const StatGroup& group);

  enum class Layout { object, array };      // {member name: ...} or [...]
  enum class Describe { merged, by_kind };  // one table, or one per member kind
  // Groups with the same statistics, dumped under `name` and described once.
  StatCollection& collection(const std::string& name, Layout layout, Describe describe);

  // Sets every counter back to 0, in nested groups too (gauges and formulas
  // follow their inputs).
  void reset();

  // {name: value}, and {name: {"unit": unit, "description": description}};
  // a nested group or collection nests its values and descriptions.
  nlohmann::json to_json() const;
  nlohmann::json descriptions() const;

 private:
  enum class Kind { counter, gauge, formula, group, collection };
  struct Stat {
    std::string name;
    Kind kind = Kind::counter;
    std::string unit;
    std::string description;
    uint64_t value = 0;
    std::function<uint64_t()> read;
    std::function<double()> compute;
    const StatGroup* group = nullptr;  // Kind::group
    StatCollection* collection = nullptr;
  };
  Stat& add(const std::string& name, Kind kind, const std::string& unit,
            const std::string& description);

  std::string m_name;
  std::string m_kind;
  std::deque<Stat> m_stats;  // a deque never moves its elements on push_back
  std::vector<std::unique_ptr<StatGroup>> m_owned_groups;
  std::vector<std::unique_ptr<StatCollection>> m_collections;
};

// Members are other parts' groups (a stage's, a FIFO's) or the
// collection's own (make()); members dump in the order they were added.
class StatCollection {
 public:
  StatCollection(std::string name, StatGroup::Layout layout, StatGroup::Describe describe)
      : m_name(std::move(name)), m_layout(layout), m_describe(describe) {}
  StatCollection(const StatCollection&) = delete;
  StatCollection& operator=(const StatCollection&) = delete;

  const std::string& name() const { return m_name; }
  void add(const StatGroup& member) { m_members.push_back(&member); }
  // A new member owned by the collection.
  StatGroup& make(const std::string& name, const std::string& kind = {});
  const std::vector<const StatGroup*>& members() const { return m_members; }

  void reset();
  nlohmann::json to_json() const;
  // Merged: {stat: description} over every member (members of one kind
  // may declare different statistics, e.g. the distributor's per unit);
  // by kind: {kind: merged over the members of that kind}.
  nlohmann::json descriptions() const;

 private:
  std::string m_name;
  StatGroup::Layout m_layout;
  StatGroup::Describe m_describe;
  std::vector<const StatGroup*> m_members;
  std::vector<std::unique_ptr<StatGroup>> m_owned;
};

}  // namespace gpusim
