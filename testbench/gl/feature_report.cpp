#include "testbench/gl/feature_report.h"

namespace gpusim::gl {

void FeatureReport::merge(const FeatureReport& other) {
  for (const auto& [what, n] : other.m_unsupported) m_unsupported[what] += n;
  for (const auto& [what, n] : other.m_ignored) m_ignored[what] += n;
}

nlohmann::json FeatureReport::to_json() const {
  nlohmann::json out = {{"unsupported", nlohmann::json::object()},
                        {"ignored", nlohmann::json::object()}};
  for (const auto& [what, n] : m_unsupported) out["unsupported"][what] = n;
  for (const auto& [what, n] : m_ignored) out["ignored"][what] = n;
  return out;
}

}  // namespace gpusim::gl
