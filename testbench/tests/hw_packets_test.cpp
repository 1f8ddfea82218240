// Primitive packets (hw/packets.h) and varying layouts
// (hw/varying_layout.h): the primitive kind and vertex count are printed and
// compared like every other field, and a layout hands out its components.
#include <gtest/gtest.h>

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
  EXPECT_NE(t.find("ClippedPrimitive{work triangle/3 draw 2 prim 17"), std::string::npos) << t;
  EXPECT_EQ(occurrences(t, "1/w"), 3u) << t;
  EXPECT_NE(t.find("flat (0.5, 0, 0, 1)"), std::string::npos) << t;
  const std::string l = print(line());
  EXPECT_NE(l.find("line/2"), std::string::npos) << l;
  EXPECT_EQ(occurrences(l, "1/w"), 2u) << l;
  ClippedPrimitive eof;
  eof.kind = PacketKind::end_of_frame;
  EXPECT_EQ(print(eof), "ClippedPrimitive{end_of_frame}");
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
  EXPECT_NE(s.find("RasterPrimitive{triangle/3 draw 1 prim 4"), std::string::npos) << s;
  EXPECT_NE(s.find("flat (0.25, 0.5)"), std::string::npos) << s;
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
