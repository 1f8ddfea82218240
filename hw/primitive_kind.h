// What an assembled primitive is: a point, a line or a triangle. A draw's
// PrimitiveType (hw/render_state.h) says which it assembles, and the kind
// travels with every primitive, so lines and points share the triangles'
// packets (hw/packets.h).
#pragma once

#include <cstdint>
#include <ostream>

namespace gpusim {

enum class PrimitiveKind : uint8_t { point, line, triangle };
std::ostream& operator<<(std::ostream& os, PrimitiveKind k);

// Vertices of a primitive of kind k: 1, 2 or 3.
constexpr uint8_t vertex_count_of(PrimitiveKind k) {
  return k == PrimitiveKind::point ? 1 : k == PrimitiveKind::line ? 2 : 3;
}

}  // namespace gpusim
