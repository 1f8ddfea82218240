#include "hw/stage_spec.h"

#include <algorithm>
#include <map>
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

const char* to_string(TraceItem item) {
  switch (item) {
    case TraceItem::draw:
      return "draw";
    case TraceItem::slot_batch:
      return "batch";
    case TraceItem::primitive:
      return "primitive";
    case TraceItem::tile_job:
      return "tile job";
    case TraceItem::stamp_batch:
      return "stamp batch";
  }
  return "primitive";
}

const char* to_string(FragmentSite site) {
  switch (site) {
    case FragmentSite::none:
      return "";
    case FragmentSite::depth_test:
      return "depth_test";
    case FragmentSite::rop:
      return "rop";
  }
  return "";
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

}  // namespace gpusim
