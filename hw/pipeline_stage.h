// The skeleton every pipeline stage is built on: its one name (kind and unit),
// its cost from the configuration, its statistics group with the counters
// every stage has, and the only ways a stage spends time and moves items:
//
//   receive(in, item)          read an item or control token   (tokens_in)
//   work(n)                    count n busy cycles and let them pass
//   emit(out, item)            write it, readable latency cycles from now (tokens_out)
//   emit_at(out, item, ready)  the same with a readiness the stage computed
//   forward_control(out, k)    a control token: ii cycles, then emitted in order
//   retire()                   a token consumed for good (the ROP)
//
// so busy_cycles can never drift from the waits it accounts for, and
// tokens_in / tokens_out always count FIFO reads and writes (the conservation
// ledger, testbench/sim/conservation.h, relies on it). A stage with nothing to
// do sleeps in receive() and costs the simulator nothing; work(0) does not
// wait at all.
//
// Stalled and starved cycles are not counted here: the FIFOs measure them
// and the netlist (stages/topology.h) adds them to the group as formulas.
//
// Temporal decoupling: a stage that reads nothing at the kernel's time
// except as it arranges itself says so with decouplable(), and the netlist
// may then set it decoupled before the simulation starts. It then keeps its
// own superdense time, local_clock(): work(n) moves it on instead of
// waiting, and receive() and emit() take their items from and into stamped
// FIFOs (hw/fifo.h) at that time and adopt the time each operation is
// given. The stage wakes in the kernel only when an item it needs has not
// been written, or a slot it needs not been read, at all; its operations
// keep the times they would have had, so cycles and statistics are the same
// bits. What a decoupled stage shares with processes in the kernel's time it
// does at the kernel's time: a memory client's requests wait for the kernel
// to reach the stage's clock (attach_clock(), MemoryPort::set_clock), any
// other action calls sync_with_kernel() first, and the rasterizer's
// hierarchical-Z link is read by stamps (hw/hierarchical_z.h).
// local_time() is the time a stage computes readiness from, decoupled or
// not.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <systemc>
#include <utility>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "hw/stage_spec.h"
#include "hw/stats.h"

namespace gpusim {

class FragmentProbe;  // hw/trace_probe.h

class PipelineStage : public sc_core::sc_module {
 public:
  // The stage's configuration name ("tile_rasterizer"), the same in
  // stats.json, the traces and the docs; instances are named
  // instance_name(kind, unit).
  const std::string& stage_kind() const { return m_spec.kind; }
  const StageSpec& spec() const { return m_spec; }
  // Its cost in this configuration.
  const StageCost& cost() const { return m_cost; }
  // The raster unit the stage belongs to; -1 for the front end.
  int unit() const { return m_unit; }
  static std::string instance_name(const std::string& kind, int unit) {
    return unit < 0 ? kind : kind + "_" + std::to_string(unit);
  }

  const StatGroup& stats() const { return m_stats; }
  StatGroup& stats() { return m_stats; }
  uint64_t tokens_in() const { return m_tokens_in; }
  uint64_t tokens_out() const { return m_tokens_out; }

  // Tracing: a stage whose spec names a fragment site
  // (StageTrace::fragments) reports each fragment there to `probe`
  // (nullptr: none); the netlist attaches it (Topology::attach_trace).
  virtual void set_fragment_probe(FragmentProbe* probe) {
    (void)probe;
    throw std::logic_error("stage '" + m_spec.kind +
                           "' names a fragment site but reports no fragments");
  }

  // Between frames (Topology::reset), from the process that resets the GPU
  // at the new frame's first instant, after every FIFO's reset: the stage
  // as elaborated (its counters zero, its own state as reset_state() puts
  // it back, a decoupled stage's clock at the kernel's time), then its
  // processes restarted from the top, as a hardware reset restarts a
  // state machine, so that what a thread keeps in locals starts afresh too.
  void reset();

  // Whether the stage may run decoupled (above): false unless the stage
  // declares it.
  virtual bool decouplable() const { return false; }
  // Before the simulation starts, on a decouplable() stage whose FIFOs are
  // then put in stamped mode (Topology::decouple).
  void set_decoupled() { m_decoupled = true; }
  bool decoupled() const { return m_decoupled; }
  // A decoupled stage's time: none of its later operations precedes it.
  const SuperdenseTime& local_clock() const { return m_local; }

 protected:
  // The stage's spec (hw/stage_spec.h) names its kind and describes its
  // token counters; its cost is the configuration's for that kind (the
  // spec's default unless overridden).
  PipelineStage(sc_core::sc_module_name name, const StageSpec& spec, int unit,
                const GpuConfig& config, const FrameState& frame)
      : sc_core::sc_module(name),
        m_config(config),
        m_frame(frame),
        m_cost(config.stage(spec.kind)),
        m_cycle(config.cycle().value()),
        m_latency(clock_cycles(m_cost.latency)),
        m_unit(unit),
        m_spec(spec),
        m_stats(basename(), spec.kind),
        m_busy_cycles(m_stats.counter("busy_cycles", "cycles", "cycles spent working")),
        m_tokens_in(m_stats.counter("tokens_in", "tokens", spec.tokens_in)),
        m_tokens_out(m_stats.counter("tokens_out", "tokens", spec.tokens_out)) {}

  // The stage's members as its constructor left them, before reset()
  // restarts its processes: what its threads keep from packet to packet
  // (caches, loaded registers, sequence numbers). Counters in m_stats are
  // reset() already; what a thread sets up before its loop it sets up again.
  virtual void reset_state() {}

  sc_core::sc_time clock_cycles(uint64_t n) const {
    return sc_core::sc_time::from_value(m_cycle * n);
  }

  // Now: the stage's own time if decoupled, else the kernel's.
  sc_core::sc_time local_time() const {
    return m_decoupled ? sc_core::sc_time::from_value(m_local.t) : sc_core::sc_time_stamp();
  }

  void work(uint64_t cycles) {
    m_busy_cycles += cycles;
    if (cycles == 0) return;
    if (m_decoupled) {
      // A timed wake-up lands in the first delta of its time.
      m_local = SuperdenseTime{m_local.t + m_cycle * cycles, 0};
    } else {
      sc_core::wait(clock_cycles(cycles));
    }
  }

  template <typename T>
  T receive(FifoInPort<T>& in) {
    T item = m_decoupled ? in->read_at(m_local, m_local) : in->read();
    ++m_tokens_in;
    return item;
  }
  // Into `item`, whose buffers go back to the FIFO for its writer to reuse.
  template <typename T>
  void receive(FifoInPort<T>& in, T& item) {
    if (m_decoupled) {
      m_local = in->read_at(item, m_local);
    } else {
      in->read(item);
    }
    ++m_tokens_in;
  }

  template <typename T, int N, sc_core::sc_port_policy Policy, typename P>
  void emit_at(sc_core::sc_port<FifoOutIf<T>, N, Policy>& out, P&& item,
               const sc_core::sc_time& ready) {
    if (m_decoupled) {
      m_local = out->write_at(std::forward<P>(item), ready.value(), m_local);
    } else {
      out->write(std::forward<P>(item), ready);
    }
    ++m_tokens_out;
  }
  template <typename T, typename P>
  void emit(FifoOutPort<T>& out, P&& item) {
    emit_at(out, std::forward<P>(item), local_time() + m_latency);
  }

  // Control tokens travel in band, behind the work before them.
  template <typename T>
  void forward_control(FifoOutPort<T>& out, PacketKind kind) {
    work(m_cost.ii);
    T token{};
    token.kind = kind;
    emit(out, std::move(token));
  }

  void retire() { ++m_tokens_out; }

  // A memory client's requests are made at the stage's time: from the
  // stage's thread, before its first request.
  void attach_clock(MemoryPort& port) { port.set_clock(m_decoupled ? &m_local : nullptr); }
  // The kernel brought to the stage's time, for an action other processes
  // see at the kernel's time; no wait when not decoupled.
  void sync_with_kernel() {
    if (m_decoupled && !wait_until(m_local)) report_behind_kernel(name(), "the stage's clock");
  }

  // The frame's clear token n (counted from 0 at the frame's start), as
  // FrameState::clear gives it; more tokens than the frame has clears is a
  // driver bug.
  ClearState next_clear(size_t n) const {
    if (n > m_frame.clears.size()) {
      SC_REPORT_ERROR("gpusim/clear",
                      (std::string(name()) + ": clear token " + std::to_string(n) +
                       " of a frame with " + std::to_string(m_frame.clears.size() + 1) + " clears")
                          .c_str());
    }
    return m_frame.clear(n);
  }

  const GpuConfig& m_config;
  const FrameState& m_frame;
  const StageCost m_cost;
  // The clock period in SystemC time units, kept: GpuConfig::cycles()
  // converts it from the MHz double on every call.
  const uint64_t m_cycle;
  // latency cycles: an output is readable this long after it is written.
  const sc_core::sc_time m_latency;

  const int m_unit;  // -1: front end

 private:
  const StageSpec& m_spec;
  bool m_decoupled = false;
  SuperdenseTime m_local;  // decoupled only

 protected:
  StatGroup m_stats;
  uint64_t& m_busy_cycles;
  uint64_t& m_tokens_in;
  uint64_t& m_tokens_out;
};

}  // namespace gpusim
