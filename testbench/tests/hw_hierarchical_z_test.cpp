// Hierarchical Z's shared pieces (hw/hierarchical_z.h): the triangle range
// bounds every value the depth test computes, and an update's visibility
// depends on simulated time only, never on the order SystemC runs processes.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "hw/hierarchical_z.h"
#include "hw/simulation_context.h"

namespace gpusim {
namespace {

// The depth test's arithmetic (stages/depth_test.cpp, spec section 9) for a
// point with edge values E1, E2 of a triangle of doubled area area2.
float depth_at(const RasterPrimitive& t, EdgeValue e1, EdgeValue e2) {
  const float dz1 = t.z[1] - t.z[0], dz2 = t.z[2] - t.z[0];
  const float f1 = static_cast<float>(e1), f2 = static_cast<float>(e2);
  float z = t.z[0] + (f1 * dz1 + f2 * dz2) / static_cast<float>(t.area2);
  if (t.has_depth_offset) z = z + t.depth_offset;
  return z;
}

// Random triangles with nearly equal, equal or spread depths, random points
// inside them (E_k >= 0, E0 = area2 - E1 - E2 >= 0, corners included) and
// random polygon offsets: every encoded depth lies in the range.
TEST(HzPrimitiveRange, BoundsEveryDepthTheDepthTestComputes) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  uint64_t checked = 0;
  for (const DepthFormat f : {DepthFormat::unorm16, DepthFormat::unorm24, DepthFormat::float32}) {
    for (int n = 0; n < 3000; ++n) {
      RasterPrimitive t;
      const float base = n % 3 == 0 ? unit(rng) * 1e-3f : unit(rng) * 1.2f - 0.1f;
      const float spread = n % 2 == 0 ? unit(rng) * 1e-6f : unit(rng);
      for (float& z : t.z) z = base + spread * unit(rng);
      if (n % 7 == 0) t.z = {base, base, base};
      t.area2 = static_cast<EdgeValue>(1 + (rng() >> (12 + n % 40)));
      t.has_depth_offset = n % 4 == 0;
      t.depth_offset = (unit(rng) - 0.5f) * (n % 8 == 0 ? 1e-6f : 0.2f);
      const HzRange r = hz_primitive_range(t, f);
      ASSERT_LE(r.min, r.max);
      for (int k = 0; k < 40; ++k) {
        EdgeValue e1 = static_cast<EdgeValue>(rng() % static_cast<uint64_t>(t.area2 + 1));
        EdgeValue e2 = static_cast<EdgeValue>(rng() % static_cast<uint64_t>(t.area2 - e1 + 1));
        if (k < 3) {  // the corners
          e1 = k == 1 ? t.area2 : 0;
          e2 = k == 2 ? t.area2 : 0;
        }
        const DepthValue v = encode_depth(f, depth_at(t, e1, e2));
        ASSERT_GE(v, r.min) << n << " " << k;
        ASSERT_LE(v, r.max) << n << " " << k;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 3u * 3000u * 40u);
}

// Issue #11: clipping can give a vertex a NaN depth, and depths far beyond
// [0, 1] can overflow the depth test's products (inf - inf): either makes
// z = NaN, which clamp01 stores as 0, outside the other vertices' range. A
// NaN in any position, an infinity, a NaN or infinite offset and depths up
// to 2^62 and beyond: every encoded depth at the corners and inside lies in
// the range.
TEST(HzPrimitiveRange, BoundsNonFiniteAndHugeDepths) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<RasterPrimitive> cases;
  const auto add = [&](std::array<float, 3> z, EdgeValue area2, float offset = 0.0f,
                       bool has_offset = false) {
    RasterPrimitive t;
    t.z = z;
    t.area2 = area2;
    t.depth_offset = offset;
    t.has_depth_offset = has_offset;
    cases.push_back(t);
  };
  for (int k = 0; k < 3; ++k) {
    std::array<float, 3> z = {0.5f, 0.5f, 0.5f};
    z[k] = nan;
    add(z, EdgeValue{1} << 33);  // ClipRoundingOnExtremeInputs's triangle, NaN moved around
    z[k] = inf;
    add(z, EdgeValue{1} << 20);
    z[k] = -inf;
    add(z, EdgeValue{1} << 20);
  }
  // Mid vertex first: f1 dz1 = -inf, f2 dz2 = +inf inside the triangle.
  add({2e30f, 1e30f, 3e30f}, EdgeValue{1} << 40);
  add({0x1p62f, 0x1p61f, 0x1.8p62f}, EdgeValue{1} << 62);
  add({0x1.fffffep61f, 0x1p61f, 0x1.8p61f}, (EdgeValue{1} << 62) + 12345);  // just below 2^62
  add({0.25f, 0.5f, 0.75f}, 1000, nan, true);
  add({0.25f, 0.5f, 0.75f}, 1000, inf, true);
  add({0.25f, 0.5f, 0.75f}, 1000, -inf, true);
  add({1e18f, -1e18f, 0.5f}, 1000, 3e38f, true);
  std::mt19937_64 rng(11);
  uint64_t checked = 0, nan_depths = 0;
  for (const DepthFormat f : {DepthFormat::unorm16, DepthFormat::unorm24, DepthFormat::float32}) {
    for (size_t n = 0; n < cases.size(); ++n) {
      const RasterPrimitive& t = cases[n];
      const HzRange r = hz_primitive_range(t, f);
      ASSERT_LE(r.min, r.max);
      for (int k = 0; k < 200; ++k) {
        EdgeValue e1 = static_cast<EdgeValue>(rng() % static_cast<uint64_t>(t.area2 + 1));
        EdgeValue e2 = static_cast<EdgeValue>(rng() % static_cast<uint64_t>(t.area2 - e1 + 1));
        if (k < 4) {  // the corners and the middle of the long edge
          e1 = k == 1 ? t.area2 : k == 3 ? t.area2 / 2 : 0;
          e2 = k == 2 ? t.area2 : k == 3 ? t.area2 / 2 : 0;
        }
        const float z = depth_at(t, e1, e2);
        nan_depths += std::isnan(z) ? 1 : 0;
        const DepthValue v = encode_depth(f, z);
        ASSERT_GE(v, r.min) << n << " " << k << " z " << z;
        ASSERT_LE(v, r.max) << n << " " << k << " z " << z;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 3u * cases.size() * 200u);
  EXPECT_GT(nan_depths, 0u);  // the cases do reach the NaN the old bound missed
}

TEST(HzPrimitiveRange, LinesAndPointsClaimNoBound) {
  RasterPrimitive t;
  t.primitive_kind = PrimitiveKind::line;
  t.z = {0.5f, 0.5f, 0.5f};
  EXPECT_EQ(hz_primitive_range(t, DepthFormat::unorm24), HzRange{});
}

// A writer sends an update at 10 ns (1 ns cycles, latency 4); a reader polls
// at 10, 14 and 15 ns. Visible only when 10 + 4 < now: at 15 ns, not at 14.
// At 10 ns the poll runs before or after the send depending on the order
// the processes were spawned in; the update is not visible either way.
void poll_times(bool writer_first) {
  fresh_simulation_context();
  const sc_core::sc_time ns(1, sc_core::SC_NS);
  HzUpdateLink link(4, ns);
  std::vector<int> seen;  // updates visible at each poll, cumulative
  int taken = 0;
  const auto writer = [&] {
    sc_core::wait(10 * ns);
    link.send(HzUpdate{sc_core::sc_time_stamp(), 3, 1, 0, HzRange{5, 9}});
  };
  const auto reader = [&] {
    for (const int t : {10, 14, 15}) {
      sc_core::wait(sc_core::sc_time(t, sc_core::SC_NS) - sc_core::sc_time_stamp());
      link.take_visible(sc_core::sc_time_stamp(), [&](const HzUpdate& u) {
        EXPECT_EQ(u.range, (HzRange{5, 9}));
        ++taken;
      });
      seen.push_back(taken);
    }
  };
  if (writer_first) {
    sc_core::sc_spawn(writer);
    sc_core::sc_spawn(reader);
  } else {
    sc_core::sc_spawn(reader);
    sc_core::sc_spawn(writer);
  }
  sc_core::sc_start();
  EXPECT_EQ(seen, (std::vector<int>{0, 0, 1}));
}

TEST(HzUpdateLink, VisibleOnlyAfterSentPlusLatencyWriterFirst) {
  poll_times(true);
}
TEST(HzUpdateLink, VisibleOnlyAfterSentPlusLatencyReaderFirst) {
  poll_times(false);
}

}  // namespace
}  // namespace gpusim
