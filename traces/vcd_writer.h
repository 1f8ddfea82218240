// signals.vcd (docs/traces.md): IEEE 1364 value change dump in simulated
// time: `$timescale` is the coarsest 1, 10 or 100 fs/ps/ns/us/ms/s that
// divides the clock period, and cycle c is written at time c × period / unit,
// an integer (the period is whole picoseconds, SystemC's resolution). Signals are declared up front
// in scopes; values are set as events arrive and written once per cycle, the value a signal holds
// at the end of that cycle's deltas, so a stage that passes through several states within one cycle
// shows its final one. Streamed through a buffer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "traces/buffered_file.h"

namespace gpusim {

class VcdWriter {
 public:
  // Changes are written for cycles in [start, end); values at `start` go to
  // $dumpvars. cycle_ps: the clock period in picoseconds.
  VcdWriter(const std::string& path, uint64_t cycle_ps, uint64_t start, uint64_t end);
  // Declaration, before begin(): a signal of `width` bits in scope `scope`
  // (scopes as "gpu.primitive_setup"; consecutive signals of one scope share
  // it). Returns the signal's handle.
  size_t add(const std::string& scope, const std::string& name, unsigned width, uint64_t initial);
  // Writes the header.
  void begin();
  // The signal's value from the current cycle on.
  void set(size_t signal, uint64_t value) {
    Signal& s = m_signals[signal];
    if (s.value == value) return;
    s.value = value;
    if (!s.dirty) {
      s.dirty = true;
      m_dirty.push_back(signal);
    }
  }
  // Every set() so far happened in `cycle` or before: writes what changed.
  void end_cycle(uint64_t cycle);
  // The run ended at `cycle`: a last time stamp (bounded by the window's end)
  // so viewers and readers see how long the last values lasted; closes.
  void finish(uint64_t cycle);
  // A declared signal's width, and its path as GTKWave names it:
  // "gpu.unit_0.rasterizer_to_depth_0[4:0]".
  unsigned width(size_t signal) const { return m_signals[signal].width; }
  std::string path(size_t signal) const;
  // Value changes written, $dumpvars entries included.
  uint64_t changes() const { return m_changes; }

  // The time unit for a clock period: its $timescale text ("1 ns", "100 ps")
  // and how many of it make one cycle.
  struct Timescale {
    std::string text;
    uint64_t per_cycle = 1;
  };
  static Timescale timescale_for(uint64_t cycle_ps);

 private:
  struct Signal {
    std::string scope, name, id;
    unsigned width = 1;
    uint64_t value = 0, written = 0;  // current, and as of the last cycle written
    bool dirty = false;
  };
  void emit(const Signal& s, uint64_t value);
  void dumpvars(bool use_written);
  void stamp(uint64_t cycle);  // "#time" of the cycle, once per cycle
  void out(const char* s, size_t n) { m_file.write(s, n); }
  void out(const std::string& s) { m_file.write(s); }

  BufferedFile m_file;
  bool m_closed = false;
  uint64_t m_cycle_ps, m_start, m_end;
  Timescale m_timescale;
  std::vector<Signal> m_signals;
  std::vector<size_t> m_dirty;
  bool m_dumped = false;
  bool m_stamped = false;
  uint64_t m_last_stamp = 0;
  uint64_t m_changes = 0;
};

}  // namespace gpusim
