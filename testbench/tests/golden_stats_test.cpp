// Golden model: statistics (docs/pipeline-spec.md section 13) on a mixed
// scene where every counter is predicted by hand, pixel counts by the exact
// reference coverage (see golden_raster_test.cpp for its derivation).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "testbench/golden/golden_model.h"
#include "testbench/tests/golden_support.h"

namespace gpusim {
namespace {

using namespace golden_support;

// Pixels of a W x H framebuffer covered by the convex polygon (pixels).
int ref_count(const std::vector<std::array<double, 2>>& poly_px, int W, int H) {
  std::vector<Pt> poly;
  for (const auto& v : poly_px)
    poly.push_back({std::llround(v[0] * 256), std::llround(v[1] * 256)});
  int64_t area = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Pt a = poly[i], b = poly[(i + 1) % poly.size()];
    area += a.x * b.y - b.x * a.y;
  }
  int n = 0;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const Pt p{256 * x + 128, 256 * y + 128};
      bool in = area != 0;
      for (size_t i = 0; i < poly.size() && in; ++i) {
        in = perturbed_side(poly[i], poly[(i + 1) % poly.size()], p) == sgn(area);
      }
      n += in;
    }
  }
  return n;
}

constexpr int kW = 64, kH = 64;
// Window pixel (x, y) with depth z_w -> clip (w = 1): x / 32 - 1.
glm::vec4 at(float x, float y, float zw = 0.5f) {
  return {x / 32.0f - 1.0f, y / 32.0f - 1.0f, 2.0f * zw - 1.0f, 1.0f};
}

TEST(GoldenStats, MixedSceneCountersAndConservation) {
  Scene s;
  s.framebuffer.width = kW;
  s.framebuffer.height = kH;
  const float nan = std::numeric_limits<float>::quiet_NaN();

  // Draw 0, cull back (front ccw), depth less:
  //  t0 (id 0) CCW (4,4) (20,4) (4,20) at z 0.5: rasterized.
  //  t1 (id 1) the same clockwise: culled.
  //  t2 (id 2) collinear: degenerate.
  //  t3 (id 3) entirely behind the eye (w = -1): clipped away.
  //  t4 (id 4) CCW, its third vertex behind the near plane: clipped into a
  //     quad (48,32) (32,48) (32,40) (40,32) (cuts at t = 1/2, exact) -> 2
  //     triangles, both rasterized.
  //  t5 (id 5) indices (0, 1, 15) into 15 positions: invalid.
  Draw d0;
  d0.positions = {at(4, 4),         at(20, 4),        at(4, 20),       // 0-2
                  at(4, 4),         at(4, 20),        at(20, 4),       // 3-5
                  at(30, 30),       at(34, 34),       at(40, 40),      // 6-8
                  {0.5f, 0, 0, -1}, {0, 0.5f, 0, -1}, {0, 0, 0, -1},   // 9-11
                  {0.5f, 0, 0, 1},  {0, 0.5f, 0, 1},  {0, 0, -2, 1}};  // 12-14
  d0.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 0, 1, 15};
  d0.state.cull = CullMode::back;
  s.draws.push_back(d0);

  // Draw 1, depth less: t6 (id 6) = t0 at z 0.75: every fragment fails;
  // t7 (id 7) has a NaN vertex: invalid.
  Draw d1;
  d1.positions = {at(4, 4, 0.75f), at(20, 4, 0.75f), at(4, 20, 0.75f),
                  {nan, 0, 0, 1},  at(10, 10),       at(12, 10)};
  d1.indices = {0, 1, 2, 3, 4, 5};
  s.draws.push_back(d1);

  // Draw 2, colour mask all false: t8 (id 8) (40,4) (60,4) (40,20) passes
  // depth but writes no colour.
  Draw d2;
  d2.positions = {at(40, 4), at(60, 4), at(40, 20)};
  d2.state.color_mask = {false, false, false, false};
  s.draws.push_back(d2);

  const golden::Result r = golden::render(s);
  const golden::Stats& st = r.stats;

  const uint64_t t0 = ref_count({{{4, 4}}, {{20, 4}}, {{4, 20}}}, kW, kH);
  const uint64_t t4 = ref_count({{{48, 32}}, {{32, 48}}, {{32, 40}}, {{40, 32}}}, kW, kH);
  const uint64_t t8 = ref_count({{{40, 4}}, {{60, 4}}, {{40, 20}}}, kW, kH);
  EXPECT_EQ(t0, 120u);  // by hand: x, y >= 4, x + y <= 22

  EXPECT_EQ(st.triangles_in, 9u);
  EXPECT_EQ(st.triangles_invalid, 2u);       // t5, t7
  EXPECT_EQ(st.triangles_clipped_away, 1u);  // t3
  EXPECT_EQ(st.triangles_clipped, 1u);       // t4
  EXPECT_EQ(st.triangles_after_clip, 7u);    // t0 t1 t2 t4a t4b t6 t8
  EXPECT_EQ(st.triangles_degenerate, 1u);    // t2
  EXPECT_EQ(st.triangles_culled, 1u);        // t1
  EXPECT_EQ(st.triangles_rasterized, 5u);    // t0 t4a t4b t6 t8
  EXPECT_EQ(st.fragments_generated, t0 + t4 + t0 + t8);
  EXPECT_EQ(st.fragments_passed_depth, t0 + t4 + t8);
  EXPECT_EQ(st.fragments_written, t0 + t4);

  // The conservation identities of section 13.
  const uint64_t survivors = st.triangles_in - st.triangles_invalid - st.triangles_clipped_away;
  EXPECT_EQ(survivors, 6u);
  EXPECT_LE(st.triangles_clipped, survivors);
  EXPECT_EQ(st.triangles_after_clip,
            st.triangles_degenerate + st.triangles_culled + st.triangles_rasterized);
  EXPECT_LE(st.fragments_written, st.fragments_passed_depth);
  EXPECT_LE(st.fragments_passed_depth, st.fragments_generated);

  // Last writers: t0 (id 0) and t4 (id 4) only.
  std::vector<uint64_t> per_id(9, 0);
  for (int64_t id : r.last_writer) {
    if (id >= 0) ++per_id[static_cast<size_t>(id)];
  }
  EXPECT_EQ(per_id, (std::vector<uint64_t>{t0, 0, 0, 0, t4, 0, 0, 0, 0}));

  // to_json carries the same numbers.
  const nlohmann::json j = st.to_json();
  EXPECT_EQ(j.at("triangles_in").get<uint64_t>(), 9u);
  EXPECT_EQ(j.at("triangles_after_clip").get<uint64_t>(), 7u);
  EXPECT_EQ(j.at("fragments_written").get<uint64_t>(), t0 + t4);
  // 11 triangle and fragment counters, triangles_unfilled and _offscreen, 6
  // for lines, 4 for points (spec section 13), 3 for samples (section 14),
  // 2 for clears (section 15); none of the lines' and points' moved in a
  // triangle scene, one sample per pixel makes the sample counts the
  // fragment counts, and the frame clear is the only clear.
  EXPECT_EQ(j.size(), 28u);
  EXPECT_EQ(st.color_clears, 1u);
  EXPECT_EQ(st.depth_clears, 1u);
  EXPECT_EQ(st.samples_generated, st.fragments_generated);
  EXPECT_EQ(st.samples_passed_depth, st.fragments_passed_depth);
  EXPECT_EQ(st.samples_written, st.fragments_written);
  for (const char* k : {"triangles_unfilled", "lines_in", "lines_invalid", "lines_clipped_away",
                        "lines_clipped", "lines_degenerate", "lines_rasterized", "points_in",
                        "points_invalid", "points_clipped_away", "points_rasterized"}) {
    EXPECT_EQ(j.at(k).get<uint64_t>(), 0u) << k;
  }
}

// triangles_offscreen counts rasterized triangles whose pixel box holds no
// pixel centre: one beyond the right edge (inside the guard band, so not
// clipped) and one sliver between pixel centres; the third covers pixels.
TEST(GoldenStats, OffscreenTrianglesAreRasterizedWithoutPixels) {
  Scene s;
  s.framebuffer.width = kW;
  s.framebuffer.height = kH;
  Draw d;
  d.positions = {at(70, 4),     at(90, 4),     at(70, 20),     // right of the frame
                 at(10.1f, 10), at(10.4f, 10), at(10.1f, 30),  // between centres x 9.5, 10.5
                 at(4, 4),      at(20, 4),     at(4, 20)};
  s.draws.push_back(d);
  const golden::Stats st = golden::render(s).stats;
  EXPECT_EQ(st.triangles_clipped, 0u);
  EXPECT_EQ(st.triangles_rasterized, 3u);
  EXPECT_EQ(st.triangles_offscreen, 2u);
  EXPECT_EQ(st.fragments_generated, ref_count({{{4, 4}}, {{20, 4}}, {{4, 20}}}, kW, kH));
  EXPECT_EQ(st.to_json().at("triangles_offscreen").get<uint64_t>(), 2u);
}

}  // namespace
}  // namespace gpusim
