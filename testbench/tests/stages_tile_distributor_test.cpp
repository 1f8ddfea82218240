// The tile distributor (stages/tile_distributor.h) alone: a host writes set-up
// primitives (only their pixel boxes matter to it) and control tokens into
// its input FIFO, and one sink per unit reads that unit's FIFO
// (testbench/tests/stage_host.h). Checked: which units get each primitive,
// against the documented ownership rule worked out in the test (tile
// (tx, ty) of pixel (x, y) is (x / tile, y / tile), owned by unit
// (tx + ty) mod units: by hand for a few boxes, pixel by pixel for random
// ones); control tokens to every unit in order; the cost, ii per unit sent
// to (at least ii) and ii per control token, every copy readable latency
// cycles after; its counters; and a full unit FIFO blocking it (head of
// line). One sc_start per TEST (ctest runs each in its own process).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "stages/tile_distributor.h"
#include "testbench/tests/stage_host.h"

namespace gpusim {
namespace {

using namespace test;

SetupPacket box(int64_t id, int x0, int y0, int x1, int y1) {
  auto p = std::make_shared<RasterPrimitive>();
  p->primitive_id = id;
  p->x0 = x0, p->y0 = y0, p->x1 = x1, p->y1 = y1;
  return SetupPacket{PacketKind::work, p};
}
SetupPacket token(PacketKind k) {
  return SetupPacket{k, nullptr};
}

// The distributor, its input and one FIFO and sink per unit; unit 0's FIFO
// holds `depth0` packets and its sink starts reading at cycle `from0`.
struct Bench {
  Fifo<SetupPacket> in;
  TileDistributor distributor;
  std::vector<std::unique_ptr<Fifo<SetupPacket>>> outs;
  std::vector<std::unique_ptr<Sink<SetupPacket>>> sinks;

  Bench(const std::string& name, const GpuConfig& c, const FrameState& f,
        std::vector<SetupPacket> tokens, unsigned depth0 = 16, uint64_t from0 = 0)
      : in((name + "_in").c_str(), 16), distributor((name + "_distributor").c_str(), c, f) {
    distributor.in(in);
    for (unsigned u = 0; u < c.units; ++u) {
      outs.push_back(std::make_unique<Fifo<SetupPacket>>(
          (name + "_unit" + std::to_string(u)).c_str(), u == 0 ? depth0 : 16));
      distributor.out[u](*outs[u]);
      sinks.push_back(std::make_unique<Sink<SetupPacket>>(*outs[u], c.cycle(), u == 0 ? from0 : 0));
    }
    feed(in, std::move(tokens));
  }
  // What unit u received: primitive ids, -1 for a clear, -2 for the end of frame.
  std::vector<int64_t> received(unsigned u) const {
    std::vector<int64_t> ids;
    for (const SetupPacket& p : sinks[u]->items) {
      ids.push_back(p.kind == PacketKind::work    ? p.primitive->primitive_id
                    : p.kind == PacketKind::clear ? -1
                                                  : -2);
    }
    return ids;
  }
};

// Units 3, tiles 16 x 16: tile (tx, ty) belongs to unit (tx + ty) % 3.
//   0: box in tile (2, 1) only                    -> unit 0
//   1: tiles (0, 0), (1, 0)                       -> units 0, 1
//   2: the whole 128 x 64 screen, 8 x 4 tiles     -> units 0, 1, 2
//   3: exactly tile (2, 0), 32..47 x 0..15        -> unit 2
//   4: an empty box                               -> none (costs ii)
//   5: tiles (4, 1), (4, 2)                       -> units 2, 0
//   6: pixels 15..16 x 15..16: tiles (0, 0), (1, 0), (0, 1), (1, 1)
//                                                 -> units 0, 1, 1, 2
TEST(TileDistributorStage, SendsEachBoxToTheOwnersOfItsTilesAtItsCost) {
  GpuConfig config = GpuConfig::baseline();
  config.units = 3;
  config.tile_size = 16;
  const unsigned ii = 2, latency = 3;  // not the defaults (1, 2)
  config.stages["tile_distributor"] = {ii, latency};
  FrameState frame;
  frame.framebuffer.width = 128;
  frame.framebuffer.height = 64;
  const std::vector<SetupPacket> tokens = {
      token(PacketKind::clear),       box(0, 35, 20, 40, 30),   box(1, 10, 5, 20, 9),
      box(2, 0, 0, 127, 63),          token(PacketKind::clear), box(3, 32, 0, 47, 15),
      box(4, 0, 0, -1, -1),           box(5, 70, 20, 75, 40),   box(6, 15, 15, 16, 16),
      token(PacketKind::end_of_frame)};
  const std::vector<std::set<unsigned>> to = {{0, 1, 2}, {0}, {0, 1}, {0, 1, 2}, {0, 1, 2},
                                              {2},       {},  {0, 2}, {0, 1, 2}, {0, 1, 2}};
  Bench bench("hand", config, frame, tokens);
  sc_core::sc_start();

  // All tokens wait at 0: token n is read when token n - 1's busy time ends,
  // and each copy of it is readable busy + latency cycles after it was read.
  std::vector<std::vector<int64_t>> want_ids(config.units);
  std::vector<std::vector<uint64_t>> want_cycles(config.units);
  uint64_t t = 0, sent = 0;
  for (size_t n = 0; n < tokens.size(); ++n) {
    const bool work = tokens[n].kind == PacketKind::work;
    const uint64_t busy = ii * (work ? std::max<uint64_t>(1, to[n].size()) : 1);
    for (unsigned u : to[n]) {
      want_ids[u].push_back(work ? tokens[n].primitive->primitive_id
                                 : (tokens[n].kind == PacketKind::clear ? -1 : -2));
      want_cycles[u].push_back(t + busy + latency);
      if (work) ++sent;
    }
    t += busy;
  }
  ASSERT_EQ(t, 32u);
  ASSERT_EQ(sent, 12u);
  const StatGroup& s = bench.distributor.stats();
  const std::vector<uint64_t> per_unit = {5, 3, 4};
  for (unsigned u = 0; u < config.units; ++u) {
    EXPECT_EQ(bench.received(u), want_ids[u]) << "unit " << u;
    EXPECT_EQ(bench.sinks[u]->cycles, want_cycles[u]) << "unit " << u;
    EXPECT_EQ(counter(s, "triangles_sent_unit" + std::to_string(u)), per_unit[u]) << "unit " << u;
  }
  EXPECT_EQ(counter(s, "triangles_sent"), 12u);
  EXPECT_EQ(counter(s, "tokens_in"), 10u);
  EXPECT_EQ(counter(s, "tokens_out"), 12u + 3 * 3);
  EXPECT_EQ(counter(s, "busy_cycles"), 32u);
}

// Random boxes, empty ones among them, in a 203 x 157 screen of 8 x 8 tiles:
// the units of each box found by looking at the owner of every pixel's tile.
class TileDistributorUnits : public ::testing::TestWithParam<unsigned> {};

TEST_P(TileDistributorUnits, RandomBoxesReachTheOwnersOfTheirPixels) {
  GpuConfig config = GpuConfig::baseline();
  config.units = GetParam();
  config.tile_size = 8;
  FrameState frame;
  frame.framebuffer.width = 203;
  frame.framebuffer.height = 157;
  std::mt19937 rng(17 + GetParam());
  std::vector<SetupPacket> tokens = {token(PacketKind::clear)};
  std::vector<std::vector<int64_t>> want(config.units, {-1});
  std::vector<uint64_t> per_unit(config.units, 0);
  uint64_t busy = 1;  // ii per control token, per unit sent to
  for (int64_t id = 0; id < 150; ++id) {
    auto pick = [&](int size) { return static_cast<int>(rng() % static_cast<unsigned>(size)); };
    const int x0 = pick(203), y0 = pick(157);
    const int span = id % 3 == 0 ? 200 : 24;  // large boxes and small ones
    const int x1 = std::min(202, x0 + pick(span)) - (id % 10 == 0 ? 203 : 0);  // some empty
    const int y1 = std::min(156, y0 + pick(span));
    tokens.push_back(box(id, x0, y0, x1, y1));
    std::set<unsigned> owners;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x)
        owners.insert(static_cast<unsigned>(x / 8 + y / 8) % GetParam());
    }
    for (unsigned u : owners) {
      want[u].push_back(id);
      ++per_unit[u];
    }
    busy += std::max<uint64_t>(1, owners.size());
  }
  tokens.push_back(token(PacketKind::end_of_frame));
  ++busy;
  Bench bench("random", config, frame, tokens);
  sc_core::sc_start();

  uint64_t sent = 0;
  for (unsigned u = 0; u < config.units; ++u) {
    want[u].push_back(-2);
    EXPECT_EQ(bench.received(u), want[u]) << "unit " << u;
    EXPECT_EQ(counter(bench.distributor.stats(), "triangles_sent_unit" + std::to_string(u)),
              per_unit[u]);
    sent += per_unit[u];
  }
  EXPECT_EQ(counter(bench.distributor.stats(), "triangles_sent"), sent);
  EXPECT_EQ(counter(bench.distributor.stats(), "tokens_out"), sent + 2 * config.units);
  EXPECT_EQ(counter(bench.distributor.stats(), "busy_cycles"), busy);
}

INSTANTIATE_TEST_SUITE_P(Units, TileDistributorUnits, ::testing::Values(1u, 2u, 4u, 7u));

// Head of line, ii 1, latency 2, unit 0's FIFO one packet deep and its sink
// reading from cycle 30. A (unit 0) is read at 0 and written at 1, readable
// at 3; B (unit 0) is read at 1 and blocks in its write at 2 until the sink
// takes A at 30, entering the FIFO then: readable at 32. C (unit 1) waits
// behind it: read at 30, readable at 33, where it would have been readable
// at 5 (2 + 1 + 2).
TEST(TileDistributorStage, AFullUnitFifoBlocksEveryUnit) {
  GpuConfig config = GpuConfig::baseline();
  config.units = 2;
  config.tile_size = 16;
  FrameState frame;
  frame.framebuffer.width = 64;
  frame.framebuffer.height = 64;
  Bench bench("blocked", config, frame,
              {box(0, 0, 0, 15, 15), box(1, 1, 1, 2, 2), box(2, 16, 0, 31, 15)}, 1, 30);
  sc_core::sc_start();

  EXPECT_EQ(bench.received(0), (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(bench.sinks[0]->cycles, (std::vector<uint64_t>{30, 32}));
  EXPECT_EQ(bench.received(1), (std::vector<int64_t>{2}));
  EXPECT_EQ(bench.sinks[1]->cycles, (std::vector<uint64_t>{33}));
  EXPECT_EQ(counter(bench.distributor.stats(), "busy_cycles"), 3u);
}

}  // namespace
}  // namespace gpusim
