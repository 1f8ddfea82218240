// Command processor: the GPU's front door. It decodes the command stream the
// driver writes (draws, clears, end of frame) and hands each command to vertex
// fetch in order. Per-draw state is already in the FrameState registers, so a
// command is just its kind and draw id.
//
// Cost model, per command (draw, clear or end of frame alike): busy
// `command_processor.ii` cycles, then the command is written to the output
// FIFO, visible to vertex fetch `command_processor.latency` cycles later.
#pragma once

#include <systemc>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/stats.h"

namespace gpusim {

class CommandProcessor : public sc_core::sc_module {
 public:
  FifoInPort<Command> in;
  FifoOutPort<Command> out;

  CommandProcessor(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);

  const StatGroup& stats() const { return m_stats; }

 private:
  void run();

  const GpuConfig& m_config;
  const FrameState& m_frame;
  const StageCost m_cost;
  // The clock period in SystemC time units, kept: GpuConfig::cycles() converts
  // it from the MHz double on every call, a cost paid per token otherwise.
  const uint64_t m_cycle;
  sc_core::sc_time clock_cycles(uint64_t n) const {
    return sc_core::sc_time::from_value(m_cycle * n);
  }
  // latency(stage) cycles: an output is readable this long after it is written.
  const sc_core::sc_time m_latency;
  StatGroup m_stats{name()};
  uint64_t& m_busy_cycles = m_stats.counter("busy_cycles", "cycles spent decoding commands");
  uint64_t& m_tokens_in = m_stats.counter("tokens_in", "commands read");
  uint64_t& m_tokens_out = m_stats.counter("tokens_out", "commands forwarded to vertex fetch");
  uint64_t& m_draws = m_stats.counter("draws", "draw commands");
  uint64_t& m_clears = m_stats.counter("clears", "clear commands");
  uint64_t& m_frames = m_stats.counter("frames", "end-of-frame commands");
};

}  // namespace gpusim
