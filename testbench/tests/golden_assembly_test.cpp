// Golden model: primitive assembly, provoking vertex, invalid triangles,
// primitive ids, face culling (docs/pipeline-spec.md sections 3 and 7).
// Expected values are written out by hand from the spec's tables.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <vector>

#include "testbench/golden/golden_model.h"
#include "testbench/tests/golden_support.h"

namespace gpusim {
namespace {

using namespace golden_support;

using Triple = std::array<uint32_t, 3>;
using Triples = std::vector<Triple>;

// Window pixel position -> clip (w = 1) in a 32 x 32 framebuffer: x / 16 - 1,
// exact for the quarter-pixel values used here.
glm::vec4 at_px(float x, float y) {
  return {x / 16.0f - 1.0f, y / 16.0f - 1.0f, 0.0f, 1.0f};
}
constexpr int kW = 32, kH = 32;

// Colour of vertex i: red = 32 i / 255, stored as the byte 32 i.
glm::vec4 tag_color(uint32_t i) {
  return {static_cast<float>(32 * i) / 255.0f, 0.0f, 0.0f, 1.0f};
}

Draw draw_of(PrimitiveType prim, const std::vector<glm::vec4>& pos) {
  Draw d;
  d.primitive = prim;
  d.positions = pos;
  d.state.depth_test = false;
  return d;
}

int covered_pixels(const golden::Result& r) {
  int n = 0;
  for (int64_t w : r.last_writer) n += w >= 0;
  return n;
}

// ---------------------------------------------------------------------------
// Section 3's table.

TEST(GoldenAssembly, TriangleList) {
  using golden::assemble_triangles;
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangles, 0), Triples{});
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangles, 2), Triples{});
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangles, 3), (Triples{{0, 1, 2}}));
  // A partial last triangle is ignored.
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangles, 5), (Triples{{0, 1, 2}}));
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangles, 6), (Triples{{0, 1, 2}, {3, 4, 5}}));
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangles, 8), (Triples{{0, 1, 2}, {3, 4, 5}}));
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangles, 9).size(), 3u);
}

TEST(GoldenAssembly, TriangleStripAlternates) {
  using golden::assemble_triangles;
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangle_strip, 0), Triples{});
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangle_strip, 2), Triples{});
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangle_strip, 3), (Triples{{0, 1, 2}}));
  // even i: (i, i+1, i+2); odd i: (i+1, i, i+2).
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangle_strip, 7),
            (Triples{{0, 1, 2}, {2, 1, 3}, {2, 3, 4}, {4, 3, 5}, {4, 5, 6}}));
}

TEST(GoldenAssembly, TriangleFan) {
  using golden::assemble_triangles;
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangle_fan, 1), Triples{});
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangle_fan, 2), Triples{});
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangle_fan, 3), (Triples{{0, 1, 2}}));
  EXPECT_EQ(assemble_triangles(PrimitiveType::triangle_fan, 6),
            (Triples{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}}));
}

// A strip zig-zagging between y = 20 and y = 4 over x = 4..20: every
// triangle is counter-clockwise once assembled (checked by hand with the
// cross product below), the strip tiles the square [4, 20]^2, whose pixels
// are x, y = 4..19 (256 pixels; no centre on its boundary), each exactly once.
TEST(GoldenAssembly, StripKeepsOneWindingAndTilesItsArea) {
  const std::vector<glm::vec4> pos = {at_px(4, 20), at_px(4, 4),   at_px(12, 20),
                                      at_px(12, 4), at_px(20, 20), at_px(20, 4)};
  const Triples tris = golden::assemble_triangles(PrimitiveType::triangle_strip, pos.size());
  ASSERT_EQ(tris.size(), 4u);
  for (const Triple& t : tris) {
    const glm::vec4 &a = pos[t[0]], &b = pos[t[1]], &c = pos[t[2]];
    const float cross = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    EXPECT_GT(cross, 0.0f) << t[0] << "," << t[1] << "," << t[2];
  }

  for (CullMode cull : {CullMode::none, CullMode::back, CullMode::front}) {
    Scene s = make_scene(kW, kH);
    Draw d = draw_of(PrimitiveType::triangle_strip, pos);
    d.state.cull = cull;
    d.state.shading = Shading::flat;
    for (uint32_t i = 0; i < pos.size(); ++i) d.colors.push_back(tag_color(i));
    s.draws.push_back(d);
    const golden::Result r = golden::render(s);
    EXPECT_EQ(r.stats.triangles_in, 4u);
    if (cull == CullMode::front) {
      // All four are front-facing (CCW, front_face ccw): all culled.
      EXPECT_EQ(r.stats.triangles_culled, 4u);
      EXPECT_EQ(covered_pixels(r), 0);
      continue;
    }
    EXPECT_EQ(r.stats.triangles_culled, 0u);
    EXPECT_EQ(r.stats.triangles_rasterized, 4u);
    EXPECT_EQ(covered_pixels(r), 256);
    EXPECT_EQ(r.stats.fragments_generated, 256u);  // no pixel twice
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        const int64_t id = r.last_writer[y * kW + x];
        const bool inside = x >= 4 && x <= 19 && y >= 4 && y <= 19;
        EXPECT_EQ(id >= 0, inside) << x << ", " << y;
        if (id < 0) continue;
        // Flat shading: the provoking vertex of strip triangle i is i + 2,
        // odd or even.
        EXPECT_EQ(r.framebuffer.color_at(x, y)[0], 32 * (id + 2)) << x << ", " << y;
      }
    }
  }
}

// A fan around (16, 16) with the rim counter-clockwise: all CCW, no pixel
// twice, triangle i flat-shaded with vertex i + 2.
TEST(GoldenAssembly, FanKeepsOneWindingAndProvokesWithTheLastVertex) {
  const std::vector<glm::vec4> pos = {at_px(16, 16), at_px(28, 16), at_px(24, 26),
                                      at_px(12, 28), at_px(4, 18),  at_px(8, 6)};
  Scene s = make_scene(kW, kH);
  Draw d = draw_of(PrimitiveType::triangle_fan, pos);
  d.state.cull = CullMode::back;
  d.state.shading = Shading::flat;
  for (uint32_t i = 0; i < pos.size(); ++i) d.colors.push_back(tag_color(i));
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_in, 4u);
  EXPECT_EQ(r.stats.triangles_culled, 0u);
  EXPECT_EQ(r.stats.triangles_rasterized, 4u);
  // Twice the triangles' areas: 120 + 136 + 136 + 136 square pixels, so
  // about 264 pixels.
  const int n = covered_pixels(r);
  EXPECT_GT(n, 230);
  EXPECT_LT(n, 300);
  EXPECT_EQ(r.stats.fragments_generated, static_cast<uint64_t>(n));
  std::set<int64_t> ids;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const int64_t id = r.last_writer[y * kW + x];
      if (id < 0) continue;
      ids.insert(id);
      EXPECT_EQ(r.framebuffer.color_at(x, y)[0], 32 * (id + 2)) << x << ", " << y;
    }
  }
  EXPECT_EQ(ids, (std::set<int64_t>{0, 1, 2, 3}));
}

// Indexed: the square [4, 20]^2 from 4 positions, indices (0, 1, 2, 2, 1, 3);
// the provoking vertex is the vertex of the third slot: position 2 for
// triangle 0, position 3 for triangle 1.
TEST(GoldenAssembly, IndexedTrianglesUseTheIndexedVertex) {
  Scene s = make_scene(kW, kH);
  Draw d =
      draw_of(PrimitiveType::triangles, {at_px(4, 4), at_px(20, 4), at_px(4, 20), at_px(20, 20)});
  d.indices = {0, 1, 2, 2, 1, 3};
  d.state.shading = Shading::flat;
  for (uint32_t i = 0; i < 4; ++i) d.colors.push_back(tag_color(i));
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_in, 2u);
  EXPECT_EQ(covered_pixels(r), 256);
  EXPECT_EQ(r.stats.fragments_generated, 256u);
  // Pixel (5, 5) is in triangle 0 (below the diagonal x + y = 24), pixel
  // (18, 18) in triangle 1.
  EXPECT_EQ(r.last_writer[5 * kW + 5], 0);
  EXPECT_EQ(r.framebuffer.color_at(5, 5)[0], 64);
  EXPECT_EQ(r.last_writer[18 * kW + 18], 1);
  EXPECT_EQ(r.framebuffer.color_at(18, 18)[0], 96);
}

TEST(GoldenAssembly, PartialTrianglesAreIgnored) {
  Scene s = make_scene(kW, kH);
  // 5 vertices as a list: one triangle; 2 as a strip and 2 as a fan: none.
  s.draws.push_back(draw_of(PrimitiveType::triangles, {at_px(4, 4), at_px(20, 4), at_px(4, 20),
                                                       at_px(24, 24), at_px(30, 24)}));
  s.draws.push_back(draw_of(PrimitiveType::triangle_strip, {at_px(4, 4), at_px(20, 4)}));
  s.draws.push_back(draw_of(PrimitiveType::triangle_fan, {at_px(4, 4), at_px(20, 4)}));
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_in, 1u);
  EXPECT_EQ(r.stats.triangles_rasterized, 1u);
}

// Invalid triangles: an index not below the number of vertices, a NaN or an
// infinite clip coordinate (in any one component). They are counted, dropped,
// and still consume a primitive id; ids run across draws.
TEST(GoldenAssembly, InvalidTrianglesAndPrimitiveIds) {
  Scene s = make_scene(kW, kH);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Draw 0: id 0 invalid (index 4 of 4 positions), id 1 valid (lower left),
  // id 2 invalid (index 7).
  Draw d0 =
      draw_of(PrimitiveType::triangles, {at_px(2, 2), at_px(10, 2), at_px(2, 10), at_px(10, 10)});
  d0.indices = {0, 1, 4, 0, 1, 2, 3, 3, 7};
  s.draws.push_back(d0);
  // Draw 1: id 3 valid (upper right); id 4 uses a NaN vertex; id 5 valid
  // (lower right).
  Draw d1 = draw_of(PrimitiveType::triangles, {at_px(20, 20),
                                               at_px(28, 20),
                                               at_px(20, 28),
                                               {nan, 0, 0, 1},
                                               at_px(20, 2),
                                               at_px(28, 2),
                                               at_px(20, 10)});
  d1.indices = {0, 1, 2, 0, 1, 3, 4, 5, 6};
  s.draws.push_back(d1);
  // Draw 2: mvp = 1e10 I (a uniform scale of clip space changes no window
  // position). id 6 valid (upper left); ids 7, 8, 9, 10 each have one vertex
  // with exactly one infinite clip coordinate (1e30 * 1e10 overflows), x, y,
  // z, w in turn.
  Draw d2 = draw_of(PrimitiveType::triangles, {at_px(2, 20),
                                               at_px(10, 20),
                                               at_px(2, 28),
                                               {1e30f, 0, 0, 1},
                                               {0, 1e30f, 0, 1},
                                               {0, 0, 1e30f, 1},
                                               {0, 0, 0, 1e30f}});
  d2.mvp = glm::mat4(1e10f);
  d2.indices = {0, 1, 2, 0, 1, 3, 0, 1, 4, 0, 1, 5, 0, 1, 6};
  s.draws.push_back(d2);
  for (uint32_t i = 3; i < 7; ++i) {
    const glm::vec4 clip = golden::shade_vertex(s, d2, i).clip;
    ASSERT_EQ(std::isinf(clip.x) + std::isinf(clip.y) + std::isinf(clip.z) + std::isinf(clip.w), 1);
    ASSERT_FALSE(std::isnan(clip.x) || std::isnan(clip.y) || std::isnan(clip.z) ||
                 std::isnan(clip.w));
  }
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_in, 11u);
  EXPECT_EQ(r.stats.triangles_invalid, 7u);  // 0, 2, 4, 7, 8, 9, 10
  EXPECT_EQ(r.stats.triangles_rasterized, 4u);
  EXPECT_EQ(r.last_writer[3 * kW + 3], 1);
  EXPECT_EQ(r.last_writer[21 * kW + 21], 3);
  EXPECT_EQ(r.last_writer[3 * kW + 21], 5);
  EXPECT_EQ(r.last_writer[21 * kW + 3], 6);
  std::set<int64_t> ids(r.last_writer.begin(), r.last_writer.end());
  EXPECT_EQ(ids, (std::set<int64_t>{-1, 1, 3, 5, 6}));
}

// Index equal to the number of positions, in a draw whose index list is
// longer than its vertex array: must be invalid (the vertex does not exist).
TEST(GoldenAssembly, IndexEqualToPositionCountIsInvalid) {
  Scene s = make_scene(kW, kH);
  Draw d = draw_of(PrimitiveType::triangles, {at_px(2, 2), at_px(10, 2), at_px(2, 10)});
  d.indices = {0, 1, 2, 0, 1, 3};
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_in, 2u);
  EXPECT_EQ(r.stats.triangles_invalid, 1u);
  EXPECT_EQ(r.stats.triangles_rasterized, 1u);
}

// ---------------------------------------------------------------------------
// Section 7: face culling. Window y up, area2 > 0 is counter-clockwise.

TEST(GoldenCulling, CullModeTimesFrontFaceTimesWinding) {
  const std::vector<glm::vec4> ccw = {at_px(4, 4), at_px(20, 4), at_px(4, 20)};
  const std::vector<glm::vec4> cw = {at_px(4, 4), at_px(4, 20), at_px(20, 4)};
  struct Case {
    CullMode cull;
    FrontFace front;
    bool ccw_drawn, cw_drawn;  // by hand from the spec
  };
  const Case cases[] = {
      {CullMode::none, FrontFace::ccw, true, true},
      {CullMode::none, FrontFace::cw, true, true},
      // back culling: keep the front face.
      {CullMode::back, FrontFace::ccw, true, false},
      {CullMode::back, FrontFace::cw, false, true},
      // front culling: keep the back face.
      {CullMode::front, FrontFace::ccw, false, true},
      {CullMode::front, FrontFace::cw, true, false},
  };
  // The triangle (4,4), (20,4), (4,20): pixels x, y >= 4 and x + y <= 22;
  // the centres with x + y = 23 lie on the hypotenuse, which runs up in the
  // CCW order (not owned). Rows y = 4..18 hold 19 - y pixels: 15 + ... + 1 = 120.
  for (const Case& c : cases) {
    for (bool is_ccw : {true, false}) {
      Scene s = make_scene(kW, kH);
      Draw d = draw_of(PrimitiveType::triangles, is_ccw ? ccw : cw);
      d.state.cull = c.cull;
      d.state.front_face = c.front;
      s.draws.push_back(d);
      const golden::Result r = golden::render(s);
      const bool drawn = is_ccw ? c.ccw_drawn : c.cw_drawn;
      SCOPED_TRACE(::testing::Message() << "cull " << to_string(c.cull) << ", front "
                                        << to_string(c.front) << ", " << (is_ccw ? "ccw" : "cw"));
      EXPECT_EQ(r.stats.triangles_culled, drawn ? 0u : 1u);
      EXPECT_EQ(r.stats.triangles_rasterized, drawn ? 1u : 0u);
      EXPECT_EQ(covered_pixels(r), drawn ? 120 : 0);
    }
  }
}

TEST(GoldenCulling, DegenerateIsNotCulled) {
  for (CullMode cull : {CullMode::none, CullMode::back, CullMode::front}) {
    Scene s = make_scene(kW, kH);
    Draw d = draw_of(PrimitiveType::triangles, {at_px(4, 4), at_px(8, 8), at_px(16, 16)});
    d.state.cull = cull;
    s.draws.push_back(d);
    const golden::Result r = golden::render(s);
    EXPECT_EQ(r.stats.triangles_degenerate, 1u);
    EXPECT_EQ(r.stats.triangles_culled, 0u);
    EXPECT_EQ(r.stats.fragments_generated, 0u);
  }
}

// Culling is per triangle leaving the clipper: a clockwise triangle cut by
// the near plane into a quad gives two clockwise triangles, both culled.
TEST(GoldenCulling, ClippedPiecesAreCulledEachOnce) {
  Scene s = make_scene(kW, kH);
  // Window (16, 24) -> (24, 16) -> (16, 16): area2 sign of
  // (8)(-8) - (-8)(0) < 0, clockwise; the third vertex is behind the near plane.
  Draw d = draw_of(PrimitiveType::triangles,
                   {{0.0f, 0.5f, 0.0f, 1.0f}, {0.5f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, -2.0f, 1.0f}});
  d.state.cull = CullMode::back;
  s.draws.push_back(d);
  const golden::Result r = golden::render(s);
  EXPECT_EQ(r.stats.triangles_clipped, 1u);
  EXPECT_EQ(r.stats.triangles_after_clip, 2u);
  EXPECT_EQ(r.stats.triangles_culled, 2u);
  EXPECT_EQ(r.stats.fragments_generated, 0u);
}

// ---------------------------------------------------------------------------
// The shaded-vertex cache (golden::render): a draw of more than
// kShadedVertexCache positions whose primitives use vertices v, v + 2^16 and
// v + 2^17, which share a cache entry, renders what the same primitives give
// from a compact copy of the draw (only the used vertices, in order of first
// use), which the cache holds whole. Triangles, lines (the second end evicts
// the first) and points, one triangle with a non-finite vertex between two
// valid ones of its entry.

struct CacheScenes {
  Scene wide, compact;
};

CacheScenes cache_scenes() {
  constexpr uint32_t kStep = golden::kShadedVertexCache;
  constexpr int kN = 20;  // triangles in a 5 x 4 grid of 12-pixel cells
  const uint32_t n = 2 * kStep + 8 * kN;
  const auto color_of = [](uint32_t vi) {
    return glm::vec4(static_cast<float>(vi * 37 % 256) / 255.0f,
                     static_cast<float>(vi * 91 % 256) / 255.0f,
                     static_cast<float>(vi * 13 % 256) / 255.0f, 1.0f);
  };
  // Window pixels -> clip (w = 1) in a 64 x 64 framebuffer.
  const auto px = [](float x, float y) {
    return glm::vec4(x / 32.0f - 1.0f, y / 32.0f - 1.0f, 0.0f, 1.0f);
  };
  Draw wide = draw_of(PrimitiveType::triangles, std::vector<glm::vec4>(n, px(1, 1)));
  wide.colors.resize(n);
  for (uint32_t vi = 0; vi < n; ++vi) wide.colors[vi] = color_of(vi);
  std::vector<uint32_t> tris, lines, points;
  for (uint32_t j = 0; j < kN; ++j) {
    const uint32_t a = 7 * j + 1;
    const float x = 12.0f * static_cast<float>(j % 5) + 2.0f;
    const float y = 12.0f * static_cast<float>(j / 5) + 2.0f;
    wide.positions[a] = px(x, y);
    wide.positions[a + kStep] = px(x + 10.5f, y + 1.25f);
    wide.positions[a + 2 * kStep] = px(x + 3.75f, y + 9.5f);
    tris.insert(tris.end(), {a, a + kStep, a + 2 * kStep});
    lines.insert(lines.end(), {a + kStep, a});
    points.insert(points.end(), {a + 2 * kStep, a});
  }
  const uint32_t bad = 7 * kN + 3;  // an invalid triangle, then its valid vertices
  const float nan = std::numeric_limits<float>::quiet_NaN();
  wide.positions[bad] = px(50, 50);
  wide.positions[bad + kStep] = glm::vec4(nan, 0.0f, 0.0f, 1.0f);
  wide.positions[bad + 2 * kStep] = px(60, 58);
  tris.insert(tris.end(), {bad, bad + kStep, bad + 2 * kStep});
  lines.insert(lines.end(), {bad, bad + 2 * kStep});

  CacheScenes s{make_scene(64, 64), make_scene(64, 64)};
  std::vector<uint32_t> used;  // compact index -> wide index
  std::vector<int64_t> compact_of(n, -1);
  const auto compact_indices = [&](const std::vector<uint32_t>& wide_indices) {
    std::vector<uint32_t> out;
    for (const uint32_t vi : wide_indices) {
      if (compact_of[vi] < 0) {
        compact_of[vi] = static_cast<int64_t>(used.size());
        used.push_back(vi);
      }
      out.push_back(static_cast<uint32_t>(compact_of[vi]));
    }
    return out;
  };
  const std::array<std::pair<PrimitiveType, std::vector<uint32_t>>, 3> draws = {
      {{PrimitiveType::triangles, tris},
       {PrimitiveType::lines, lines},
       {PrimitiveType::points, points}}};
  std::vector<std::vector<uint32_t>> compact_draw_indices;
  for (const auto& [type, indices] : draws) {
    Draw d = wide;
    d.primitive = type;
    d.indices = indices;
    s.wide.draws.push_back(d);
    compact_draw_indices.push_back(compact_indices(indices));
  }
  Draw compact = draw_of(PrimitiveType::triangles, {});
  for (const uint32_t vi : used) {
    compact.positions.push_back(wide.positions[vi]);
    compact.colors.push_back(wide.colors[vi]);
  }
  for (size_t i = 0; i < draws.size(); ++i) {
    Draw d = compact;
    d.primitive = draws[i].first;
    d.indices = compact_draw_indices[i];
    s.compact.draws.push_back(d);
  }
  return s;
}

TEST(GoldenVertexCache, EvictedVerticesRenderAsTheirCompactCopy) {
  const CacheScenes s = cache_scenes();
  ASSERT_GT(s.wide.draws[0].positions.size(), 2u * golden::kShadedVertexCache);
  ASSERT_LE(s.compact.draws[0].positions.size(), 3u * 21);
  const golden::Result wide = golden::render(s.wide);
  const golden::Result compact = golden::render(s.compact);
  // Not vacuous: every primitive assembled, the NaN triangle alone invalid,
  // every valid one drawn.
  EXPECT_EQ(wide.stats.triangles_in, 21u);
  EXPECT_EQ(wide.stats.triangles_invalid, 1u);
  EXPECT_EQ(wide.stats.triangles_rasterized, 20u);
  EXPECT_EQ(wide.stats.lines_in, 21u);
  EXPECT_EQ(wide.stats.lines_rasterized, 21u);
  EXPECT_EQ(wide.stats.points_rasterized, 40u);
  EXPECT_GT(covered_pixels(wide), 20 * 30);
  EXPECT_EQ(wide.stats.to_json(), compact.stats.to_json());
  EXPECT_TRUE(wide.framebuffer.color == compact.framebuffer.color);
  EXPECT_TRUE(wide.framebuffer.depth == compact.framebuffer.depth);
  EXPECT_TRUE(wide.last_writer == compact.last_writer);
}

// `gpusim golden` renders without the per-pixel last writers: the same
// frame and counters as with them, and no map. A colour clear in the draw
// list resets the map it does not have.
TEST(GoldenVertexCache, NoLastWritersSameFrameAndCounters) {
  Scene scene = cache_scenes().wide;
  ClearState clear;
  clear.color = true;
  clear.color_value = {0.25f, 0.5f, 0.75f, 1.0f};
  clear.before_draw = 1;
  scene.clears.push_back(clear);
  const golden::Result with = golden::render(scene);
  golden::RenderOptions options;
  options.record_last_writer = false;
  const golden::Result without = golden::render(scene, options);
  ASSERT_EQ(with.last_writer.size(), 64u * 64u);
  EXPECT_GT(covered_pixels(with), 20 * 10);  // the lines and points after the clear
  EXPECT_TRUE(without.last_writer.empty());
  EXPECT_EQ(with.stats.to_json(), without.stats.to_json());
  EXPECT_TRUE(with.framebuffer.color == without.framebuffer.color);
  EXPECT_TRUE(with.framebuffer.depth == without.framebuffer.depth);
}

}  // namespace
}  // namespace gpusim
