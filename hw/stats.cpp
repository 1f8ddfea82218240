#include "hw/stats.h"

#include <cmath>
#include <stdexcept>

namespace gpusim {
namespace {

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace

nlohmann::json stat_description(const std::string& unit, const std::string& description) {
  return {{"unit", unit}, {"description", description}};
}

StatGroup::Stat& StatGroup::add(const std::string& name, const std::string& unit,
                                const std::string& description) {
  for (const auto& s : m_stats) {
    if (s.name == name) {
      throw std::invalid_argument("StatGroup " + m_name + ": stat '" + name + "' declared twice");
    }
  }
  m_stats.push_back({name, unit, description, 0, {}});
  return m_stats.back();
}

uint64_t& StatGroup::counter(const std::string& name, const std::string& unit,
                             const std::string& description) {
  return add(name, unit, description).value;
}

void StatGroup::formula(const std::string& name, const std::string& unit,
                        const std::string& description, std::function<double()> compute) {
  if (!compute) throw std::invalid_argument("StatGroup " + m_name + ": empty formula " + name);
  add(name, unit, description).compute = std::move(compute);
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
  for (const auto& s : m_stats) j[s.name] = stat_description(s.unit, s.description);
  return j;
}

}  // namespace gpusim
