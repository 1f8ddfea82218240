// What a trace records about one item (docs/traces.md, "Model"): its kind,
// draw, the primitive ids it carries, its tile and a count, read off the
// packet a stage took from its input FIFO.
#pragma once

#include <cstdint>

#include "hw/draw_state.h"
#include "hw/packets.h"
#include "hw/vertex_packets.h"
#include "traces/trace_records.h"

namespace gpusim {

// transactions.bin's `prim_kind`: what the item's primitives are, as the
// stage sees them (a triangle of polygon mode `line` is a triangle up to
// setup and lines after it).
constexpr uint8_t kPrimKindNone = TransactionRecord::prim_none;  // control tokens
constexpr uint8_t prim_kind_code(PrimitiveKind k) {
  return k == PrimitiveKind::point  ? TransactionRecord::prim_point
         : k == PrimitiveKind::line ? TransactionRecord::prim_line
                                    : TransactionRecord::prim_triangle;
}

struct ItemInfo {
  static constexpr uint32_t kNoDraw = 0xFFFFFFFFu;
  uint8_t kind = 0;  // transactions.bin: 0 work, 1 clear, 2 end of frame
  uint8_t prim_kind = kPrimKindNone;
  uint32_t draw = kNoDraw;
  int64_t prim_first = -1, prim_last = -1;  // -1: none
  int16_t tile_x = -1, tile_y = -1;         // -1: not in one tile
  uint32_t count = 1;
  uint32_t first_slot = 0;  // vertex batches: the draw's slot of the first one
  bool is_batch = false;    // a vertex batch (names slots in the timeline)
};

// Turns packets into ItemInfo. The frame must outlive it.
class ItemDescriber {
 public:
  ItemDescriber(const FrameState& frame, unsigned tile_size);

  // A command: a draw carries every primitive of the draw; count = primitives.
  ItemInfo describe(const Command& c) const;
  // A vertex batch: the primitives whose assembly uses any of its slots;
  // count = slots.
  ItemInfo describe(const BatchHeader& b) const;
  ItemInfo describe(const ClippedPrimitive& t) const;
  ItemInfo describe(const SetupPacket& p) const;
  // Stamp batches: the tile of the first stamp's origin; count = stamps.
  ItemInfo describe(const StampBatch& b) const;
  ItemInfo describe(const ShadedStampBatch& b) const;
  ItemInfo describe(const ControlToken& t) const { return control(t.kind); }

 private:
  ItemInfo control(PacketKind kind) const;
  ItemInfo stamps(PacketKind kind, const RasterPrimitive* tri, const std::vector<Stamp>& s) const;

  const FrameState& m_frame;
  int m_tile_shift;
};

}  // namespace gpusim
