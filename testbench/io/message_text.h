// Text for messages and summaries: names and file contents made printable
// (one line stays one line), vectors and colours as people write them.
#pragma once

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace gpusim {

// Control characters and bytes that are not UTF-8 shown as \xNN.
std::string printable(const std::string& s);
// Each line of a multi-line report made printable.
std::string printable_report(const std::string& report);
// The words joined by `sep`.
std::string join(const std::vector<std::string>& words, const std::string& sep);
// "(1, 2.5, -3)": a resolved vector or colour (an array of numbers).
std::string vec_text(const nlohmann::json& v);
std::string vec_text(const glm::vec3& v);

}  // namespace gpusim
