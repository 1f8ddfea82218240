#include "traces/trace_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <map>
#include <set>

#include "hw/input_error.h"

namespace gpusim {
namespace {

// A stall or starvation share below this ends the upstream chain: the stage
// is not held back by the bottleneck in any way worth reporting.
constexpr double kChainThreshold = 0.01;
// The memory bus limits the frame when it is this busy and memory stalls
// make up at least this share of the bottleneck's busy cycles.
constexpr double kBusyBus = 0.7;
constexpr double kMemoryDominated = 0.5;

std::string format(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* f, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  return buf;
}

std::string pct(double share) {
  return format("%.1f%%", 100.0 * share);
}

std::optional<double> number_at(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

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
  read_stats(reader.stats());
  find_bottleneck();
}

double TraceSummary::share(uint64_t cycles) const {
  const uint64_t w = m_end - m_start;
  return w ? static_cast<double>(cycles) / static_cast<double>(w) : 0.0;
}

const TraceSummary::Stage* TraceSummary::stage(const std::string& name) const {
  for (const Stage& s : m_stages) {
    if (s.name == name) return &s;
  }
  return nullptr;
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
  const nlohmann::json stages = timing.value("stages", nlohmann::json::object());
  for (Stage& s : m_stages) {
    const auto it = stages.find(s.name);
    if (it == stages.end()) continue;
    s.stats_busy = number_at(*it, "busy_cycles");
    s.stats_stalled = number_at(*it, "stalled_cycles");
    s.stats_starved = number_at(*it, "starved_cycles");
    s.memory_stall = number_at(*it, "memory_stall_cycles").value_or(0.0);
  }
  if (timing.contains("memory")) {
    m_bottleneck.memory_utilization = number_at(timing["memory"], "utilization");
  }

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
          m_cross_check.push_back(format("%s %s: %llu cycles in signals.vcd, %.0f in stats.json",
                                         s.name.c_str(), what,
                                         static_cast<unsigned long long>(v.first), v.second));
        }
      }
    }
  }

  // Load balance: the work counts are the frame's, the busy cycles the
  // window's.
  const nlohmann::json units = timing.value("units", nlohmann::json::array());
  for (unsigned u = 0; u < m_manifest.units; ++u) {
    Unit unit;
    unit.unit = u;
    for (const nlohmann::json& j : units) {
      if (!j.is_object() || j.value("unit", -1) != static_cast<int>(u)) continue;
      const auto count = [&](const char* key) -> std::optional<uint64_t> {
        const auto it = j.find(key);
        if (it == j.end() || !it->is_number_unsigned()) return std::nullopt;
        return it->get<uint64_t>();
      };
      unit.tiles = count("tiles");
      unit.stamps = count("stamps");
      unit.fragments = count("fragments");
    }
    for (const std::string& kind : m_manifest.unit_kinds()) {
      const Stage* s = stage(kind + "_" + std::to_string(u));
      unit.busy.push_back(s ? std::optional<uint64_t>(s->busy) : std::nullopt);
    }
    m_units.push_back(unit);
  }
}

std::vector<TraceSummary::KindShare> TraceSummary::chain(const std::vector<const Stage*>& from,
                                                         bool upstream) const {
  std::vector<KindShare> out;
  std::set<std::string> seen;
  for (const Stage* s : from) seen.insert(s->name);
  std::vector<const Stage*> frontier = from;
  while (!frontier.empty()) {
    std::vector<const Stage*> next;
    for (const Stage* s : frontier) {
      const TraceStage* ts = m_manifest.stage(s->name);
      std::vector<std::string> neighbours;
      if (upstream) {
        for (const std::string& i : ts->inputs) {
          if (const TraceFifo* f = m_manifest.fifo(i)) neighbours.push_back(f->writer);
        }
      } else {
        for (const std::string& o : ts->outputs) {
          if (const TraceFifo* f = m_manifest.fifo(o)) neighbours.push_back(f->reader);
        }
      }
      for (const std::string& n : neighbours) {
        const Stage* st = stage(n);  // "host", or a stage not traced: the chain ends
        if (st && seen.insert(n).second) next.push_back(st);
      }
    }
    if (next.empty()) break;
    // One entry per kind met at this step (in practice one kind).
    std::map<int, KindShare> kinds;
    for (const Stage* s : next) {
      KindShare& k = kinds[m_manifest.pipeline_rank(s->kind)];
      k.kind = s->kind;
      k.stages.push_back(s->name);
      const double v = share(upstream ? s->stalled : s->starved);
      k.mean += v;
      if (k.max_stage.empty() || v > k.max) {
        k.max = v;
        k.max_stage = s->name;
      }
    }
    double step_max = 0.0;
    for (auto& [rank, k] : kinds) step_max = std::max(step_max, k.max);
    // Upstream, backpressure fades out: a stage that is hardly stalled does
    // not pass the bottleneck on to its own writer. The nearest step is
    // always shown, stalled or not.
    const bool fades = upstream && step_max < kChainThreshold;
    if (fades && !out.empty()) break;
    for (auto& [rank, k] : kinds) {
      k.mean /= static_cast<double>(k.stages.size());
      out.push_back(k);
    }
    if (fades) break;
    frontier = next;
  }
  return out;
}

void TraceSummary::find_bottleneck() {
  // A kind is as busy as its busiest unit: the frame waits for the slowest
  // unit however idle the others are (the load-balance table shows them).
  std::map<std::string, std::vector<const Stage*>> kinds;
  for (const Stage& s : m_stages) kinds[s.kind].push_back(&s);
  Bottleneck& b = m_bottleneck;
  const Stage* best = nullptr;
  for (const auto& [kind, stages] : kinds) {
    for (const Stage* s : stages) {
      // Ties go to the earlier pipeline stage, then the lower unit.
      if (!best || s->busy > best->busy ||
          (s->busy == best->busy &&
           m_manifest.pipeline_rank(s->kind) < m_manifest.pipeline_rank(best->kind))) {
        best = s;
      }
    }
  }
  const std::vector<const Stage*>& group = kinds[best->kind];
  b.kind = best->kind;
  b.busiest = best->name;
  b.busy = share(best->busy);
  b.stalled = share(best->stalled);
  b.stages = group.size();
  double busy_sum = 0.0, stats_busy = 0.0, memory_stall = 0.0;
  for (const Stage* s : group) {
    busy_sum += share(s->busy);
    stats_busy += s->stats_busy.value_or(0.0);
    memory_stall += s->memory_stall;
  }
  b.mean_busy = busy_sum / static_cast<double>(group.size());
  b.memory_stall_share = stats_busy > 0.0 ? memory_stall / stats_busy : 0.0;
  b.memory_bound = b.memory_utilization && *b.memory_utilization >= kBusyBus &&
                   b.memory_stall_share >= kMemoryDominated;
  b.stalls = chain(group, true);
  b.starves = chain(group, false);
}

std::string TraceSummary::text() const {
  std::string out;
  const TraceManifest& m = m_manifest;
  out += format("trace summary: %s (%s, %u unit%s, %llu cycles at %g MHz)\n", m_dir.c_str(),
                m.scene.c_str(), m.units, m.units == 1 ? "" : "s",
                static_cast<unsigned long long>(m.cycles), m.clock_mhz);
  out += format("  window: cycles %llu..%llu (%s); filters: %s\n",
                static_cast<unsigned long long>(m_start), static_cast<unsigned long long>(m_end),
                m_start == 0 && m_end == m.cycles ? "the whole frame" : "part of the frame",
                m.filters.describe().c_str());

  out += "\nStage utilization (share of the window, from signals.vcd)\n";
  out += format("  %-22s %8s %8s %8s %12s\n", "stage", "busy", "stalled", "starved", "busy cycles");
  for (const Stage& s : m_stages) {
    out += format("  %-22s %8s %8s %8s %12llu\n", s.name.c_str(), pct(share(s.busy)).c_str(),
                  pct(share(s.stalled)).c_str(), pct(share(s.starved)).c_str(),
                  static_cast<unsigned long long>(s.busy));
  }
  if (!m_cross_checked) {
    out += "  (not cross-checked with stats.json: it covers the whole frame, the trace a window)\n";
  } else if (m_cross_check.empty()) {
    out += format(
        "  cross-check: busy, stalled and starved cycles of all %zu stages equal "
        "stats.json's\n",
        m_stages.size());
  } else {
    out += format("  cross-check: %zu disagreement%s with stats.json:\n", m_cross_check.size(),
                  m_cross_check.size() == 1 ? "" : "s");
    for (const std::string& e : m_cross_check) out += "    " + e + "\n";
  }

  const Bottleneck& b = m_bottleneck;
  // With a stage filter the true bottleneck may not have been traced.
  out += std::string("\nBottleneck") + (m.filters.stages ? " among the traced stages" : "") + ": " +
         b.kind;
  if (b.stages > 1) {
    out += format(" (busiest of %zu units: %s, busy %s of the window; mean %s)\n", b.stages,
                  b.busiest.c_str(), pct(b.busy).c_str(), pct(b.mean_busy).c_str());
  } else {
    out += format(" (busy %s of the window, stalled %s)\n", pct(b.busy).c_str(),
                  pct(b.stalled).c_str());
  }
  if (b.memory_bound) {
    out += format(
        "  memory-bound: the bus is %s utilized and memory stalls are %s of %s's busy "
        "cycles (stats.json, whole frame)\n",
        pct(*b.memory_utilization).c_str(), pct(b.memory_stall_share).c_str(), b.kind.c_str());
  } else if (b.memory_utilization) {
    out += format("  memory bus %s utilized; memory stalls are %s of %s's busy cycles\n",
                  pct(*b.memory_utilization).c_str(), pct(b.memory_stall_share).c_str(),
                  b.kind.c_str());
  }
  const auto describe = [&](const KindShare& k, const char* what) {
    std::string s = k.kind + " " + pct(k.mean) + " " + what;
    if (k.stages.size() > 1) {
      s += format(" (mean of %zu; most: %s %s)", k.stages.size(), k.max_stage.c_str(),
                  pct(k.max).c_str());
    }
    return s;
  };
  out += "  stalls (upstream, blocked writing into its input):";
  if (b.stalls.empty()) out += " none traced";
  for (size_t i = 0; i < b.stalls.size(); ++i) {
    out += (i ? ", " : " ") + describe(b.stalls[i], "stalled");
  }
  out += "\n  starves (downstream, waiting for its output):";
  if (b.starves.empty()) out += " none (the last stage traced)";
  for (size_t i = 0; i < b.starves.size(); ++i) {
    out += (i ? ", " : " ") + describe(b.starves[i], "starved");
  }
  out += "\n";

  if (!m_fifos.empty()) {
    out +=
        "\nFIFO occupancy (time-weighted; one column per level 0..depth, height = share of "
        "the window)\n";
    out += format("  %-28s %5s %7s %5s %7s %7s  %s\n", "fifo", "depth", "mean", "max", "empty",
                  "full", "histogram");
    for (const Fifo& f : m_fifos) {
      const auto at = [&](uint64_t level) {
        const auto it = f.cycles_at.find(level);
        return it == f.cycles_at.end() ? uint64_t{0} : it->second;
      };
      out += format("  %-28s %5llu %7.2f %5llu %7s %7s  %s\n", f.name.c_str(),
                    static_cast<unsigned long long>(f.depth), f.mean,
                    static_cast<unsigned long long>(f.max), pct(share(at(0))).c_str(),
                    pct(share(at(f.depth))).c_str(),
                    occupancy_bar(f.cycles_at, f.depth, m_end - m_start).c_str());
    }
  }

  if (!m_units.empty()) {
    out +=
        "\nLoad balance per raster unit (tiles, stamps, fragments: stats.json, whole frame; "
        "busy: cycles in the window)\n";
    // Columns: the work counts, then the busy cycles of each kind of stage a
    // unit has (manifest.json's stages, in pipeline order).
    std::vector<std::string> heads{"tiles", "stamps", "fragments"};
    std::vector<int> widths{9, 9, 10};
    for (const std::string& kind : m_manifest.unit_kinds()) {
      heads.push_back(kind + " busy");
      widths.push_back(std::max<int>(12, static_cast<int>(heads.back().size())));
    }
    const size_t columns = heads.size();
    std::string head = format("  %-9s", "unit");
    for (size_t c = 0; c < columns; ++c) head += format(" %*s", widths[c], heads[c].c_str());
    out += head + "\n";
    // Column values per unit, absent ones skipped in max / mean.
    std::vector<std::vector<std::optional<uint64_t>>> cols(columns);
    for (const Unit& u : m_units) {
      std::vector<std::optional<uint64_t>> row{u.tiles, u.stamps, u.fragments};
      row.insert(row.end(), u.busy.begin(), u.busy.end());
      std::string line = format("  %-9u", u.unit);
      for (size_t c = 0; c < columns; ++c) {
        cols[c].push_back(row[c]);
        line += format(" %*s", widths[c], row[c] ? std::to_string(*row[c]).c_str() : "-");
      }
      out += line + "\n";
    }
    std::string line = format("  %-9s", "max/mean");
    for (size_t c = 0; c < columns; ++c) {
      double sum = 0.0, max = 0.0;
      size_t n = 0;
      for (const auto& v : cols[c]) {
        if (!v) continue;
        sum += static_cast<double>(*v);
        max = std::max(max, static_cast<double>(*v));
        ++n;
      }
      line +=
          format(" %*s", widths[c], n && sum > 0.0 ? format("%.2f", max / (sum / n)).c_str() : "-");
    }
    out += line + "\n";
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
  nlohmann::json stages = nlohmann::json::array();
  for (const Stage& s : m_stages) {
    nlohmann::json e = {{"name", s.name},
                        {"kind", s.kind},
                        {"unit", s.unit < 0 ? nlohmann::json() : nlohmann::json(s.unit)},
                        {"busy_cycles", s.busy},
                        {"stalled_cycles", s.stalled},
                        {"starved_cycles", s.starved},
                        {"busy", share(s.busy)},
                        {"stalled", share(s.stalled)},
                        {"starved", share(s.starved)}};
    stages.push_back(e);
  }
  j["stages"] = stages;
  j["cross_check"] = m_cross_checked ? nlohmann::json(m_cross_check) : nlohmann::json();
  const Bottleneck& b = m_bottleneck;
  const auto shares = [](const std::vector<KindShare>& v, const char* what) {
    nlohmann::json a = nlohmann::json::array();
    for (const KindShare& k : v) {
      a.push_back({{"kind", k.kind},
                   {"stages", k.stages},
                   {what, k.mean},
                   {std::string("max_") + what, k.max},
                   {"max_stage", k.max_stage}});
    }
    return a;
  };
  j["bottleneck"] = {
      {"kind", b.kind},
      {"busiest", b.busiest},
      {"busy", b.busy},
      {"mean_busy", b.mean_busy},
      {"stalled", b.stalled},
      {"stages", b.stages},
      {"stalls", shares(b.stalls, "stalled")},
      {"starves", shares(b.starves, "starved")},
      {"memory_utilization",
       b.memory_utilization ? nlohmann::json(*b.memory_utilization) : nlohmann::json()},
      {"memory_stall_share", b.memory_stall_share},
      {"memory_bound", b.memory_bound},
  };
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
  nlohmann::json units = nlohmann::json::array();
  for (const Unit& u : m_units) {
    const auto opt = [](const std::optional<uint64_t>& v) {
      return v ? nlohmann::json(*v) : nlohmann::json();
    };
    nlohmann::json busy = nlohmann::json::object();
    const std::vector<std::string> kinds = m.unit_kinds();
    for (size_t k = 0; k < kinds.size() && k < u.busy.size(); ++k) busy[kinds[k]] = opt(u.busy[k]);
    units.push_back({{"unit", u.unit},
                     {"tiles", opt(u.tiles)},
                     {"stamps", opt(u.stamps)},
                     {"fragments", opt(u.fragments)},
                     {"busy_cycles", busy}});
  }
  j["load_balance"] = units;
  return j;
}

}  // namespace gpusim
