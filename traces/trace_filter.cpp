#include "traces/trace_filter.h"

#include <algorithm>
#include <cctype>

#include "hw/input_error.h"
#include "hw/stage_spec.h"

namespace gpusim {
namespace {

// A decimal number without sign, or nullopt-like false.
bool parse_number(const std::string& s, uint64_t& v) {
  if (s.empty() || s.size() > 19) return false;
  v = 0;
  for (const char c : s) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    v = v * 10 + static_cast<uint64_t>(c - '0');
  }
  return true;
}

}  // namespace

const std::vector<std::string>& TraceFormats::all() {
  static const std::vector<std::string> names{"vcd", "timeline", "transactions", "fragments"};
  return names;
}

TraceFormats TraceFormats::parse(const std::string& list) {
  if (list.empty()) return TraceFormats{};
  TraceFormats f;
  f.vcd = f.timeline = f.transactions = f.fragments = false;
  for (size_t a = 0, b; a <= list.size(); a = b + 1) {
    b = list.find(',', a);
    if (b == std::string::npos) b = list.size();
    const std::string name = list.substr(a, b - a);
    bool* chosen = name == "vcd"            ? &f.vcd
                   : name == "timeline"     ? &f.timeline
                   : name == "transactions" ? &f.transactions
                   : name == "fragments"    ? &f.fragments
                                            : nullptr;
    if (chosen == nullptr) {
      throw InputError(
          "--trace-formats " + list + ": " +
          (name.empty() ? std::string("empty format name") : "unknown format '" + name + "'") +
          " (allowed: vcd, timeline, transactions, fragments)");
    }
    *chosen = true;
  }
  return f;
}

std::vector<std::string> TraceFormats::names() const {
  std::vector<std::string> n;
  if (vcd) n.push_back("vcd");
  if (timeline) n.push_back("timeline");
  if (transactions) n.push_back("transactions");
  if (fragments) n.push_back("fragments");
  return n;
}

std::vector<std::string> TraceFormats::files() const {
  std::vector<std::string> n;
  if (vcd) n.insert(n.end(), {"signals.vcd", "signals.gtkw"});
  if (timeline) n.push_back("timeline.json");
  if (transactions) n.push_back("transactions.bin");
  if (fragments) n.push_back("fragments.bin");
  return n;
}

TraceFilter TraceFilter::parse(const std::string& stages, const std::string& window,
                               const std::string& prims) {
  TraceFilter f;
  if (!stages.empty()) {
    for (size_t a = 0, b; a <= stages.size(); a = b + 1) {
      b = stages.find(',', a);
      if (b == std::string::npos) b = stages.size();
      const std::string name = stages.substr(a, b - a);
      if (name.empty()) {
        throw InputError("--trace-stages " + stages +
                         ": expected comma-separated stage names or kinds, e.g. "
                         "primitive_setup,depth_test");
      }
      const std::string current = StageRegistry::current_name(name);
      if (!current.empty()) warn_former_name("--trace-stages", name, current);
      f.m_stages.push_back(current.empty() ? name : current);
    }
  }
  if (!window.empty()) {
    const size_t colon = window.find(':');
    const std::string a = colon == std::string::npos ? "" : window.substr(0, colon);
    const std::string b = colon == std::string::npos ? "" : window.substr(colon + 1);
    uint64_t start = 0, end = kOpenEnd;
    if (colon == std::string::npos || (!a.empty() && !parse_number(a, start)) ||
        (!b.empty() && !parse_number(b, end))) {
      throw InputError("--trace-window " + window +
                       ": expected START:END in cycles, either side may be empty (1000:5000, "
                       ":5000, 1000:)");
    }
    if (start >= end) throw InputError("--trace-window " + window + ": START must be below END");
    f.m_has_window = true;
    f.m_start_given = !a.empty();
    f.m_start = start;
    f.m_end = end;
  }
  if (!prims.empty()) {
    const size_t colon = prims.find(':');
    uint64_t a = 0, b = 0;
    if (colon == std::string::npos || !parse_number(prims.substr(0, colon), a) ||
        !parse_number(prims.substr(colon + 1), b) || a > static_cast<uint64_t>(INT64_MAX) ||
        b > static_cast<uint64_t>(INT64_MAX)) {
      throw InputError("--trace-prims " + prims +
                       ": expected A:B, primitive ids with A <= B (inclusive), e.g. 0:99");
    }
    if (a > b) throw InputError("--trace-prims " + prims + ": A must not exceed B");
    f.m_has_prims = true;
    f.m_prim_first = static_cast<int64_t>(a);
    f.m_prim_last = static_cast<int64_t>(b);
  }
  return f;
}

std::vector<bool> TraceFilter::stages_kept(const NetlistTables& tables) const {
  std::vector<bool> kept(tables.stages.size(), m_stages.empty());
  for (const std::string& name : m_stages) {
    bool found = false;
    for (size_t i = 0; i < tables.stages.size(); ++i) {
      if (tables.stages[i].name == name || tables.stages[i].kind == name) {
        kept[i] = true;
        found = true;
      }
    }
    if (!found) {
      std::vector<std::string> kinds;
      std::string known;
      for (const NetlistTables::Stage& s : tables.stages) {
        if (std::find(kinds.begin(), kinds.end(), s.kind) != kinds.end()) continue;
        kinds.push_back(s.kind);
        known += (known.empty() ? "" : ", ") + s.kind;
      }
      throw InputError("--trace-stages: unknown stage '" + name + "' (stages: " + known +
                       ", or a unit's, e.g. depth_test_0)");
    }
  }
  return kept;
}

nlohmann::json TraceFilter::to_json(const NetlistTables& tables,
                                    const std::vector<bool>& kept) const {
  nlohmann::json j;
  if (m_stages.empty()) {
    j["stages"] = nullptr;
  } else {
    j["stages"] = nlohmann::json::array();
    for (size_t i = 0; i < tables.stages.size(); ++i) {
      if (kept[i]) j["stages"].push_back(tables.stages[i].name);
    }
  }
  if (m_has_window) {
    j["window"] = {m_start_given ? nlohmann::json(m_start) : nlohmann::json(nullptr),
                   m_end == kOpenEnd ? nlohmann::json(nullptr) : nlohmann::json(m_end)};
  } else {
    j["window"] = nullptr;
  }
  j["prims"] = m_has_prims ? nlohmann::json({m_prim_first, m_prim_last}) : nlohmann::json(nullptr);
  return j;
}

}  // namespace gpusim
