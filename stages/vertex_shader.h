// Vertex shader: fixed-function transform and lighting of every fetched
// vertex of a batch (docs/pipeline-spec.md, section 2), in the spec's exact
// floating-point order. The colour goes into the components of the vertex's
// varyings that the draw's VaryingLayout names; for a lit Phong draw the
// eye-space unit normal and position too (section 9b). Cached and invalid slots pass
// through untouched; the clipper resolves them.
//
// Cost model, per batch: busy = ii(vertex_shader) x fetched vertices, the same
// for lit and unlit vertices and whatever the number of lights (the lighting
// datapath is sized for the scene's lights; a batch with no new vertex costs
// nothing). The shaded batch is readable by the clipper latency(vertex_shader)
// cycles later. Control tokens cost ii and are forwarded in order. No memory
// traffic: the draw's matrices, material and the lights are registers.
#pragma once

#include <systemc>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/lighting_unit.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"
#include "hw/vertex_packets.h"

namespace gpusim {

class VertexShader : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<VertexBatch> in;
  FifoOutPort<ShadedBatch> out;

  VertexShader(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);
  // Its only inputs and outputs are its FIFOs (PipelineStage: temporal decoupling).
  bool decouplable() const override { return true; }

 private:
  void run();
  void reset_state() override;

  ShadedBatch m_out;
  LightingUnit m_lighting;  // loaded with each new draw's registers

  uint64_t& m_vertices = m_stats.counter("vertices_shaded", "vertices", "vertices transformed");
  uint64_t& m_lit =
      m_stats.counter("vertices_lit", "vertices", "vertices lit (of vertices_shaded)");
};

}  // namespace gpusim
