// `gpusim stats summary STATS.json` and `gpusim stats diff A B`: what a run's
// stats.json (`gpusim run --out DIR`) says about the frame without a trace.
//
// The summary is `gpusim trace summary` less what needs the signals: per
// stage the share of the frame it was busy, stalled and starved, the
// bottleneck and what bounds the frame (traces/bottleneck.h, the same
// analysis over the same numbers, with the whole frame as the window), the
// raster units' load balance, achieved against peak rates, and the memory
// bus's utilization with each client's bytes and waits. The diff lists
// every number that differs between two stats.json files. text() is for
// people, json() for scripts; docs/stats.md documents both.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "traces/bottleneck.h"
#include "traces/trace_reader.h"

namespace gpusim {

// Parses `path`; InputError (one line naming the file) when it cannot be
// read, is not JSON, or is not a stats.json gpusim wrote: an object with a
// `stats` object. `need_timing`: also the cycle model's `timing` (cycles,
// stages) and `config`, which `gpusim golden` does not write.
nlohmann::json read_stats_file(const std::string& path, bool need_timing);

// The netlist a cycle model's stats.json records (timing.netlist, in
// pipeline order), with its units, clock and cycles, as a trace's manifest
// would list it. `path` names the file in errors.
TraceManifest manifest_from_stats(const nlohmann::json& stats, const std::string& path);

class StatsSummary {
 public:
  struct Rate {
    std::string name;  // "raster_pixels_per_clock"
    double achieved = 0.0, peak = 0.0;
  };
  struct Client {
    std::string name;  // "depth_test_0"
    uint64_t requests = 0, bytes_read = 0, bytes_written = 0, busy_cycles = 0;
    double queued_cycles = 0.0, queued_cycles_mean = 0.0, queued_cycles_max = 0.0;
  };

  // `stats` as read_stats_file(path, true) returns it.
  StatsSummary(const nlohmann::json& stats, const std::string& path);

  const std::vector<StageLoad>& stages() const { return m_stages; }
  const Bottleneck& bottleneck() const { return m_bottleneck; }
  const std::vector<UnitLoad>& units() const { return m_units; }
  const std::vector<Rate>& rates() const { return m_rates; }
  const std::vector<Client>& clients() const { return m_clients; }
  uint64_t cycles() const { return m_manifest.cycles; }

  std::string text() const;
  nlohmann::json json() const;

 private:
  std::string m_path, m_scene;
  TraceManifest m_manifest;
  double m_seconds = 0.0;
  std::vector<StageLoad> m_stages;
  Bottleneck m_bottleneck;
  std::vector<UnitLoad> m_units;
  std::vector<Rate> m_rates;
  std::optional<double> m_memory_utilization;
  uint64_t m_memory_busy = 0, m_bytes_per_cycle = 0;
  std::vector<Client> m_clients;
  nlohmann::json m_channels;  // timing.memory.channels, shown when there are several
};

// Every number that differs between two stats.json files.
class StatsDiff {
 public:
  struct Entry {
    std::string key;                 // "timing.stages.rop_0.busy_cycles"
    std::optional<double> a, b;      // absent: the key is missing on that side
    double absolute = 0.0;           // b - a
    std::optional<double> relative;  // (b - a) / |a|; absent when a is 0 or missing
  };

  // Walks `stats`, `timing` and `config` of both (read_stats_file(..., false)).
  StatsDiff(const nlohmann::json& a, const std::string& path_a, const nlohmann::json& b,
            const std::string& path_b);

  // Sorted by |relative change| descending (an infinite change, from 0 or a
  // missing key, first), then by key.
  const std::vector<Entry>& entries() const { return m_entries; }
  size_t compared() const { return m_compared; }

  std::string text() const;
  nlohmann::json json() const;

 private:
  void walk(const nlohmann::json* a, const nlohmann::json* b, const std::string& key);

  std::string m_a, m_b;
  std::vector<Entry> m_entries;
  size_t m_compared = 0;
};

}  // namespace gpusim
