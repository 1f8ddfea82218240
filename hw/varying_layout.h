// Varyings: the per-vertex values a draw interpolates across its primitives,
// carried from the vertex shader to the interpolator as one fixed-capacity
// array of float32 components per vertex (Varyings). The stages in between
// do not know what the components mean: the clipper interpolates all of a
// draw's components at a cut and multiplies them by 1/w, primitive setup passes
// them on, the interpolator interpolates them per pixel, each with one loop
// over the draw's component count. Only the draw's VaryingLayout says which varying
// occupies which components; the vertex shader writes them by it and the
// interpolator reads the colour it hands to the ROP, or the normal and eye
// position it lights the pixel from, by it.
//
// The layout is per draw: computed once when the frame state is built
// (varying_layout_for, hw/draw_state.h) and kept in DrawState, so packets carry
// no layout, only their draw id. Components from `count` to the capacity are
// 0 in every packet (each producer starts from zeroed arrays and leaves them
// 0), so packets compare equal by their whole arrays.
#pragma once

#include <array>
#include <cstdint>
#include <ostream>

namespace gpusim {

// Capacity of a vertex's varying array, in float32 components. A draw uses
// 4 (its colour); a Phong draw 10. Per-pixel lighting adds an eye-space normal (3) and
// position (3), texturing a texture coordinate (2): 12 in all, the capacity.
// Every packet after the vertex shader carries the whole capacity, so it is
// not larger: on the geometry-bound 1M-triangle frame (scripts/bench), 16
// components took 2-3% more simulation time than 12, which take about 1%
// more than the colour alone did. 12 is also a whole number of the
// interpolator's 4-component groups (kVaryingGroup), so a group never reads
// past the array.
constexpr unsigned kMaxVaryings = 12;
// The interpolator evaluates varyings 4 components at a time (one SSE
// register; in hardware, 4 interpolation lanes).
constexpr unsigned kVaryingGroup = 4;
static_assert(kMaxVaryings % kVaryingGroup == 0, "whole groups");

using Varyings = std::array<float, kMaxVaryings>;

// r, g, b, a.
constexpr unsigned kColorComponents = 4;

// A varying a layout does not hold.
constexpr uint8_t kNoVarying = 0xff;

// Which components of a draw's Varyings hold what. Default-constructed: the
// colour alone in components 0-3, the layout of every draw but a lit Phong one.
struct VaryingLayout {
  uint8_t count = kColorComponents;  // components in use: [0, count)
  // The colour's first component. Every draw carries a colour: the ROP
  // consumes one per pixel (a Phong draw's triangles and lines compute it
  // from the normal and eye position instead; its points use this one).
  uint8_t color = 0;
  // Phong shading (docs/pipeline-spec.md, section 9b): the eye-space unit
  // normal and the eye-space position (x, y, z each), from which the
  // interpolator lights every pixel; kNoVarying in every other draw.
  uint8_t normal = kNoVarying;
  uint8_t eye = kNoVarying;
  // Texturing (section 9c): the texture coordinate (s, t); kNoVarying in an
  // untextured draw.
  uint8_t texcoord = kNoVarying;

  // Reserves `components` more components after the last in use and returns
  // the first of them. Throws std::length_error past kMaxVaryings.
  unsigned append(unsigned components);
  // `count` rounded up to whole groups: the groups the interpolator evaluates.
  unsigned groups() const { return (count + kVaryingGroup - 1) / kVaryingGroup; }
  // Whether the draw's pixels are lit per pixel (it carries a normal).
  bool per_pixel_lighting() const { return normal != kNoVarying; }
  bool textured() const { return texcoord != kNoVarying; }

  bool operator==(const VaryingLayout& o) const {
    return count == o.count && color == o.color && normal == o.normal && eye == o.eye &&
           texcoord == o.texcoord;
  }
  bool operator!=(const VaryingLayout& o) const { return !(*this == o); }
};
std::ostream& operator<<(std::ostream& os, const VaryingLayout& l);

}  // namespace gpusim
