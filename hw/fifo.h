// A bounded FIFO channel joining two pipeline stages, after Accellera's
// simple_perf example: it records its own occupancy and how long its writers
// were stalled and its readers starved, so every stage boundary reports its
// bottleneck without extra code in the stages.
//
// Semantics are sc_fifo's: an item written in one delta cycle becomes
// readable in the next, and a slot freed by a read becomes writable in the
// next, so the result never depends on the order in which the kernel runs the
// processes of one delta. Events are delta notifications from update().
//
// Cost: a ring buffer allocated once, one request_update() per delta with
// activity, no clock and no per-cycle work. A stage with nothing to do sleeps
// in read() (or on data_written_event()) and costs the kernel nothing.
// Packets with heap storage (vectors) are recycled rather than reallocated:
// read(T&) and write(T&&) exchange the packet with the slot (std::swap), so
// the slot keeps the reader's previous buffers and hands them to the next
// writer, like a register that keeps its storage. The events are notified
// only when someone can be waiting on them (see update()): a notification
// without a waiter still costs the kernel a delta-event trigger per delta.
// A reader blocked on an empty FIFO is woken once, when the item it waits
// for is ready (a timed notification at its ready time), rather than in the
// delta after the write and again by a timed wait for the producer's
// latency: one thread switch per item instead of two, at the same instant
// and in the same delta (see wait_for_item()).
//
// Its parts, each in its own header: the ports' interfaces
// (hw/fifo_ports.h); its statistics (hw/fifo_statistics.h: occupancy,
// stall and starve integrals, reported as the channel's stat group); the
// stall policy installed from outside (hw/random_stalls.h); the stamped
// synchronisation of a temporally decoupled side (hw/fifo_stamped_sync.h).
// Blocked time is counted only in the blocking read() and write(); a stage
// that polls with nb_read()/nb_write() accounts for its own waiting.
//
// Tracing: set_probe() attaches a FifoProbe (hw/fifo_probe.h) that sees every
// read, write, blocked interval and occupancy change; without one, each hook
// is a single branch on a null pointer.
//
// Stamped mode (temporal decoupling, hw/fifo_stamped_sync.h): a FIFO
// joining a stage that runs ahead of the kernel's time is switched, before
// the simulation starts, to take reads and writes at superdense times, with
// the same results and statistics as the kernel-timed semantics above.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <systemc>
#include <type_traits>
#include <utility>
#include <vector>

#include "hw/fifo_ports.h"
#include "hw/fifo_probe.h"
#include "hw/fifo_stamped_sync.h"
#include "hw/fifo_statistics.h"
#include "hw/random_stalls.h"
#include "hw/stats.h"
#include "hw/superdense_time.h"

namespace gpusim {

// A FIFO seen through its type-independent parts: what the netlist
// (stages/topology.h), the statistics, the watchdog and stall injection need,
// whatever packet the FIFO carries.
class FifoChannel : public sc_core::sc_prim_channel {
 public:
  FifoChannel(const char* name, size_t depth);
  virtual size_t capacity() const = 0;
  // Items held, readable or not.
  virtual size_t occupancy() const = 0;
  virtual FifoStats stats() const = 0;
  // Its figures as a stat group named after it (its depth, items, occupancy,
  // full and empty cycles, stall and starve cycles, injected stalls), times
  // in cycles of set_cycle()'s period (null until it is set).
  const StatGroup& stat_group() const { return *m_stats; }
  void set_cycle(sc_core::sc_time cycle) { m_cycle = cycle; }

  // The stall policy (hw/random_stalls.h), from now on; a reset starts it
  // again from its first draw.
  void set_stalls(const RandomStalls& stalls) { m_stalls = m_installed_stalls = stalls; }

  // Between frames (Gpu::reset), from the process that resets the GPU at
  // the new frame's first instant `start` (an sc_time value): as
  // elaborated, empty, its statistics observed from `start`, its stall
  // policy at its first draw. Only the processes the reset restarts may be
  // blocked on it.
  virtual void reset(uint64_t start) = 0;
  // The events for an observer outside the pipeline (the watchdog, the
  // progress display), which waits on them only while nothing moves: they are
  // notified only between its watch(true) and watch(false) calls.
  virtual const sc_core::sc_event& written_event() const = 0;
  virtual const sc_core::sc_event& read_event() const = 0;
  void watch(bool on) { m_watchers += on ? 1 : -1; }

  // Test-only fault (docs/robustness.md, "Watchdog"): from now on the reader
  // never sees an item, as if its port were bound to a FIFO nobody writes.
  void withhold_from_reader() { m_withheld = true; }
  bool withheld() const { return m_withheld; }

  // Stamped mode (above), before the simulation starts. A clock is the local
  // time of a decoupled stage on that side (PipelineStage::local_clock()),
  // which no later operation of it precedes; null: a side in the kernel's
  // time.
  virtual void set_stamped(const SuperdenseTime* writer_clock,
                           const SuperdenseTime* reader_clock) = 0;
  bool stamped() const { return m_stamped; }

 protected:
  bool m_withheld = false;
  bool m_stamped = false;
  int m_watchers = 0;  // observers now waiting on written_event() / read_event()
  FifoStatistics m_statistics;
  RandomStalls m_stalls;
  RandomStalls m_installed_stalls;  // as set_stalls() gave it

  // The type-independent part of reset().
  void restart(uint64_t start) {
    m_statistics.restart(start);
    m_stalls = m_installed_stalls;
  }

  // The stall policy's delay of the next operation on `side` (an sc_time
  // value, 0: none), counted in the statistics; one test when no policy is
  // active.
  uint64_t next_stall(RandomStalls::Side side) {
    if (!m_stalls.active()) return 0;
    const uint64_t t = m_stalls.draw(side);
    if (t != 0) m_statistics.stalled(sc_core::sc_time::from_value(t));
    return t;
  }

 private:
  // Read at the end of a run only: on the heap, out of the cache lines the
  // per-item path touches.
  std::unique_ptr<StatGroup> m_stats;
  sc_core::sc_time m_cycle;  // what the stat group's cycles count
};

template <typename T>
class Fifo : public FifoChannel, public FifoInIf<T>, public FifoOutIf<T> {
 public:
  // T must be default-constructible, copy-assignable and swappable: the ring
  // holds `depth` values from construction on, so a write is one assignment
  // (or one swap).
  Fifo(const char* name, size_t depth)
      : FifoChannel(name, depth),
        m_buf(depth),
        m_ready(depth),
        m_data_written_event((std::string(name) + "_written").c_str()),
        m_data_read_event((std::string(name) + "_read").c_str()),
        m_item_ready_event((std::string(name) + "_ready").c_str()) {}

  const char* kind() const override { return "gpusim::Fifo"; }

  // Blocking; SC_THREAD only. Waits while the FIFO is full.
  void write(const T& item) override { write(item, sc_core::SC_ZERO_TIME); }
  void write(T&& item) override { write(std::move(item), sc_core::SC_ZERO_TIME); }

  void write(const T& item, sc_core::sc_time ready_at) override {
    if (m_stamped) {
      stamped_write(item, ready_at.value(), kernel_stamp(), true);
      return;
    }
    const sc_core::sc_time ready = wait_for_slot(ready_at);
    m_buf[m_tail] = item;
    push(ready);
  }

  void write(T&& item, sc_core::sc_time ready_at) override {
    if (m_stamped) {
      stamped_write(std::move(item), ready_at.value(), kernel_stamp(), true);
      return;
    }
    const sc_core::sc_time ready = wait_for_slot(ready_at);
    using std::swap;
    swap(m_buf[m_tail], item);
    push(ready);
  }

  SuperdenseTime write_at(const T& item, uint64_t ready_at, const SuperdenseTime& call) override {
    require_stamped();
    return stamped_write(item, ready_at, call, false);
  }

  SuperdenseTime write_at(T&& item, uint64_t ready_at, const SuperdenseTime& call) override {
    require_stamped();
    return stamped_write(std::move(item), ready_at, call, false);
  }

  // Blocking; SC_THREAD only. Waits while no item is readable.
  T read() override {
    if (m_stamped) {
      SuperdenseTime at;
      return stamped_read(kernel_stamp(), true, at);
    }
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->read_called(now());
    }
    wait_for_item();
    T item = std::move(m_buf[m_head]);
    pop();
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->taken(item, now());
    }
    return item;
  }

  void read(T& item) override {
    if (m_stamped) {
      stamped_read(item, kernel_stamp(), true);
      return;
    }
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->read_called(now());
    }
    wait_for_item();
    using std::swap;
    swap(m_buf[m_head], item);
    pop();
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->taken(item, now());
    }
  }

  SuperdenseTime read_at(T& item, const SuperdenseTime& call) override {
    require_stamped();
    return stamped_read(item, call, false);
  }

  T read_at(const SuperdenseTime& call, SuperdenseTime& at) override {
    require_stamped();
    return stamped_read(call, false, at);
  }

  bool nb_write(const T& item) override {
    if (m_stamped) throw std::logic_error(std::string(name()) + ": nb_write in stamped mode");
    if (num_free() == 0) return false;
    m_buf[m_tail] = item;
    push(sc_core::SC_ZERO_TIME);
    return true;
  }

  bool nb_read(T& item) override {
    if (m_stamped) throw std::logic_error(std::string(name()) + ": nb_read in stamped mode");
    if (size() == 0 || m_ready[m_head] > time_stamp()) return false;
    using std::swap;
    swap(m_buf[m_head], item);
    pop();
    if constexpr (kTraceHooks) {
      if (m_probe) {
        m_probe->read_called(now());
        m_probe->taken(item, now());
      }
    }
    return true;
  }

  // Trace hooks (hw/fifo_probe.h); nullptr detaches. The probe must outlive
  // the simulation. A no-op in a build without trace hooks.
  void set_probe(FifoProbe<T>* probe) {
    if (m_stamped && probe != nullptr)
      throw std::logic_error(std::string(name()) + ": a stamped FIFO takes no trace probe");
    if constexpr (kTraceHooks) m_probe = probe;
  }

  void set_stamped(const SuperdenseTime* writer_clock,
                   const SuperdenseTime* reader_clock) override {
    if (m_probe != nullptr)
      throw std::logic_error(std::string(name()) + ": a traced FIFO cannot be stamped");
    if (m_total_written > 0 || m_total_read > 0)
      throw std::logic_error(std::string(name()) + ": stamped mode is set before any item moves");
    m_stamped = true;
    m_sync.start(m_buf.size(), writer_clock, reader_clock);
  }

  void reset(uint64_t start) override {
    std::fill(m_buf.begin(), m_buf.end(), T{});
    std::fill(m_ready.begin(), m_ready.end(), sc_core::SC_ZERO_TIME);
    m_head = m_tail = m_committed = m_num_read = m_num_written = 0;
    m_total_written = m_total_read = 0;
    m_reader_asleep = false;
    m_item_ready_event.cancel();
    if (m_stamped) m_sync.restart(m_buf.size());
    restart(start);
  }

  // Items the reader can take now (written before this delta, not yet read).
  size_t size() const override {
    if (m_withheld) return 0;
    if (!m_stamped) return m_committed - m_num_read;
    const SuperdenseTime k = kernel_stamp();
    size_t n = 0;
    for (uint64_t i = m_total_read; i < m_total_written; ++i, ++n) {
      if (k < m_sync.readable_from[i % m_buf.size()]) break;
    }
    return n;
  }
  // Slots a writer can fill now (slots freed in this delta count from the next).
  size_t num_free() const override {
    if (!m_stamped) return m_buf.size() - m_committed - m_num_written;
    const SuperdenseTime k = kernel_stamp();
    size_t n = 0;
    for (uint64_t i = m_total_written; i < m_total_read + m_buf.size(); ++i, ++n) {
      if (k < m_sync.free_from[i % m_buf.size()]) break;
    }
    return n;
  }
  size_t depth() const override { return m_buf.size(); }
  // The oldest readable item; requires size() > 0.
  const T& front() const override {
    assert(size() > 0);
    return m_buf[m_head];
  }

  // Notified (delta) after a delta cycle in which items were written / read.
  // Whoever asks for an event may wait on it, so from then on it is notified
  // after every delta with activity, waiter or not (see update()).
  const sc_core::sc_event& data_written_event() const override {
    m_events_handed_out = true;
    return m_data_written_event;
  }
  const sc_core::sc_event& data_read_event() const override {
    m_events_handed_out = true;
    return m_data_read_event;
  }

  size_t capacity() const override { return m_buf.size(); }
  // As depth() - num_free(): a slot read in this delta is free only from the next.
  size_t occupancy() const override { return m_committed + m_num_written; }
  const sc_core::sc_event& written_event() const override { return m_data_written_event; }
  const sc_core::sc_event& read_event() const override { return m_data_read_event; }

  FifoStats stats() const override {
    // Stamped: the operations before the horizon, or all of them up to now
    // once the simulation has stopped; mid-run, decoupled sides may have
    // logged operations beyond now (their figures are then approximate).
    if (m_stamped) const_cast<Fifo*>(this)->settle_for_stats();
    return m_statistics.snapshot(m_total_written, m_total_read, time_stamp());
  }

 private:
  // The current time as an sc_time value. The simulation context is the
  // channel's own (the same as sc_time_stamp()'s while it runs), read
  // inline rather than through the library call.
  const sc_core::sc_time& time_stamp() const { return simcontext()->time_stamp(); }
  uint64_t now() const { return time_stamp().value(); }
  SuperdenseTime kernel_stamp() const { return gpusim::kernel_stamp(*simcontext()); }

  // ---- Stamped mode (see the top of the file) ----

  void require_stamped() const {
    if (!m_stamped) {
      throw std::logic_error(std::string(name()) +
                             ": read_at/write_at need a stamped FIFO (set_stamped)");
    }
  }

  // Random stall injection at a stamp: the same draws as maybe_stall(), the
  // delay added to the operation's time (a process in the kernel's time
  // waits it, as maybe_stall() does).
  SuperdenseTime stall_at(RandomStalls::Side side, const SuperdenseTime& call, bool kernel) {
    const uint64_t t = next_stall(side);
    if (t == 0) return call;
    const SuperdenseTime stalled{call.t + t, 0};
    if (kernel) {
      wait_until(stalled);
    } else {
      m_sync.keep_stall_end(stalled.t, now());
    }
    return stalled;
  }

  // A process in the kernel's time: until the kernel reaches `s`. Reaching
  // it late would move the process's later actions: the model error means a
  // decoupled stage logged an operation after the kernel had passed its time.
  void wait_until(const SuperdenseTime& s) {
    if (!gpusim::wait_until(s)) late("an operation of a process in the kernel's time");
  }

  [[noreturn]] void late(const char* what) const { report_behind_kernel(name(), what); }

  // The time at or after `call` at which one side's next operation can be
  // made: sleeps while `waits` (the other side has not made the operation it
  // depends on), then takes `from`, that operation's delta after (a slot's
  // entry, read once the wait is over). A process in the kernel's time
  // (`kernel`) waits until then.
  SuperdenseTime stamped_wait(TimeIntegral& blocked, bool& asleep, sc_core::sc_event& wake,
                              bool (Fifo::*waits)() const, const SuperdenseTime& from,
                              const SuperdenseTime& call, bool kernel) {
    blocked.set(1, call.t);
    while ((this->*waits)()) {
      asleep = true;
      sc_core::wait(wake);
      asleep = false;
    }
    const SuperdenseTime s = later(call, from);
    if (kernel) wait_until(s);
    blocked.set(0, s.t);
    return s;
  }
  bool no_slot_read() const { return m_total_written - m_total_read == m_buf.size(); }
  bool no_item_written() const { return m_total_written == m_total_read || m_withheld; }

  // The next write: after the read that emptied its slot.
  SuperdenseTime stamped_write_wait(const SuperdenseTime& call, bool kernel) {
    return stamped_wait(m_statistics.blocked_writers(), m_sync.writer_asleep, m_sync.writer_wake,
                        &Fifo::no_slot_read, m_sync.free_from[m_tail], call, kernel);
  }

  // The next read: after the oldest item's write and its ready time (the
  // reader sleeps too while withheld).
  SuperdenseTime stamped_read_wait(const SuperdenseTime& call, bool kernel) {
    return stamped_wait(m_statistics.blocked_readers(), m_sync.reader_asleep, m_sync.reader_wake,
                        &Fifo::no_item_written, m_sync.readable_from[m_head], call, kernel);
  }

  // A stamped write made at `call` (a side in the kernel's time waits until
  // the time it is given): a moved item is swapped with the slot's old
  // contents, for the reader to reuse.
  template <typename P>
  SuperdenseTime stamped_write(P&& item, uint64_t ready_at, const SuperdenseTime& call,
                               bool kernel) {
    const SuperdenseTime s =
        stamped_write_wait(stall_at(RandomStalls::Side::writer, call, kernel), kernel);
    if constexpr (std::is_rvalue_reference_v<P&&>) {
      using std::swap;
      swap(m_buf[m_tail], item);
    } else {
      m_buf[m_tail] = item;
    }
    stamped_push(s, ready_at + (s.t - call.t));
    return s;
  }

  // A stamped read made at `call`: into `item` (swapped with the slot), or
  // returned with its time in `at`.
  SuperdenseTime stamped_read(T& item, const SuperdenseTime& call, bool kernel) {
    const SuperdenseTime s =
        stamped_read_wait(stall_at(RandomStalls::Side::reader, call, kernel), kernel);
    using std::swap;
    swap(m_buf[m_head], item);
    stamped_pop(s);
    return s;
  }
  T stamped_read(const SuperdenseTime& call, bool kernel, SuperdenseTime& at) {
    at = stamped_read_wait(stall_at(RandomStalls::Side::reader, call, kernel), kernel);
    T item = std::move(m_buf[m_head]);
    stamped_pop(at);
    return item;
  }

  // The item is in m_buf[m_tail], written at `s`, ready at `ready`.
  void stamped_push(const SuperdenseTime& s, uint64_t ready) {
    m_sync.readable_from[m_tail] = later(s.next_delta(), SuperdenseTime{ready, 0});
    m_tail = m_tail + 1 == m_buf.size() ? 0 : m_tail + 1;
    ++m_total_written;
    m_sync.write_log.push(s);
    if (m_sync.reader_asleep) {
      FifoStampedSync::wake(m_sync.reader_wake, m_sync.reader_clock, m_sync.readable_from[m_head],
                            now());
    }
    if (m_events_handed_out || m_watchers > 0) m_data_written_event.notify(sc_core::SC_ZERO_TIME);
    settle_if_long();
  }

  // The item has been taken from m_buf[m_head] at `s`.
  void stamped_pop(const SuperdenseTime& s) {
    m_sync.free_from[m_head] = s.next_delta();
    const size_t freed = m_head;
    m_head = m_head + 1 == m_buf.size() ? 0 : m_head + 1;
    ++m_total_read;
    m_sync.read_log.push(s);
    if (m_sync.writer_asleep) {
      FifoStampedSync::wake(m_sync.writer_wake, m_sync.writer_clock, m_sync.free_from[freed],
                            now());
    }
    if (m_events_handed_out || m_watchers > 0) m_data_read_event.notify(sc_core::SC_ZERO_TIME);
    settle_if_long();
  }

  void settle_if_long() {
    if (m_sync.logs_long(m_buf.size())) settle(m_sync.horizon(kernel_stamp()));
  }
  void settle(const SuperdenseTime& limit) {
    m_sync.settle(limit, m_statistics, m_committed, name());
  }

  void settle_for_stats() {
    if (sc_core::sc_get_status() == sc_core::SC_RUNNING) {
      settle(m_sync.horizon(kernel_stamp()));
    } else {
      settle(SuperdenseTime{now(), ~uint64_t{0}});
    }
  }

  // The blocking part of write(): waits until a slot is free and returns the
  // item's ready time (`ready_at`, later by the wait).
  sc_core::sc_time wait_for_slot(const sc_core::sc_time& ready_at) {
    const sc_core::sc_time called = time_stamp();
    maybe_stall(RandomStalls::Side::writer);
    if (num_free() == 0) {
      begin_blocked(m_statistics.blocked_writers(), true);
      do {
        sc_core::wait(m_data_read_event);
      } while (num_free() == 0);
      end_blocked(m_statistics.blocked_writers(), true);
    }
    // The latency runs from when the item enters the FIFO: a result waiting
    // for a free slot has not started down the output's register chain.
    return ready_at + (time_stamp() - called);
  }

  // The blocking part of read(): waits until the oldest item is readable.
  //
  // On an empty FIFO the reader sleeps on m_item_ready_event, which update()
  // notifies for the ready time of the first item written: the reader wakes
  // at that time, in its first delta, as it would from the timed wait below,
  // and its blocked time is the same single interval. With a trace probe
  // attached it wakes in the delta after the write and then waits for the
  // latency, so that the probe sees the item arrive (the two intervals
  // integrate to the same starve time).
  void wait_for_item() {
    maybe_stall(RandomStalls::Side::reader);
    if (size() == 0) {
      begin_blocked(m_statistics.blocked_readers(), false);
      const bool traced = kTraceHooks && m_probe != nullptr;
      m_reader_asleep = !traced;
      do {
        sc_core::wait(traced ? m_data_written_event : m_item_ready_event);
      } while (size() == 0);
      m_reader_asleep = false;
      end_blocked(m_statistics.blocked_readers(), false);
    }
    // An item still in the writer's pipeline: waiting for it is starving too.
    const sc_core::sc_time& ready = m_ready[m_head];
    const sc_core::sc_time& now = time_stamp();
    if (ready > now) {
      begin_blocked(m_statistics.blocked_readers(), false);
      sc_core::wait(ready - now);
      end_blocked(m_statistics.blocked_readers(), false);
    }
  }

  // The item is already in m_buf[m_tail]; `ready` is its ready time.
  void push(const sc_core::sc_time& ready) {
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->written(m_buf[m_tail], now());
    }
    m_ready[m_tail] = ready;
    m_tail = m_tail + 1 == m_buf.size() ? 0 : m_tail + 1;
    ++m_num_written;
    ++m_total_written;
    request_update();
  }

  // The item has already been taken from m_buf[m_head].
  void pop() {
    m_head = m_head + 1 == m_buf.size() ? 0 : m_head + 1;
    ++m_num_read;
    ++m_total_read;
    request_update();
  }

  // Commits this delta's reads and writes: the occupancy seen by the other
  // side, and the statistics, change only here.
  //
  // An event is notified only if someone can be waiting on it: a reader or
  // writer blocked in this FIFO (counted by the blocked-time integrals), or
  // anyone the event was handed out to. Skipping a notification nobody waits
  // on changes nothing in the schedule: no process was going to wake, and the
  // kernel triggers the other delta events in the same order.
  void update() override {
    const uint64_t now = this->now();
    m_committed = m_committed - m_num_read + m_num_written;
    m_statistics.held(m_committed, now);
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->occupancy(m_committed, now);
    }
    if (m_num_written && m_reader_asleep) {
      // The oldest item is the first one written since the FIFO was empty.
      const sc_core::sc_time& ready = m_ready[m_head];
      const sc_core::sc_time& now_t = time_stamp();
      m_item_ready_event.notify(ready > now_t ? ready - now_t : sc_core::SC_ZERO_TIME);
    }
    const bool observed = m_events_handed_out || m_watchers > 0;
    if (m_num_written &&
        ((m_statistics.blocked_readers().level > 0 && !m_reader_asleep) || observed))
      m_data_written_event.notify(sc_core::SC_ZERO_TIME);
    if (m_num_read && (m_statistics.blocked_writers().level > 0 || observed))
      m_data_read_event.notify(sc_core::SC_ZERO_TIME);
    m_num_written = 0;
    m_num_read = 0;
  }

  void begin_blocked(TimeIntegral& blocked, bool writer_side) {
    blocked.set(blocked.level + 1, now());
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->blocked(writer_side, true, now());
    }
  }
  void end_blocked(TimeIntegral& blocked, bool writer_side) {
    blocked.set(blocked.level - 1, now());
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->blocked(writer_side, false, now());
    }
  }

  void maybe_stall(RandomStalls::Side side) {
    const uint64_t t = next_stall(side);
    if (t != 0) sc_core::wait(sc_core::sc_time::from_value(t));
  }

  std::vector<T> m_buf;
  std::vector<sc_core::sc_time> m_ready;  // per slot: when the reader may take it
  size_t m_head = 0;                      // oldest item
  size_t m_tail = 0;                      // next free slot
  size_t m_committed = 0;                 // items held at the start of this delta
  size_t m_num_read = 0;                  // in this delta
  size_t m_num_written = 0;               // in this delta
  sc_core::sc_event m_data_written_event;
  sc_core::sc_event m_data_read_event;
  mutable bool m_events_handed_out = false;  // set by data_written/read_event()
  sc_core::sc_event m_item_ready_event;      // the reader's alone (wait_for_item)
  bool m_reader_asleep = false;              // on m_item_ready_event

  uint64_t m_total_written = 0;
  uint64_t m_total_read = 0;
  FifoProbe<T>* m_probe = nullptr;  // trace hooks; unused without them
  FifoStampedSync m_sync;           // stamped mode only
};

}  // namespace gpusim
