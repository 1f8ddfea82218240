#include "hw/pipeline_counts.h"

#include <stdexcept>

namespace gpusim {

nlohmann::json PipelineCounts::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  visit_fields([&j](const char* name, uint64_t v) { j[name] = v; });
  return j;
}

PipelineCounts PipelineCounts::from_json(const nlohmann::json& j) {
  PipelineCounts c;
  c.visit_fields([&j](const char* name, uint64_t& v) {
    const auto it = j.is_object() ? j.find(name) : j.end();
    if (it == j.end() || !it->is_number_unsigned()) {
      throw std::invalid_argument(std::string(name) + ": missing");
    }
    v = it->get<uint64_t>();
  });
  return c;
}

std::ostream& operator<<(std::ostream& os, const PipelineCounts& c) {
  return os << c.to_json().dump();
}

bool PipelineCounts::operator==(const PipelineCounts& o) const {
  return differences(*this, o).empty();
}

std::vector<CountDifference> differences(const PipelineCounts& a, const PipelineCounts& b) {
  std::vector<uint64_t> values;
  b.visit_fields([&values](const char*, uint64_t v) { values.push_back(v); });
  std::vector<CountDifference> out;
  size_t i = 0;
  a.visit_fields([&](const char* name, uint64_t v) {
    if (v != values[i]) out.push_back({name, v, values[i]});
    ++i;
  });
  return out;
}

}  // namespace gpusim
