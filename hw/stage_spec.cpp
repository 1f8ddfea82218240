#include "hw/stage_spec.h"

#include <algorithm>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>

namespace gpusim {
namespace {

// Function-local: registrations run during static initialisation, in any
// order across translation units.
std::map<std::string, const StageSpec*, std::less<>>& registry() {
  static std::map<std::string, const StageSpec*, std::less<>> specs;
  return specs;
}

}  // namespace

// Indexed by the enumerators, in their order (hw/stage_spec.h).
const char* to_string(TraceItem item) {
  static constexpr const char* kNames[] = {"draw", "batch", "primitive", "tile job", "stamp batch"};
  return kNames[static_cast<size_t>(item)];
}

const char* to_string(FragmentSite site) {
  static constexpr const char* kNames[] = {"", "test", "write"};
  return kNames[static_cast<size_t>(site)];
}

void StageRegistry::add(const StageSpec& spec) {
  if (spec.kind.empty()) throw std::logic_error("StageRegistry: a spec without a kind");
  if (!registry().emplace(spec.kind, &spec).second) {
    throw std::logic_error("StageRegistry: stage kind '" + spec.kind + "' registered twice");
  }
  for (const std::string& f : spec.inputs) {
    for (const auto& [kind, other] : registry()) {
      if (other == &spec) continue;
      if (std::find(other->inputs.begin(), other->inputs.end(), f) != other->inputs.end()) {
        throw std::logic_error("StageRegistry: FIFO '" + f + "' read by both '" + other->kind +
                               "' and '" + spec.kind + "'");
      }
    }
  }
}

const StageSpec* StageRegistry::find(std::string_view kind) {
  const auto it = registry().find(kind);
  return it == registry().end() ? nullptr : it->second;
}

std::vector<const StageSpec*> StageRegistry::all() {
  std::vector<const StageSpec*> v;
  for (const auto& [kind, spec] : registry()) v.push_back(spec);
  return v;
}

std::vector<std::string> StageRegistry::fifo_kinds() {
  std::vector<std::string> v;
  for (const auto& [kind, spec] : registry())
    v.insert(v.end(), spec->inputs.begin(), spec->inputs.end());
  std::sort(v.begin(), v.end());
  return v;
}

std::vector<std::string> StageRegistry::optional_kinds() {
  std::vector<std::string> v;
  for (const auto& [kind, spec] : registry()) {
    if (!spec->optional) continue;
    v.push_back(kind);
    v.insert(v.end(), spec->inputs.begin(), spec->inputs.end());
  }
  std::sort(v.begin(), v.end());
  return v;
}

std::string StageRegistry::current_name(std::string_view name) {
  for (const auto& [kind, spec] : registry()) {
    for (const std::string& former : spec->former_kinds) {
      if (name == former) return kind;
      // A unit's instance: <former>_<digits>.
      const std::string_view rest = name.substr(std::min(name.size(), former.size()));
      if (name.size() > former.size() + 1 && name.compare(0, former.size(), former) == 0 &&
          rest[0] == '_' &&
          std::all_of(rest.begin() + 1, rest.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        return kind + std::string(rest);
      }
    }
  }
  return {};
}

void warn_former_name(const std::string& where, const std::string& former,
                      const std::string& current) {
  static std::mutex lock;
  static std::set<std::string> warned;
  const std::lock_guard<std::mutex> hold(lock);
  if (!warned.insert(where + "\n" + former).second) return;
  std::cerr << "gpusim: warning: " << where << ": '" << former << "' is deprecated, read as '"
            << current << "' (the stage was renamed; the old name goes in the next release)\n";
}

}  // namespace gpusim
