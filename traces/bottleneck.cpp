#include "traces/bottleneck.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <map>
#include <set>

namespace gpusim {
namespace {

// A stall or starvation share below this ends the upstream chain: the stage
// is not held back by the bottleneck in any way worth reporting.
constexpr double kChainThreshold = 0.01;
// The memory bus limits the frame when it is this busy and memory stalls
// make up at least this share of the bottleneck's busy cycles.
constexpr double kBusyBus = 0.7;
constexpr double kMemoryDominated = 0.5;

std::optional<double> number_at(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

double share_of(uint64_t cycles, uint64_t span) {
  return span ? static_cast<double>(cycles) / static_cast<double>(span) : 0.0;
}

const StageLoad* find_stage(const std::vector<StageLoad>& stages, const std::string& name) {
  for (const StageLoad& s : stages) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

// The kinds of stages joined to `from` through FIFOs, upstream (writers of
// their inputs) or downstream (readers of their outputs), step by step.
std::vector<KindShare> chain(const TraceManifest& m, const std::vector<StageLoad>& stages,
                             uint64_t span, const std::vector<const StageLoad*>& from,
                             bool upstream) {
  std::vector<KindShare> out;
  std::set<std::string> seen;
  for (const StageLoad* s : from) seen.insert(s->name);
  std::vector<const StageLoad*> frontier = from;
  while (!frontier.empty()) {
    std::vector<const StageLoad*> next;
    for (const StageLoad* s : frontier) {
      const TraceStage* ts = m.stage(s->name);
      if (!ts) continue;
      std::vector<std::string> neighbours;
      if (upstream) {
        for (const std::string& i : ts->inputs) {
          if (const TraceFifo* f = m.fifo(i)) neighbours.push_back(f->writer);
        }
      } else {
        for (const std::string& o : ts->outputs) {
          if (const TraceFifo* f = m.fifo(o)) neighbours.push_back(f->reader);
        }
      }
      for (const std::string& n : neighbours) {
        const StageLoad* st = find_stage(stages, n);  // "host", or not measured: the chain ends
        if (st && seen.insert(n).second) next.push_back(st);
      }
    }
    if (next.empty()) break;
    // One entry per kind met at this step (in practice one kind).
    std::map<int, KindShare> kinds;
    for (const StageLoad* s : next) {
      KindShare& k = kinds[m.pipeline_rank(s->kind)];
      k.kind = s->kind;
      k.stages.push_back(s->name);
      const double v = share_of(upstream ? s->stalled : s->starved, span);
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

}  // namespace

std::string format_text(const char* f, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  return buf;
}

std::string percent(double share) {
  return format_text("%.1f%%", 100.0 * share);
}

void read_stage_stats(const nlohmann::json& timing_stages, std::vector<StageLoad>& stages) {
  for (StageLoad& s : stages) {
    const auto it = timing_stages.find(s.name);
    if (it == timing_stages.end()) continue;
    s.stats_busy = number_at(*it, "busy_cycles");
    s.stats_stalled = number_at(*it, "stalled_cycles");
    s.stats_starved = number_at(*it, "starved_cycles");
    s.memory_stall = number_at(*it, "memory_stall_cycles").value_or(0.0);
  }
}

std::optional<MemoryLoad> memory_load(const nlohmann::json& timing) {
  const auto it = timing.find("memory");
  if (it == timing.end() || !it->is_object()) return std::nullopt;
  const std::optional<double> top = number_at(*it, "utilization");
  const auto channels = it->find("channels");
  if (channels == it->end() || !channels->is_array() || channels->empty()) {
    if (!top) return std::nullopt;
    return MemoryLoad{*top, -1, 1, *top};
  }
  MemoryLoad load;
  load.channels = static_cast<unsigned>(channels->size());
  double sum = 0.0;
  for (size_t i = 0; i < channels->size(); ++i) {
    const nlohmann::json& ch = (*channels)[i];
    const double u = ch.is_object() ? number_at(ch, "utilization").value_or(0.0) : 0.0;
    sum += u;
    if (load.channel < 0 || u > load.utilization) {
      load.utilization = u;
      load.channel = static_cast<int>(i);
    }
  }
  load.mean = sum / load.channels;
  return load;
}

Bottleneck find_bottleneck(const TraceManifest& netlist, const std::vector<StageLoad>& stages,
                           uint64_t span, std::optional<MemoryLoad> memory) {
  // A kind is as busy as its busiest unit: the frame waits for the slowest
  // unit however idle the others are (the load-balance table shows them).
  std::map<std::string, std::vector<const StageLoad*>> kinds;
  for (const StageLoad& s : stages) kinds[s.kind].push_back(&s);
  Bottleneck b;
  if (memory) {
    b.memory_utilization = memory->utilization;
    b.memory_channel = memory->channel;
    b.memory_channels = memory->channels;
    b.memory_mean_utilization = memory->mean;
  }
  const StageLoad* best = nullptr;
  for (const auto& [kind, group] : kinds) {
    for (const StageLoad* s : group) {
      // Ties go to the earlier pipeline stage, then the lower unit.
      if (!best || s->busy > best->busy ||
          (s->busy == best->busy &&
           netlist.pipeline_rank(s->kind) < netlist.pipeline_rank(best->kind))) {
        best = s;
      }
    }
  }
  if (!best) return b;
  const std::vector<const StageLoad*>& group = kinds[best->kind];
  b.kind = best->kind;
  b.busiest = best->name;
  b.busy = share_of(best->busy, span);
  b.stalled = share_of(best->stalled, span);
  b.stages = group.size();
  double busy_sum = 0.0, stats_busy = 0.0, memory_stall = 0.0;
  for (const StageLoad* s : group) {
    busy_sum += share_of(s->busy, span);
    stats_busy += s->stats_busy.value_or(0.0);
    memory_stall += s->memory_stall;
  }
  b.mean_busy = busy_sum / static_cast<double>(group.size());
  b.memory_stall_share = stats_busy > 0.0 ? memory_stall / stats_busy : 0.0;
  b.memory_bound = b.memory_utilization && *b.memory_utilization >= kBusyBus &&
                   b.memory_stall_share >= kMemoryDominated;
  b.bound = b.memory_bound ? "memory" : b.kind;
  b.stalls = chain(netlist, stages, span, group, true);
  b.starves = chain(netlist, stages, span, group, false);
  return b;
}

std::vector<UnitLoad> unit_loads(const TraceManifest& netlist, const std::vector<StageLoad>& stages,
                                 const nlohmann::json& timing) {
  const auto found = timing.find("units");
  const nlohmann::json timing_units =
      found != timing.end() && found->is_array() ? *found : nlohmann::json::array();
  std::vector<UnitLoad> out;
  for (unsigned u = 0; u < netlist.units; ++u) {
    UnitLoad unit;
    unit.unit = u;
    for (const nlohmann::json& j : timing_units) {
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
    for (const std::string& kind : netlist.unit_kinds()) {
      const StageLoad* s = find_stage(stages, kind + "_" + std::to_string(u));
      unit.busy.push_back(s ? std::optional<uint64_t>(s->busy) : std::nullopt);
    }
    out.push_back(unit);
  }
  return out;
}

std::string utilization_text(const std::vector<StageLoad>& stages, uint64_t span) {
  std::string out = format_text("  %-22s %8s %8s %8s %12s\n", "stage", "busy", "stalled", "starved",
                                "busy cycles");
  for (const StageLoad& s : stages) {
    out += format_text(
        "  %-22s %8s %8s %8s %12llu\n", s.name.c_str(), percent(share_of(s.busy, span)).c_str(),
        percent(share_of(s.stalled, span)).c_str(), percent(share_of(s.starved, span)).c_str(),
        static_cast<unsigned long long>(s.busy));
  }
  return out;
}

std::string bottleneck_text(const Bottleneck& b, const std::string& span, bool among_traced) {
  // With a stage filter the true bottleneck may not have been traced.
  std::string out =
      std::string("Bottleneck") + (among_traced ? " among the traced stages" : "") + ": " + b.kind;
  if (b.stages > 1) {
    out += format_text(" (busiest of %zu units: %s, busy %s of the %s; mean %s)\n", b.stages,
                       b.busiest.c_str(), percent(b.busy).c_str(), span.c_str(),
                       percent(b.mean_busy).c_str());
  } else {
    out += format_text(" (busy %s of the %s, stalled %s)\n", percent(b.busy).c_str(), span.c_str(),
                       percent(b.stalled).c_str());
  }
  // One channel is "the bus"; of several, the busiest is named with the mean.
  const std::string bus =
      b.memory_channels > 1 && b.memory_utilization
          ? format_text("memory channel %d (busiest of %u, mean %s)", b.memory_channel,
                        b.memory_channels, percent(b.memory_mean_utilization).c_str())
          : std::string("memory bus");
  if (b.memory_bound) {
    out += format_text(
        "  memory-bound: %s %s utilized and memory stalls are %s of %s's busy "
        "cycles (stats.json, whole frame)\n",
        b.memory_channels > 1 ? (bus + " is").c_str() : "the bus is",
        percent(*b.memory_utilization).c_str(), percent(b.memory_stall_share).c_str(),
        b.kind.c_str());
  } else if (b.memory_utilization) {
    out += format_text("  %s-bound: %s %s utilized; memory stalls are %s of %s's busy cycles\n",
                       b.kind.c_str(), bus.c_str(), percent(*b.memory_utilization).c_str(),
                       percent(b.memory_stall_share).c_str(), b.kind.c_str());
  }
  const auto describe = [&](const KindShare& k, const char* what) {
    std::string s = k.kind + " " + percent(k.mean) + " " + what;
    if (k.stages.size() > 1) {
      s += format_text(" (mean of %zu; most: %s %s)", k.stages.size(), k.max_stage.c_str(),
                       percent(k.max).c_str());
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
  return out + "\n";
}

std::string load_balance_text(const std::vector<std::string>& unit_kinds,
                              const std::vector<UnitLoad>& units) {
  // Columns: the work counts, then the busy cycles of each kind of stage a
  // unit has (in pipeline order).
  std::vector<std::string> heads{"tiles", "stamps", "fragments"};
  std::vector<int> widths{9, 9, 10};
  for (const std::string& kind : unit_kinds) {
    heads.push_back(kind + " busy");
    widths.push_back(std::max<int>(12, static_cast<int>(heads.back().size())));
  }
  const size_t columns = heads.size();
  std::string head = format_text("  %-9s", "unit");
  for (size_t c = 0; c < columns; ++c) head += format_text(" %*s", widths[c], heads[c].c_str());
  std::string out = head + "\n";
  // Column values per unit, absent ones skipped in max / mean.
  std::vector<std::vector<std::optional<uint64_t>>> cols(columns);
  for (const UnitLoad& u : units) {
    std::vector<std::optional<uint64_t>> row{u.tiles, u.stamps, u.fragments};
    row.insert(row.end(), u.busy.begin(), u.busy.end());
    row.resize(columns);
    std::string line = format_text("  %-9u", u.unit);
    for (size_t c = 0; c < columns; ++c) {
      cols[c].push_back(row[c]);
      line += format_text(" %*s", widths[c], row[c] ? std::to_string(*row[c]).c_str() : "-");
    }
    out += line + "\n";
  }
  std::string line = format_text("  %-9s", "max/mean");
  for (size_t c = 0; c < columns; ++c) {
    double sum = 0.0, max = 0.0;
    size_t n = 0;
    for (const auto& v : cols[c]) {
      if (!v) continue;
      sum += static_cast<double>(*v);
      max = std::max(max, static_cast<double>(*v));
      ++n;
    }
    line += format_text(" %*s", widths[c],
                        n && sum > 0.0 ? format_text("%.2f", max / (sum / n)).c_str() : "-");
  }
  return out + line + "\n";
}

nlohmann::json stages_json(const std::vector<StageLoad>& stages, uint64_t span) {
  nlohmann::json out = nlohmann::json::array();
  for (const StageLoad& s : stages) {
    out.push_back({{"name", s.name},
                   {"kind", s.kind},
                   {"unit", s.unit < 0 ? nlohmann::json() : nlohmann::json(s.unit)},
                   {"busy_cycles", s.busy},
                   {"stalled_cycles", s.stalled},
                   {"starved_cycles", s.starved},
                   {"busy", share_of(s.busy, span)},
                   {"stalled", share_of(s.stalled, span)},
                   {"starved", share_of(s.starved, span)}});
  }
  return out;
}

nlohmann::json bottleneck_json(const Bottleneck& b) {
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
  return {
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
      {"memory_channel",
       b.memory_channel < 0 ? nlohmann::json() : nlohmann::json(b.memory_channel)},
      {"memory_channels", b.memory_channels},
      {"memory_mean_utilization",
       b.memory_utilization ? nlohmann::json(b.memory_mean_utilization) : nlohmann::json()},
      {"memory_stall_share", b.memory_stall_share},
      {"memory_bound", b.memory_bound},
      {"bound", b.bound},
  };
}

nlohmann::json load_balance_json(const std::vector<std::string>& unit_kinds,
                                 const std::vector<UnitLoad>& units) {
  nlohmann::json out = nlohmann::json::array();
  const auto opt = [](const std::optional<uint64_t>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json();
  };
  for (const UnitLoad& u : units) {
    nlohmann::json busy = nlohmann::json::object();
    for (size_t k = 0; k < unit_kinds.size() && k < u.busy.size(); ++k) {
      busy[unit_kinds[k]] = opt(u.busy[k]);
    }
    out.push_back({{"unit", u.unit},
                   {"tiles", opt(u.tiles)},
                   {"stamps", opt(u.stamps)},
                   {"fragments", opt(u.fragments)},
                   {"busy_cycles", busy}});
  }
  return out;
}

}  // namespace gpusim
