// The first difference between two JSON documents, for failure messages of
// tests that compare statistics byte for byte.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace gpusim {

// "" when equal, else the path of the first difference and both values.
inline std::string json_difference(const nlohmann::json& a, const nlohmann::json& b,
                                   const std::string& path = "") {
  if (a == b) return "";
  if (a.is_object() && b.is_object()) {
    for (const auto& item : a.items()) {
      if (!b.contains(item.key())) return path + "." + item.key() + " missing";
      const std::string d = json_difference(item.value(), b[item.key()], path + "." + item.key());
      if (!d.empty()) return d;
    }
    return path + ": keys differ";
  }
  if (a.is_array() && b.is_array() && a.size() == b.size()) {
    for (size_t i = 0; i < a.size(); ++i) {
      const std::string d = json_difference(a[i], b[i], path + "[" + std::to_string(i) + "]");
      if (!d.empty()) return d;
    }
  }
  return path + ": " + a.dump() + " vs " + b.dump();
}

}  // namespace gpusim
