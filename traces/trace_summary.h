// `gpusim trace summary DIR`: what limited the frame, from a trace.
//
// Per stage, the share of the traced window it spent busy, stalled and
// starved, integrated from signals.vcd (cross-checked against stats.json
// when the window is the whole frame); the bottleneck, the stage kind with
// the busiest unit, with the stages it stalls upstream and starves
// downstream, and whether the memory bus is what makes it busy; each FIFO's
// time-weighted occupancy histogram; and each raster unit's share of the
// work. text() is for people, json() for scripts. The bottleneck analysis
// and the tables it shares with `gpusim stats summary` are in
// traces/bottleneck.h.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "traces/bottleneck.h"
#include "traces/trace_reader.h"
#include "traces/vcd_reader.h"

namespace gpusim {

class TraceSummary {
 public:
  // The shared analysis's types (traces/bottleneck.h).
  using Stage = StageLoad;
  using KindShare = gpusim::KindShare;
  using Bottleneck = gpusim::Bottleneck;
  using Unit = UnitLoad;
  struct Fifo {
    std::string name;
    uint64_t depth = 0;
    VcdReader::Histogram cycles_at;  // occupancy -> cycles in the window
    double mean = 0.0;
    uint64_t max = 0;
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
