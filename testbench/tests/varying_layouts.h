// Varyings beyond the colour, for the stage tests of the stages that carry
// them without knowing what they mean: the clipper's
// (stages_clipper_test.cpp: interpolation at clip-plane cuts, division by w)
// and the interpolator's (stages_interpolator_test.cpp: perspective-correct,
// per pixel, which also checks these layouts). The layouts hold a made-up
// varying next to the colour, before or after it, and one that fills the
// whole capacity. Every varying is an affine function of the vertex's
// clip-space position, so its correct value anywhere on a primitive is that
// function of the position there.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>

#include "hw/varying_layout.h"

namespace gpusim {
namespace test {

// Varying k at clip position c: 0.5 plus small, distinct slopes, so that for
// |x|, |y|, |z| <= w <= 2 every value stays inside (0, 1), where the
// interpolator's clamp of the colour it outputs changes nothing.
inline double affine(unsigned k, const glm::dvec4& c) {
  const double sx = 0.008 * (k + 1) * (k % 2 ? -1.0 : 1.0);
  const double sy = 0.04 - 0.005 * k;
  const double sz = 0.02 * (static_cast<double>(k % 4) - 1.5);
  const double sw = 0.03 * (static_cast<double>(k % 3) - 1.0);
  return 0.5 + sx * c.x + sy * c.y + sz * c.z + sw * c.w;
}

// Colour and a made-up 3-component varying: colour first or second.
inline VaryingLayout color_then_extra() {
  VaryingLayout l;
  l.count = 0;
  l.color = static_cast<uint8_t>(l.append(kColorComponents));
  l.append(3);
  return l;
}
inline VaryingLayout extra_then_color() {
  VaryingLayout l;
  l.count = 0;
  l.append(3);
  l.color = static_cast<uint8_t>(l.append(kColorComponents));
  return l;
}
// Every component in use, the colour last.
inline VaryingLayout full_capacity() {
  VaryingLayout l;
  l.count = 0;
  l.append(kMaxVaryings - kColorComponents);
  l.color = static_cast<uint8_t>(l.append(kColorComponents));
  return l;
}

}  // namespace test
}  // namespace gpusim
