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
// Statistics integrate in simulated time and are computed up to "now" on
// demand, so they can be read at any point, including after sc_start()
// returned with a stage still blocked. Blocked time is counted only in the
// blocking read() and write(); a stage that polls with nb_read()/nb_write()
// accounts for its own waiting. Mean occupancy is over [0, now].
//
// Tracing: set_probe() attaches a FifoProbe (hw/fifo_probe.h) that sees every
// read, write, blocked interval and occupancy change; without one, each hook
// is a single branch on a null pointer.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <systemc>
#include <utility>
#include <vector>

#include "hw/fifo_probe.h"
#include "hw/stats.h"

namespace gpusim {

// The reader's side, for stages that reach their input through an sc_port.
template <typename T>
class FifoInIf : public virtual sc_core::sc_interface {
 public:
  virtual T read() = 0;
  // The same, into `item`: its previous value goes to the freed slot, for the
  // next writer to reuse its buffers (a reader that reads into one packet
  // object every time allocates nothing).
  virtual void read(T& item) = 0;
  virtual bool nb_read(T& item) = 0;
  virtual size_t size() const = 0;
  virtual const T& front() const = 0;
  virtual const sc_core::sc_event& data_written_event() const = 0;
};

// The writer's side.
template <typename T>
class FifoOutIf : public virtual sc_core::sc_interface {
 public:
  virtual void write(const T& item) = 0;
  // Write, but the reader sees the item only from `ready_at` on: a stage's
  // pipeline latency. The item holds its slot from when it enters; if the
  // write had to wait for a slot, `ready_at` moves later by that wait.
  virtual void write(const T& item, const sc_core::sc_time& ready_at) = 0;
  // Moving writes: `item` is left holding the slot's previous contents (a
  // stale packet whose buffers a writer may clear and refill).
  virtual void write(T&& item) = 0;
  virtual void write(T&& item, const sc_core::sc_time& ready_at) = 0;
  virtual bool nb_write(const T& item) = 0;
  virtual size_t num_free() const = 0;
  virtual size_t depth() const = 0;
  virtual const sc_core::sc_event& data_read_event() const = 0;
};

template <typename T>
using FifoInPort = sc_core::sc_port<FifoInIf<T>>;
template <typename T>
using FifoOutPort = sc_core::sc_port<FifoOutIf<T>>;

// Times are sc_time; *_cycles conversions use the cycle given to stats_json().
struct FifoStats {
  uint64_t written = 0;
  uint64_t read = 0;
  size_t max_occupancy = 0;
  double mean_occupancy = 0.0;      // time-weighted over [0, now]
  sc_core::sc_time full;            // time holding depth() items
  sc_core::sc_time empty;           // time holding no item
  sc_core::sc_time writer_blocked;  // summed over writers blocked in write(): stall
  sc_core::sc_time reader_blocked;  // summed over readers blocked in read(): starve
  uint64_t injected_stalls = 0;     // reads and writes delayed by inject_random_stalls
  sc_core::sc_time injected_stall;  // total delay they added
  sc_core::sc_time observed;        // now: the window of every time above
};

namespace fifo_detail {

// Time integral of a level that changes at discrete instants: occupancy, or
// the number of processes currently blocked. Values are in units of the
// SystemC time resolution; 64 bits hold depth 65536 for 2^48 ps (~280 s).
struct Integral {
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

// splitmix64: tiny, fast and fully specified, so a seed gives the same stall
// pattern with every compiler and standard library.
struct SplitMix64 {
  uint64_t state = 0;
  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
};

}  // namespace fifo_detail

// A FIFO seen through its type-independent parts: what the netlist
// (stages/topology.h), the statistics, the watchdog and stall injection need,
// whatever packet the FIFO carries.
class FifoChannel : public sc_core::sc_prim_channel {
 public:
  explicit FifoChannel(const char* name) : sc_core::sc_prim_channel(name) {}
  virtual size_t capacity() const = 0;
  // Items held, readable or not.
  virtual size_t occupancy() const = 0;
  virtual FifoStats stats() const = 0;
  // Times in cycles of `cycle` (fractional if not whole cycles).
  virtual nlohmann::json stats_json(sc_core::sc_time cycle) const = 0;
  // The stats_json() fields: {name: {"unit", "description"}}.
  static nlohmann::json descriptions();
  virtual void inject_random_stalls(uint64_t seed, double probability, unsigned max_cycles,
                                    sc_core::sc_time cycle) = 0;
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

 protected:
  bool m_withheld = false;
  int m_watchers = 0;  // observers now waiting on written_event() / read_event()
};

inline nlohmann::json FifoChannel::descriptions() {
  const auto& d = stat_description;
  return {
      {"depth", d("items", "slots")},
      {"written", d("items", "items written")},
      {"read", d("items", "items read")},
      {"max_occupancy", d("items", "most items held at once")},
      {"mean_occupancy", d("items", "items held, averaged over the frame")},
      {"full_cycles", d("cycles", "cycles holding depth items")},
      {"empty_cycles", d("cycles", "cycles holding no item")},
      {"writer_blocked_cycles", d("cycles", "cycles its writer waited for a free slot (stall)")},
      {"reader_blocked_cycles",
       d("cycles", "cycles its reader waited for a readable item (starve)")},
      {"injected_stalls", d("events", "reads and writes delayed by random stall injection")},
      {"injected_stall_cycles", d("cycles", "delay added by random stall injection")},
      {"observed_cycles", d("cycles", "the window every figure above covers")},
  };
}

template <typename T>
class Fifo : public FifoChannel, public FifoInIf<T>, public FifoOutIf<T> {
 public:
  // T must be default-constructible, copy-assignable and swappable: the ring
  // holds `depth` values from construction on, so a write is one assignment
  // (or one swap).
  Fifo(const char* name, size_t depth)
      : FifoChannel(name),
        m_buf(depth),
        m_ready(depth),
        m_data_written_event((std::string(name) + "_written").c_str()),
        m_data_read_event((std::string(name) + "_read").c_str()),
        m_item_ready_event((std::string(name) + "_ready").c_str()) {
    if (depth == 0) throw std::invalid_argument(std::string("Fifo ") + name + ": depth 0");
  }

  const char* kind() const override { return "gpusim::Fifo"; }

  // Blocking; SC_THREAD only. Waits while the FIFO is full.
  void write(const T& item) override { write(item, sc_core::SC_ZERO_TIME); }
  void write(T&& item) override { write(std::move(item), sc_core::SC_ZERO_TIME); }

  void write(const T& item, const sc_core::sc_time& ready_at) override {
    const sc_core::sc_time ready = wait_for_slot(ready_at);
    m_buf[m_tail] = item;
    push(ready);
  }

  void write(T&& item, const sc_core::sc_time& ready_at) override {
    const sc_core::sc_time ready = wait_for_slot(ready_at);
    using std::swap;
    swap(m_buf[m_tail], item);
    push(ready);
  }

  // Blocking; SC_THREAD only. Waits while no item is readable.
  T read() override {
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

  bool nb_write(const T& item) override {
    if (num_free() == 0) return false;
    m_buf[m_tail] = item;
    push(sc_core::SC_ZERO_TIME);
    return true;
  }

  bool nb_read(T& item) override {
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
    if constexpr (kTraceHooks) m_probe = probe;
  }

  // Items the reader can take now (written before this delta, not yet read).
  size_t size() const override { return m_withheld ? 0 : m_committed - m_num_read; }
  // Slots a writer can fill now (slots freed in this delta count from the next).
  size_t num_free() const override { return m_buf.size() - m_committed - m_num_written; }
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

  // From now on, every blocking read() and write() first waits, with
  // `probability`, a uniformly drawn 1..max_cycles cycles. Readers and writers
  // draw from separate streams derived from `seed`, so a run is reproducible.
  // Used to prove that results do not depend on timing (as MatchLib does).
  void inject_random_stalls(uint64_t seed, double probability, unsigned max_cycles,
                            sc_core::sc_time cycle) override {
    if (!(probability >= 0.0 && probability <= 1.0) || max_cycles == 0 ||
        cycle == sc_core::SC_ZERO_TIME) {
      throw std::invalid_argument(std::string("Fifo ") + name() +
                                  ": inject_random_stalls needs probability in [0, 1], "
                                  "max_cycles >= 1 and a non-zero cycle");
    }
    m_stall_probability = probability;
    m_stall_max_cycles = max_cycles;
    m_stall_cycle = cycle;
    m_write_rng.state = seed;
    m_read_rng.state = seed ^ 0xD1B54A32D192ED03ull;
  }

  size_t capacity() const override { return m_buf.size(); }
  // As depth() - num_free(): a slot read in this delta is free only from the next.
  size_t occupancy() const override { return m_committed + m_num_written; }
  const sc_core::sc_event& written_event() const override { return m_data_written_event; }
  const sc_core::sc_event& read_event() const override { return m_data_read_event; }

  FifoStats stats() const override {
    const uint64_t now = this->now();
    const uint64_t dt = now - m_occupancy.since;
    FifoStats s;
    s.written = m_total_written;
    s.read = m_total_read;
    s.max_occupancy = m_max_occupancy;
    s.mean_occupancy =
        now == 0 ? 0.0 : static_cast<double>(m_occupancy.area_at(now)) / static_cast<double>(now);
    s.full = sc_core::sc_time::from_value(m_full + (m_committed == depth() ? dt : 0));
    s.empty = sc_core::sc_time::from_value(m_empty + (m_committed == 0 ? dt : 0));
    s.writer_blocked = sc_core::sc_time::from_value(m_blocked_writers.area_at(now));
    s.reader_blocked = sc_core::sc_time::from_value(m_blocked_readers.area_at(now));
    s.injected_stalls = m_injected_stalls;
    s.injected_stall = m_injected_stall;
    s.observed = sc_core::sc_time_stamp();
    return s;
  }

  nlohmann::json stats_json(sc_core::sc_time cycle) const override {
    const FifoStats s = stats();
    const auto cycles = [&](sc_core::sc_time t) { return t / cycle; };
    return {
        {"depth", depth()},
        {"written", s.written},
        {"read", s.read},
        {"max_occupancy", s.max_occupancy},
        {"mean_occupancy", s.mean_occupancy},
        {"full_cycles", cycles(s.full)},
        {"empty_cycles", cycles(s.empty)},
        {"writer_blocked_cycles", cycles(s.writer_blocked)},
        {"reader_blocked_cycles", cycles(s.reader_blocked)},
        {"injected_stalls", s.injected_stalls},
        {"injected_stall_cycles", cycles(s.injected_stall)},
        {"observed_cycles", cycles(s.observed)},
    };
  }

 private:
  // The current time as an sc_time value. The simulation context is the
  // channel's own (the same as sc_time_stamp()'s while it runs), read
  // inline rather than through the library call.
  const sc_core::sc_time& time_stamp() const { return simcontext()->time_stamp(); }
  uint64_t now() const { return time_stamp().value(); }

  // The blocking part of write(): waits until a slot is free and returns the
  // item's ready time (`ready_at`, later by the wait).
  sc_core::sc_time wait_for_slot(const sc_core::sc_time& ready_at) {
    const sc_core::sc_time called = time_stamp();
    maybe_stall(m_write_rng);
    if (num_free() == 0) {
      begin_blocked(m_blocked_writers, true);
      do {
        sc_core::wait(m_data_read_event);
      } while (num_free() == 0);
      end_blocked(m_blocked_writers, true);
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
    maybe_stall(m_read_rng);
    if (size() == 0) {
      begin_blocked(m_blocked_readers, false);
      const bool traced = kTraceHooks && m_probe != nullptr;
      m_reader_asleep = !traced;
      do {
        sc_core::wait(traced ? m_data_written_event : m_item_ready_event);
      } while (size() == 0);
      m_reader_asleep = false;
      end_blocked(m_blocked_readers, false);
    }
    // An item still in the writer's pipeline: waiting for it is starving too.
    const sc_core::sc_time& ready = m_ready[m_head];
    const sc_core::sc_time& now = time_stamp();
    if (ready > now) {
      begin_blocked(m_blocked_readers, false);
      sc_core::wait(ready - now);
      end_blocked(m_blocked_readers, false);
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
    const uint64_t dt = now - m_occupancy.since;
    if (m_committed == m_buf.size()) m_full += dt;
    if (m_committed == 0) m_empty += dt;
    m_committed = m_committed - m_num_read + m_num_written;
    m_occupancy.set(m_committed, now);
    m_max_occupancy = std::max(m_max_occupancy, m_committed);
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
    if (m_num_written && ((m_blocked_readers.level > 0 && !m_reader_asleep) || observed))
      m_data_written_event.notify(sc_core::SC_ZERO_TIME);
    if (m_num_read && (m_blocked_writers.level > 0 || observed))
      m_data_read_event.notify(sc_core::SC_ZERO_TIME);
    m_num_written = 0;
    m_num_read = 0;
  }

  void begin_blocked(fifo_detail::Integral& blocked, bool writer_side) {
    blocked.set(blocked.level + 1, now());
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->blocked(writer_side, true, now());
    }
  }
  void end_blocked(fifo_detail::Integral& blocked, bool writer_side) {
    blocked.set(blocked.level - 1, now());
    if constexpr (kTraceHooks) {
      if (m_probe) m_probe->blocked(writer_side, false, now());
    }
  }

  void maybe_stall(fifo_detail::SplitMix64& rng) {
    if (m_stall_probability <= 0.0 || rng.uniform() >= m_stall_probability) return;
    const uint64_t n = 1 + rng.next() % m_stall_max_cycles;
    const sc_core::sc_time t = sc_core::sc_time::from_value(m_stall_cycle.value() * n);
    ++m_injected_stalls;
    m_injected_stall += t;
    sc_core::wait(t);
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
  size_t m_max_occupancy = 0;
  fifo_detail::Integral m_occupancy;
  uint64_t m_full = 0;  // sc_time values, closed at each update()
  uint64_t m_empty = 0;
  fifo_detail::Integral m_blocked_writers;
  fifo_detail::Integral m_blocked_readers;

  double m_stall_probability = 0.0;
  unsigned m_stall_max_cycles = 0;
  sc_core::sc_time m_stall_cycle;
  fifo_detail::SplitMix64 m_write_rng;
  fifo_detail::SplitMix64 m_read_rng;
  uint64_t m_injected_stalls = 0;
  sc_core::sc_time m_injected_stall;
  FifoProbe<T>* m_probe = nullptr;  // trace hooks; unused without them
};

}  // namespace gpusim
