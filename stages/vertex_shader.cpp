#include "stages/vertex_shader.h"

#include <algorithm>
#include <cmath>

#include "hw/pixel_formats.h"

namespace gpusim {
namespace {

// Every sum below is written left to right as the spec orders it; the build
// forbids contraction into fused multiply-adds.
glm::vec4 transform(const glm::mat4& m, const glm::vec4& v) {
  glm::vec4 r;
  for (int i = 0; i < 4; ++i) r[i] = m[0][i] * v.x + m[1][i] * v.y + m[2][i] * v.z + m[3][i] * v.w;
  return r;
}

glm::vec3 transform(const glm::mat3& m, const glm::vec3& v) {
  glm::vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = m[0][i] * v.x + m[1][i] * v.y + m[2][i] * v.z;
  return r;
}

glm::vec4 clamp01(const glm::vec4& c) {
  return glm::vec4(gpusim::clamp01(c.x), gpusim::clamp01(c.y), gpusim::clamp01(c.z),
                   gpusim::clamp01(c.w));
}

}  // namespace

namespace {

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  // Every fetched vertex is shaded.
  const std::string vf = l.upstream("vertex_fetch");
  l.equal("tokens_out", l.get("tokens_out"), "tokens_in", l.get("tokens_in"));
  l.equal("vertices_shaded", l.get("vertices_shaded"), vf + ".vertices_fetched",
          l.stage(vf, "vertices_fetched"));
}

}  // namespace

const StageSpec& VertexShader::spec() {
  static const StageSpec s{
      "vertex_shader",
      StagePlacement::front_end,
      /*optional=*/false,
      {/*ii=*/4, /*latency=*/24},
      "vertex",
      "transform and lighting: 4×4 position and normal transforms plus "
      "lighting on one rank of multiply-adds shared 4 ways, deeply pipelined",
      "batches and control tokens read",
      "batches and control tokens written",
      {"fetch_to_shader"},
      &conserve,
      StageTrace{TraceItem::slot_batch, {}, FragmentSite::none},
      {{"", "`ii` × new vertices", "Lights add no cost (the datapath is sized for the scene)."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(VertexShader);

VertexShader::VertexShader(sc_core::sc_module_name name, const GpuConfig& config,
                           const FrameState& frame)
    : PipelineStage(name, spec(), -1, config, frame), in("in"), out("out"), m_lighting(frame) {
  SC_HAS_PROCESS(VertexShader);
  SC_THREAD(run);
}

void VertexShader::reset_state() {
  m_out = ShadedBatch{};
  m_lighting.reset();
}

void VertexShader::run() {
  for (;;) {
    const VertexBatch batch = receive(in);
    ShadedBatch& o = m_out;
    static_cast<BatchHeader&>(o) = batch;
    uint64_t busy = m_cost.ii;  // control tokens
    if (batch.kind == PacketKind::work) {
      const DrawState& draw = m_frame.draws[batch.draw_id];
      const bool lit = draw.lighting && draw.buffers.normals != kNoBuffer;
      const bool colors = draw.buffers.colors != kNoBuffer;
      const VaryingLayout& layout = draw.varyings;
      const unsigned color_slot = layout.color;
      for (uint32_t v = 0; v < batch.vertex_count; ++v) {
        const glm::vec4& p = batch.positions[v];
        ShadedVertex& sv = o.vertices[v];
        sv.clip = transform(draw.mvp, p);
        // Zeroed first: the slot may hold a vertex of a draw with more varyings.
        sv.varyings = Varyings{};
        glm::vec4 color;
        if (lit) {
          const glm::vec4 eye = transform(draw.model_view, p);
          const glm::vec3 n =
              LightingUnit::normalize(transform(draw.normal_matrix, batch.normals[v]));
          m_lighting.load(batch.draw_id);
          color = m_lighting.shade(n, glm::vec3(eye));
          // Phong: the interpolator lights each pixel from these (spec 9b).
          if (layout.per_pixel_lighting()) {
            for (unsigned k = 0; k < 3; ++k) {
              sv.varyings[layout.normal + k] = n[k];
              sv.varyings[layout.eye + k] = eye[k];
            }
          }
        } else {
          color = clamp01(colors ? batch.colors[v] : draw.material.diffuse);
        }
        for (unsigned k = 0; k < kColorComponents; ++k) sv.varyings[color_slot + k] = color[k];
        if (layout.textured()) {
          sv.varyings[layout.texcoord] = batch.texcoords[v].x;
          sv.varyings[layout.texcoord + 1] = batch.texcoords[v].y;
        }
      }
      m_vertices += batch.vertex_count;
      if (lit) m_lit += batch.vertex_count;
      busy = uint64_t{m_cost.ii} * batch.vertex_count;
    }
    work(busy);
    emit(out, o);
  }
}

}  // namespace gpusim
