// What a replay met that the GPU cannot draw as OpenGL would (unsupported:
// the frame may differ from OpenGL's), and what it dropped because it cannot
// change the picture (ignored: glTexCoord with texturing off, queries, hints),
// each counted by name: "glTexImage2D", "GL_FOG enabled while drawing".
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace gpusim::gl {

class FeatureReport {
 public:
  void add_unsupported(const std::string& what, uint64_t n = 1) { m_unsupported[what] += n; }
  void add_ignored(const std::string& what, uint64_t n = 1) { m_ignored[what] += n; }
  void merge(const FeatureReport& other);
  void clear() { m_unsupported.clear(), m_ignored.clear(); }

  bool any_unsupported() const { return !m_unsupported.empty(); }
  const std::map<std::string, uint64_t>& unsupported() const { return m_unsupported; }
  const std::map<std::string, uint64_t>& ignored() const { return m_ignored; }
  // {"unsupported": {name: count}, "ignored": {name: count}}, names sorted.
  nlohmann::json to_json() const;

 private:
  std::map<std::string, uint64_t> m_unsupported, m_ignored;
};

}  // namespace gpusim::gl
