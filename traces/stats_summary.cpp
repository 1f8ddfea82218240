#include "traces/stats_summary.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "hw/input_error.h"
#include "hw/stage_spec.h"

namespace gpusim {
namespace {

const nlohmann::json kEmptyObject = nlohmann::json::object();

const nlohmann::json& object_at(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_object() ? *it : kEmptyObject;
}

double number(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : 0.0;
}

uint64_t cycles_at(const nlohmann::json& j, const char* key) {
  return static_cast<uint64_t>(std::llround(std::max(0.0, number(j, key))));
}

}  // namespace

nlohmann::json read_stats_file(const std::string& path, bool need_timing) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(path + ": is a directory, not a stats.json (give DIR/stats.json)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open: " + std::strerror(errno));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not valid JSON: " + e.what());
  }
  const char* hint = " (write one with gpusim run SCENE --out DIR: DIR/stats.json)";
  if (!j.is_object() || !j.contains("stats") || !j["stats"].is_object()) {
    throw InputError(path + ": not a gpusim stats.json: no \"stats\" object" + hint);
  }
  if (!need_timing) return j;
  const nlohmann::json& timing = object_at(j, "timing");
  if (!j.contains("timing")) {
    throw InputError(path + ": no \"timing\": " +
                     (j.value("model", std::string()) == "golden"
                          ? "the golden model's stats.json has no cycles"
                          : "not a cycle model's stats.json") +
                     hint);
  }
  if (!timing.contains("cycles") || !timing["cycles"].is_number_unsigned() ||
      !timing.contains("stages") || !timing["stages"].is_object() || timing["stages"].empty() ||
      !timing.contains("netlist") || !timing["netlist"].is_object() || !j.contains("config") ||
      !j["config"].is_object()) {
    throw InputError(path +
                     ": not a gpusim stats.json: needs timing.cycles, timing.stages, "
                     "timing.netlist and config (a stats.json written before "
                     "timing.netlist existed needs a new run)" +
                     hint);
  }
  return j;
}

TraceManifest manifest_from_stats(const nlohmann::json& stats, const std::string& path) {
  TraceManifest m;
  const nlohmann::json& config = object_at(stats, "config");
  const nlohmann::json& timing = object_at(stats, "timing");
  m.scene = stats.value("scene", std::string());
  m.config = config;
  m.clock_mhz = number(config, "clock_mhz");
  m.cycles = cycles_at(timing, "cycles");
  m.units = static_cast<unsigned>(number(config, "units"));
  read_netlist(object_at(timing, "netlist"), path, "timing.netlist", m);
  return m;
}

StatsSummary::StatsSummary(const nlohmann::json& stats, const std::string& path)
    : m_path(path),
      m_scene(stats.value("scene", std::string())),
      m_manifest(manifest_from_stats(stats, path)) {
  const nlohmann::json& timing = object_at(stats, "timing");
  m_seconds = number(timing, "simulated_seconds");
  const nlohmann::json& stages = object_at(timing, "stages");
  for (const TraceStage& ts : m_manifest.stages) {
    StageLoad s;
    s.name = ts.name;
    s.kind = ts.kind;
    s.unit = ts.unit;
    const nlohmann::json& j = stages[ts.name];
    s.busy = cycles_at(j, "busy_cycles");
    s.stalled = cycles_at(j, "stalled_cycles");
    s.starved = cycles_at(j, "starved_cycles");
    m_stages.push_back(s);
  }
  read_stage_stats(stages, m_stages);

  const nlohmann::json& memory = object_at(timing, "memory");
  {
    const auto u = memory.find("utilization");
    if (u != memory.end() && u->is_number()) m_memory_utilization = u->get<double>();
  }
  if (memory.contains("channels") && memory["channels"].is_array()) m_channels = memory["channels"];
  m_memory_busy = cycles_at(memory, "busy_cycles");
  m_bytes_per_cycle = cycles_at(memory, "bytes_per_cycle");
  for (const auto& item : object_at(memory, "clients").items()) {
    Client c;
    c.name = item.key();
    const nlohmann::json& j = item.value();
    c.requests = cycles_at(j, "requests");
    c.bytes_read = cycles_at(j, "bytes_read");
    c.bytes_written = cycles_at(j, "bytes_written");
    c.busy_cycles = cycles_at(j, "busy_cycles");
    c.queued_cycles = number(j, "queued_cycles");
    c.queued_cycles_mean = number(j, "queued_cycles_mean");
    c.queued_cycles_max = number(j, "queued_cycles_max");
    m_clients.push_back(c);
  }
  // Clients in pipeline order, as the stages that own them.
  std::stable_sort(m_clients.begin(), m_clients.end(), [&](const Client& a, const Client& b) {
    const auto rank = [&](const std::string& name) {
      const TraceStage* s = m_manifest.stage(name);
      return s ? s->index : m_manifest.stages.size();
    };
    return rank(a.name) < rank(b.name);
  });

  // Every rate with a peak: "<name>" next to "<name>_peak".
  const nlohmann::json& rates = object_at(timing, "rates");
  for (const auto& item : rates.items()) {
    const std::string peak = item.key() + "_peak";
    if (!item.value().is_number() || !rates.contains(peak)) continue;
    m_rates.push_back({item.key(), item.value().get<double>(), number(rates, peak.c_str())});
  }

  m_bottleneck = find_bottleneck(m_manifest, m_stages, m_manifest.cycles, memory_load(timing));
  m_units = unit_loads(m_manifest, m_stages, timing);
}

std::string StatsSummary::text() const {
  const TraceManifest& m = m_manifest;
  std::string out =
      format_text("stats summary: %s (%s, %u unit%s, %llu cycles, %.3f ms at %g MHz)\n",
                  m_path.c_str(), m_scene.c_str(), m.units, m.units == 1 ? "" : "s",
                  static_cast<unsigned long long>(m.cycles), m_seconds * 1e3, m.clock_mhz);
  out += "\nStage utilization (share of the frame, from stats.json)\n";
  out += utilization_text(m_stages, m.cycles);
  out += "\n" + bottleneck_text(m_bottleneck, "frame", false);

  if (!m_rates.empty()) {
    out += "\nRates (achieved per clock over the frame, against peak)\n";
    for (const Rate& r : m_rates) {
      out += format_text("  %-32s %10.4f of %8g (%s of peak)\n", r.name.c_str(), r.achieved, r.peak,
                         r.peak > 0.0 ? percent(r.achieved / r.peak).c_str() : "-");
    }
  }

  if (m_memory_utilization && m_channels.size() > 1) {
    out += format_text(
        "\nMemory: %zu channels, %s utilized on average (%llu busy cycles of %zu x %llu, %llu "
        "bytes per cycle each)\n",
        m_channels.size(), percent(*m_memory_utilization).c_str(),
        static_cast<unsigned long long>(m_memory_busy), m_channels.size(),
        static_cast<unsigned long long>(m.cycles),
        static_cast<unsigned long long>(m_bytes_per_cycle));
  } else if (m_memory_utilization) {
    out += format_text(
        "\nMemory: the bus is %s utilized (%llu busy cycles of %llu, %llu bytes "
        "per cycle)\n",
        percent(*m_memory_utilization).c_str(), static_cast<unsigned long long>(m_memory_busy),
        static_cast<unsigned long long>(m.cycles),
        static_cast<unsigned long long>(m_bytes_per_cycle));
    out += format_text("  %-16s %10s %12s %12s %10s %7s %12s %10s\n", "client", "requests",
                       "bytes read", "written", "bus cycles", "bus", "wait mean", "wait max");
    for (const Client& c : m_clients) {
      out += format_text(
          "  %-16s %10llu %12llu %12llu %10llu %7s %12.1f %10.0f\n", c.name.c_str(),
          static_cast<unsigned long long>(c.requests),
          static_cast<unsigned long long>(c.bytes_read),
          static_cast<unsigned long long>(c.bytes_written),
          static_cast<unsigned long long>(c.busy_cycles),
          percent(m.cycles ? static_cast<double>(c.busy_cycles) / static_cast<double>(m.cycles)
                           : 0.0)
              .c_str(),
          c.queued_cycles_mean, c.queued_cycles_max);
    }
    if (m_channels.size() > 1) {
      out += format_text("  %-16s %10s %12s %12s %10s %7s %12s %10s\n", "channel", "requests",
                         "bytes read", "written", "bus cycles", "bus", "wait mean", "wait max");
      for (const nlohmann::json& ch : m_channels) {
        if (!ch.is_object()) continue;
        const auto count = [&](const char* k) {
          return static_cast<unsigned long long>(cycles_at(ch, k));
        };
        out += format_text("  %-16s %10llu %12llu %12llu %10llu %7s %12.1f %10.0f\n",
                           ("channel " + std::to_string(count("channel"))).c_str(),
                           count("requests"), count("bytes_read"), count("bytes_written"),
                           count("busy_cycles"), percent(number(ch, "utilization")).c_str(),
                           number(ch, "queued_cycles_mean"), number(ch, "queued_cycles_max"));
      }
    }
  }

  if (!m_units.empty()) {
    out += "\nLoad balance per raster unit (stats.json, whole frame)\n";
    out += load_balance_text(m.unit_kinds(), m_units);
  }
  return out;
}

nlohmann::json StatsSummary::json() const {
  const TraceManifest& m = m_manifest;
  nlohmann::json j;
  j["stats"] = m_path;
  j["scene"] = m_scene;
  j["units"] = m.units;
  j["clock_mhz"] = m.clock_mhz;
  j["cycles"] = m.cycles;
  j["simulated_seconds"] = m_seconds;
  j["stages"] = stages_json(m_stages, m.cycles);
  j["bottleneck"] = bottleneck_json(m_bottleneck);
  j["bound"] = m_bottleneck.bound;
  nlohmann::json rates = nlohmann::json::object();
  for (const Rate& r : m_rates) {
    rates[r.name] = {
        {"achieved", r.achieved},
        {"peak", r.peak},
        {"of_peak", r.peak > 0.0 ? nlohmann::json(r.achieved / r.peak) : nlohmann::json()}};
  }
  j["rates"] = rates;
  nlohmann::json clients = nlohmann::json::array();
  for (const Client& c : m_clients) {
    clients.push_back({{"name", c.name},
                       {"requests", c.requests},
                       {"bytes_read", c.bytes_read},
                       {"bytes_written", c.bytes_written},
                       {"busy_cycles", c.busy_cycles},
                       {"queued_cycles", c.queued_cycles},
                       {"queued_cycles_mean", c.queued_cycles_mean},
                       {"queued_cycles_max", c.queued_cycles_max}});
  }
  j["memory"] = {{"utilization",
                  m_memory_utilization ? nlohmann::json(*m_memory_utilization) : nlohmann::json()},
                 {"busy_cycles", m_memory_busy},
                 {"bytes_per_cycle", m_bytes_per_cycle},
                 {"clients", clients}};
  j["load_balance"] = load_balance_json(m.unit_kinds(), m_units);
  return j;
}

// ---------------------------------------------------------------- diff

namespace {

// `j` with every object key that is a renamed stage's former name
// ("triangle_setup") under the current one, so that a file written before
// the rename compares with one written after.
nlohmann::json current_stage_names(const nlohmann::json& j) {
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& v : j) out.push_back(current_stage_names(v));
    return out;
  }
  if (!j.is_object()) return j;
  nlohmann::json out = nlohmann::json::object();
  for (const auto& item : j.items()) {
    const std::string current = StageRegistry::current_name(item.key());
    out[current.empty() ? item.key() : current] = current_stage_names(item.value());
  }
  return out;
}

}  // namespace

StatsDiff::StatsDiff(const nlohmann::json& a_file, const std::string& path_a,
                     const nlohmann::json& b_file, const std::string& path_b)
    : m_a(path_a), m_b(path_b) {
  const nlohmann::json a = current_stage_names(a_file), b = current_stage_names(b_file);
  for (const char* key : {"stats", "timing", "config"}) {
    const auto ia = a.find(key), ib = b.find(key);
    walk(ia != a.end() ? &*ia : nullptr, ib != b.end() ? &*ib : nullptr, key);
  }
  const auto magnitude = [](const Entry& e) {
    return e.relative ? std::fabs(*e.relative) : std::numeric_limits<double>::infinity();
  };
  std::stable_sort(m_entries.begin(), m_entries.end(), [&](const Entry& x, const Entry& y) {
    const double mx = magnitude(x), my = magnitude(y);
    return mx != my ? mx > my : x.key < y.key;
  });
}

void StatsDiff::walk(const nlohmann::json* a, const nlohmann::json* b, const std::string& key) {
  const auto is_container = [](const nlohmann::json* j) {
    return j && (j->is_object() || j->is_array());
  };
  if (is_container(a) || is_container(b)) {
    // Objects by key, arrays by index; a side that is not the same kind of
    // container has none of the children.
    const bool object = (a && a->is_object()) || (b && b->is_object());
    const auto same_kind = [&](const nlohmann::json* j) {
      return j && (object ? j->is_object() : j->is_array());
    };
    std::vector<std::string> keys;
    for (const nlohmann::json* j : {a, b}) {
      if (!same_kind(j)) continue;
      if (object) {
        for (const auto& item : j->items()) {
          if (std::find(keys.begin(), keys.end(), item.key()) == keys.end()) {
            keys.push_back(item.key());
          }
        }
      } else {
        for (size_t i = keys.size(); i < j->size(); ++i) keys.push_back(std::to_string(i));
      }
    }
    const auto child = [&](const nlohmann::json* j, const std::string& k) -> const nlohmann::json* {
      if (!same_kind(j)) return nullptr;
      if (object) {
        const auto it = j->find(k);
        return it != j->end() ? &*it : nullptr;
      }
      const size_t i = std::stoul(k);
      return i < j->size() ? &(*j)[i] : nullptr;
    };
    for (const std::string& k : keys) {
      walk(child(a, k), child(b, k), object ? key + "." + k : key + "[" + k + "]");
    }
    return;
  }
  const bool na = a && a->is_number(), nb = b && b->is_number();
  if (!na && !nb) return;  // strings, booleans, null: not counters
  ++m_compared;
  Entry e;
  e.key = key;
  if (na) e.a = a->get<double>();
  if (nb) e.b = b->get<double>();
  if (e.a && e.b && *e.a == *e.b) return;
  if (e.a && e.b) {
    e.absolute = *e.b - *e.a;
    if (*e.a != 0.0) e.relative = e.absolute / std::fabs(*e.a);
  }
  m_entries.push_back(e);
}

namespace {

std::string value_text(const std::optional<double>& v) {
  return v ? format_text("%.10g", *v) : std::string("(missing)");
}

}  // namespace

std::string StatsDiff::text() const {
  if (m_entries.empty()) {
    return format_text("stats diff: %s and %s: identical (all %zu numbers equal)\n", m_a.c_str(),
                       m_b.c_str(), m_compared);
  }
  std::string out = format_text("stats diff: %s -> %s: %zu of %zu numbers differ\n", m_a.c_str(),
                                m_b.c_str(), m_entries.size(), m_compared);
  size_t width = 3;
  for (const Entry& e : m_entries) width = std::max(width, e.key.size());
  out += format_text("  %-*s %16s %16s %16s %10s\n", static_cast<int>(width), "key", "A", "B",
                     "change", "relative");
  for (const Entry& e : m_entries) {
    const std::string change = e.a && e.b ? format_text("%+.10g", e.absolute) : "-";
    const std::string relative = e.relative   ? format_text("%+.2f%%", 100.0 * *e.relative)
                                 : e.a && e.b ? std::string("from 0")
                                 : e.a        ? std::string("only in A")
                                              : std::string("only in B");
    out += format_text("  %-*s %16s %16s %16s %10s\n", static_cast<int>(width), e.key.c_str(),
                       value_text(e.a).c_str(), value_text(e.b).c_str(), change.c_str(),
                       relative.c_str());
  }
  return out;
}

nlohmann::json StatsDiff::json() const {
  const auto opt = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json();
  };
  nlohmann::json differences = nlohmann::json::array();
  for (const Entry& e : m_entries) {
    differences.push_back({{"key", e.key},
                           {"a", opt(e.a)},
                           {"b", opt(e.b)},
                           {"absolute", e.a && e.b ? nlohmann::json(e.absolute) : nlohmann::json()},
                           {"relative", opt(e.relative)},
                           {"missing", !e.a   ? nlohmann::json("a")
                                       : !e.b ? nlohmann::json("b")
                                              : nlohmann::json()}});
  }
  return {{"a", m_a},
          {"b", m_b},
          {"compared", m_compared},
          {"identical", m_entries.empty()},
          {"differences", differences}};
}

}  // namespace gpusim
