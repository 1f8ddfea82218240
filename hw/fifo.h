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
//
// Stamped mode (temporal decoupling, docs/architecture.md): a FIFO joining a
// stage that runs ahead of the kernel's time (PipelineStage::set_decoupled)
// is switched before the simulation starts to take reads and writes at
// superdense times (SuperdenseTime: a time and a delta cycle within it). Every
// operation is given the time at which the semantics above would perform
// it, computed from the one operation of the other side it depends on: the
// write of the item a read takes (readable from the delta after it, and not
// before its ready time), or the read that freed the slot a write fills
// (writable from the delta after it). A decoupled stage adopts that time as
// its own; a stage in the kernel's time waits until it. A side sleeps in the
// kernel only while that other operation has not happened at all. The
// statistics integrate the logged operations in time order once neither
// side can still log an earlier one, delta by delta as update() does, so
// every figure equals the one the kernel-timed FIFO gives.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <systemc>
#include <type_traits>
#include <utility>
#include <vector>

#include "hw/fifo_probe.h"
#include "hw/stats.h"
#include "hw/superdense_time.h"

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
  // Stamped mode only: the read a decoupled reader makes at its own time
  // `call` (which may be ahead of the kernel's); returns the read's time.
  virtual SuperdenseTime read_at(T& item, const SuperdenseTime& call) = 0;
  // The same, moving the item out of its slot (no swap: cheaper for packets
  // of fixed-size arrays); the read's time goes to `at`.
  virtual T read_at(const SuperdenseTime& call, SuperdenseTime& at) = 0;
};

// The writer's side.
template <typename T>
class FifoOutIf : public virtual sc_core::sc_interface {
 public:
  virtual void write(const T& item) = 0;
  // Write, but the reader sees the item only from `ready_at` on: a stage's
  // pipeline latency. The item holds its slot from when it enters; if the
  // write had to wait for a slot, `ready_at` moves later by that wait.
  // By value: a caller's sc_time_stamp() is a reference to the kernel's
  // time, which the wait would move too (counting the wait twice).
  virtual void write(const T& item, sc_core::sc_time ready_at) = 0;
  // Moving writes: `item` is left holding the slot's previous contents (a
  // stale packet whose buffers a writer may clear and refill).
  virtual void write(T&& item) = 0;
  virtual void write(T&& item, sc_core::sc_time ready_at) = 0;
  virtual bool nb_write(const T& item) = 0;
  virtual size_t num_free() const = 0;
  virtual size_t depth() const = 0;
  virtual const sc_core::sc_event& data_read_event() const = 0;
  // Stamped mode only: the write a decoupled writer makes at its own time
  // `call`; returns the write's time. `ready_at` (an sc_time value) moves
  // later by the wait.
  virtual SuperdenseTime write_at(const T& item, uint64_t ready_at, const SuperdenseTime& call) = 0;
  virtual SuperdenseTime write_at(T&& item, uint64_t ready_at, const SuperdenseTime& call) = 0;
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
    m_writer_clock = writer_clock;
    m_reader_clock = reader_clock;
    m_readable_from.assign(m_buf.size(), SuperdenseTime{});
    m_free_from.assign(m_buf.size(), SuperdenseTime{});
    m_write_log.reset(m_buf.size());
    m_read_log.reset(m_buf.size());
  }

  // Items the reader can take now (written before this delta, not yet read).
  size_t size() const override {
    if (m_withheld) return 0;
    if (!m_stamped) return m_committed - m_num_read;
    const SuperdenseTime k = kernel_stamp();
    size_t n = 0;
    for (uint64_t i = m_total_read; i < m_total_written; ++i, ++n) {
      if (k < m_readable_from[i % m_buf.size()]) break;
    }
    return n;
  }
  // Slots a writer can fill now (slots freed in this delta count from the next).
  size_t num_free() const override {
    if (!m_stamped) return m_buf.size() - m_committed - m_num_written;
    const SuperdenseTime k = kernel_stamp();
    size_t n = 0;
    for (uint64_t i = m_total_written; i < m_total_read + m_buf.size(); ++i, ++n) {
      if (k < m_free_from[i % m_buf.size()]) break;
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
    // Stamped: the operations before the horizon, or all of them up to now
    // once the simulation has stopped; mid-run, decoupled sides may have
    // logged operations beyond now (their figures are then approximate).
    if (m_stamped) const_cast<Fifo*>(this)->settle_for_stats();
    const uint64_t now = std::max(
        {this->now(), m_occupancy.since, m_blocked_writers.since, m_blocked_readers.since});
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
    s.observed = time_stamp();
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
  SuperdenseTime kernel_stamp() const { return gpusim::kernel_stamp(*simcontext()); }

  // ---- Stamped mode (see the top of the file) ----

  // Operations logged in order of their stamps, not yet integrated into the
  // statistics. Neither side's log outgrows depth + 1 entries between two
  // settlements (an operation is settled once both sides have passed it),
  // but the ring grows if it must.
  class StampLog {
   public:
    void reset(size_t depth) {
      size_t n = 4;
      while (n < 2 * depth + 4) n *= 2;
      m_ring.assign(n, SuperdenseTime{});
      m_mask = n - 1;
      m_head = m_tail = 0;
    }
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
    void push(const SuperdenseTime& s) {
      if (m_tail - m_head == m_ring.size()) grow();
      m_ring[m_tail++ & m_mask] = s;
    }

   private:
    void grow() {
      std::vector<SuperdenseTime> bigger(2 * m_ring.size());
      for (uint64_t i = m_head; i != m_tail; ++i) bigger[i - m_head] = m_ring[i & m_mask];
      m_tail -= m_head;
      m_head = 0;
      m_ring.swap(bigger);
      m_mask = m_ring.size() - 1;
    }
    std::vector<SuperdenseTime> m_ring;
    uint64_t m_mask = 0;  // ring size - 1 (a power of two)
    uint64_t m_head = 0, m_tail = 0;
  };

  void require_stamped() const {
    if (!m_stamped) {
      throw std::logic_error(std::string(name()) +
                             ": read_at/write_at need a stamped FIFO (set_stamped)");
    }
  }

  // Random stall injection at a stamp: the same draws as maybe_stall(), the
  // delay added to the operation's time (a process in the kernel's time
  // waits it, as maybe_stall() does).
  SuperdenseTime stall_at(fifo_detail::SplitMix64& rng, const SuperdenseTime& call, bool kernel) {
    if (m_stall_probability <= 0.0 || rng.uniform() >= m_stall_probability) return call;
    const uint64_t n = 1 + rng.next() % m_stall_max_cycles;
    const sc_core::sc_time t = sc_core::sc_time::from_value(m_stall_cycle.value() * n);
    ++m_injected_stalls;
    m_injected_stall += t;
    const SuperdenseTime stalled{call.t + t.value(), 0};
    if (kernel) {
      wait_until(stalled);
    } else {
      keep_stall_end(stalled.t);
    }
    return stalled;
  }

  // A decoupled side does not wait its stall in the kernel, but the
  // kernel-timed model does, and the kernel's last time is the "now" every
  // statistic is observed up to: a stall drawn before a read that never
  // comes (the ROP's after its end of frame) ends the simulation. An event
  // at the latest stall end keeps that time.
  void keep_stall_end(uint64_t t) {
    if (t <= m_stall_end) return;
    m_stall_end = t;
    m_stall_end_event.cancel();  // an earlier pending time would keep this one out
    m_stall_end_event.notify(sc_core::sc_time::from_value(t - now()));
  }

  // A process in the kernel's time: until the kernel reaches `s`. Reaching
  // it late would move the process's later actions: the model error means a
  // decoupled stage logged an operation after the kernel had passed its time.
  void wait_until(const SuperdenseTime& s) {
    if (!gpusim::wait_until(s)) late("an operation of a process in the kernel's time");
  }

  [[noreturn]] void late(const char* what) const { report_behind_kernel(name(), what); }

  // Wakes the other side sleeping on `event`: a decoupled stage at once, in
  // this evaluation phase (it computes its own time, which is then at or
  // after the kernel's), a process in the kernel's time at the time of the
  // operation it waits to make, `at`.
  void wake(sc_core::sc_event& event, const SuperdenseTime* sleeper_clock,
            const SuperdenseTime& at) {
    const uint64_t t = now();
    if (sleeper_clock != nullptr) {
      event.notify();  // runs in this evaluation phase: no delta cycle
    } else if (at.t <= t) {
      event.notify(sc_core::SC_ZERO_TIME);
    } else {
      event.notify(sc_core::sc_time::from_value(at.t - t));
    }
  }

  // The time at or after `call` at which one side's next operation can be
  // made: sleeps while `waits` (the other side has not made the operation it
  // depends on), then takes `from`, that operation's delta after (a slot's
  // entry, read once the wait is over). A process in the kernel's time
  // (`kernel`) waits until then.
  SuperdenseTime stamped_wait(fifo_detail::Integral& blocked, bool& asleep, sc_core::sc_event& wake,
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
    return stamped_wait(m_blocked_writers, m_writer_asleep, m_writer_wake, &Fifo::no_slot_read,
                        m_free_from[m_tail], call, kernel);
  }

  // The next read: after the oldest item's write and its ready time (the
  // reader sleeps too while withheld).
  SuperdenseTime stamped_read_wait(const SuperdenseTime& call, bool kernel) {
    return stamped_wait(m_blocked_readers, m_reader_asleep, m_reader_wake, &Fifo::no_item_written,
                        m_readable_from[m_head], call, kernel);
  }

  // A stamped write made at `call` (a side in the kernel's time waits until
  // the time it is given): a moved item is swapped with the slot's old
  // contents, for the reader to reuse.
  template <typename P>
  SuperdenseTime stamped_write(P&& item, uint64_t ready_at, const SuperdenseTime& call,
                               bool kernel) {
    const SuperdenseTime s = stamped_write_wait(stall_at(m_write_rng, call, kernel), kernel);
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
    const SuperdenseTime s = stamped_read_wait(stall_at(m_read_rng, call, kernel), kernel);
    using std::swap;
    swap(m_buf[m_head], item);
    stamped_pop(s);
    return s;
  }
  T stamped_read(const SuperdenseTime& call, bool kernel, SuperdenseTime& at) {
    at = stamped_read_wait(stall_at(m_read_rng, call, kernel), kernel);
    T item = std::move(m_buf[m_head]);
    stamped_pop(at);
    return item;
  }

  // The item is in m_buf[m_tail], written at `s`, ready at `ready`.
  void stamped_push(const SuperdenseTime& s, uint64_t ready) {
    m_readable_from[m_tail] = later(s.next_delta(), SuperdenseTime{ready, 0});
    m_tail = m_tail + 1 == m_buf.size() ? 0 : m_tail + 1;
    ++m_total_written;
    m_write_log.push(s);
    if (m_reader_asleep) wake(m_reader_wake, m_reader_clock, m_readable_from[m_head]);
    if (m_events_handed_out || m_watchers > 0) m_data_written_event.notify(sc_core::SC_ZERO_TIME);
    settle_if_long();
  }

  // The item has been taken from m_buf[m_head] at `s`.
  void stamped_pop(const SuperdenseTime& s) {
    m_free_from[m_head] = s.next_delta();
    const size_t freed = m_head;
    m_head = m_head + 1 == m_buf.size() ? 0 : m_head + 1;
    ++m_total_read;
    m_read_log.push(s);
    if (m_writer_asleep) wake(m_writer_wake, m_writer_clock, m_free_from[freed]);
    if (m_events_handed_out || m_watchers > 0) m_data_read_event.notify(sc_core::SC_ZERO_TIME);
    settle_if_long();
  }

  // Settling costs a comparison per logged operation, so it waits until a
  // log holds more than the FIFO's depth (stats() settles what is left).
  void settle_if_long() {
    if (m_write_log.size() > m_buf.size() || m_read_log.size() > m_buf.size()) settle(horizon());
  }

  // No operation earlier than this can still be logged: a decoupled side's
  // later operations are at or after its clock, the kernel's at or after now.
  SuperdenseTime horizon() const {
    const SuperdenseTime k = kernel_stamp();
    const SuperdenseTime& w = m_writer_clock ? *m_writer_clock : k;
    const SuperdenseTime& r = m_reader_clock ? *m_reader_clock : k;
    return r < w ? r : w;
  }

  // Integrates the logged operations before `limit`, a delta at a time, as
  // update() does for the kernel-timed FIFO.
  void settle(const SuperdenseTime& limit) {
    for (;;) {
      const SuperdenseTime* w = m_write_log.oldest_before(limit);
      const SuperdenseTime* r = m_read_log.oldest_before(limit);
      if (!w && !r) return;
      const SuperdenseTime at = !r || (w && *w < *r) ? *w : *r;
      if (at.t < m_occupancy.since) late("a logged operation");
      const size_t written = m_write_log.take(at), read = m_read_log.take(at);
      const uint64_t dt = at.t - m_occupancy.since;
      if (m_committed == m_buf.size()) m_full += dt;
      if (m_committed == 0) m_empty += dt;
      m_committed = m_committed - read + written;
      m_occupancy.set(m_committed, at.t);
      m_max_occupancy = std::max(m_max_occupancy, m_committed);
    }
  }

  void settle_for_stats() {
    if (sc_core::sc_get_status() == sc_core::SC_RUNNING) {
      settle(horizon());
    } else {
      settle(SuperdenseTime{now(), ~uint64_t{0}});
    }
  }

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

  // Stamped mode: per slot, when its item may be read and when it may be
  // written again; the decoupled sides' clocks; the sleeping sides.
  std::vector<SuperdenseTime> m_readable_from;
  std::vector<SuperdenseTime> m_free_from;
  const SuperdenseTime* m_writer_clock = nullptr;
  const SuperdenseTime* m_reader_clock = nullptr;
  StampLog m_write_log, m_read_log;
  sc_core::sc_event m_writer_wake, m_reader_wake;
  bool m_writer_asleep = false;
  uint64_t m_stall_end = 0;  // the latest stall end of a decoupled side
  sc_core::sc_event m_stall_end_event;
};

}  // namespace gpusim
