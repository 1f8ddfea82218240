// The --trace-stages, --trace-window and --trace-prims filters and the
// --trace-formats choice (docs/traces.md, "Options"): parsed before the run,
// so bad syntax fails before anything is simulated or written; the filters
// are applied to every record.
#pragma once

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hw/trace_probe.h"

namespace gpusim {

// Which of a trace's files are written (--trace-formats): manifest.json,
// frame.exr and stats.json always are.
struct TraceFormats {
  bool vcd = true;           // signals.vcd and signals.gtkw
  bool timeline = true;      // timeline.json
  bool transactions = true;  // transactions.bin
  bool fragments = true;     // fragments.bin

  // The format names, in this order.
  static const std::vector<std::string>& all();
  // "vcd,timeline": comma-separated names of all(); empty: every format.
  // Throws InputError with one line naming the option on an unknown or
  // empty name.
  static TraceFormats parse(const std::string& list);
  // The names chosen, in the order of all().
  std::vector<std::string> names() const;
  // The files they write, in the order of all() ("signals.vcd", "signals.gtkw", ...).
  std::vector<std::string> files() const;
};

class TraceFilter {
 public:
  static constexpr uint64_t kOpenEnd = std::numeric_limits<uint64_t>::max();

  // Empty strings: no filter. Throws InputError with one line naming the
  // option on bad syntax ("--trace-window 5:2: START must be below END").
  static TraceFilter parse(const std::string& stages, const std::string& window,
                           const std::string& prims);

  // Per stage of `tables`, whether it is traced. Throws InputError naming an
  // unknown stage or kind.
  std::vector<bool> stages_kept(const NetlistTables& tables) const;

  // The item's interval [in, out) meets the window [start, end); an empty
  // interval counts as the instant `in`.
  bool item_in_window(uint64_t in, uint64_t out) const {
    return in < m_end && (out > m_start || (out == in && in >= m_start));
  }
  bool cycle_in_window(uint64_t c) const { return c >= m_start && c < m_end; }
  // Primitive ids [first, last] meet [A, B] (-1: none, which never does).
  bool prims_match(int64_t first, int64_t last) const {
    return !m_has_prims || (first >= 0 && first <= m_prim_last && last >= m_prim_first);
  }
  uint64_t window_start() const { return m_start; }
  uint64_t window_end() const { return m_end; }

  // manifest.json's "filters": stages kept (null when all), window, prims.
  nlohmann::json to_json(const NetlistTables& tables, const std::vector<bool>& kept) const;

 private:
  std::vector<std::string> m_stages;  // as given; empty: all
  uint64_t m_start = 0, m_end = kOpenEnd;
  bool m_has_window = false, m_start_given = false, m_has_prims = false;
  int64_t m_prim_first = 0, m_prim_last = 0;
};

}  // namespace gpusim
