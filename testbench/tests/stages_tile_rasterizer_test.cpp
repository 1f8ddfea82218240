// The tile rasterizer (stages/tile_rasterizer.h) alone: a host writes a
// clear, one set-up triangle and the end of frame into the input FIFO of
// each unit's rasterizer, as the distributor would, and a sink per unit reads
// its stamp batches (testbench/tests/stage_host.h). The triangle is placed by
// hand so that pixel centres lie on all three edges; its setup comes from
// the golden model's rules (testbench/tests/back_end_input.h).
//
// Checked, in 1, 2 and 3 units, with and without the tile test overlapped:
// the covered pixels, by the fill rule's ties worked out in the test
// (docs/pipeline-spec.md, section 8), in one batch per owned tile with
// coverage, tiles and stamps in walk order (rows bottom-up, left to right),
// with the raw edge values at each stamp's origin (golden::edge_function);
// the tiles rejected and accepted by the documented tile test, evaluated
// pixel centre by pixel centre; the cost (1 per tile test, ii per stamp
// evaluated or emitted, ii per control token) and when each batch is
// readable; and the counters, whose sums over the units are the hand counts
// below. One sc_start per TEST (ctest runs each in its own process).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "hw/fixed_point.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "stages/tile_rasterizer.h"
#include "testbench/golden/golden_model.h"
#include "testbench/tests/back_end_input.h"
#include "testbench/tests/stage_host.h"

namespace gpusim {
namespace {

using namespace test;

// The triangle (8.5, 8.5), (24.5, 8.5), (8.5, 24.5) in pixels, counter-
// clockwise, in a 32 x 32 framebuffer. Pixel (x, y) is sampled at
// (x + 0.5, y + 0.5):
//   E2, v0 -> v1, the bottom edge y = 8.5: owns its boundary, passes y >= 8;
//   E1, v2 -> v0, the left edge x = 8.5: owns its boundary, passes x >= 8;
//   E0, v1 -> v2, x + y = 33, neither: passes x + 0.5 + y + 0.5 < 33, that is
//     x + y <= 31 (the centres with x + y = 32 lie on it and are left out).
// Covered: x, y >= 8 and x + y <= 31, 16 * 17 / 2 = 136 pixels. Box: 8..24.
bool passes(int k, int x, int y) {
  return k == 0 ? x + y <= 31 : k == 1 ? x >= 8 : y >= 8;
}
bool covered(int x, int y) {
  return passes(0, x, y) && passes(1, x, y) && passes(2, x, y);
}

std::array<golden::WindowVertex, 3> vertices() {
  std::array<golden::WindowVertex, 3> v;
  const std::array<std::array<Subpixel, 2>, 3> xy = {{{2176, 2176}, {6272, 2176}, {2176, 6272}}};
  for (int k = 0; k < 3; ++k) v[k].x = xy[k][0], v[k].y = xy[k][1], v[k].inv_w = 1.0f;
  return v;
}

// What unit u emits and when, and its counters, by the cost model: the clear
// (read at 0), the triangle, the end of frame. Tiles 8 x 8 of unit
// (tx + ty) % units; stamps 4 x 2.
struct Expected {
  std::vector<StampBatch> out;
  std::vector<uint64_t> cycles;
  uint64_t tiles = 0, rejected = 0, accepted = 0, evaluated = 0, stamps_accepted = 0;
  uint64_t emitted = 0, fragments = 0, busy = 0;
};

Expected expect_unit(const std::shared_ptr<RasterPrimitive>& t, const GpuConfig& c, unsigned u) {
  const unsigned ii = c.stage("tile_rasterizer").ii, latency = c.stage("tile_rasterizer").latency;
  const auto v = vertices();
  Expected x;
  uint64_t now = 0, pending = 0;
  auto control = [&](PacketKind k) {
    now += ii;
    x.out.push_back(StampBatch{k, nullptr, {}, {}});
    x.cycles.push_back(now + latency);
  };
  control(PacketKind::clear);
  for (int ty = t->y0 / 8; ty <= t->y1 / 8; ++ty) {
    for (int tx = t->x0 / 8; tx <= t->x1 / 8; ++tx) {
      if (static_cast<unsigned>(tx + ty) % c.units != u) continue;
      ++x.tiles;
      ++pending;  // the tile test
      bool reject = false, accept = true;
      for (int k = 0; k < 3; ++k) {
        bool somewhere = false;
        for (int p = 0; p < 64; ++p) {
          const bool pass = passes(k, tx * 8 + p % 8, ty * 8 + p / 8);
          somewhere = somewhere || pass;
          accept = accept && pass;
        }
        reject = reject || !somewhere;
      }
      if (reject) {
        ++x.rejected;
        continue;
      }
      if (accept) ++x.accepted;
      if (c.tile_test_overlap) --pending;  // hidden behind the tile's stamps
      StampBatch b{PacketKind::work, t, {}, {}};
      for (int sy = ty * 8; sy < ty * 8 + 8; sy += 2) {
        for (int sx = tx * 8; sx < tx * 8 + 8; sx += 4) {
          if (sx + 3 < t->x0 || sx > t->x1 || sy + 1 < t->y0 || sy > t->y1) continue;
          pending += ii;
          ++(accept ? x.stamps_accepted : x.evaluated);
          Stamp s{sx, sy, 0, {}};
          for (int k = 0; k < 3; ++k) {
            s.e[k] = golden::edge_function(v[(k + 1) % 3], v[(k + 2) % 3], pixel_center(sx),
                                           pixel_center(sy));
          }
          for (int bit = 0; bit < 8; ++bit) {
            const int px = sx + bit % 4, py = sy + bit / 4;
            if (px >= t->x0 && px <= t->x1 && py >= t->y0 && py <= t->y1 && covered(px, py)) {
              s.mask |= uint64_t{1} << bit;
              ++x.fragments;
            }
          }
          if (s.mask == 0) continue;
          b.stamps.push_back(s);
          ++x.emitted;
        }
      }
      if (b.stamps.empty()) continue;
      now += pending;  // the walk waits its cycles, then writes the batch
      pending = 0;
      x.out.push_back(b);
      x.cycles.push_back(now + latency);
    }
  }
  now += pending;  // trailing tiles without coverage
  control(PacketKind::end_of_frame);
  x.busy = now;
  return x;
}

class TileRasterizerStage : public ::testing::TestWithParam<std::tuple<unsigned, bool>> {};

TEST_P(TileRasterizerStage, CoversTheFillRulesPixelsTileByTileAtItsCost) {
  const auto [units, overlap] = GetParam();
  GpuConfig config = GpuConfig::baseline();
  config.units = units;
  config.tile_size = 8;
  config.stamp = {4, 2};
  config.tile_test_overlap = overlap;
  config.stages["tile_rasterizer"] = {2, 3};  // not the defaults (1, 2)
  FrameState frame;
  frame.framebuffer.width = 32;
  frame.framebuffer.height = 32;
  frame.draws.resize(1);
  const std::shared_ptr<RasterPrimitive> tri =
      setup(vertices(), RenderState{}, 0, 0, glm::vec4(1.0f), frame.framebuffer);
  ASSERT_EQ(std::make_tuple(tri->x0, tri->x1, tri->y0, tri->y1), std::make_tuple(8, 24, 8, 24));

  std::vector<std::unique_ptr<Fifo<SetupPacket>>> in;
  std::vector<std::unique_ptr<Fifo<StampBatch>>> out;
  std::vector<std::unique_ptr<TileRasterizer>> rasterizers;
  std::vector<std::unique_ptr<Sink<StampBatch>>> sinks;
  for (unsigned u = 0; u < units; ++u) {
    const std::string n = std::to_string(u);
    in.push_back(std::make_unique<Fifo<SetupPacket>>(("in_" + n).c_str(), 4));
    out.push_back(std::make_unique<Fifo<StampBatch>>(("out_" + n).c_str(), 16));
    rasterizers.push_back(
        std::make_unique<TileRasterizer>(("tile_rasterizer_" + n).c_str(), config, frame, u));
    rasterizers[u]->in(*in[u]);
    rasterizers[u]->out(*out[u]);
    feed(*in[u], {SetupPacket{PacketKind::clear, nullptr}, SetupPacket{PacketKind::work, tri},
                  SetupPacket{PacketKind::end_of_frame, nullptr}});
    sinks.push_back(std::make_unique<Sink<StampBatch>>(*out[u], config.cycle()));
  }
  sc_core::sc_start();

  // Over all units, by hand: tiles (1..3, 1..3) in the box; those with
  // tx + ty >= 4 rejected (the smallest x + y in them is 32), (1, 1)
  // accepted (x + y <= 30 everywhere), (2, 1) and (1, 2) partial. Stamps
  // inside the box: 8 in each of these three; 8 emitted from (1, 1), 6 from
  // each partial one (the stamps at (20, 12), (20, 14) and their mirror
  // images lie beyond x + y = 31).
  Expected sum;
  for (unsigned u = 0; u < units; ++u) {
    SCOPED_TRACE("unit " + std::to_string(u));
    const Expected x = expect_unit(tri, config, u);
    ASSERT_EQ(sinks[u]->items.size(), x.out.size());
    for (size_t i = 0; i < x.out.size(); ++i) EXPECT_EQ(sinks[u]->items[i], x.out[i]) << i;
    EXPECT_EQ(sinks[u]->cycles, x.cycles);
    const StatGroup& s = rasterizers[u]->stats();
    EXPECT_EQ(counter(s, "triangles"), 1u);
    EXPECT_EQ(counter(s, "tiles_visited"), x.tiles);
    EXPECT_EQ(counter(s, "tiles_rejected"), x.rejected);
    EXPECT_EQ(counter(s, "tiles_accepted"), x.accepted);
    EXPECT_EQ(counter(s, "stamps_evaluated"), x.evaluated);
    EXPECT_EQ(counter(s, "stamps_accepted"), x.stamps_accepted);
    EXPECT_EQ(counter(s, "stamps_emitted"), x.emitted);
    EXPECT_EQ(counter(s, "fragments"), x.fragments);
    EXPECT_EQ(counter(s, "samples"), x.fragments);
    EXPECT_EQ(counter(s, "busy_cycles"), x.busy);
    EXPECT_EQ(counter(s, "tokens_in"), 3u);
    EXPECT_EQ(counter(s, "tokens_out"), x.out.size());
    for (uint64_t Expected::*f :
         {&Expected::tiles, &Expected::rejected, &Expected::accepted, &Expected::evaluated,
          &Expected::stamps_accepted, &Expected::emitted, &Expected::fragments}) {
      sum.*f += x.*f;
    }
  }
  EXPECT_EQ(std::make_tuple(sum.tiles, sum.rejected, sum.accepted), std::make_tuple(9, 6, 1));
  EXPECT_EQ(std::make_tuple(sum.stamps_accepted, sum.evaluated, sum.emitted),
            std::make_tuple(8, 16, 20));
  EXPECT_EQ(sum.fragments, 136u);
}

INSTANTIATE_TEST_SUITE_P(UnitsAndOverlap, TileRasterizerStage,
                         ::testing::Combine(::testing::Values(1u, 2u, 3u), ::testing::Bool()));

}  // namespace
}  // namespace gpusim
