#include "testbench/io/message_text.h"

#include <cstdio>

namespace gpusim {

std::string printable(const std::string& s) {
  std::string out;
  const auto escape = [&](unsigned char c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "\\x%02X", c);
    out += buf;
  };
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7F) {
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence passes unchanged.
    size_t n = c >= 0xC2 && c <= 0xDF   ? 2
               : c >= 0xE0 && c <= 0xEF ? 3
               : c >= 0xF0 && c <= 0xF4 ? 4
                                        : 0;
    bool ok = n > 0 && i + n <= s.size();
    for (size_t k = 1; ok && k < n; ++k) ok = (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80;
    if (ok) {
      out.append(s, i, n);
      i += n;
    } else {
      escape(c);
      ++i;
    }
  }
  return out;
}

std::string printable_report(const std::string& report) {
  std::string out, line;
  for (size_t i = 0; i <= report.size(); ++i) {
    if (i == report.size() || report[i] == '\n') {
      out += (i == line.size() ? "" : "\n") + printable(line);
      line.clear();
    } else {
      line += report[i];
    }
  }
  return out;
}

std::string join(const std::vector<std::string>& words, const std::string& sep) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : sep) + w;
  return out;
}

std::string vec_text(const nlohmann::json& v) {
  std::string out;
  for (const nlohmann::json& x : v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x.get<double>());
    out += (out.empty() ? "(" : ", ") + std::string(buf);
  }
  return out + ")";
}

std::string vec_text(const glm::vec3& v) {
  return vec_text(nlohmann::json::array({v.x, v.y, v.z}));
}

}  // namespace gpusim
