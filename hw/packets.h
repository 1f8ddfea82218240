// Packets crossing the FIFOs between stage groups. Small value types: no
// owning raw pointers; a triangle set up once is shared read-only by every
// unit and stage that needs it. Control tokens (clear, end of frame) travel
// in band, so they stay ordered with the work around them. Packets holding
// buffers have a member-wise swap(): a FIFO exchanges packets with its slots
// (hw/fifo.h), and swapping the members is a few pointer exchanges, where the
// generic std::swap moves everything three times.
//
// After assembly the packets are primitive-generic: a ClippedPrimitive and a
// RasterPrimitive name their kind (point, line, triangle) and vertex count
// (1, 2, 3), in vertex slots sized for a triangle. Every vertex carries its
// draw's varyings as one fixed-capacity array, Varyings (kMaxVaryings = 12
// float32 components, hw/varying_layout.h), whose meaning the draw's
// VaryingLayout gives; the stages loop over the draw's `count` components
// without knowing what they are. 12 holds what is planned: colour 4,
// eye-space normal 3 and position 3, texture coordinate 2.
//
// Widths: each packet lists its fields once (hw/packet_fields.h) with the
// width hardware would carry each in (float32 components; the integer
// formats of hw/fixed_point.h, field_bits), and a static_assert below it
// holds the total:
// - ClippedVertex: x, y, z, 1/w and 12 varyings: 16 words, 512 bits.
// - ClippedPrimitive: 3 vertices, 12 flat-shading varyings and the line end
//   flags, 1922 bits, plus a header of packet kind (2 bits), primitive kind
//   (2), vertex count (2), draw id (32) and primitive id (64): 2024.
// - RasterPrimitive: 3 x 12 varyings over w and 12 flat ones, 1536 bits;
//   z and 1/w, 192; snapped vertices and area2, 207; the interpolation and
//   coverage equations, 7 x 106 and a count; pixel box, polygon offset and
//   the line fields (rule, width, the Bresenham end pixels and flags), 177;
//   with the header, 2957 bits.
// - Stamp batches: a header (kind, the primitive, 32 bits of hierarchical-Z
//   sequence) and per stamp 251 bits, per covered pixel a 16-bit sample mask
//   and, shaded, a 128-bit colour.
// A draw uses only its `count` components (4 today, so 8 words per clipped
// vertex), which is what hardware would move; the model keeps the full
// capacity in every packet so that packets have one fixed size and moving a
// vertex allocates nothing.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <ostream>
#include <utility>
#include <vector>

#include "hw/fixed_point.h"
#include "hw/packet_fields.h"
#include "hw/primitive_kind.h"
#include "hw/varying_layout.h"

namespace gpusim {

enum class PacketKind : uint8_t {
  work,          // a draw, a triangle, stamps
  clear,         // clear colour and depth to the frame's clear values
  end_of_frame,  // flush and report completion
};
std::ostream& operator<<(std::ostream& os, PacketKind k);
constexpr unsigned hardware_bits(PacketKind) {
  return 2;
}
constexpr unsigned hardware_bits(PrimitiveKind) {
  return 2;
}

// Driver -> command processor -> vertex fetch.
struct Command {
  PacketKind kind = PacketKind::work;  // work: draw `draw_id`
  uint32_t draw_id = 0;

  static constexpr const char* kPacketName = "Command";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    v("kind", &Command::kind, control);
    v("draw_id", &Command::draw_id);
  }
};
static_assert(packet_bits<Command>() == 34);

// Vertex slots in a primitive packet: a triangle's.
constexpr unsigned kMaxPrimitiveVertices = 3;

// A vertex leaving the clipper: window coordinates before snapping
// (docs/pipeline-spec.md, section 5), and the draw's varyings times 1/w, which
// the interpolator divides by the interpolated 1/w (perspective correction).
struct ClippedVertex {
  float x = 0.0f, y = 0.0f, z = 0.0f;
  float inv_w = 0.0f;  // the attribute weight: 1/w, or 1 with screen interpolation
  Varyings varyings_over_w{};

  static constexpr const char* kPacketName = "ClippedVertex";
  template <typename V>
  static constexpr void fields(V& v) {
    v("x", &ClippedVertex::x);
    v("y", &ClippedVertex::y);
    v("z", &ClippedVertex::z);
    v("inv_w", &ClippedVertex::inv_w);
    v("varyings_over_w", &ClippedVertex::varyings_over_w);
  }
};
static_assert(packet_bits<ClippedVertex>() == 512);

// Clipper -> primitive setup: one primitive, v[0, vertex_count) in use.
struct ClippedPrimitive {
  PacketKind kind = PacketKind::work;
  PrimitiveKind primitive_kind = PrimitiveKind::triangle;
  uint8_t vertex_count = vertex_count_of(PrimitiveKind::triangle);
  uint32_t draw_id = 0;
  int64_t primitive_id = 0;
  std::array<ClippedVertex, kMaxPrimitiveVertices> v;
  // The provoking vertex's varyings (not divided by w), for flat shading.
  Varyings flat_varyings{};
  // Lines: whether the Bresenham rule draws the first and the last pixel
  // (docs/pipeline-spec.md, section 3: a strip's shared vertices once).
  bool draw_first = true, draw_last = true;

  static constexpr const char* kPacketName = "ClippedPrimitive";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    using P = ClippedPrimitive;
    v("kind", &P::kind, control);
    v("primitive_kind", &P::primitive_kind);
    v("vertex_count", &P::vertex_count, bits(2));
    v("draw_id", &P::draw_id);
    v("primitive_id", &P::primitive_id);
    v("v", &P::v, used(&P::vertex_count));
    v("flat_varyings", &P::flat_varyings);
    v("draw_first", &P::draw_first);
    v("draw_last", &P::draw_last);
  }
};
static_assert(packet_bits<ClippedPrimitive>() == 2024);

// Edge function E(px, py) = a * px + b * py + c over subpixel coordinates:
// for the edge from (Xa, Ya) to (Xb, Yb), a = -(Yb - Ya), b = Xb - Xa,
// c = (Yb - Ya) * Xa - (Xb - Xa) * Ya, which equals the spec's
// (Xb - Xa)(py - Ya) - (Yb - Ya)(px - Xa) exactly. |a|, |b| < 2^25 and
// |c| < 2^50 (hw/fixed_point.h), so every evaluation fits int64.
struct EdgeEquation {
  EdgeValue a = 0, b = 0, c = 0;
  EdgeValue bias = 0;  // 0 when the edge owns its boundary, else 1: covered iff E - bias >= 0
  EdgeValue at(Subpixel px, Subpixel py) const { return a * px + b * py + c; }

  static constexpr const char* kPacketName = "EdgeEquation";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    v("a", &EdgeEquation::a, bits(field_bits::kEdgeCoefficient));
    v("b", &EdgeEquation::b, bits(field_bits::kEdgeCoefficient));
    v("c", &EdgeEquation::c, bits(field_bits::kEdgeValue));
    v("bias", &EdgeEquation::bias, bits(1));
  }
};
static_assert(packet_bits<EdgeEquation>() == 106);

// How a line's pixels are found (docs/pipeline-spec.md, section 8b).
enum class LineRule : uint8_t {
  none,          // a triangle or a point
  diamond_exit,  // coverage edges, like a triangle (a parallelogram)
  bresenham,     // the rasterizer's line walker
  rectangle,     // multisampled (section 14): four coverage edges
};
std::ostream& operator<<(std::ostream& os, LineRule r);
constexpr unsigned hardware_bits(LineRule) {
  return 2;
}

// Primitive setup's result, for every primitive kind. Two sets of equations:
//
// - `edge` and `area2` are the *interpolation* functions the depth test and
//   interpolator use (docs/pipeline-spec.md, section 9), with the vertices in
//   slots 0-2. A triangle: counter-clockwise, edge k opposite vertex k
//   (E0 = edge v1 -> v2, E1 = v2 -> v0, E2 = v0 -> v1), area2 > 0. A line
//   (a, b): slots (a, b, a), E0 = L2 - T, E1 = T, E2 = 0 (a = b = c = 0),
//   area2 = L2, with T = (px - Xa) dx + (py - Ya) dy and L2 = dx^2 + dy^2
//   (a Bresenham line of zero length, and a point: E0 = 1, area2 = 1).
// - `coverage[0, coverage_count)` are the edges the tile rasterizer tests,
//   each with its bias: a pixel centre inside the box is covered iff
//   E - bias >= 0 for all of them. A triangle: its three edges (equal to
//   `edge`). A diamond-exit line: the two sides of its band (section 8b's
//   integer form), the box bounding its first and last column (row). A point:
//   none, the box is the square. A Bresenham line: none; the walker uses
//   `ia`, `ib`, `width` and the end flags instead. Multisampled (section
//   14): a line's rectangle and a point's square are four edges each, and
//   the box holds every pixel with a sample inside the primitive's box.
//
// Widths (hw/fixed_point.h): line equations have |a|, |b| < 2^25 (a delta)
// and |c| < 2^51 (L2 plus two products < 2^49), so |E| < 2^52 at any pixel
// centre of the framebuffer; band edges add at most 128 * 255 * 2^25 < 2^40
// to c. int64 holds all of them.
struct RasterPrimitive {
  PrimitiveKind primitive_kind = PrimitiveKind::triangle;
  uint8_t vertex_count = vertex_count_of(PrimitiveKind::triangle);
  uint32_t draw_id = 0;
  int64_t primitive_id = 0;
  std::array<Subpixel, 3> x{}, y{};
  EdgeValue area2 = 0;  // > 0
  std::array<EdgeEquation, 3> edge;
  // A multisampled line's rectangle is the most any kind needs; a
  // triangle has three, a diamond-exit line two (its ends are its box's
  // sides), a single-sampled point none (it is its box).
  static constexpr unsigned kMaxCoverageEdges = 4;
  std::array<EdgeEquation, kMaxCoverageEdges> coverage{};
  uint8_t coverage_count = 3;
  int32_t x0 = 0, y0 = 0, x1 = -1,
          y1 = -1;  // pixel bounding box, inclusive, inside the framebuffer
  std::array<float, 3> z{}, inv_w{};
  std::array<Varyings, 3> varyings_over_w{};  // as ClippedVertex
  Varyings flat_varyings{};                   // as ClippedPrimitive
  bool has_depth_offset = false;
  float depth_offset = 0.0f;
  // Lines and points.
  LineRule line_rule = LineRule::none;
  uint16_t width = 1;  // a line's width in pixels, max(1, round(line_width)), 1..255
  // Bresenham: the end points' pixels (floor(X / 256), floor(Y / 256)), and
  // whether the first and last pixel are drawn (ClippedPrimitive).
  int32_t ia_x = 0, ia_y = 0, ib_x = 0, ib_y = 0;
  bool draw_first = true, draw_last = true;

  static constexpr const char* kPacketName = "RasterPrimitive";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    using P = RasterPrimitive;
    namespace w = field_bits;
    v("primitive_kind", &P::primitive_kind);
    v("vertex_count", &P::vertex_count, bits(2));
    v("draw_id", &P::draw_id);
    v("primitive_id", &P::primitive_id);
    v("x", &P::x, bits(w::kSubpixel));
    v("y", &P::y, bits(w::kSubpixel));
    v("area2", &P::area2, bits(w::kArea2));
    v("edge", &P::edge);
    v("coverage", &P::coverage, used(&P::coverage_count));
    v("coverage_count", &P::coverage_count, bits(3));
    v("x0", &P::x0, bits(w::kPixel + 1));  // an empty box is [0..-1]
    v("y0", &P::y0, bits(w::kPixel + 1));
    v("x1", &P::x1, bits(w::kPixel + 1));
    v("y1", &P::y1, bits(w::kPixel + 1));
    v("z", &P::z);
    v("inv_w", &P::inv_w);
    v("varyings_over_w", &P::varyings_over_w);
    v("flat_varyings", &P::flat_varyings);
    v("has_depth_offset", &P::has_depth_offset);
    v("depth_offset", &P::depth_offset);
    v("line_rule", &P::line_rule);
    v("width", &P::width, bits(8));
    v("ia_x", &P::ia_x, bits(w::kSnappedPixel));
    v("ia_y", &P::ia_y, bits(w::kSnappedPixel));
    v("ib_x", &P::ib_x, bits(w::kSnappedPixel));
    v("ib_y", &P::ib_y, bits(w::kSnappedPixel));
    v("draw_first", &P::draw_first);
    v("draw_last", &P::draw_last);
  }
};
static_assert(packet_bits<RasterPrimitive>() == 2957);

// Primitive setup -> tile distributor -> each tile rasterizer unit.
struct SetupPacket {
  PacketKind kind = PacketKind::work;
  std::shared_ptr<const RasterPrimitive> primitive;  // work only

  static constexpr const char* kPacketName = "SetupPacket";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    v("kind", &SetupPacket::kind, control);
    v("primitive", &SetupPacket::primitive);
  }
  friend void swap(SetupPacket& a, SetupPacket& b) noexcept {
    std::swap(a.kind, b.kind);
    a.primitive.swap(b.primitive);
  }
};
static_assert(packet_bits<SetupPacket>() == 2 + packet_bits<RasterPrimitive>());

// A stamp: stamp_w x stamp_h pixels with origin pixel (x, y) at its lower left.
// Bit i of `mask` is pixel (x + i % stamp_w, y + i / stamp_w). `e` holds the
// three raw edge values (without bias) at the origin pixel's centre; the back
// end steps them by the triangle's edge coefficients to reach any pixel.
struct Stamp {
  int32_t x = 0, y = 0;
  uint64_t mask = 0;
  std::array<EdgeValue, 3> e{};

  static constexpr const char* kPacketName = "Stamp";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    v("x", &Stamp::x, bits(field_bits::kPixel));
    v("y", &Stamp::y, bits(field_bits::kPixel));
    v("mask", &Stamp::mask, hex);
    v("e", &Stamp::e, bits(field_bits::kEdgeValue));
  }
};
static_assert(packet_bits<Stamp>() == 2 * 14 + 64 + 3 * 53);

// Rasterizer -> depth test -> interpolator, per unit: the stamps one triangle
// covers in one tile, in the order the unit walked them.
struct StampBatch {
  PacketKind kind = PacketKind::work;
  std::shared_ptr<const RasterPrimitive> primitive;
  std::vector<Stamp> stamps;
  // Multisampling (docs/pipeline-spec.md, section 14): per covered pixel
  // (stamp order, then bit order), its covered samples, bit s for sample s;
  // empty with one sample per pixel, where a covered pixel is its sample.
  std::vector<uint16_t> samples;
  // Hierarchical Z (hw/hierarchical_z.h): the tile's sequence number when the
  // batch may write depth and hierarchical Z is on, so the depth test's exact
  // update names the batch it follows; 0 otherwise (no update).
  uint32_t hz_seq = 0;

  static constexpr const char* kPacketName = "StampBatch";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    v("kind", &StampBatch::kind, control);
    v("primitive", &StampBatch::primitive);
    v("stamps", &StampBatch::stamps);
    v("samples", &StampBatch::samples);
    v("hz_seq", &StampBatch::hz_seq);
  }
  friend void swap(StampBatch& a, StampBatch& b) noexcept {
    std::swap(a.kind, b.kind);
    std::swap(a.hz_seq, b.hz_seq);
    a.primitive.swap(b.primitive);
    a.stamps.swap(b.stamps);
    a.samples.swap(b.samples);
  }
};
static_assert(packet_bits<StampBatch>() == 2 + packet_bits<RasterPrimitive>() + 32,
              "the header: kind, primitive, hz_seq; a stamp and a sample mask (16) each");

// Interpolator -> ROP, per unit: surviving stamps and a colour per covered
// pixel (stamp order, then bit order). A colour, not the pixel's varyings:
// the colour is what the ROP blends, and the interpolator takes it from the
// layout's colour slot, or for a Phong draw lights the pixel from its
// interpolated normal and eye position (docs/pipeline-spec.md, 9b).
struct ShadedStampBatch {
  PacketKind kind = PacketKind::work;
  std::shared_ptr<const RasterPrimitive> primitive;
  std::vector<Stamp> stamps;
  std::vector<glm::vec4> colors;
  std::vector<uint16_t> samples;  // as StampBatch: the samples each colour goes to
  // Textured draws, interpolator -> texture unit (docs/pipeline-spec.md,
  // section 9c): per covered pixel its texture coordinate (s, t); empty
  // otherwise, and once the texture unit has applied the texture.
  std::vector<glm::vec2> texcoords;
  // With them, when the texture's sampling needs the level of detail: per
  // covered pixel the coordinate's derivatives over its 2x2 quad (ds/dx,
  // dt/dx, ds/dy, dt/dy); empty otherwise.
  std::vector<glm::vec4> texcoord_derivatives;

  static constexpr const char* kPacketName = "ShadedStampBatch";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    v("kind", &ShadedStampBatch::kind, control);
    v("primitive", &ShadedStampBatch::primitive);
    v("stamps", &ShadedStampBatch::stamps);
    v("colors", &ShadedStampBatch::colors);
    v("samples", &ShadedStampBatch::samples);
    v("texcoords", &ShadedStampBatch::texcoords);
    v("texcoord_derivatives", &ShadedStampBatch::texcoord_derivatives);
  }
  friend void swap(ShadedStampBatch& a, ShadedStampBatch& b) noexcept {
    std::swap(a.kind, b.kind);
    a.primitive.swap(b.primitive);
    a.stamps.swap(b.stamps);
    a.colors.swap(b.colors);
    a.samples.swap(b.samples);
    a.texcoords.swap(b.texcoords);
    a.texcoord_derivatives.swap(b.texcoord_derivatives);
  }
};
static_assert(packet_bits<ShadedStampBatch>() == 2 + packet_bits<RasterPrimitive>(),
              "the header: kind, primitive; a stamp, a colour (128) and a sample mask each");

// ROP -> resolve, per unit (multisampled or supersampled frames only): the
// control tokens the ROP retired, so the resolve starts once every unit has
// flushed its tiles.
struct ControlToken {
  PacketKind kind = PacketKind::end_of_frame;

  static constexpr const char* kPacketName = "ControlToken";
  template <typename V>
  static constexpr void fields(V& v) {
    v("kind", &ControlToken::kind);
  }
};
static_assert(packet_bits<ControlToken>() == 2);

// Screen tiles: tile (tx, ty) covers pixels [tx * size, (tx + 1) * size) x
// [ty * size, ...). Ownership interleaves diagonally so neighbouring tiles
// go to different units and a triangle's work spreads across them.
inline unsigned tile_owner(int tx, int ty, unsigned units) {
  return static_cast<unsigned>(tx + ty) % units;
}

// Tile and stamp sides are powers of two (docs/gpu-config.md), so a pixel's
// tile, or a stamp pixel's row, is found with a shift by log2(side), as
// hardware does. Throws std::invalid_argument if `side` is not a power of two.
int log2_side(unsigned side);

}  // namespace gpusim
