#include "traces/trace_items.h"

#include <algorithm>

namespace gpusim {

ItemDescriber::ItemDescriber(const FrameState& frame, unsigned tile_size)
    : m_frame(frame), m_tile_shift(log2_side(tile_size)) {}

ItemInfo ItemDescriber::control(PacketKind kind) const {
  ItemInfo i;
  i.kind = kind == PacketKind::clear ? 1 : 2;
  return i;
}

ItemInfo ItemDescriber::describe(const Command& c) const {
  if (c.kind != PacketKind::work) return control(c.kind);
  ItemInfo i;
  i.draw = c.draw_id;
  const DrawState& d = m_frame.draws.at(c.draw_id);
  i.prim_kind = prim_kind_code(primitive_kind_of(d.primitive));
  const uint64_t n = primitive_count(d.primitive, d.buffers.slot_count);
  i.count = static_cast<uint32_t>(n);
  if (n > 0) {
    i.prim_first = d.first_primitive_id;
    i.prim_last = d.first_primitive_id + static_cast<int64_t>(n) - 1;
  }
  return i;
}

ItemInfo ItemDescriber::describe(const BatchHeader& b) const {
  if (b.kind != PacketKind::work) return control(b.kind);
  ItemInfo i;
  i.draw = b.draw_id;
  i.count = b.slot_count;
  i.first_slot = b.first_slot;
  i.is_batch = true;
  const DrawState& d = m_frame.draws.at(b.draw_id);
  i.prim_kind = prim_kind_code(primitive_kind_of(d.primitive));
  const int64_t n = static_cast<int64_t>(primitive_count(d.primitive, d.buffers.slot_count));
  if (n == 0 || b.slot_count == 0) return i;
  const int64_t lo = b.first_slot, hi = lo + b.slot_count - 1;
  // Triangle k uses slots 3k..3k+2 (list), k..k+2 (strip), 0, k+1, k+2 (fan);
  // point k slot k; line k slots 2k, 2k+1 (list), k, k+1 (strip, loop), and
  // a loop's last line n-1 and 0.
  int64_t first = 0, last = 0;
  switch (d.primitive) {
    case PrimitiveType::triangles:
      first = lo / 3;
      last = hi / 3;
      break;
    case PrimitiveType::triangle_strip:
      first = lo - 2;
      last = hi;
      break;
    case PrimitiveType::triangle_fan:
      first = lo == 0 ? 0 : lo - 2;
      last = lo == 0 ? n - 1 : hi - 1;
      break;
    case PrimitiveType::points:
      first = lo;
      last = hi;
      break;
    case PrimitiveType::lines:
      first = lo / 2;
      last = hi / 2;
      break;
    case PrimitiveType::line_strip:
      first = lo - 1;
      last = hi;
      break;
    case PrimitiveType::line_loop:
      first = lo == 0 ? 0 : lo - 1;
      last = lo == 0 ? n - 1 : hi;
      break;
  }
  first = std::max<int64_t>(first, 0);
  last = std::min<int64_t>(last, n - 1);
  if (first > last) return i;
  i.prim_first = d.first_primitive_id + first;
  i.prim_last = d.first_primitive_id + last;
  return i;
}

ItemInfo ItemDescriber::describe(const ClippedPrimitive& t) const {
  if (t.kind != PacketKind::work) return control(t.kind);
  ItemInfo i;
  i.draw = t.draw_id;
  i.prim_kind = prim_kind_code(t.primitive_kind);
  i.prim_first = i.prim_last = t.primitive_id;
  return i;
}

ItemInfo ItemDescriber::describe(const SetupPacket& p) const {
  if (p.kind != PacketKind::work) return control(p.kind);
  ItemInfo i;
  i.draw = p.primitive->draw_id;
  i.prim_kind = prim_kind_code(p.primitive->primitive_kind);
  i.prim_first = i.prim_last = p.primitive->primitive_id;
  return i;
}

ItemInfo ItemDescriber::stamps(PacketKind kind, const RasterPrimitive* tri,
                               const std::vector<Stamp>& s) const {
  if (kind != PacketKind::work) return control(kind);
  ItemInfo i;
  i.draw = tri->draw_id;
  i.prim_kind = prim_kind_code(tri->primitive_kind);
  i.prim_first = i.prim_last = tri->primitive_id;
  i.count = static_cast<uint32_t>(s.size());
  if (!s.empty()) {
    i.tile_x = static_cast<int16_t>(s.front().x >> m_tile_shift);
    i.tile_y = static_cast<int16_t>(s.front().y >> m_tile_shift);
  }
  return i;
}

ItemInfo ItemDescriber::describe(const StampBatch& b) const {
  return stamps(b.kind, b.primitive.get(), b.stamps);
}

ItemInfo ItemDescriber::describe(const ShadedStampBatch& b) const {
  return stamps(b.kind, b.primitive.get(), b.stamps);
}

}  // namespace gpusim
