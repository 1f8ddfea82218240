// Primitive setup (stages/primitive_setup.h): the hand-worked setup of one
// clockwise triangle (vertex order, edge equations and their fill-rule
// biases, bounding box, polygon offset; its one stamp through a rasterizer),
// triangles whose box holds no pixel centre counted but not sent, both in
// the raster-core bench (testbench/tests/raster_bench.h, whose tap records
// setup's packets); and, alone, the model error of a vertex count that does
// not match the primitive kind. A SystemC model elaborates once per process:
// ctest runs each TEST alone.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <memory>
#include <tuple>
#include <vector>

#include "hw/fifo.h"
#include "hw/fixed_point.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "stages/primitive_setup.h"
#include "testbench/tests/raster_bench.h"

namespace gpusim {
namespace {

using namespace test;

// ---------------------------------------------------------------------------
// Hand-worked setup of one triangle.

// (0, 0), (0, 4), (4, 0) pixels is clockwise; setup swaps v1 and v2 to get
// v0 = (0, 0), v1 = (1024, 0), v2 = (0, 1024) subpixels, area2 = 1024^2.
//   E0 (v1 -> v2): dx = -1024, dy = 1024: a = -1024, b = -1024,
//                  c = 1024 * 1024 - (-1024) * 0 = 1048576; dy > 0: bias 1
//   E1 (v2 -> v0): dx = 0, dy = -1024: a = 1024, b = 0, c = 0; left edge: bias 0
//   E2 (v0 -> v1): dx = 1024, dy = 0: a = 0, b = 1024, c = 0; bottom edge: bias 0
// Box: x0 = ceil(-128 / 256) = 0, x1 = floor(896 / 256) = 3, likewise y.
// Offset (factor 1, units 2, unorm16): z0 = 0.5, z1 = 0.75, z2 = 0.5 (after the
// swap): dzdx = (0.25 * 4 - 0 * 0) / 16 = 0.0625, dzdy = (0 * 4 - 0.25 * 0) / 16 = 0,
// m = 0.0625; offset = 1 * 0.0625 + 2 * float(1 / 65535).
// Covered: the 6 pixels with x + y <= 2 (x + y = 3 lies on E0, not owned).
TEST(PrimitiveSetup, HandWorkedClockwiseTriangle) {
  GpuConfig cfg = GpuConfig::baseline();
  cfg.units = 1;
  FrameState frame;
  frame.framebuffer.width = 64;
  frame.framebuffer.height = 64;
  frame.framebuffer.depth_format = DepthFormat::unorm16;
  DrawState d;
  d.state.offset_factor = 1.0f;
  d.state.offset_units = 2.0f;
  frame.draws.push_back(d);
  ClippedPrimitive t = window_triangle(0, 0, {0.0f, 0.0f, 0.0f, 4.0f, 4.0f, 0.0f});
  t.v[0].z = 0.5f;
  t.v[1].z = 0.5f;
  t.v[2].z = 0.75f;
  auto bench = std::make_unique<RasterBench>("hand", cfg, frame, true);
  bench->feed({t});
  sc_core::sc_start();

  ASSERT_EQ(bench->setup_packets.size(), 1u);
  const RasterPrimitive& r = *bench->setup_packets[0].primitive;
  EXPECT_EQ(r.x, (std::array<Subpixel, 3>{0, 1024, 0}));
  EXPECT_EQ(r.y, (std::array<Subpixel, 3>{0, 0, 1024}));
  EXPECT_EQ(r.z, (std::array<float, 3>{0.5f, 0.75f, 0.5f}));
  EXPECT_EQ(r.inv_w, (std::array<float, 3>{1.0f, 3.0f, 2.0f}));
  EXPECT_EQ(r.area2, 1048576);
  EXPECT_EQ(r.edge[0], (EdgeEquation{-1024, -1024, 1048576, 1}));
  EXPECT_EQ(r.edge[1], (EdgeEquation{1024, 0, 0, 0}));
  EXPECT_EQ(r.edge[2], (EdgeEquation{0, 1024, 0, 0}));
  EXPECT_EQ(std::tie(r.x0, r.x1, r.y0, r.y1), std::make_tuple(0, 3, 0, 3));
  EXPECT_TRUE(r.has_depth_offset);
  EXPECT_EQ(r.depth_offset, 0.0625f + 2.0f * static_cast<float>(1.0 / 65535.0));
  EXPECT_EQ(counter(bench->setup.stats(), "triangles_swapped"), 1u);

  // One 16x16 tile, partial; 4x4 stamp (0, 0) only: bits of x + y <= 2.
  ASSERT_EQ(bench->out[0].size(), 1u);
  ASSERT_EQ(bench->out[0][0].stamps.size(), 1u);
  const Stamp& s = bench->out[0][0].stamps[0];
  EXPECT_EQ(s.mask, 0b0000'0001'0011'0111u);
  // E at (128, 128): E0 = -1024*128 - 1024*128 + 1048576 = 786432; E1 = E2 = 131072.
  EXPECT_EQ(s.e, (std::array<EdgeValue, 3>{786432, 131072, 131072}));
  EXPECT_EQ(counter(bench->units[0]->stats(), "fragments"), 6u);
}

// Triangles counted rasterized whose box holds no pixel centre are not sent:
// a sliver between centres, one left of the screen, one above it.
TEST(PrimitiveSetup, EmptyBoxCountsRasterizedButSendsNothing) {
  GpuConfig cfg = GpuConfig::baseline();
  cfg.units = 2;
  FrameState frame;
  frame.framebuffer.width = 32;
  frame.framebuffer.height = 32;
  frame.draws.push_back(DrawState{});
  const std::vector<ClippedPrimitive> tokens{
      window_triangle(0, 0, {10.6f, 10.6f, 10.9f, 10.6f, 10.6f, 10.9f}),
      window_triangle(1, 0, {-9.0f, 1.0f, -1.0f, 1.0f, -1.0f, 20.0f}),
      window_triangle(2, 0, {1.0f, 33.0f, 20.0f, 33.0f, 5.0f, 40.0f}),
      control_primitive(PacketKind::end_of_frame)};
  auto bench = std::make_unique<RasterBench>("empty", cfg, frame, true);
  bench->feed(tokens);
  sc_core::sc_start();
  const StatGroup& s = bench->setup.stats();
  EXPECT_EQ(counter(s, "triangles_rasterized"), 3u);
  EXPECT_EQ(counter(s, "triangles_offscreen"), 3u);
  EXPECT_EQ(counter(s, "tokens_out"), 1u);
  ASSERT_EQ(bench->setup_packets.size(), 1u);
  for (unsigned u = 0; u < 2; ++u) {
    ASSERT_EQ(bench->out[u].size(), 1u);
    EXPECT_EQ(bench->out[u][0].kind, PacketKind::end_of_frame);
  }
}

// ---------------------------------------------------------------------------
// Primitive setup sets up every kind, but a vertex count that does not match
// the kind is a model error.

TEST(PrimitiveSetup, RejectsAVertexCountThatDoesNotMatchTheKind) {
  FrameState frame;
  frame.draws.resize(1);
  const GpuConfig config;
  Fifo<ClippedPrimitive> in("in", 4);
  Fifo<SetupPacket> out("out", 4);
  PrimitiveSetup setup("setup", config, frame);
  setup.in(in);
  setup.out(out);
  ClippedPrimitive line;
  line.primitive_kind = PrimitiveKind::line;
  line.vertex_count = vertex_count_of(PrimitiveKind::triangle);
  line.v[0].x = 1.0f;
  line.v[1].x = 10.0f;
  line.v[1].y = 5.0f;
  sc_core::sc_spawn([&] { in.write(line); });
  EXPECT_THROW(sc_core::sc_start(), sc_core::sc_report);
}

}  // namespace
}  // namespace gpusim
