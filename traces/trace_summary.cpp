#include "traces/trace_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "hw/input_error.h"

namespace gpusim {
namespace {

// A bar of block characters, one column per occupancy level (or range of
// levels for deep FIFOs), each as tall as the share of time spent there.
std::string occupancy_bar(const VcdReader::Histogram& h, uint64_t depth, uint64_t window) {
  static const char* const kBlocks[9] = {" ", "▁", "▂", "▃", "▄", "▅", "▆", "▇", "█"};
  // Up to 17 columns: every level of a FIFO up to depth 16; deeper ones keep
  // empty and full as their own columns and split the rest in 15 ranges.
  const uint64_t columns = std::min<uint64_t>(depth + 1, 17);
  std::vector<uint64_t> time(columns, 0);
  for (const auto& [level, cycles] : h) {
    uint64_t c;
    if (depth + 1 <= 17 || level == 0) {
      c = std::min(level, columns - 1);
    } else if (level >= depth) {
      c = columns - 1;
    } else {
      c = 1 + (level - 1) * 15 / (depth - 1);
    }
    time[c] += cycles;
  }
  std::string bar = "|";
  for (const uint64_t t : time) {
    const double s = window ? static_cast<double>(t) / static_cast<double>(window) : 0.0;
    const int level = t == 0 ? 0 : std::clamp(static_cast<int>(std::ceil(s * 8.0)), 1, 8);
    bar += kBlocks[level];
  }
  return bar + "|";
}

}  // namespace

TraceSummary::TraceSummary(const TraceReader& reader)
    : m_manifest(reader.manifest()), m_dir(reader.dir()) {
  std::tie(m_start, m_end) = m_manifest.window();
  read_signals(reader);
  const nlohmann::json stats = reader.stats();
  read_stats(stats);
  const nlohmann::json timing = stats.value("timing", nlohmann::json::object());
  m_bottleneck = find_bottleneck(m_manifest, m_stages, m_end - m_start, memory_load(timing));
  m_units = unit_loads(m_manifest, m_stages, timing);
}

double TraceSummary::share(uint64_t cycles) const {
  const uint64_t w = m_end - m_start;
  return w ? static_cast<double>(cycles) / static_cast<double>(w) : 0.0;
}

void TraceSummary::read_signals(const TraceReader& reader) {
  reader.require("vcd");
  const VcdReader vcd(reader.path("signals.vcd"), m_manifest.cycle_ps);
  // Signals by (innermost scope, name): a stage's wires are in a scope named
  // as the stage, "<stage>_busy" (traces written before units were grouped:
  // plain "busy"); a FIFO's occupancy is named as the FIFO, in its unit's
  // scope (before: in a scope "fifos").
  std::map<std::pair<std::string, std::string>, size_t> by_name;
  std::map<std::string, size_t> by_leaf;
  for (size_t i = 0; i < vcd.signals().size(); ++i) {
    const VcdSignal& s = vcd.signals()[i];
    const size_t dot = s.scope.rfind('.');
    by_name[{dot == std::string::npos ? s.scope : s.scope.substr(dot + 1), s.name}] = i;
    by_leaf[s.name] = i;
  }
  const auto wire = [&](const std::string& stage, const std::string& state) {
    const auto it = by_name.find({stage, stage + "_" + state});
    return it != by_name.end() ? it : by_name.find({stage, state});
  };
  const std::vector<VcdReader::Histogram> h = vcd.histograms(m_start, m_end);
  const auto time_at = [&](size_t signal, uint64_t value) {
    const auto it = h[signal].find(value);
    return it == h[signal].end() ? uint64_t{0} : it->second;
  };
  for (const TraceStage& ts : m_manifest.stages) {
    const auto busy = wire(ts.name, "busy");
    const auto stalled = wire(ts.name, "stalled");
    const auto starved = wire(ts.name, "starved");
    if (busy == by_name.end() || stalled == by_name.end() || starved == by_name.end()) continue;
    Stage s;
    s.name = ts.name;
    s.kind = ts.kind;
    s.unit = ts.unit;
    s.busy = time_at(busy->second, 1);
    s.stalled = time_at(stalled->second, 1);
    s.starved = time_at(starved->second, 1);
    m_stages.push_back(std::move(s));
  }
  if (m_stages.empty()) {
    throw InputError(vcd.path() + ": no stage signals (busy, stalled, starved) for any stage of " +
                     reader.path("manifest.json"));
  }
  for (const TraceFifo& tf : m_manifest.fifos) {
    const auto it = by_leaf.find(tf.name);
    if (it == by_leaf.end()) continue;
    Fifo f;
    f.name = tf.name;
    f.depth = tf.depth;
    f.cycles_at = h[it->second];
    double area = 0.0, time = 0.0;
    for (const auto& [level, cycles] : f.cycles_at) {
      if (level == VcdReader::kUnknown || cycles == 0) continue;
      area += static_cast<double>(level) * static_cast<double>(cycles);
      time += static_cast<double>(cycles);
      f.max = std::max(f.max, level);
    }
    f.mean = time > 0.0 ? area / time : 0.0;
    m_fifos.push_back(std::move(f));
  }
}

void TraceSummary::read_stats(const nlohmann::json& stats) {
  const nlohmann::json timing = stats.value("timing", nlohmann::json::object());
  read_stage_stats(timing.value("stages", nlohmann::json::object()), m_stages);

  // The counters cover the whole frame, the signals the window: they are
  // comparable only when the window is the frame.
  m_cross_checked = m_start == 0 && m_end == m_manifest.cycles;
  if (m_cross_checked) {
    for (const Stage& s : m_stages) {
      if (!s.stats_busy || !s.stats_stalled || !s.stats_starved) {
        m_cross_check.push_back(s.name + ": missing from stats.json");
        continue;
      }
      const std::pair<const char*, std::pair<uint64_t, double>> pairs[] = {
          {"busy", {s.busy, *s.stats_busy}},
          {"stalled", {s.stalled, *s.stats_stalled}},
          {"starved", {s.starved, *s.stats_starved}}};
      for (const auto& [what, v] : pairs) {
        // Both count whole cycles; one cycle of slack absorbs a state
        // change recorded at a different delta of the same cycle.
        if (std::fabs(static_cast<double>(v.first) - v.second) > 1.0) {
          m_cross_check.push_back(
              format_text("%s %s: %llu cycles in signals.vcd, %.0f in stats.json", s.name.c_str(),
                          what, static_cast<unsigned long long>(v.first), v.second));
        }
      }
    }
  }
}

std::string TraceSummary::text() const {
  std::string out;
  const TraceManifest& m = m_manifest;
  out += format_text("trace summary: %s (%s, %u unit%s, %llu cycles at %g MHz)\n", m_dir.c_str(),
                     m.scene.c_str(), m.units, m.units == 1 ? "" : "s",
                     static_cast<unsigned long long>(m.cycles), m.clock_mhz);
  out +=
      format_text("  window: cycles %llu..%llu (%s); filters: %s\n",
                  static_cast<unsigned long long>(m_start), static_cast<unsigned long long>(m_end),
                  m_start == 0 && m_end == m.cycles ? "the whole frame" : "part of the frame",
                  m.filters.describe().c_str());

  out += "\nStage utilization (share of the window, from signals.vcd)\n";
  out += utilization_text(m_stages, m_end - m_start);
  if (!m_cross_checked) {
    out += "  (not cross-checked with stats.json: it covers the whole frame, the trace a window)\n";
  } else if (m_cross_check.empty()) {
    out += format_text(
        "  cross-check: busy, stalled and starved cycles of all %zu stages equal "
        "stats.json's\n",
        m_stages.size());
  } else {
    out += format_text("  cross-check: %zu disagreement%s with stats.json:\n", m_cross_check.size(),
                       m_cross_check.size() == 1 ? "" : "s");
    for (const std::string& e : m_cross_check) out += "    " + e + "\n";
  }

  out += "\n" + bottleneck_text(m_bottleneck, "window", m.filters.stages.has_value());

  if (!m_fifos.empty()) {
    out +=
        "\nFIFO occupancy (time-weighted; one column per level 0..depth, height = share of "
        "the window)\n";
    out += format_text("  %-28s %5s %7s %5s %7s %7s  %s\n", "fifo", "depth", "mean", "max", "empty",
                       "full", "histogram");
    for (const Fifo& f : m_fifos) {
      const auto at = [&](uint64_t level) {
        const auto it = f.cycles_at.find(level);
        return it == f.cycles_at.end() ? uint64_t{0} : it->second;
      };
      out += format_text("  %-28s %5llu %7.2f %5llu %7s %7s  %s\n", f.name.c_str(),
                         static_cast<unsigned long long>(f.depth), f.mean,
                         static_cast<unsigned long long>(f.max), percent(share(at(0))).c_str(),
                         percent(share(at(f.depth))).c_str(),
                         occupancy_bar(f.cycles_at, f.depth, m_end - m_start).c_str());
    }
  }

  if (!m_units.empty()) {
    out +=
        "\nLoad balance per raster unit (tiles, stamps, fragments: stats.json, whole frame; "
        "busy: cycles in the window)\n";
    out += load_balance_text(m_manifest.unit_kinds(), m_units);
  }
  return out;
}

nlohmann::json TraceSummary::json() const {
  const TraceManifest& m = m_manifest;
  nlohmann::json j;
  j["trace"] = m_dir;
  j["scene"] = m.scene;
  j["units"] = m.units;
  j["cycles"] = m.cycles;
  j["window"] = {m_start, m_end};
  j["filters"] = m.filters.describe();
  j["stages"] = stages_json(m_stages, m_end - m_start);
  j["cross_check"] = m_cross_checked ? nlohmann::json(m_cross_check) : nlohmann::json();
  j["bottleneck"] = bottleneck_json(m_bottleneck);
  nlohmann::json fifos = nlohmann::json::array();
  for (const Fifo& f : m_fifos) {
    nlohmann::json hist = nlohmann::json::object();
    for (const auto& [level, cycles] : f.cycles_at) {
      if (level != VcdReader::kUnknown) hist[std::to_string(level)] = cycles;
    }
    fifos.push_back({{"name", f.name},
                     {"depth", f.depth},
                     {"mean", f.mean},
                     {"max", f.max},
                     {"cycles_at_occupancy", hist}});
  }
  j["fifos"] = fifos;
  j["load_balance"] = load_balance_json(m.unit_kinds(), m_units);
  return j;
}

}  // namespace gpusim
