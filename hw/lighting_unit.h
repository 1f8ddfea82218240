// The fixed-function lighting datapath (docs/pipeline-spec.md, section 2),
// one design instantiated twice: in the vertex shader, per vertex, and in each
// interpolator's per-pixel lighting unit (section 9b). Registers hold the
// per-draw products of light and material colours, loaded when a new draw
// arrives; shade() evaluates the equation for one unit normal and eye-space
// position, every sum left to right as the spec orders it (the build forbids
// contraction into fused multiply-adds), so both instances give the spec's
// bits.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "hw/draw_state.h"

namespace gpusim {

class LightingUnit {
 public:
  explicit LightingUnit(const FrameState& frame) : m_frame(frame) {}

  // No draw loaded, as constructed (between frames: the next frame's draw 0
  // is another draw).
  void reset() {
    m_draw_id = ~uint32_t{0};
    m_base_color = glm::vec3(0.0f);
    m_light_terms.clear();
    m_shininess = 0.0f;
    m_alpha = 1.0f;
  }
  // Loads draw `draw_id`'s registers, unless they hold that draw already.
  void load(uint32_t draw_id);
  // The lit colour (clamped to [0, 1], alpha the material's diffuse alpha)
  // at eye-space position `eye` with unit normal `n`.
  glm::vec4 shade(const glm::vec3& n, const glm::vec3& eye) const;

  // The spec's normalize: v * (1 / sqrt(v.v)), v itself unless v.v > 0.
  static glm::vec3 normalize(const glm::vec3& v);

 private:
  // Products of light and material colours that do not depend on the vertex
  // or pixel: the same float products the spec's formula evaluates, so
  // precomputing them changes no bit.
  struct LightTerms {
    glm::vec3 ambient{0.0f};   // light.ambient * material.ambient
    glm::vec3 diffuse{0.0f};   // light.diffuse * material.diffuse
    glm::vec3 specular{0.0f};  // light.specular * material.specular
  };

  const FrameState& m_frame;
  uint32_t m_draw_id = ~uint32_t{0};  // none loaded
  glm::vec3 m_base_color{0.0f};       // emission + global_ambient * material.ambient
  std::vector<LightTerms> m_light_terms;
  float m_shininess = 0.0f;
  float m_alpha = 1.0f;
};

}  // namespace gpusim
