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
#include "hw/pipeline_stage.h"
#include "hw/stats.h"

namespace gpusim {

class CommandProcessor : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<Command> in;
  FifoOutPort<Command> out;

  CommandProcessor(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);

 private:
  void run();

  uint64_t& m_draws = m_stats.counter("draws", "commands", "draw commands");
  uint64_t& m_clears = m_stats.counter("clears", "commands", "clear commands");
  uint64_t& m_frames = m_stats.counter("frames", "frames", "end-of-frame commands");
};

}  // namespace gpusim
