// What a FIFO (hw/fifo.h) measures about itself: its occupancy, how long its
// writers were stalled and its readers starved, and the delays its stall
// policy added, integrated in simulated time and computed up to "now" on
// demand, so they can be read at any point (including after sc_start()
// returned with a stage still blocked). Every figure covers the frame so
// far, [start, now]: start is 0 for a GPU's first frame and the frame's
// first instant after a reset (restart()).
// The FIFO reports each change as it commits it; the figures reach
// stats.json as the FIFO's stat group (FifoChannel::stat_group()).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <systemc>

namespace gpusim {

// A snapshot. Times are sc_time; the stat group gives them in cycles.
struct FifoStats {
  uint64_t written = 0;
  uint64_t read = 0;
  size_t max_occupancy = 0;
  double mean_occupancy = 0.0;      // time-weighted over [start, now]
  sc_core::sc_time full;            // time holding depth() items
  sc_core::sc_time empty;           // time holding no item
  sc_core::sc_time writer_blocked;  // summed over writers blocked in write(): stall
  sc_core::sc_time reader_blocked;  // summed over readers blocked in read(): starve
  uint64_t injected_stalls = 0;     // reads and writes delayed by the stall policy
  sc_core::sc_time injected_stall;  // total delay they added
  sc_core::sc_time observed;        // now - start: the window of every time above
};

// Time integral of a level that changes at discrete instants: occupancy, or
// the number of processes currently blocked. Values are in units of the
// SystemC time resolution; 64 bits hold depth 65536 for 2^48 ps (~280 s).
struct TimeIntegral {
  uint64_t level = 0;
  uint64_t since = 0;  // sc_time value of the last change
  uint64_t area = 0;

  void set(uint64_t new_level, uint64_t now) {
    area += level * (now - since);
    since = now;
    level = new_level;
  }
  uint64_t area_at(uint64_t now) const { return area + level * (now - since); }
};

class FifoStatistics {
 public:
  explicit FifoStatistics(size_t depth) : m_depth(depth) {}

  // Everything zero, observed from `start` (an sc_time value) on: the
  // figures of a FIFO elaborated at `start`.
  void restart(uint64_t start) { *this = FifoStatistics(m_depth, start); }

  // The items held become `held` at `now` (sc_time values): the time since
  // the last change was spent at the previous level.
  void held(size_t held, uint64_t now) {
    const uint64_t dt = now - m_occupancy.since;
    if (m_occupancy.level == m_depth) m_full += dt;
    if (m_occupancy.level == 0) m_empty += dt;
    m_occupancy.set(held, now);
    m_max_occupancy = std::max(m_max_occupancy, held);
  }
  uint64_t last_change() const { return m_occupancy.since; }

  // Processes blocked on each side: a writer waiting for a slot (stalled),
  // a reader waiting for an item (starved).
  TimeIntegral& blocked_writers() { return m_blocked_writers; }
  TimeIntegral& blocked_readers() { return m_blocked_readers; }
  const TimeIntegral& blocked_writers() const { return m_blocked_writers; }
  const TimeIntegral& blocked_readers() const { return m_blocked_readers; }

  // An operation the stall policy delayed by `delay`.
  void stalled(const sc_core::sc_time& delay) {
    ++m_injected_stalls;
    m_injected_stall += delay;
  }

  // The figures from the start up to `now` (the kernel's time; the last
  // change if that is later, as a decoupled side's may be), with `written`
  // and `read` items.
  FifoStats snapshot(uint64_t written, uint64_t read, const sc_core::sc_time& now) const;

 private:
  FifoStatistics(size_t depth, uint64_t start) : m_depth(depth), m_start(start) {
    m_occupancy.since = m_blocked_writers.since = m_blocked_readers.since = start;
  }

  size_t m_depth;
  uint64_t m_start = 0;  // sc_time value
  size_t m_max_occupancy = 0;
  TimeIntegral m_occupancy;
  uint64_t m_full = 0;  // sc_time values, closed at each change
  uint64_t m_empty = 0;
  TimeIntegral m_blocked_writers;
  TimeIntegral m_blocked_readers;
  uint64_t m_injected_stalls = 0;
  sc_core::sc_time m_injected_stall;
};

}  // namespace gpusim
