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
// Widths, as hardware would carry them (float32 components):
// - ClippedVertex: x, y, z, 1/w and 12 varyings: 16 words, 512 bits.
// - ClippedPrimitive: 3 vertices and 12 flat-shading varyings, 1920 bits,
//   plus a header of packet kind (2 bits), primitive kind (2), vertex count
//   (2), draw id (32) and primitive id (64).
// - RasterPrimitive: 3 x 12 varyings over w and 12 flat ones, 1536 bits;
//   z and 1/w, 192; snapped vertices, area2, the interpolation and coverage
//   equations (6 x about 105 bits), pixel box and polygon offset at the
//   widths hw/fixed_point.h proves, and the line fields (rule, width, the
//   Bresenham end pixels and flags, about 80), about 1000; plus the header
//   above.
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
#include "hw/primitive_kind.h"
#include "hw/varying_layout.h"

namespace gpusim {

enum class PacketKind : uint8_t {
  work,          // a draw, a triangle, stamps
  clear,         // clear colour and depth to the frame's clear values
  end_of_frame,  // flush and report completion
};
std::ostream& operator<<(std::ostream& os, PacketKind k);

// Driver -> command processor -> vertex fetch.
struct Command {
  PacketKind kind = PacketKind::work;  // work: draw `draw_id`
  uint32_t draw_id = 0;
  bool operator==(const Command& o) const { return kind == o.kind && draw_id == o.draw_id; }
};
std::ostream& operator<<(std::ostream& os, const Command& c);

// Vertex slots in a primitive packet: a triangle's.
constexpr unsigned kMaxPrimitiveVertices = 3;

// A vertex leaving the clipper: window coordinates before snapping
// (docs/pipeline-spec.md, section 5), and the draw's varyings times 1/w, which
// the interpolator divides by the interpolated 1/w (perspective correction).
struct ClippedVertex {
  float x = 0.0f, y = 0.0f, z = 0.0f;
  float inv_w = 0.0f;  // the attribute weight: 1/w, or 1 with screen interpolation
  Varyings varyings_over_w{};
  bool operator==(const ClippedVertex& o) const {
    return x == o.x && y == o.y && z == o.z && inv_w == o.inv_w &&
           varyings_over_w == o.varyings_over_w;
  }
};

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
  bool operator==(const ClippedPrimitive& o) const;
};
std::ostream& operator<<(std::ostream& os, const ClippedPrimitive& t);

// Edge function E(px, py) = a * px + b * py + c over subpixel coordinates:
// for the edge from (Xa, Ya) to (Xb, Yb), a = -(Yb - Ya), b = Xb - Xa,
// c = (Yb - Ya) * Xa - (Xb - Xa) * Ya, which equals the spec's
// (Xb - Xa)(py - Ya) - (Yb - Ya)(px - Xa) exactly. |a|, |b| < 2^25 and
// |c| < 2^50 (hw/fixed_point.h), so every evaluation fits int64.
struct EdgeEquation {
  EdgeValue a = 0, b = 0, c = 0;
  EdgeValue bias = 0;  // 0 when the edge owns its boundary, else 1: covered iff E - bias >= 0
  EdgeValue at(Subpixel px, Subpixel py) const { return a * px + b * py + c; }
  bool operator==(const EdgeEquation& o) const {
    return a == o.a && b == o.b && c == o.c && bias == o.bias;
  }
};

// How a line's pixels are found (docs/pipeline-spec.md, section 8b).
enum class LineRule : uint8_t {
  none,          // a triangle or a point
  diamond_exit,  // coverage edges, like a triangle (a parallelogram)
  bresenham,     // the rasterizer's line walker
  rectangle,     // multisampled (section 14): four coverage edges
};

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
  bool operator==(const RasterPrimitive& o) const;
};
std::ostream& operator<<(std::ostream& os, const RasterPrimitive& t);

// Primitive setup -> tile distributor -> each tile rasterizer unit.
struct SetupPacket {
  PacketKind kind = PacketKind::work;
  std::shared_ptr<const RasterPrimitive> primitive;  // work only
  bool operator==(const SetupPacket& o) const;
  friend void swap(SetupPacket& a, SetupPacket& b) noexcept {
    std::swap(a.kind, b.kind);
    a.primitive.swap(b.primitive);
  }
};
std::ostream& operator<<(std::ostream& os, const SetupPacket& p);

// A stamp: stamp_w x stamp_h pixels with origin pixel (x, y) at its lower left.
// Bit i of `mask` is pixel (x + i % stamp_w, y + i / stamp_w). `e` holds the
// three raw edge values (without bias) at the origin pixel's centre; the back
// end steps them by the triangle's edge coefficients to reach any pixel.
struct Stamp {
  int32_t x = 0, y = 0;
  uint64_t mask = 0;
  std::array<EdgeValue, 3> e{};
  bool operator==(const Stamp& o) const {
    return x == o.x && y == o.y && mask == o.mask && e == o.e;
  }
};

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
  bool operator==(const StampBatch& o) const;
  friend void swap(StampBatch& a, StampBatch& b) noexcept {
    std::swap(a.kind, b.kind);
    std::swap(a.hz_seq, b.hz_seq);
    a.primitive.swap(b.primitive);
    a.stamps.swap(b.stamps);
    a.samples.swap(b.samples);
  }
};
std::ostream& operator<<(std::ostream& os, const StampBatch& b);

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
  bool operator==(const ShadedStampBatch& o) const;
  friend void swap(ShadedStampBatch& a, ShadedStampBatch& b) noexcept {
    std::swap(a.kind, b.kind);
    a.primitive.swap(b.primitive);
    a.stamps.swap(b.stamps);
    a.colors.swap(b.colors);
    a.samples.swap(b.samples);
  }
};
std::ostream& operator<<(std::ostream& os, const ShadedStampBatch& b);

// ROP -> resolve, per unit (multisampled or supersampled frames only): the
// control tokens the ROP retired, so the resolve starts once every unit has
// flushed its tiles.
struct ControlToken {
  PacketKind kind = PacketKind::end_of_frame;
  bool operator==(const ControlToken& o) const { return kind == o.kind; }
};
std::ostream& operator<<(std::ostream& os, const ControlToken& t);

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
