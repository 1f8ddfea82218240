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
#include "hw/pipeline_stage.h"
#include "hw/stats.h"
#include "hw/vertex_packets.h"

namespace gpusim {

class VertexShader : public PipelineStage {
 public:
  FifoInPort<VertexBatch> in;
  FifoOutPort<ShadedBatch> out;

  VertexShader(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);

 private:
  // Per-draw lighting constants, loaded when a batch of a new draw arrives:
  // the products of light and material colours that do not depend on the
  // vertex. Each is the same float product the spec's formula evaluates per
  // vertex, so precomputing it changes no bit.
  struct LightTerms {
    glm::vec3 ambient{0.0f};   // light.ambient * material.ambient
    glm::vec3 diffuse{0.0f};   // light.diffuse * material.diffuse
    glm::vec3 specular{0.0f};  // light.specular * material.specular
  };

  void run();
  void load_draw(uint32_t draw_id);
  // The lit colour of a vertex at eye-space position `eye` with unit normal `n`.
  glm::vec4 light(const DrawState& draw, const glm::vec4& eye, const glm::vec3& n) const;

  ShadedBatch m_out;
  bool m_loaded = false;
  uint32_t m_draw_id = 0;
  glm::vec3 m_base_color{0.0f};  // emission + global_ambient * material.ambient
  std::vector<LightTerms> m_light_terms;

  uint64_t& m_vertices = m_stats.counter("vertices_shaded", "vertices", "vertices transformed");
  uint64_t& m_lit =
      m_stats.counter("vertices_lit", "vertices", "vertices lit (of vertices_shaded)");
};

}  // namespace gpusim
