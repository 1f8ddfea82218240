// Golden model: the provoking vertex under either convention (section 3) and
// screen interpolation (sections 4 and 9). Expected values are written by
// hand from the OpenGL specification's table of provoking vertices (4.6 core,
// table 13.2) or worked out analytically in the comments.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include "hw/pixel_formats.h"
#include "testbench/golden/golden_model.h"

namespace gpusim {
namespace {

constexpr int kW = 32, kH = 32;

// Window pixel position -> clip (w = 1) in a 32 x 32 framebuffer.
glm::vec4 at_px(float x, float y) {
  return {x / 16.0f - 1.0f, y / 16.0f - 1.0f, 0.0f, 1.0f};
}

// Colour of vertex i: red = 32 i / 255, stored as the byte 32 i.
glm::vec4 tag_color(uint32_t i) {
  return {static_cast<float>(32 * i) / 255.0f, 0.0f, 0.0f, 1.0f};
}

Scene scene_with(PrimitiveType prim, const std::vector<glm::vec4>& pos, ProvokingVertex pv,
                 PolygonMode mode = PolygonMode::fill) {
  Scene s;
  s.framebuffer.width = kW;
  s.framebuffer.height = kH;
  s.framebuffer.clear_color = {0, 0, 0, 0};
  Draw d;
  d.primitive = prim;
  d.positions = pos;
  for (uint32_t i = 0; i < pos.size(); ++i) d.colors.push_back(tag_color(i));
  d.state.depth_test = false;
  d.state.shading = Shading::flat;
  d.state.provoking_vertex = pv;
  d.state.polygon_mode = mode;
  s.draws.push_back(d);
  return s;
}

// Every written pixel's red byte equals 32 * want(id) for the primitive id
// that wrote it; returns the ids seen.
template <typename Want>
std::set<int64_t> expect_colours_by_id(const golden::Result& r, Want want) {
  std::set<int64_t> ids;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const int64_t id = r.last_writer[y * kW + x];
      if (id < 0) continue;
      ids.insert(id);
      EXPECT_EQ(r.framebuffer.color_at(x, y)[0], 32 * want(id)) << x << ", " << y << " id " << id;
    }
  }
  return ids;
}

// GL's table, 0-based: triangle i of a list provokes with vertex 3i (first)
// or 3i+2 (last); of a strip with i or i+2; of a fan with i+1 or i+2.
// provoking_position indexes the assembled triple: a strip's odd triangle is
// assembled (i+1, i, i+2), a fan's (0, i+1, i+2).
TEST(GoldenProvoking, PositionFollowsGlsTable) {
  for (uint32_t i = 0; i < 4; ++i) {
    SCOPED_TRACE(i);
    for (PrimitiveType t :
         {PrimitiveType::triangles, PrimitiveType::triangle_strip, PrimitiveType::triangle_fan}) {
      EXPECT_EQ(golden::provoking_position(t, i, ProvokingVertex::last), 2);
    }
    EXPECT_EQ(golden::provoking_position(PrimitiveType::triangles, i, ProvokingVertex::first), 0);
    EXPECT_EQ(golden::provoking_position(PrimitiveType::triangle_fan, i, ProvokingVertex::first),
              1);
    const int strip =
        golden::provoking_position(PrimitiveType::triangle_strip, i, ProvokingVertex::first);
    // The slot at that position is vertex i in either parity.
    const auto slots = golden::assemble_triangles(PrimitiveType::triangle_strip, 6);
    EXPECT_EQ(slots[i][strip], i);
    const auto fan = golden::assemble_triangles(PrimitiveType::triangle_fan, 6);
    EXPECT_EQ(
        fan[i][golden::provoking_position(PrimitiveType::triangle_fan, i, ProvokingVertex::first)],
        i + 1);
  }
}

// The fan of golden_assembly_test (4 CCW triangles around (16, 16)):
// first-vertex flat colours are vertex i+1's, not the centre's.
TEST(GoldenProvoking, FanFirstVertexIsTheSecondSlotNotTheCentre) {
  const std::vector<glm::vec4> pos = {at_px(16, 16), at_px(28, 16), at_px(24, 26),
                                      at_px(12, 28), at_px(4, 18),  at_px(8, 6)};
  for (ProvokingVertex pv : {ProvokingVertex::first, ProvokingVertex::last}) {
    SCOPED_TRACE(to_string(pv));
    const golden::Result r = golden::render(scene_with(PrimitiveType::triangle_fan, pos, pv));
    const int64_t shift = pv == ProvokingVertex::first ? 1 : 2;
    const auto ids = expect_colours_by_id(r, [&](int64_t id) { return id + shift; });
    EXPECT_EQ(ids, (std::set<int64_t>{0, 1, 2, 3}));
  }
}

// A strip of 4 triangles, the square [4, 28] x [8, 24]: first-vertex flat
// colours are vertex i's (the odd triangles' second slot).
TEST(GoldenProvoking, StripFirstVertexIsVertexI) {
  const std::vector<glm::vec4> pos = {at_px(4, 8),   at_px(4, 24), at_px(10, 8),
                                      at_px(10, 24), at_px(20, 8), at_px(20, 24)};
  for (ProvokingVertex pv : {ProvokingVertex::first, ProvokingVertex::last}) {
    SCOPED_TRACE(to_string(pv));
    const golden::Result r = golden::render(scene_with(PrimitiveType::triangle_strip, pos, pv));
    const int64_t shift = pv == ProvokingVertex::first ? 0 : 2;
    const auto ids = expect_colours_by_id(r, [&](int64_t id) { return id + shift; });
    EXPECT_EQ(ids, (std::set<int64_t>{0, 1, 2, 3}));
  }
}

// A line loop of 4 (a square's sides): line i = (i, i+1) provokes with i
// (first) or i+1 (last); the closing line (3, 0) with 3 or 0.
TEST(GoldenProvoking, LineLoopBothConventions) {
  const std::vector<glm::vec4> pos = {at_px(4.5f, 4.5f), at_px(27.5f, 4.5f), at_px(27.5f, 27.5f),
                                      at_px(4.5f, 27.5f)};
  for (ProvokingVertex pv : {ProvokingVertex::first, ProvokingVertex::last}) {
    SCOPED_TRACE(to_string(pv));
    const golden::Result r = golden::render(scene_with(PrimitiveType::line_loop, pos, pv));
    const auto ids = expect_colours_by_id(
        r, [&](int64_t id) { return pv == ProvokingVertex::first ? id : (id + 1) % 4; });
    EXPECT_EQ(ids, (std::set<int64_t>{0, 1, 2, 3}));
  }
}

// Polygon mode line: every edge of a triangle shows its provoking colour.
TEST(GoldenProvoking, PolygonModeEdgesTakeTheTrianglesProvokingColour) {
  const std::vector<glm::vec4> pos = {at_px(4, 4), at_px(28, 6), at_px(10, 28)};
  for (ProvokingVertex pv : {ProvokingVertex::first, ProvokingVertex::last}) {
    const golden::Result r =
        golden::render(scene_with(PrimitiveType::triangles, pos, pv, PolygonMode::line));
    EXPECT_EQ(r.stats.triangles_unfilled, 1u);
    const auto ids =
        expect_colours_by_id(r, [&](int64_t) { return pv == ProvokingVertex::first ? 0 : 2; });
    EXPECT_EQ(ids, (std::set<int64_t>{0}));
  }
}

// Vertex 0 beyond the near plane (z < -w): the clipper replaces it, yet the
// first-vertex flat colour is still vertex 0's.
TEST(GoldenProvoking, ProvokingColourSurvivesClipping) {
  std::vector<glm::vec4> pos = {at_px(16, 4), at_px(28, 26), at_px(4, 26)};
  pos[0].z = -3.0f;
  const golden::Result r =
      golden::render(scene_with(PrimitiveType::triangles, pos, ProvokingVertex::first));
  EXPECT_EQ(r.stats.triangles_clipped, 1u);
  EXPECT_GE(r.stats.triangles_after_clip, 2u);
  const auto ids = expect_colours_by_id(r, [](int64_t) { return 0; });
  EXPECT_EQ(ids, (std::set<int64_t>{0}));
}

// Section 4, screen interpolation: the edge a = (0, 0, 0, 1) -> b = (2, 0,
// -4, 2) crosses the near plane (d = z + w: 1 and -2) at t = 1/3 from a, the
// clip point (2/3, 0, -4/3, 4/3), whose x/w is 0.5, halfway between a's 0 and
// b's 1 on screen. Red 0 at a, 1 at b: perspective-correct 1/3, screen 0.5.
// Edge b -> c = (0, 1, 0, 1) is cut at t = 1/3 from c, the point (2/3, 2/3,
// -4/3, 4/3), projected (0.5, 0.5). Affine over the projected triangle
// (0, 0), (1, 0), (0, 1) red is x/w: 0.5 at both cuts.
TEST(GoldenProvoking, ScreenInterpolationCutIsLinearInWindowSpace) {
  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  std::array<golden::ShadedVertex, 3> tri;
  tri[0].clip = {0, 0, 0, 1};
  tri[1].clip = {2, 0, -4, 2};
  tri[2].clip = {0, 1, 0, 1};
  tri[0].color = {0, 0, 0, 1};
  tri[1].color = {1, 0, 0, 1};
  tri[2].color = {0, 0, 0, 1};
  for (Interpolation in : {Interpolation::perspective, Interpolation::screen}) {
    SCOPED_TRACE(to_string(in));
    const std::vector<golden::ShadedVertex> poly = golden::clip_triangle(tri, gb, in);
    ASSERT_EQ(poly.size(), 4u);
    const double want = in == Interpolation::screen ? 0.5 : 1.0 / 3.0;
    EXPECT_NEAR(poly[1].color.r, want, 1e-6);
    EXPECT_NEAR(poly[2].color.r, want, 1e-6);
    EXPECT_NEAR(poly[1].clip.x / poly[1].clip.w, 0.5, 1e-6);
    // Alpha is 1 at both ends, whatever the parameter.
    EXPECT_EQ(poly[1].color.a, 1.0f);
  }
  // Every vertex on one screen point: the projection is degenerate (den = 0)
  // and the cut keeps its perspective-correct colour, at t = 1/3.
  tri[1].clip = {0, 0, -4, 2};
  tri[2].clip = {0, 0, 0, 1};
  const std::vector<golden::ShadedVertex> same =
      golden::clip_triangle(tri, gb, Interpolation::screen);
  ASSERT_EQ(same.size(), 4u);
  EXPECT_NEAR(same[1].color.r, 1.0 / 3.0, 1e-6);
}

// Section 9, screen interpolation, on golden_shading_test's perspective quad:
// A (-1,-1,-1), B (1,-1,-2), C (1,1,-2), D (-1,1,-1), projection n = 1,
// f = 3, window A (0,0), B (48,16), C (48,48), D (0,64) in 64 x 64; red 0 at
// A and D, 1 at B and C. Affine in window space on both triangles (ABC and
// ACD) red is x_w / 48: at pixel x, (x + 0.5) / 48, where the
// perspective-correct value is (1 + x_n) / (2 - x_n), x_n = (x + 0.5) / 32 - 1.
// Depth is linear in window space either way, so it does not change.
TEST(GoldenProvoking, ScreenInterpolatedQuadIsAffineAndDepthUnchanged) {
  glm::mat4 proj(0.0f);
  proj[0][0] = 1.0f;
  proj[1][1] = 1.0f;
  proj[2][2] = -2.0f;
  proj[2][3] = -1.0f;
  proj[3][2] = -3.0f;
  const glm::vec4 A(-1, -1, -1, 1), B(1, -1, -2, 1), C(1, 1, -2, 1), D(-1, 1, -1, 1);
  const glm::vec4 black(0, 0, 0, 1), red(1, 0, 0, 1);
  golden::Result results[2];
  for (Interpolation in : {Interpolation::perspective, Interpolation::screen}) {
    Scene s;
    s.framebuffer.width = 64;
    s.framebuffer.height = 64;
    s.framebuffer.color_format = ColorFormat::rgba16f;
    s.framebuffer.depth_format = DepthFormat::float32;
    s.framebuffer.clear_color = {0, 0, 0, 0};
    Draw d;
    d.positions = {A, B, C, A, C, D};
    d.colors = {black, red, red, black, red, black};
    d.projection = proj;
    d.mvp = proj;
    d.state.interpolation = in;
    s.draws.push_back(d);
    results[static_cast<int>(in)] = golden::render(s);
  }
  const golden::Result& persp = results[static_cast<int>(Interpolation::perspective)];
  const golden::Result& screen = results[static_cast<int>(Interpolation::screen)];
  const int y = 31;
  for (int x = 0; x < 48; ++x) {
    ASSERT_GE(screen.last_writer[y * 64 + x], 0) << x;
    const double xn = (x + 0.5) / 32.0 - 1.0;
    const double affine = (x + 0.5) / 48.0;
    const double perspective = (1.0 + xn) / (2.0 - xn);
    const double got = decode_half(screen.framebuffer.color_at(x, y)[0]);
    // Half rounding: at most 2^-12 below 1; the float arithmetic ~1e-6.
    EXPECT_NEAR(got, affine, 2.5e-4) << "pixel " << x;
    const double got_p = decode_half(persp.framebuffer.color_at(x, y)[0]);
    EXPECT_NEAR(got_p, perspective, 2.5e-4) << "pixel " << x;
    // w varies across the quad: the two differ inside it.
    if (x >= 8 && x <= 40) {
      EXPECT_GT(std::fabs(got - got_p), 0.05) << "pixel " << x;
    }
  }
  EXPECT_EQ(screen.framebuffer.depth, persp.framebuffer.depth);
  EXPECT_EQ(screen.last_writer, persp.last_writer);
}

}  // namespace
}  // namespace gpusim
