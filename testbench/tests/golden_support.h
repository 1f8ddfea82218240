// What the golden model's tests share: an empty scene of a given size, and
// the exact side-of-edge test with the tie rule (docs/pipeline-spec.md,
// section 8) on subpixel integers, from which each test builds its own
// reference coverage, written apart from the model it checks.
#pragma once

#include <cstdint>

#include "testbench/scene/scene.h"

namespace gpusim::golden_support {

// w x h, cleared to transparent black.
inline Scene make_scene(int w, int h) {
  Scene s;
  s.framebuffer.width = w;
  s.framebuffer.height = h;
  s.framebuffer.clear_color = {0.0f, 0.0f, 0.0f, 0.0f};
  return s;
}

// A point in subpixels.
struct Pt {
  int64_t x, y;
};

inline int sgn(int64_t v) {
  return (v > 0) - (v < 0);
}

// +1 when p + (e, e^2), for an infinitesimal e > 0, is strictly left of the
// directed line a -> b, -1 right: the tie rule without the owner table (why:
// golden_raster_test.cpp).
inline int perturbed_side(Pt a, Pt b, Pt p) {
  const int64_t cross = (a.x - p.x) * (b.y - p.y) - (a.y - p.y) * (b.x - p.x);
  if (cross != 0) return sgn(cross);
  if (b.y != a.y) return sgn(a.y - b.y);  // d/de of the cross product is -(b.y - a.y)
  return sgn(b.x - a.x);                  // d/d(e^2) is +(b.x - a.x)
}

}  // namespace gpusim::golden_support
