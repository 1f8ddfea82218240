// What limited a frame, from per-stage busy, stalled and starved cycles:
// the analysis `gpusim trace summary` (over a trace's window, from
// signals.vcd) and `gpusim stats summary` (over the whole frame, from
// stats.json) share, with the text and JSON both print for it.
//
// The bottleneck is the stage kind with the busiest stage (the frame waits
// for the slowest unit); it is memory-bound when the busiest memory channel
// is busy and memory stalls make up most of that kind's busy cycles (one
// channel: the bus). The stages it stalls
// (upstream) and starves (downstream) are found by walking the netlist's
// FIFOs, which a TraceManifest describes: manifest.json's for a trace,
// manifest_from_stats() (traces/stats_summary.h) for a stats.json.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "traces/trace_reader.h"

namespace gpusim {

// One stage's time, in cycles of the span analysed (a window or the frame).
struct StageLoad {
  std::string name, kind;
  int unit = -1;
  uint64_t busy = 0, stalled = 0, starved = 0;
  // Whole-frame figures from stats.json, when it has the stage.
  std::optional<double> stats_busy, stats_stalled, stats_starved;
  double memory_stall = 0.0;  // stats.json memory_stall_cycles (depth test, ROP)
};

// Stages of one kind seen together: the chain of stalls and starvation.
struct KindShare {
  std::string kind;
  std::vector<std::string> stages;
  double mean = 0.0;  // mean share of the span over the stages
  double max = 0.0;
  std::string max_stage;
};

struct Bottleneck {
  std::string kind;
  std::string busiest;  // the stage of that kind with the highest busy share
  double busy = 0.0;    // its busy share
  double mean_busy = 0.0;
  double stalled = 0.0;  // the busiest stage's own stalled share
  size_t stages = 0;
  std::vector<KindShare> stalls;   // upstream, nearest first: stalled shares
  std::vector<KindShare> starves;  // downstream, nearest first: starved shares
  // stats.json, whole frame: the busiest channel's utilization, which
  // channel it is (-1: not known), of how many, and the channels' mean.
  std::optional<double> memory_utilization;
  int memory_channel = -1;
  unsigned memory_channels = 1;
  double memory_mean_utilization = 0.0;
  double memory_stall_share = 0.0;  // of the kind's busy cycles (stats.json)
  bool memory_bound = false;
  // What bounds the frame: "memory" when memory_bound, else `kind`.
  std::string bound;
};

// One raster unit's work (stats.json, whole frame) and busy cycles per kind
// of its stages (TraceManifest::unit_kinds(); absent when not measured).
struct UnitLoad {
  unsigned unit = 0;
  std::optional<uint64_t> tiles, stamps, fragments;
  std::vector<std::optional<uint64_t>> busy;
};

// printf into a std::string (up to 511 characters), and "12.3%".
std::string format_text(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string percent(double share);

// Fills each stage's stats_busy, stats_stalled, stats_starved and
// memory_stall from stats.json's timing.stages.
void read_stage_stats(const nlohmann::json& timing_stages, std::vector<StageLoad>& stages);

// The memory's load in stats.json's timing.memory: the busiest channel of
// timing.memory.channels (the lowest on a tie), or the top-level
// utilization when there is no channel list.
struct MemoryLoad {
  double utilization = 0.0;  // the busiest channel's
  int channel = -1;          // which, -1 without a channel list
  unsigned channels = 1;
  double mean = 0.0;  // the mean over the channels
};
std::optional<MemoryLoad> memory_load(const nlohmann::json& timing);

// The bottleneck among `stages` (non-empty), shares over `span` cycles.
Bottleneck find_bottleneck(const TraceManifest& netlist, const std::vector<StageLoad>& stages,
                           uint64_t span, std::optional<MemoryLoad> memory);

// Per unit of the netlist: stats.json timing.units' counts and the unit's
// stages' busy cycles from `stages`.
std::vector<UnitLoad> unit_loads(const TraceManifest& netlist, const std::vector<StageLoad>& stages,
                                 const nlohmann::json& timing);

// The utilization table's rows (after a heading the caller prints): per
// stage its busy, stalled and starved shares of `span` and its busy cycles.
std::string utilization_text(const std::vector<StageLoad>& stages, uint64_t span);
// "Bottleneck: kind (...)" and its memory, stalls and starves lines; `span`
// names what the shares are of ("window", "frame").
std::string bottleneck_text(const Bottleneck& b, const std::string& span, bool among_traced);
// The load-balance table's rows with the max / mean line.
std::string load_balance_text(const std::vector<std::string>& unit_kinds,
                              const std::vector<UnitLoad>& units);

nlohmann::json stages_json(const std::vector<StageLoad>& stages, uint64_t span);
nlohmann::json bottleneck_json(const Bottleneck& b);
nlohmann::json load_balance_json(const std::vector<std::string>& unit_kinds,
                                 const std::vector<UnitLoad>& units);

}  // namespace gpusim
