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

float dot(const glm::vec3& a, const glm::vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

glm::vec3 normalize(const glm::vec3& v) {
  const float len2 = dot(v, v);
  if (!(len2 > 0.0f)) return v;
  const float inv = 1.0f / std::sqrt(len2);
  return glm::vec3(v.x * inv, v.y * inv, v.z * inv);
}

glm::vec4 clamp01(const glm::vec4& c) {
  return glm::vec4(gpusim::clamp01(c.x), gpusim::clamp01(c.y), gpusim::clamp01(c.z),
                   gpusim::clamp01(c.w));
}

// max(v, 0) as std::max evaluates it: a NaN stays NaN.
float max0(float v) {
  return std::max(v, 0.0f);
}

}  // namespace

VertexShader::VertexShader(sc_core::sc_module_name name, const GpuConfig& config,
                           const FrameState& frame)
    : PipelineStage(name, "vertex_shader", -1, config, frame, "batches and control tokens read",
                    "batches and control tokens written"),
      in("in"),
      out("out") {
  SC_HAS_PROCESS(VertexShader);
  SC_THREAD(run);
}

void VertexShader::load_draw(uint32_t draw_id) {
  m_loaded = true;
  m_draw_id = draw_id;
  const Material& m = m_frame.draws.at(draw_id).material;
  for (int i = 0; i < 3; ++i)
    m_base_color[i] = m.emission[i] + m_frame.global_ambient[i] * m.ambient[i];
  m_light_terms.resize(m_frame.lights.size());
  for (size_t l = 0; l < m_frame.lights.size(); ++l) {
    const Light& light = m_frame.lights[l];
    for (int i = 0; i < 3; ++i) {
      m_light_terms[l].ambient[i] = light.ambient[i] * m.ambient[i];
      m_light_terms[l].diffuse[i] = light.diffuse[i] * m.diffuse[i];
      m_light_terms[l].specular[i] = light.specular[i] * m.specular[i];
    }
  }
}

glm::vec4 VertexShader::light(const DrawState& draw, const glm::vec4& eye,
                              const glm::vec3& n) const {
  const float shininess = draw.material.shininess;
  glm::vec3 c = m_base_color;
  for (size_t l = 0; l < m_frame.lights.size(); ++l) {
    const Light& light = m_frame.lights[l];
    glm::vec3 to_light = light.vector;
    float attenuation = 1.0f;
    if (light.type == LightType::point) {
      const glm::vec3 d(light.vector.x - eye.x, light.vector.y - eye.y, light.vector.z - eye.z);
      const float dist2 = dot(d, d);
      const float dist = std::sqrt(dist2);
      if (dist > 0.0f) {
        const float inv = 1.0f / dist;
        to_light = glm::vec3(d.x * inv, d.y * inv, d.z * inv);
      } else {
        to_light = d;
      }
      attenuation = 1.0f / (light.constant_attenuation + light.linear_attenuation * dist +
                            light.quadratic_attenuation * dist2);
    }
    const float n_dot_l = max0(dot(n, to_light));
    float specular = 0.0f;
    if (n_dot_l > 0.0f) {
      // Infinite viewer: the half vector of the light direction and +z.
      const glm::vec3 h = normalize(glm::vec3(to_light.x, to_light.y, to_light.z + 1.0f));
      specular = std::pow(max0(dot(n, h)), shininess);
    }
    const LightTerms& t = m_light_terms[l];
    for (int i = 0; i < 3; ++i) {
      const float term = t.ambient[i] + t.diffuse[i] * n_dot_l + t.specular[i] * specular;
      c[i] = c[i] + attenuation * term;
    }
  }
  return clamp01(glm::vec4(c, draw.material.diffuse.w));
}

void VertexShader::run() {
  for (;;) {
    const VertexBatch batch = receive(in);
    ShadedBatch& o = m_out;
    static_cast<BatchHeader&>(o) = batch;
    uint64_t busy = m_cost.ii;  // control tokens
    if (batch.kind == PacketKind::work) {
      if (!m_loaded || m_draw_id != batch.draw_id) load_draw(batch.draw_id);
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
          const glm::vec3 n = normalize(transform(draw.normal_matrix, batch.normals[v]));
          color = light(draw, eye, n);
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
