#include "hw/stats.h"

#include <cmath>
#include <stdexcept>

namespace gpusim {
namespace {

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

void flatten(std::ostream& os, const std::string& prefix, const nlohmann::json& j) {
  if (j.is_object()) {
    for (const auto& item : j.items()) flatten(os, prefix + "." + item.key(), item.value());
  } else {
    os << prefix << ' ' << j.dump() << '\n';
  }
}

}  // namespace

StatGroup::Stat& StatGroup::add(const std::string& name, const std::string& description) {
  for (const auto& s : m_stats) {
    if (s.name == name) {
      throw std::invalid_argument("StatGroup " + m_name + ": stat '" + name + "' declared twice");
    }
  }
  m_stats.push_back({name, description, 0, {}});
  return m_stats.back();
}

uint64_t& StatGroup::counter(const std::string& name, const std::string& description) {
  return add(name, description).value;
}

void StatGroup::formula(const std::string& name, const std::string& description,
                        std::function<double()> compute) {
  if (!compute) throw std::invalid_argument("StatGroup " + m_name + ": empty formula " + name);
  add(name, description).compute = std::move(compute);
}

void StatGroup::reset() {
  for (auto& s : m_stats) s.value = 0;
}

nlohmann::json StatGroup::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& s : m_stats) {
    j[s.name] = s.compute ? finite_or_null(s.compute()) : nlohmann::json(s.value);
  }
  return j;
}

nlohmann::json StatGroup::descriptions() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& s : m_stats) j[s.name] = s.description;
  return j;
}

void StatGroup::dump_text(std::ostream& os, const std::string& prefix) const {
  for (const auto& s : m_stats) {
    const nlohmann::json v = s.compute ? finite_or_null(s.compute()) : nlohmann::json(s.value);
    os << prefix << s.name << ' ' << v.dump() << " # " << s.description << '\n';
  }
}

void StatRegistry::check_unique(const std::string& name) const {
  for (const auto& e : m_entries) {
    if (e.name == name) {
      throw std::invalid_argument("StatRegistry: '" + name + "' registered twice");
    }
  }
}

void StatRegistry::add(const StatGroup& group) {
  check_unique(group.name());
  m_entries.push_back({group.name(), &group, {}});
}

void StatRegistry::add(const std::string& name, std::function<nlohmann::json()> dump) {
  if (!dump) throw std::invalid_argument("StatRegistry: empty callback for " + name);
  check_unique(name);
  m_entries.push_back({name, nullptr, std::move(dump)});
}

nlohmann::json StatRegistry::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& e : m_entries) j[e.name] = e.group ? e.group->to_json() : e.dump();
  return j;
}

void StatRegistry::dump_text(std::ostream& os) const {
  for (const auto& e : m_entries) {
    if (e.group) {
      e.group->dump_text(os, e.name + ".");
    } else {
      flatten(os, e.name, e.dump());
    }
  }
}

}  // namespace gpusim
