#include "hw/stats.h"

#include <cmath>
#include <stdexcept>

namespace gpusim {
namespace {

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

void merge_into(nlohmann::json& into, const nlohmann::json& from) {
  for (const auto& item : from.items()) into[item.key()] = item.value();
}

}  // namespace

nlohmann::json stat_description(const std::string& unit, const std::string& description) {
  return {{"unit", unit}, {"description", description}};
}

StatGroup::~StatGroup() = default;

StatGroup::Stat& StatGroup::add(const std::string& name, Kind kind, const std::string& unit,
                                const std::string& description) {
  for (const auto& s : m_stats) {
    if (s.name == name) {
      throw std::invalid_argument("StatGroup " + m_name + ": stat '" + name + "' declared twice");
    }
  }
  Stat& s = m_stats.emplace_back();
  s.name = name;
  s.kind = kind;
  s.unit = unit;
  s.description = description;
  return s;
}

uint64_t& StatGroup::counter(const std::string& name, const std::string& unit,
                             const std::string& description) {
  return add(name, Kind::counter, unit, description).value;
}

void StatGroup::gauge(const std::string& name, const std::string& unit,
                      const std::string& description, std::function<uint64_t()> read) {
  if (!read) throw std::invalid_argument("StatGroup " + m_name + ": empty gauge " + name);
  add(name, Kind::gauge, unit, description).read = std::move(read);
}

void StatGroup::formula(const std::string& name, const std::string& unit,
                        const std::string& description, std::function<double()> compute) {
  if (!compute) throw std::invalid_argument("StatGroup " + m_name + ": empty formula " + name);
  add(name, Kind::formula, unit, description).compute = std::move(compute);
}

StatGroup& StatGroup::group(const std::string& name) {
  Stat& s = add(name, Kind::group, {}, {});
  s.group = m_owned_groups.emplace_back(std::make_unique<StatGroup>(name)).get();
  return *m_owned_groups.back();
}

void StatGroup::attach(const StatGroup& group) {
  add(group.name(), Kind::group, {}, {}).group = &group;
}

StatCollection& StatGroup::collection(const std::string& name, Layout layout, Describe describe) {
  Stat& s = add(name, Kind::collection, {}, {});
  s.collection =
      m_collections.emplace_back(std::make_unique<StatCollection>(name, layout, describe)).get();
  return *s.collection;
}

void StatGroup::reset() {
  for (auto& s : m_stats) s.value = 0;
  for (auto& g : m_owned_groups) g->reset();
  for (auto& c : m_collections) c->reset();
}

nlohmann::json StatGroup::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& s : m_stats) {
    switch (s.kind) {
      case Kind::counter:
        j[s.name] = s.value;
        break;
      case Kind::gauge:
        j[s.name] = s.read();
        break;
      case Kind::formula:
        j[s.name] = finite_or_null(s.compute());
        break;
      case Kind::group:
        j[s.name] = s.group->to_json();
        break;
      case Kind::collection:
        j[s.name] = s.collection->to_json();
        break;
    }
  }
  return j;
}

nlohmann::json StatGroup::descriptions() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& s : m_stats) {
    switch (s.kind) {
      case Kind::group:
        j[s.name] = s.group->descriptions();
        break;
      case Kind::collection:
        j[s.name] = s.collection->descriptions();
        break;
      default:
        j[s.name] = stat_description(s.unit, s.description);
    }
  }
  return j;
}

StatGroup& StatCollection::make(const std::string& name, const std::string& kind) {
  StatGroup& g = *m_owned.emplace_back(std::make_unique<StatGroup>(name, kind));
  add(g);
  return g;
}

void StatCollection::reset() {
  for (auto& g : m_owned) g->reset();
}

nlohmann::json StatCollection::to_json() const {
  if (m_layout == StatGroup::Layout::array) {
    nlohmann::json j = nlohmann::json::array();
    for (const StatGroup* g : m_members) j.push_back(g->to_json());
    return j;
  }
  nlohmann::json j = nlohmann::json::object();
  for (const StatGroup* g : m_members) j[g->name()] = g->to_json();
  return j;
}

nlohmann::json StatCollection::descriptions() const {
  nlohmann::json j = nlohmann::json::object();
  for (const StatGroup* g : m_members) {
    merge_into(m_describe == StatGroup::Describe::by_kind ? j[g->kind()] : j, g->descriptions());
  }
  return j;
}

}  // namespace gpusim
