// Packets inside the geometry front end: vertex fetch -> vertex shader ->
// clipper. A batch carries up to kVertexBatchSlots consecutive vertex slots of
// one draw in fixed-size arrays, so a packet has a known size and moving it
// through a FIFO allocates nothing.
//
// The post-transform vertex cache is split the way hardware splits it: vertex
// fetch owns the tags (it decides hit or miss and which entry a miss fills),
// the clipper owns the data (the shaded vertices). Each slot tells the clipper
// what fetch decided, and since both see the slots in the same order the two
// halves never disagree, whatever the timing.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <ostream>

#include "hw/packets.h"
#include "hw/varying_layout.h"

namespace gpusim {

// Slots per batch: 32 uint32 indices are one 128-byte index read.
constexpr uint32_t kVertexBatchSlots = 32;
// A slot's cache entry when the cache does not hold it.
constexpr uint32_t kNoCacheEntry = ~uint32_t{0};

enum class SlotKind : uint8_t {
  fetched,  // a new vertex: its attributes are in the batch, it is shaded
  cached,   // a cache hit: the clipper reads the shaded vertex from `entry`
  invalid,  // the index is not below the draw's vertex count: no vertex
};
std::ostream& operator<<(std::ostream& os, SlotKind k);
constexpr unsigned hardware_bits(SlotKind) {
  return 2;
}

struct VertexSlot {
  SlotKind kind = SlotKind::invalid;
  // fetched: the cache entry the shaded vertex is stored in (kNoCacheEntry
  // when the draw is not indexed or the cache is disabled); cached: the entry
  // holding it.
  uint32_t entry = kNoCacheEntry;
  uint32_t vertex = 0;  // fetched: its position in the batch's vertex arrays

  static constexpr const char* kPacketName = "VertexSlot";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    v("kind", &VertexSlot::kind);
    v("entry", &VertexSlot::entry);
    v("vertex", &VertexSlot::vertex, bits(5));  // 0..31
  }
};
static_assert(kVertexBatchSlots <= 32, "a slot's vertex index is 5 bits");

// The common header: which slots of which draw the batch holds.
struct BatchHeader {
  PacketKind kind = PacketKind::work;  // control tokens carry no slots
  uint32_t draw_id = 0;
  uint32_t first_slot = 0;    // slot number of slots[0] within the draw
  uint32_t slot_count = 0;    // 1..kVertexBatchSlots for work
  uint32_t vertex_count = 0;  // fetched slots, i.e. vertices in the arrays below
  std::array<VertexSlot, kVertexBatchSlots> slots{};

  // The header's fields, first in both batches (each lists its own).
  template <typename V>
  static constexpr void header_fields(V& v) {
    using namespace packet_fields;
    using H = BatchHeader;
    v("kind", &H::kind, control);
    v("draw_id", &H::draw_id);
    v("first_slot", &H::first_slot);
    v("slot_count", &H::slot_count, bits(6));      // 1..32
    v("vertex_count", &H::vertex_count, bits(6));  // 0..32
    v("slots", &H::slots, used(&H::slot_count));
  }
};

// Vertex fetch -> vertex shader: the raw attributes of the fetched vertices,
// as read from memory. `normals` is filled only for lit draws with a normal
// array, `colors` only for draws with a colour array, `texcoords` only for
// textured draws.
struct VertexBatch : BatchHeader {
  std::array<glm::vec4, kVertexBatchSlots> positions{};
  std::array<glm::vec3, kVertexBatchSlots> normals{};
  std::array<glm::vec4, kVertexBatchSlots> colors{};
  std::array<glm::vec2, kVertexBatchSlots> texcoords{};

  static constexpr const char* kPacketName = "VertexBatch";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    header_fields(v);
    v("positions", &VertexBatch::positions, used(&BatchHeader::vertex_count));
    v("normals", &VertexBatch::normals, used(&BatchHeader::vertex_count));
    v("colors", &VertexBatch::colors, used(&BatchHeader::vertex_count));
    v("texcoords", &VertexBatch::texcoords, used(&BatchHeader::vertex_count));
  }
};
static_assert(packet_bits<VertexBatch>() == 1326 + 32 * (128 + 96 + 128 + 64),
              "a header (2 + 3 x 32 + 2 x 6 + 32 slots x 39 bits) and 32 fetched vertices");

// A vertex after transform and lighting (docs/pipeline-spec.md, section 2):
// its clip-space position and its varyings, laid out by its draw's
// VaryingLayout (hw/varying_layout.h).
struct ShadedVertex {
  glm::vec4 clip{0.0f};
  Varyings varyings{};

  static constexpr const char* kPacketName = "ShadedVertex";
  template <typename V>
  static constexpr void fields(V& v) {
    v("clip", &ShadedVertex::clip);
    v("varyings", &ShadedVertex::varyings);
  }
};
static_assert(packet_bits<ShadedVertex>() == 512);

// Vertex shader -> clipper: the same slots, the fetched vertices shaded.
struct ShadedBatch : BatchHeader {
  std::array<ShadedVertex, kVertexBatchSlots> vertices{};

  static constexpr const char* kPacketName = "ShadedBatch";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    header_fields(v);
    v("vertices", &ShadedBatch::vertices, used(&BatchHeader::vertex_count));
  }
};
static_assert(packet_bits<ShadedBatch>() == 1326 + 32 * 512, "a header and 32 shaded vertices");

}  // namespace gpusim
