// The ROP (stages/rop.h) alone: a host writes shaded stamp batches and control
// tokens into its input FIFO (testbench/tests/stage_host.h), and its tile
// cache reads and writes a real Memory whose colour buffer the test fills
// with destination colours beforehand and reads back after the frame.
//
// Checked: the colour written per docs/pipeline-spec.md section 12, worked
// out by hand in the test for blending off, each equation (add, subtract,
// reverse_subtract) and every blend factor, colour masks (some channels,
// none: nothing written), rgba8's clamp and round to nearest and rgba16f's
// unclamped half with ties to even; pixels a stamp does not cover left
// alone; a fast clear of only the unit's own tiles and a depth clear leaving
// colour alone; the cost (ii per stamp or token plus the memory stalls of
// the tile reads and the end of frame's write-back, by the memory model of
// hw/memory.h) and when the frame is done; and the counters. One sc_start
// per TEST (ctest runs each in its own process).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "stages/rop.h"
#include "testbench/tests/back_end_input.h"
#include "testbench/tests/stage_host.h"

namespace gpusim {
namespace {

using namespace test;
using F = BlendFactor;
using E = BlendEquation;

constexpr uint64_t kMask = 0x7FFE;  // pixels 0 and 15 of each stamp uncovered

// A ROP on a fresh memory (every byte 0xA5) holding a colour buffer at
// kGuard, with the cycle at which it reports the frame done.
struct Bench {
  Memory memory;
  Fifo<ShadedStampBatch> in;
  Rop rop;
  uint64_t done_at = 0;
  Bench(const std::string& n, const GpuConfig& c, const FrameState& f,
        std::vector<ShadedStampBatch> t, unsigned unit = 0)
      : memory((n + "_memory").c_str(),
               f.color_address +
                   f.framebuffer.width * f.framebuffer.height *
                       color_bytes_per_pixel(f.framebuffer.color_format) +
                   kGuard,
               c.memory.latency, c.memory.bytes_per_cycle, c.cycle()),
        in((n + "_in").c_str(), 32),
        rop((n + "_rop").c_str(), c, f, unit) {
    std::memset(memory.data(0, memory.size()), 0xA5, memory.size());
    rop.in(in);
    rop.mem.bind(memory);
    feed(in, std::move(t));
    sc_core::sc_spawn([this, cycle = c.cycle()] {
      sc_core::wait(rop.frame_done_event());
      done_at = static_cast<uint64_t>(sc_core::sc_time_stamp() / cycle);
    });
  }
};

FrameState frame_of(int width, int height, ColorFormat format, std::vector<RenderState> draws) {
  FrameState f;
  f.framebuffer.width = width;
  f.framebuffer.height = height;
  f.framebuffer.color_format = format;
  f.framebuffer.clear_color = {0.2f, 0.4f, 0.6f, 1.0f};  // rgba8 51, 102, 153, 255
  for (const RenderState& st : draws) {
    f.draws.emplace_back();
    f.draws.back().state = st;
  }
  f.color_address = kGuard;
  return f;
}

// The stamp at (4 d, 0) of draw d, every covered pixel of colour `src`.
ShadedStampBatch batch(uint32_t d, const glm::vec4& src) {
  auto t = std::make_shared<RasterPrimitive>();
  t->draw_id = d;
  ShadedStampBatch b{PacketKind::work, t, {Stamp{4 * static_cast<int>(d), 0, kMask, {}}}, {}, {}};
  b.colors.assign(14, src);
  return b;
}

const ShadedStampBatch kEndOfFrame{PacketKind::end_of_frame, nullptr, {}, {}, {}};

GpuConfig rop_config(unsigned units) {
  GpuConfig c = config(units, 16, 4, 4, 32, 4);  // memory: latency 20, 32 bytes a cycle
  c.stages["rop"] = {2, 3};                      // not the defaults (1, 4)
  return c;
}

RenderState blending(F src, F dst, E eq) {
  RenderState st;
  st.blend = true;
  st.blend_src = src, st.blend_dst = dst, st.blend_equation = eq;
  return st;
}

struct Case {
  RenderState st;
  glm::vec4 src;
  std::array<uint8_t, 4> dst, want;  // the stored colour before and after
};

// out = s F_src + d F_dst (add), with d = stored / 255, stored as
// nearbyint(clamp01(out) * 255); each worked out to a value at least 0.05
// from a rounding boundary.
std::vector<Case> cases() {
  std::vector<Case> c(11);
  // Off: s. 0.2 * 255 = 51, 0.4 * 255 = 102, 0.6 * 255 = 153.
  c[0] = {RenderState{}, {0.2f, 0.4f, 0.6f, 1.0f}, {9, 9, 9, 9}, {51, 102, 153, 255}};
  // s * 0.25 + d * 0.75: (0.25, 0, 0.75, 0.8125) * 255 = 63.75, 0, 191.25, 207.19.
  c[1] = {blending(F::src_alpha, F::one_minus_src_alpha, E::add),
          {1.0f, 0.0f, 0.0f, 0.25f},
          {0, 0, 255, 255},
          {64, 0, 191, 207}};
  // s - d: (0.8 - 0.2, 0.5 - 0.8 -> 0, 0.4 - 0, 1 - 1).
  c[2] = {blending(F::one, F::one, E::subtract),
          {0.8f, 0.5f, 0.4f, 1.0f},
          {51, 204, 0, 255},
          {153, 0, 102, 0}};
  // d - s: (1 - 0.4, 0.502 - 0.25 = 0.252 -> 64.25, 0.392 - 0.5 -> 0, 0.75 -> 191.25).
  c[3] = {blending(F::one, F::one, E::reverse_subtract),
          {0.4f, 0.25f, 0.5f, 0.25f},
          {255, 128, 100, 255},
          {153, 64, 0, 191}};
  // s * d: (0.5 * 200, 1 * 100, 0.25 * 40, 1 * 128) / 255.
  c[4] = {blending(F::dst_color, F::zero, E::add),
          {0.5f, 1.0f, 0.25f, 1.0f},
          {200, 100, 40, 128},
          {100, 100, 10, 128}};
  // min(s.a, 1 - d.a) = 0.4 for r, g, b, 1 for alpha: (0.4, 0.2, 0.08) -> 102,
  // 51, 20.4; alpha 0.6 + 0.6 -> 1.
  c[5] = {blending(F::src_alpha_saturate, F::one, E::add),
          {1.0f, 0.5f, 0.2f, 0.6f},
          {0, 0, 0, 153},
          {102, 51, 20, 255}};
  // Red and alpha enabled, unblended: green and blue keep theirs.
  c[6] = {RenderState{}, {0.2f, 0.4f, 0.6f, 0.0f}, {1, 2, 3, 4}, {51, 2, 3, 0}};
  c[6].st.color_mask = {true, false, false, true};
  // No channel: nothing changes (and no memory is touched).
  c[7] = {RenderState{}, {0.2f, 0.4f, 0.6f, 1.0f}, {5, 6, 7, 8}, {5, 6, 7, 8}};
  c[7].st.color_mask = {false, false, false, false};
  // s * s + d * (1 - d.a), d.a = 0.2: 0.25 + 0.392 * 0.8 = 0.564 -> 143.75,
  // 0.04 + 0.196 * 0.8 -> 50.2, 0.81 -> 206.55, 0.25 + 0.16 -> 104.55.
  c[8] = {blending(F::src_color, F::one_minus_dst_alpha, E::add),
          {0.5f, 0.2f, 0.9f, 0.5f},
          {100, 50, 0, 51},
          {144, 50, 207, 105}};
  // s * (1 - s) + d * d.a, d.a = 0.502: 0.25 + 0.502 -> 191.75, 0.09 -> 22.95,
  // 0.4 * 0.502 -> 51.2, 0.21 + 0.252 -> 117.8.
  c[9] = {blending(F::one_minus_src_color, F::dst_alpha, E::add),
          {0.5f, 0.1f, 1.0f, 0.3f},
          {255, 0, 102, 128},
          {192, 23, 51, 118}};
  // s * (1 - d): (0.8, 0, 0.4, 0.2).
  c[10] = {blending(F::one_minus_dst_color, F::zero, E::add),
           {1.0f, 1.0f, 0.4f, 1.0f},
           {51, 255, 0, 204},
           {204, 0, 102, 51}};
  return c;
}

// rgba8, 64 x 16, one unit; case d's stamp at (4 d, 0), its 4 x 4 pixels
// holding the case's destination colour.
TEST(RopStage, BlendsEveryEquationAndFactorIntoTheStoredColour) {
  const GpuConfig cfg = rop_config(1);
  const std::vector<Case> cs = cases();
  std::vector<RenderState> states;
  std::vector<ShadedStampBatch> tokens;
  for (uint32_t d = 0; d < cs.size(); ++d) {
    states.push_back(cs[d].st);
    tokens.push_back(batch(d, cs[d].src));
  }
  tokens.push_back(kEndOfFrame);
  const FrameState frame = frame_of(64, 16, ColorFormat::rgba8, states);
  Bench b("blend", cfg, frame, tokens);
  auto address = [&](int x, int y) { return frame.color_address + (y * 64 + x) * 4; };
  for (size_t d = 0; d < cs.size(); ++d) {
    for (int p = 0; p < 16; ++p) b.memory.debug_write(address(4 * d + p % 4, p / 4), &cs[d].dst, 4);
  }
  sc_core::sc_start();

  EXPECT_EQ(b.done_at, b.rop.stats().to_json().at("busy_cycles").get<uint64_t>());
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 64; ++x) {
      const size_t d = x / 4;
      const int bit = (y % 4) * 4 + x % 4;
      std::array<uint8_t, 4> want = {0xA5, 0xA5, 0xA5, 0xA5}, got;
      if (d < cs.size() && y < 4) want = kMask >> bit & 1 ? cs[d].want : cs[d].dst;
      b.memory.debug_read(address(x, y), got.data(), 4);
      EXPECT_EQ(got, want) << "pixel " << x << ", " << y;
    }
  }
  // Tiles 0, 1, 2 (x < 48) each read once: 16 rows of 64 bytes, 32 bus
  // cycles + latency 20 of stall. The end of frame writes them back from its
  // latency (3) on: done 3 + 96 + 20 cycles later, its ii (2) included.
  const StatGroup& s = b.rop.stats();
  expect_counters(s, {{"stamps", 11},
                      {"fragments_in", 11 * 14},
                      {"fragments_written", 10 * 14},  // all but case 7's
                      {"samples_written", 10 * 14},
                      {"fragments_blended", 8 * 14},
                      {"color_clears", 0},
                      {"frames", 1},
                      {"tokens_in", 12},
                      {"tokens_out", 12},  // every token retired
                      {"cache_misses", 3},
                      {"cache_hits", 7},
                      {"bytes_read", 3 * 1024},
                      {"bytes_written", 3 * 1024},
                      {"memory_stall_cycles", 3 * (32 + 20) + (3 + 96 + 20 - 2)}});
  EXPECT_EQ(counter(s, "busy_cycles") - counter(s, "memory_stall_cycles"), 2u * (11 + 1));
}

// rgba16f stores half(out), unclamped, rounded to nearest even: d = (0.5,
// 0.5, 0.25, 1) plus s = (1, 0.25, -0.5, 2) is (1.5, 0.75, -0.25, 3); and
// unblended, 1 + 3 * 2^-11 lies halfway between the halves 1 + 2^-10 (odd)
// and 1 + 2^-9 (even), 1/3 nearest to 0x3555, 1e5 beyond the largest half.
TEST(RopStage, Rgba16fStoresHalvesUnclampedTiesToEven) {
  const GpuConfig cfg = rop_config(1);
  const FrameState frame =
      frame_of(16, 16, ColorFormat::rgba16f, {blending(F::one, F::one, E::add), RenderState{}});
  Bench b("half", cfg, frame,
          {batch(0, {1.0f, 0.25f, -0.5f, 2.0f}),
           batch(1, {1.00146484375f, 1.0f / 3.0f, 1e5f, -2.0f}), kEndOfFrame});
  const std::array<uint16_t, 4> dst = {0x3800, 0x3800, 0x3400, 0x3C00};
  for (int p = 0; p < 16; ++p)
    b.memory.debug_write(frame.color_address + (p / 4 * 16 + p % 4) * 8, &dst, 8);
  sc_core::sc_start();

  const std::array<std::array<uint16_t, 4>, 2> want = {
      {{0x3E00, 0x3A00, 0xB400, 0x4200}, {0x3C02, 0x3555, 0x7C00, 0xC000}}};
  std::array<uint16_t, 4> got;
  for (int d = 0; d < 2; ++d) {
    b.memory.debug_read(frame.color_address + (16 + 4 * d + 1) * 8, got.data(), 8);  // pixel 5
    EXPECT_EQ(got, want[d]) << "draw " << d;
  }
  b.memory.debug_read(frame.color_address, got.data(), 8);  // pixel 0: not covered
  EXPECT_EQ(got, dst);
}

// Unit 0 of 2 in 64 x 32 (4 x 2 tiles) owns (0, 0), (2, 0), (1, 1), (3, 1).
// The frame clear (colour 51, 102, 153, 255) marks them cleared; the draw
// list's depth clear passes by; the end of frame writes them, 64 rows of 64
// bytes. ii 2, latency 3: the clears are read at 0 and 2, the end of frame at
// 4 starts the write-back at 4 + 3 = 7, the bus streams the rows until 135,
// the last completes at 155: the frame is done then.
TEST(RopStage, FastClearFillsOnlyItsOwnTiles) {
  const GpuConfig cfg = rop_config(2);
  FrameState frame = frame_of(64, 32, ColorFormat::rgba8, {});
  ClearState depth;
  depth.depth = true;
  frame.clears.push_back(depth);
  const ShadedStampBatch clear{PacketKind::clear, nullptr, {}, {}, {}};
  Bench b("clear", cfg, frame, {clear, clear, kEndOfFrame});
  sc_core::sc_start();

  EXPECT_TRUE(b.rop.frame_done());
  EXPECT_EQ(b.done_at, 155u);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      std::array<uint8_t, 4> got;
      b.memory.debug_read(frame.color_address + (y * 64 + x) * 4, got.data(), 4);
      const bool own = (x / 16 + y / 16) % 2 == 0;
      EXPECT_EQ(got, (own ? std::array<uint8_t, 4>{51, 102, 153, 255}
                          : std::array<uint8_t, 4>{0xA5, 0xA5, 0xA5, 0xA5}))
          << x << ", " << y;
    }
  }
  expect_counters(b.rop.stats(), {{"color_clears", 1},
                                  {"busy_cycles", 155},
                                  {"memory_stall_cycles", 155 - 3 * 2},
                                  {"bytes_read", 0},
                                  {"bytes_written", 4 * 1024},
                                  {"tokens_out", 3}});
}

}  // namespace
}  // namespace gpusim
