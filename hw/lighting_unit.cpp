#include "hw/lighting_unit.h"

#include <algorithm>
#include <cmath>

#include "hw/pixel_formats.h"

namespace gpusim {
namespace {

float dot(const glm::vec3& a, const glm::vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

}  // namespace

glm::vec3 LightingUnit::normalize(const glm::vec3& v) {
  const float len2 = dot(v, v);
  if (!(len2 > 0.0f)) return v;
  const float inv = 1.0f / std::sqrt(len2);
  return glm::vec3(v.x * inv, v.y * inv, v.z * inv);
}

void LightingUnit::load(uint32_t draw_id) {
  if (draw_id == m_draw_id) return;
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
  m_shininess = m.shininess;
  m_alpha = m.diffuse.w;
}

glm::vec4 LightingUnit::shade(const glm::vec3& n, const glm::vec3& eye) const {
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
    // max(x, 0) as std::max evaluates it: a NaN stays NaN (spec section 2).
    const float n_dot_l = std::max(dot(n, to_light), 0.0f);
    float specular = 0.0f;
    if (n_dot_l > 0.0f) {
      // Infinite viewer: the half vector of the light direction and +z.
      const glm::vec3 h = normalize(glm::vec3(to_light.x, to_light.y, to_light.z + 1.0f));
      specular = std::pow(std::max(dot(n, h), 0.0f), m_shininess);
    }
    const LightTerms& t = m_light_terms[l];
    for (int i = 0; i < 3; ++i) {
      const float term = t.ambient[i] + t.diffuse[i] * n_dot_l + t.specular[i] * specular;
      c[i] = c[i] + attenuation * term;
    }
  }
  return glm::vec4(clamp01(c.x), clamp01(c.y), clamp01(c.z), clamp01(m_alpha));
}

}  // namespace gpusim
