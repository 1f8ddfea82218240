// Packets (hw/packets.h, hw/vertex_packets.h) and varying layouts
// (hw/varying_layout.h): each packet's field list (hw/packet_fields.h) gives
// its equality, its printer and its width; the primitive kind and vertex
// count are printed and compared like every other field, and a layout hands
// out its components.
#include <gtest/gtest.h>

#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "hw/draw_state.h"
#include "hw/packets.h"
#include "hw/vertex_packets.h"

namespace gpusim {
namespace {

template <typename T>
std::string print(const T& v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

size_t occurrences(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

ClippedPrimitive triangle() {
  ClippedPrimitive t;
  t.draw_id = 2;
  t.primitive_id = 17;
  for (int i = 0; i < 3; ++i) {
    t.v[i].x = 10.0f * i;
    t.v[i].y = 5.0f;
    t.v[i].inv_w = 1.0f;
    t.v[i].varyings_over_w[0] = 0.25f * i;
  }
  t.flat_varyings[0] = 0.5f;
  t.flat_varyings[3] = 1.0f;
  return t;
}

ClippedPrimitive line() {
  ClippedPrimitive t = triangle();
  t.primitive_kind = PrimitiveKind::line;
  t.vertex_count = vertex_count_of(PrimitiveKind::line);
  return t;
}

TEST(PrimitiveKind, NamesAndVertexCounts) {
  EXPECT_EQ(print(PrimitiveKind::point), "point");
  EXPECT_EQ(print(PrimitiveKind::line), "line");
  EXPECT_EQ(print(PrimitiveKind::triangle), "triangle");
  EXPECT_EQ(vertex_count_of(PrimitiveKind::point), 1);
  EXPECT_EQ(vertex_count_of(PrimitiveKind::line), 2);
  EXPECT_EQ(vertex_count_of(PrimitiveKind::triangle), 3);
  EXPECT_EQ(vertex_count_of(PrimitiveKind::triangle), kMaxPrimitiveVertices);
}

TEST(ClippedPrimitive, DefaultsToATriangle) {
  const ClippedPrimitive t;
  EXPECT_EQ(t.primitive_kind, PrimitiveKind::triangle);
  EXPECT_EQ(t.vertex_count, 3);
}

TEST(ClippedPrimitive, PrintsKindVertexCountAndItsVertices) {
  const std::string t = print(triangle());
  EXPECT_EQ(
      t.rfind("ClippedPrimitive{kind work, primitive_kind triangle, vertex_count 3, draw_id 2, "
              "primitive_id 17, v (ClippedVertex{x 0, y 5, z 0, inv_w 1, ",
              0),
      0u)
      << t;
  EXPECT_EQ(occurrences(t, "inv_w"), 3u) << t;
  // Trailing zeros past the first four components are counted, not listed.
  EXPECT_NE(t.find("flat_varyings (0.5, 0, 0, 1, 0 x8), draw_first true, draw_last true}"),
            std::string::npos)
      << t;
  const std::string l = print(line());
  EXPECT_NE(l.find("primitive_kind line, vertex_count 2"), std::string::npos) << l;
  EXPECT_EQ(occurrences(l, "inv_w"), 2u) << l;  // the unused third slot is not printed
  ClippedPrimitive eof;
  eof.kind = PacketKind::end_of_frame;
  EXPECT_EQ(print(eof), "ClippedPrimitive{kind end_of_frame}");
}

TEST(ClippedPrimitive, ComparesKindVertexCountAndVaryings) {
  // Vertex slots past vertex_count are not part of the primitive.
  ClippedPrimitive unused = line();
  unused.v[2].x = 123.0f;
  unused.v[2].varyings_over_w[0] = 7.0f;
  EXPECT_TRUE(unused == line());
  EXPECT_FALSE(line() == triangle());
  ClippedPrimitive two = triangle();
  two.vertex_count = 2;  // the kind alone agreeing is not enough
  EXPECT_FALSE(two == triangle());
  ClippedPrimitive v = triangle();
  v.v[1].varyings_over_w[kMaxVaryings - 1] = 1.0f;
  EXPECT_FALSE(v == triangle());
  ClippedPrimitive f = triangle();
  f.flat_varyings[kMaxVaryings - 1] = 1.0f;
  EXPECT_FALSE(f == triangle());
  // Vertices past vertex_count are unused: not compared.
  ClippedPrimitive a = line(), b = line();
  b.v[2].x = 99.0f;
  EXPECT_EQ(a, b);
}

TEST(RasterPrimitive, PrintsAndComparesKindAndVertexCount) {
  RasterPrimitive r;
  r.draw_id = 1;
  r.primitive_id = 4;
  r.flat_varyings = {0.25f, 0.5f};
  const std::string s = print(r);
  EXPECT_EQ(s.rfind("RasterPrimitive{primitive_kind triangle, vertex_count 3, draw_id 1, "
                    "primitive_id 4, ",
                    0),
            0u)
      << s;
  EXPECT_NE(s.find("flat_varyings (0.25, 0.5, 0, 0, 0 x8)"), std::string::npos) << s;
  EXPECT_NE(s.find("line_rule none"), std::string::npos) << s;
  RasterPrimitive p = r;
  EXPECT_EQ(p, r);
  p.primitive_kind = PrimitiveKind::point;
  EXPECT_FALSE(p == r);
  p = r;
  p.vertex_count = 1;
  EXPECT_FALSE(p == r);
  p = r;
  p.varyings_over_w[2][kMaxVaryings - 1] = 3.0f;
  EXPECT_FALSE(p == r);
}

TEST(RasterPrimitive, UnusedCoverageEdgesAreNotCompared) {
  RasterPrimitive a;
  a.coverage_count = 2;
  RasterPrimitive b = a;
  b.coverage[3].c = 7;  // past coverage_count
  EXPECT_EQ(a, b);
  b.coverage[1].c = 7;
  EXPECT_FALSE(a == b);
  EXPECT_EQ(print(a).find("EdgeEquation{a 0, b 0, c 7"), std::string::npos);
  EXPECT_NE(print(b).find("coverage (EdgeEquation{a 0, b 0, c 0, bias 0}, "
                          "EdgeEquation{a 0, b 0, c 7, bias 0}), coverage_count 2"),
            std::string::npos)
      << print(b);
}

// The widths the field lists give, summed here by hand from the documented
// formats (hw/fixed_point.h, field_bits): a packet's width changes only with
// its field list, and the headers' static_asserts hold the same sums.
TEST(PacketBits, SumTheDocumentedFieldWidths) {
  EXPECT_EQ(packet_bits<Command>(), 2u + 32u);
  EXPECT_EQ(packet_bits<ClippedVertex>(), 16u * 32u);
  // kind, primitive kind, vertex count, draw, primitive id; 3 vertices; 12
  // flat varyings; two end flags.
  EXPECT_EQ(packet_bits<ClippedPrimitive>(), 2u + 2u + 2u + 32u + 64u + 3u * 512u + 384u + 2u);
  // a, b: a difference of snapped coordinates and a sign (26); c: below 2^52
  // and a sign (53); the bias bit.
  EXPECT_EQ(packet_bits<EdgeEquation>(), 26u + 26u + 53u + 1u);
  EXPECT_EQ(packet_bits<Stamp>(), 14u + 14u + 64u + 3u * 53u);
  const size_t raster = 2 + 2 + 32 + 64     // header
                        + 6 * 26 + 51       // snapped vertices, area2
                        + 7 * 106 + 3       // 3 + 4 edges, coverage count
                        + 4 * 15            // pixel box
                        + 6 * 32 + 4 * 384  // z, 1/w, varyings, flat varyings
                        + 1 + 32 + 2 + 8    // offset, line rule, width
                        + 4 * 18 + 2;       // Bresenham end pixels, flags
  EXPECT_EQ(packet_bits<RasterPrimitive>(), raster);
  // A shared primitive counts as carried; vectors are the variable part.
  EXPECT_EQ(packet_bits<SetupPacket>(), 2 + raster);
  EXPECT_EQ(packet_bits<StampBatch>(), 2 + raster + 32);
  EXPECT_EQ(packet_bits<ControlToken>(), 2u);
  EXPECT_EQ(packet_bits<VertexSlot>(), 2u + 32u + 5u);
  EXPECT_EQ(packet_bits<ShadedVertex>(), 128u + 384u);
}

TEST(Packets, ControlTokensPrintTheirKindAlone) {
  EXPECT_EQ(print(Command{PacketKind::clear, 0}), "Command{kind clear}");
  EXPECT_EQ(print(Command{PacketKind::work, 5}), "Command{kind work, draw_id 5}");
  EXPECT_EQ(print(StampBatch{PacketKind::end_of_frame, nullptr, {}, {}}),
            "StampBatch{kind end_of_frame}");
  EXPECT_EQ(print(ControlToken{}), "ControlToken{kind end_of_frame}");
}

TEST(Packets, SharedPrimitivesCompareByValue) {
  StampBatch a;
  a.primitive = std::make_shared<RasterPrimitive>();
  a.stamps = {Stamp{4, 8, 0xF0, {1, 2, 3}}};
  StampBatch b = a;
  b.primitive = std::make_shared<RasterPrimitive>(*a.primitive);  // another copy, equal
  EXPECT_EQ(a, b);
  auto other = std::make_shared<RasterPrimitive>(*a.primitive);
  other->primitive_id = 9;
  b.primitive = other;
  EXPECT_FALSE(a == b);
  b.primitive = nullptr;
  EXPECT_FALSE(a == b);
  EXPECT_NE(print(b).find("primitive none, stamps [Stamp{x 4, y 8, mask 0xf0, e (1, 2, 3)}]"),
            std::string::npos)
      << print(b);
}

TEST(VertexBatch, SlotsAndVerticesPastTheirCountsAreNotCompared) {
  VertexBatch a;
  a.slot_count = 2;
  a.vertex_count = 1;
  VertexBatch b = a;
  b.slots[2].kind = SlotKind::fetched;
  b.positions[1] = glm::vec4(1.0f);
  EXPECT_EQ(a, b);
  b.positions[0] = glm::vec4(1.0f);
  EXPECT_FALSE(a == b);
  EXPECT_NE(print(b).find("positions ((1, 1, 1, 1)), normals"), std::string::npos) << print(b);
}

TEST(ShadedVertex, ComparesEveryVarying) {
  ShadedVertex a, b;
  b.varyings[kMaxVaryings - 1] = 1.0f;
  EXPECT_FALSE(a == b);
  b.varyings[kMaxVaryings - 1] = 0.0f;
  EXPECT_EQ(a, b);
}

TEST(VaryingLayout, DefaultIsTheColourAloneAsEveryDrawCarriesToday) {
  const VaryingLayout l;
  EXPECT_EQ(l.count, kColorComponents);
  EXPECT_EQ(l.color, 0);
  EXPECT_EQ(l.groups(), 1u);
  EXPECT_EQ(varying_layout_for(DrawState{}), l);
  EXPECT_EQ(DrawState{}.varyings, l);
  EXPECT_EQ(print(l), "VaryingLayout{4 components, colour at 0}");
}

TEST(VaryingLayout, LitPhongDrawAddsTheNormalAndEyePosition) {
  DrawState d;
  d.state.shading = Shading::phong;
  d.lighting = true;
  d.buffers.normals = 64;
  const VaryingLayout l = varying_layout_for(d);
  EXPECT_EQ(l.count, 10);
  EXPECT_EQ(l.color, 0);
  EXPECT_EQ(l.normal, 4);
  EXPECT_EQ(l.eye, 7);
  EXPECT_EQ(l.groups(), 3u);
  EXPECT_TRUE(l.per_pixel_lighting());
  EXPECT_EQ(print(l), "VaryingLayout{10 components, colour at 0, normal at 4, eye position at 7}");
  // Not lit (no lighting, or no normals) or not Phong: the colour alone.
  for (int k = 0; k < 3; ++k) {
    DrawState other = d;
    if (k == 0) other.lighting = false;
    if (k == 1) other.buffers.normals = kNoBuffer;
    if (k == 2) other.state.shading = Shading::gouraud;
    EXPECT_EQ(varying_layout_for(other), VaryingLayout{}) << k;
    EXPECT_FALSE(varying_layout_for(other).per_pixel_lighting()) << k;
  }
  // Equality sees the new slots.
  VaryingLayout m = l;
  m.eye = 8;
  EXPECT_NE(m, l);
}

TEST(VaryingLayout, AppendHandsOutComponentsUpToTheCapacity) {
  // The planned varyings after the colour: normal, eye position, texture
  // coordinate. They fill the capacity.
  VaryingLayout l;
  EXPECT_EQ(l.append(3), 4u);
  EXPECT_EQ(l.append(3), 7u);
  EXPECT_EQ(l.count, 10);
  EXPECT_EQ(l.groups(), 3u);
  EXPECT_EQ(l.append(2), 10u);
  EXPECT_EQ(l.count, kMaxVaryings);
  EXPECT_EQ(l.groups(), kMaxVaryings / kVaryingGroup);
  EXPECT_THROW(l.append(1), std::length_error);
  EXPECT_EQ(l.count, kMaxVaryings);
  EXPECT_EQ(l.append(0), kMaxVaryings);
  VaryingLayout m;
  EXPECT_THROW(m.append(kMaxVaryings), std::length_error);
  EXPECT_EQ(m.count, kColorComponents);
}

}  // namespace
}  // namespace gpusim
