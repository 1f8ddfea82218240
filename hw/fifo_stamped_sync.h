// The stamped (temporally decoupled) synchronisation of a FIFO
// (hw/fifo.h, docs/architecture.md): a FIFO joining a stage that runs ahead
// of the kernel's time (PipelineStage::set_decoupled) takes reads and writes
// at superdense times. Every operation is given the time at which the
// kernel-timed semantics would perform it, computed from the one operation
// of the other side it depends on: the write of the item a read takes
// (readable from the delta after it, and not before its ready time), or the
// read that freed the slot a write fills (writable from the delta after it).
// A decoupled stage adopts that time as its own; a stage in the kernel's
// time waits until it. A side sleeps in the kernel only while that other
// operation has not happened at all. The statistics integrate the logged
// operations in time order once neither side can still log an earlier one,
// delta by delta as the kernel-timed FIFO's update() does, so every figure
// equals the one the kernel-timed FIFO gives.
//
// This holds what does not depend on the packet type: per slot, when its
// item may be read and when it may be written again; the decoupled sides'
// clocks; the logs of operations not yet integrated; the sleeping sides.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <systemc>
#include <vector>

#include "hw/fifo_statistics.h"
#include "hw/superdense_time.h"

namespace gpusim {

// Operations logged in order of their stamps, not yet integrated into the
// statistics. Neither side's log outgrows depth + 1 entries between two
// settlements (an operation is settled once both sides have passed it), but
// the ring grows if it must.
class StampLog {
 public:
  void reset(size_t depth);
  size_t size() const { return m_tail - m_head; }
  // The oldest entry if it precedes `limit`, else null.
  const SuperdenseTime* oldest_before(const SuperdenseTime& limit) const {
    if (m_head == m_tail) return nullptr;
    const SuperdenseTime& s = m_ring[m_head & m_mask];
    return s < limit ? &s : nullptr;
  }
  // Removes the oldest entries while they are at `at`; how many.
  size_t take(const SuperdenseTime& at) {
    size_t n = 0;
    for (; m_head != m_tail && m_ring[m_head & m_mask] == at; ++m_head) ++n;
    return n;
  }
  // On every stamped read and write: kept inline (GCC otherwise calls it,
  // +1.6% instructions on the 1M-triangle grid).
  [[gnu::always_inline]] void push(const SuperdenseTime& s) {
    if (m_tail - m_head == m_ring.size()) grow();
    m_ring[m_tail++ & m_mask] = s;
  }

 private:
  void grow();
  std::vector<SuperdenseTime> m_ring;
  uint64_t m_mask = 0;  // ring size - 1 (a power of two)
  uint64_t m_head = 0, m_tail = 0;
};

struct FifoStampedSync {
  // Before any item moves: `depth` slots; a clock is the local time of a
  // decoupled stage on that side (PipelineStage::local_clock()), which no
  // later operation of it precedes; null: a side in the kernel's time.
  void start(size_t depth, const SuperdenseTime* writer, const SuperdenseTime* reader);
  // Between frames (FifoChannel::reset): as start() left it, the same clocks.
  void restart(size_t depth);

  // No operation earlier than this can still be logged: a decoupled side's
  // later operations are at or after its clock, the kernel's at or after
  // `kernel`.
  SuperdenseTime horizon(const SuperdenseTime& kernel) const {
    const SuperdenseTime& w = writer_clock ? *writer_clock : kernel;
    const SuperdenseTime& r = reader_clock ? *reader_clock : kernel;
    return r < w ? r : w;
  }

  // Wakes the other side sleeping on `event`: a decoupled stage at once, in
  // this evaluation phase (it computes its own time, which is then at or
  // after the kernel's), a process in the kernel's time at the time of the
  // operation it waits to make, `at`; `now` is the kernel's time.
  static void wake(sc_core::sc_event& event, const SuperdenseTime* sleeper_clock,
                   const SuperdenseTime& at, uint64_t now) {
    if (sleeper_clock != nullptr) {
      event.notify();  // runs in this evaluation phase: no delta cycle
    } else if (at.t <= now) {
      event.notify(sc_core::SC_ZERO_TIME);
    } else {
      event.notify(sc_core::sc_time::from_value(at.t - now));
    }
  }

  // A decoupled side does not wait its stall in the kernel, but the
  // kernel-timed model does, and the kernel's last time is the "now" every
  // statistic is observed up to: a stall drawn before a read that never
  // comes (the ROP's after its end of frame) ends the simulation. An event
  // at the latest stall end keeps that time.
  void keep_stall_end(uint64_t t, uint64_t now) {
    if (t <= stall_end) return;
    stall_end = t;
    stall_end_event.cancel();  // an earlier pending time would keep this one out
    stall_end_event.notify(sc_core::sc_time::from_value(t - now));
  }

  // Settling costs a comparison per logged operation, so it waits until a
  // log holds more than the FIFO's depth.
  bool logs_long(size_t depth) const { return write_log.size() > depth || read_log.size() > depth; }

  // Integrates the logged operations before `limit` into `stats`, a delta
  // at a time, as update() does for the kernel-timed FIFO; `committed` is
  // the items held. A logged operation earlier than the statistics' last
  // change is a model error, reported for FIFO `fifo`.
  void settle(const SuperdenseTime& limit, FifoStatistics& stats, size_t& committed,
              const char* fifo);

  std::vector<SuperdenseTime> readable_from;
  std::vector<SuperdenseTime> free_from;
  const SuperdenseTime* writer_clock = nullptr;
  const SuperdenseTime* reader_clock = nullptr;
  StampLog write_log, read_log;
  sc_core::sc_event writer_wake, reader_wake;
  bool writer_asleep = false;
  bool reader_asleep = false;
  uint64_t stall_end = 0;  // the latest stall end of a decoupled side
  sc_core::sc_event stall_end_event;
};

}  // namespace gpusim
