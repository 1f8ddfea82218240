#include "hw/vertex_packets.h"

#include <algorithm>

namespace gpusim {
namespace {

// Entries beyond slot_count / vertex_count are stale and not compared.
template <typename T, size_t N>
bool equal_prefix(const std::array<T, N>& a, const std::array<T, N>& b, uint32_t n) {
  return std::equal(a.begin(), a.begin() + std::min<size_t>(n, N), b.begin());
}

void print_header(std::ostream& os, const BatchHeader& b) {
  os << b.kind;
  if (b.kind != PacketKind::work) return;
  os << " draw " << b.draw_id << " slots " << b.first_slot << ".."
     << b.first_slot + b.slot_count - 1 << " (" << b.vertex_count << " new):";
  for (uint32_t i = 0; i < b.slot_count && i < kVertexBatchSlots; ++i) {
    const VertexSlot& s = b.slots[i];
    os << ' ' << s.kind;
    if (s.kind == SlotKind::fetched) os << '#' << s.vertex;
    if (s.entry != kNoCacheEntry) os << '@' << s.entry;
  }
}

}  // namespace

std::ostream& operator<<(std::ostream& os, SlotKind k) {
  switch (k) {
    case SlotKind::fetched:
      return os << "fetched";
    case SlotKind::cached:
      return os << "cached";
    case SlotKind::invalid:
      return os << "invalid";
  }
  return os << "?";
}

bool BatchHeader::operator==(const BatchHeader& o) const {
  return kind == o.kind && draw_id == o.draw_id && first_slot == o.first_slot &&
         slot_count == o.slot_count && vertex_count == o.vertex_count &&
         equal_prefix(slots, o.slots, slot_count);
}

bool VertexBatch::operator==(const VertexBatch& o) const {
  return BatchHeader::operator==(o) && equal_prefix(positions, o.positions, vertex_count) &&
         equal_prefix(normals, o.normals, vertex_count) &&
         equal_prefix(colors, o.colors, vertex_count);
}

std::ostream& operator<<(std::ostream& os, const VertexBatch& b) {
  os << "VertexBatch{";
  print_header(os, b);
  return os << "}";
}

bool ShadedBatch::operator==(const ShadedBatch& o) const {
  return BatchHeader::operator==(o) && equal_prefix(vertices, o.vertices, vertex_count);
}

std::ostream& operator<<(std::ostream& os, const ShadedBatch& b) {
  os << "ShadedBatch{";
  print_header(os, b);
  return os << "}";
}

}  // namespace gpusim
