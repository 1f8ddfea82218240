// `gpusim trace summary DIR`: what limited the frame, from a trace.
//
// Per stage, the share of the traced window it spent busy, stalled and
// starved, integrated from signals.vcd (cross-checked against stats.json
// when the window is the whole frame); the bottleneck, the stage kind with
// the busiest unit, with the stages it stalls upstream and starves
// downstream, and whether the memory bus is what makes it busy; each FIFO's
// time-weighted occupancy histogram; and each raster unit's share of the
// work. text() is for people, json() for scripts.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "traces/trace_reader.h"
#include "traces/vcd_reader.h"

namespace gpusim {

class TraceSummary {
 public:
  struct Stage {
    std::string name, kind;
    int unit = -1;
    // Cycles in the window, from signals.vcd.
    uint64_t busy = 0, stalled = 0, starved = 0;
    // Whole-frame figures from stats.json, when it has the stage.
    std::optional<double> stats_busy, stats_stalled, stats_starved;
    double memory_stall = 0.0;  // stats.json memory_stall_cycles (depth test, ROP)
  };
  // Stages of one kind seen together: the chain of stalls and starvation.
  struct KindShare {
    std::string kind;
    std::vector<std::string> stages;
    double mean = 0.0;  // mean share of the window over the stages
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
    std::vector<KindShare> stalls;             // upstream, nearest first: stalled shares
    std::vector<KindShare> starves;            // downstream, nearest first: starved shares
    std::optional<double> memory_utilization;  // stats.json, whole frame
    double memory_stall_share = 0.0;           // of the kind's busy cycles (stats.json)
    bool memory_bound = false;
  };
  struct Fifo {
    std::string name;
    uint64_t depth = 0;
    VcdReader::Histogram cycles_at;  // occupancy -> cycles in the window
    double mean = 0.0;
    uint64_t max = 0;
  };
  struct Unit {
    unsigned unit = 0;
    std::optional<uint64_t> tiles, stamps, fragments;  // stats.json, whole frame
    // Busy cycles in the window per kind of a unit's stages, as
    // TraceManifest::unit_kinds() lists them (absent when not traced).
    std::vector<std::optional<uint64_t>> busy;
  };

  // Reads signals.vcd and stats.json; InputError when either is unusable.
  explicit TraceSummary(const TraceReader& reader);

  const std::vector<Stage>& stages() const { return m_stages; }
  const Bottleneck& bottleneck() const { return m_bottleneck; }
  const std::vector<Fifo>& fifos() const { return m_fifos; }
  const std::vector<Unit>& units() const { return m_units; }
  // Disagreements between signals.vcd and stats.json, one line each; empty
  // when they agree or when the window is not the whole frame.
  const std::vector<std::string>& cross_check() const { return m_cross_check; }
  bool cross_checked() const { return m_cross_checked; }

  std::string text() const;
  nlohmann::json json() const;

 private:
  double share(uint64_t cycles) const;
  void read_signals(const TraceReader& reader);
  void read_stats(const nlohmann::json& stats);
  void find_bottleneck();
  // The kinds of stages joined to `from` through FIFOs, upstream (writers
  // of their inputs) or downstream (readers of their outputs), step by step.
  std::vector<KindShare> chain(const std::vector<const Stage*>& from, bool upstream) const;
  const Stage* stage(const std::string& name) const;

  TraceManifest m_manifest;
  std::string m_dir;
  uint64_t m_start = 0, m_end = 0;
  std::vector<Stage> m_stages;
  std::vector<Fifo> m_fifos;
  std::vector<Unit> m_units;
  Bottleneck m_bottleneck;
  std::vector<std::string> m_cross_check;
  bool m_cross_checked = false;
};

}  // namespace gpusim
