// The depth test (stages/depth_test.h) alone: a host writes stamp batches and
// control tokens into its input FIFO, a sink reads what it forwards
// (testbench/tests/stage_host.h), and its tile cache reads and writes a real
// Memory whose depth buffer the test fills beforehand and reads back after.
// The batches are stamps of a triangle of constant depth (the fragment's
// depth is then exactly its z) placed where the test likes
// (testbench/tests/back_end_input.h).
//
// Checked: every compare function with depth writes on and off, and the
// depth test off, against stored values just below, equal to and just above
// the fragment's, with the pass or fail of each pixel worked out in the test
// from docs/pipeline-spec.md section 11; the surviving masks forwarded and
// batches left empty dropped; the depth buffer read back from memory; a
// fast clear filling only the unit's own tiles and a colour clear leaving
// depth alone; the cost (ii per stamp or token, the memory stalls of the
// tile reads and of the end of frame's write-back, by the memory model of
// hw/memory.h) with each token's cycle; and the counters. One sc_start per
// TEST (ctest runs each in its own process).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "stages/depth_test.h"
#include "testbench/tests/back_end_input.h"
#include "testbench/tests/stage_host.h"

namespace gpusim {
namespace {

using namespace test;

// 0.5 * 65535 = 32767.5 rounds to the even 32768: the fragments' unorm16 depth.
constexpr uint16_t kZ = 32768;
// The stored value of pixel (x, y): one below, equal to, one above kZ.
uint16_t stored(int x, int y) {
  return static_cast<uint16_t>(kZ - 1 + (x + y) % 3);
}
// Section 11, fragment `op` stored, as a table: whether each function
// passes when the fragment is below, equal to or above the stored value.
bool passes(CompareFunc f, uint16_t z, uint16_t s) {
  static const std::map<CompareFunc, std::array<bool, 3>> kTable = {
      {CompareFunc::never, {false, false, false}},  {CompareFunc::less, {true, false, false}},
      {CompareFunc::equal, {false, true, false}},   {CompareFunc::lequal, {true, true, false}},
      {CompareFunc::greater, {false, false, true}}, {CompareFunc::notequal, {true, false, true}},
      {CompareFunc::gequal, {false, true, true}},   {CompareFunc::always, {true, true, true}}};
  return kTable.at(f)[z < s ? 0 : z == s ? 1 : 2];
}

// A depth test on a fresh memory (every byte 0xA5), its FIFOs and a sink.
struct Bench {
  Memory memory;
  Fifo<StampBatch> in, out;
  DepthTest depth;
  Sink<StampBatch> sink;
  Bench(const std::string& n, const GpuConfig& c, const FrameState& f, std::vector<StampBatch> t,
        unsigned unit = 0)
      : memory((n + "_memory").c_str(),
               f.depth_address + f.framebuffer.width * f.framebuffer.height * 2 + kGuard,
               c.memory.latency, c.memory.bytes_per_cycle, c.cycle()),
        in((n + "_in").c_str(), 32),
        out((n + "_out").c_str(), 32),
        depth((n + "_depth_test").c_str(), c, f, unit),
        sink(out, c.cycle()) {
    std::memset(memory.data(0, memory.size()), 0xA5, memory.size());
    depth.in(in);
    depth.out(out);
    depth.mem.bind(memory);
    feed(in, std::move(t));
  }
  uint16_t at(const FrameState& f, int x, int y) const {
    uint16_t v = 0;
    memory.debug_read(f.depth_address + (static_cast<uint64_t>(y) * f.framebuffer.width + x) * 2,
                      &v, 2);
    return v;
  }
};

// A unorm16 depth buffer at kGuard, one draw per render state.
FrameState frame_of(int width, int height, std::vector<RenderState> draws) {
  FrameState f;
  f.framebuffer.width = width;
  f.framebuffer.height = height;
  f.framebuffer.depth_format = DepthFormat::unorm16;
  f.framebuffer.clear_depth = 0.25f;  // 16383.75: 16384
  for (const RenderState& st : draws) {
    f.draws.emplace_back();
    f.draws.back().state = st;
  }
  f.depth_address = kGuard;
  return f;
}

// One stamp at (x, y) of draw `d`'s copy of the full-screen triangle.
StampBatch batch(const FrameState& f, const GpuConfig& c, uint32_t d, int x, int y, uint64_t mask) {
  auto t = full_screen_triangle(f.framebuffer, 0.5f);
  t->draw_id = d;
  Stamp s = make_stamp(*t, x, y, c, f.framebuffer);
  s.mask = mask;
  return StampBatch{PacketKind::work, t, {s}, {}};
}

const StampBatch kEndOfFrame{PacketKind::end_of_frame, nullptr, {}, {}};
constexpr uint64_t kMask = 0x7FFE;  // pixels 0 and 15 of each stamp uncovered

GpuConfig depth_config(unsigned units) {
  GpuConfig c = config(units, 16, 4, 4, 32, 4);  // memory: latency 20, 32 bytes a cycle
  c.stages["depth_test"] = {2, 3};               // not the defaults (1, 2)
  return c;
}

// Draws 0-7: function f with writes, stamp (4 f, 0); 8-15: without, stamp
// (4 f, 4); 16: the depth test off (func never, writes on), stamp (0, 8).
TEST(DepthTestStage, EveryCompareFunctionAgainstTheStoredDepth) {
  const GpuConfig cfg = depth_config(1);
  std::vector<RenderState> states(17);
  for (int d = 0; d < 16; ++d) {
    states[d].depth_func = static_cast<CompareFunc>(d % 8);
    states[d].depth_write = d < 8;
  }
  states[16].depth_test = false;
  states[16].depth_func = CompareFunc::never;
  const FrameState frame = frame_of(64, 16, states);
  std::vector<StampBatch> tokens;
  for (uint32_t d = 0; d < 17; ++d) {
    tokens.push_back(
        batch(frame, cfg, d, d < 16 ? 4 * (d % 8) : 0, d < 16 ? 4 * (d / 8) : 8, kMask));
  }
  tokens.push_back(kEndOfFrame);
  Bench b("compare", cfg, frame, tokens);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 64; ++x) {
      const uint16_t s = stored(x, y);
      b.memory.debug_write(frame.depth_address + (y * 64 + x) * 2, &s, 2);
    }
  }
  sc_core::sc_start();

  std::vector<StampBatch> want;
  std::vector<uint16_t> depth(64 * 16);
  for (int p = 0; p < 64 * 16; ++p) depth[p] = stored(p % 64, p / 64);
  uint64_t passed = 0;
  for (uint32_t d = 0; d < 17; ++d) {
    StampBatch w = tokens[d];
    Stamp& s = w.stamps[0];
    for (int bit = 0; bit < 16; ++bit) {
      const int x = s.x + bit % 4, y = s.y + bit / 4;
      const bool pass = !states[d].depth_test || passes(states[d].depth_func, kZ, stored(x, y));
      if (!(kMask >> bit & 1) || !pass) {
        s.mask &= ~(uint64_t{1} << bit);
        continue;
      }
      ++passed;
      if (states[d].depth_test && states[d].depth_write) depth[y * 64 + x] = kZ;
    }
    if (s.mask != 0) want.push_back(w);  // an empty batch is not forwarded
  }
  want.push_back(kEndOfFrame);
  ASSERT_EQ(want.size(), 16u);  // the two `never` batches dropped
  ASSERT_EQ(b.sink.items.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(b.sink.items[i], want[i]) << "batch " << i;
  for (int p = 0; p < 64 * 16; ++p) {
    EXPECT_EQ(b.at(frame, p % 64, p / 64), depth[p]) << "pixel " << p % 64 << ", " << p / 64;
  }

  // The buffer is read for the 13 stamps whose outcome or write needs it
  // (not never, not always without writes, not with the test off): tile 0
  // (x < 16) and tile 1 each missed once, 16 rows of 32 bytes, and both
  // written back at the end of the frame. Each miss stalls 16 bus cycles +
  // latency 20; the end of frame writes 32 rows from its latency (3) on:
  // done after 3 + 32 + 20 cycles, its ii (2) included.
  const StatGroup& s = b.depth.stats();
  expect_counters(s, {{"stamps", 17},
                      {"stamps_passed", 15},
                      {"fragments_in", 17 * 14},
                      {"fragments_passed", passed},
                      {"samples_passed", passed},
                      {"depth_clears", 0},
                      {"tokens_in", 18},
                      {"tokens_out", 16},
                      {"cache_misses", 2},
                      {"cache_hits", 11},
                      {"bytes_read", 2 * 512},
                      {"bytes_written", 2 * 512},
                      {"memory_stall_cycles", 2 * (16 + 20) + (3 + 32 + 20 - 2)}});
  EXPECT_EQ(counter(s, "busy_cycles") - counter(s, "memory_stall_cycles"), 2u * (17 + 1));
}

// Unit 1 of 2 in 64 x 32 (4 x 2 tiles) owns (1, 0), (3, 0), (0, 1), (2, 1).
// The frame clear (depth 0.25: 16384) marks them cleared; the draw list's
// colour clear passes by; the end of frame writes them, 64 rows of 32 bytes.
// ii 2, latency 3: the clear is read at 0, readable at 5; the colour clear
// read at 2, readable at 7; the end of frame read at 4 starts the write-back
// at 4 + 3 = 7, the bus streams the rows until 71, the last completes at
// 91: forwarded at 91, readable at once.
TEST(DepthTestStage, FastClearFillsOnlyItsOwnTiles) {
  const GpuConfig cfg = depth_config(2);
  FrameState frame = frame_of(64, 32, {});
  ClearState colour;
  colour.color = true;
  frame.clears.push_back(colour);
  const StampBatch clear{PacketKind::clear, nullptr, {}, {}};
  Bench b("clear", cfg, frame, {clear, clear, kEndOfFrame}, 1);
  sc_core::sc_start();

  EXPECT_EQ(b.sink.items, (std::vector<StampBatch>{clear, clear, kEndOfFrame}));
  EXPECT_EQ(b.sink.cycles, (std::vector<uint64_t>{5, 7, 91}));
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool own = (x / 16 + y / 16) % 2 == 1;
      EXPECT_EQ(b.at(frame, x, y), own ? 16384 : 0xA5A5) << x << ", " << y;
    }
  }
  expect_counters(b.depth.stats(), {{"depth_clears", 1},
                                    {"busy_cycles", 91},
                                    {"memory_stall_cycles", 91 - 3 * 2},
                                    {"bytes_read", 0},
                                    {"bytes_written", 4 * 512},
                                    {"tokens_out", 3}});
}

// No stored value can matter: the test off, always without writes, never
// (the batch dropped). No memory traffic, so ii 3, latency 2 alone decide:
// A (3 stamps) read at 0, readable at 9 + 2 = 11; B (2) read at 9, readable
// at 17; C (1, never) read at 15, busy until 18; D (2) read at 18, readable
// at 26; the end of frame read at 24, busy 3, forwarded at 27.
TEST(DepthTestStage, StampsThatNeedNoStoredDepthCostIiEach) {
  GpuConfig cfg = depth_config(1);
  cfg.stages["depth_test"] = {3, 2};
  std::vector<RenderState> states(3);
  states[0].depth_test = false;
  states[1].depth_func = CompareFunc::always;
  states[1].depth_write = false;
  states[2].depth_func = CompareFunc::never;
  const FrameState frame = frame_of(64, 16, states);
  auto stamps = [&](uint32_t d, int n) {
    StampBatch b = batch(frame, cfg, d, 0, 0, 0xFFFF);
    for (int i = 1; i < n; ++i)
      b.stamps.push_back(batch(frame, cfg, d, 4 * i, 0, 0xFFFF).stamps[0]);
    return b;
  };
  Bench b("free", cfg, frame,
          {stamps(0, 3), stamps(1, 2), stamps(2, 1), stamps(0, 2), kEndOfFrame});
  sc_core::sc_start();

  EXPECT_EQ(b.sink.cycles, (std::vector<uint64_t>{11, 17, 26, 27}));
  expect_counters(b.depth.stats(), {{"busy_cycles", 27},
                                    {"memory_stall_cycles", 0},
                                    {"bytes_read", 0},
                                    {"bytes_written", 0},
                                    {"fragments_passed", 7 * 16},
                                    {"stamps_passed", 7}});
}

}  // namespace
}  // namespace gpusim
