// The clipper's provoking vertex under both conventions (docs/pipeline-spec.md
// section 3) and its screen interpolation at cuts and division (sections 4
// and 5). Expected provoking vertices are written by hand from the OpenGL
// specification's table (4.6 core, table 13.2); the cut varyings are an
// analytic function of the cut's window position. One sc_start per TEST:
// ctest runs each in its own process.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/vertex_packets.h"
#include "stages/clipper.h"

namespace gpusim {
namespace {

// Runs a clipper over one batch per draw (slot i of a draw holds vertex
// positions[d][i], every slot fetched) and returns what it wrote before the
// end of the frame.
std::vector<ClippedPrimitive> run_clipper(FrameState& frame,
                                          const std::vector<std::vector<glm::vec4>>& positions,
                                          const std::vector<std::vector<float>>& tags) {
  std::vector<ShadedBatch> batches;
  for (uint32_t d = 0; d < frame.draws.size(); ++d) {
    frame.draws[d].buffers.slot_count = static_cast<uint32_t>(positions[d].size());
    ShadedBatch b;
    b.kind = PacketKind::work;
    b.draw_id = d;
    b.first_slot = 0;
    b.slot_count = b.vertex_count = static_cast<uint32_t>(positions[d].size());
    for (uint32_t i = 0; i < b.slot_count; ++i) {
      b.slots[i] = {SlotKind::fetched, kNoCacheEntry, i};
      b.vertices[i].clip = positions[d][i];
      b.vertices[i].varyings[0] = tags[d][i];
      b.vertices[i].varyings[3] = 1.0f;
    }
    batches.push_back(b);
  }
  ShadedBatch eof;
  eof.kind = PacketKind::end_of_frame;
  batches.push_back(eof);

  const GpuConfig config;
  Fifo<ShadedBatch> in("in", 4);
  Fifo<ClippedPrimitive> out("out", 4);
  Clipper clipper("clipper", config, frame);
  clipper.in(in);
  clipper.out(out);
  std::vector<ClippedPrimitive> got;
  sc_core::sc_spawn([&] {
    for (const ShadedBatch& b : batches) in.write(b);
  });
  sc_core::sc_spawn([&] {
    for (;;) {
      const ClippedPrimitive p = out.read();
      if (p.kind == PacketKind::end_of_frame) break;
      got.push_back(p);
    }
  });
  sc_core::sc_start();
  return got;
}

// Six vertices on a circle (no three in a line), vertex i tagged i.
TEST(Clipper, ProvokingVertexOfEveryPrimitiveTypeUnderBothConventions) {
  std::vector<glm::vec4> ring;
  std::vector<float> tag;
  for (int i = 0; i < 6; ++i) {
    const float a = 0.4f + 1.0f * static_cast<float>(i);
    ring.push_back({0.5f * std::cos(a), 0.5f * std::sin(a), 0.0f, 1.0f});
    tag.push_back(static_cast<float>(i));
  }
  const PrimitiveType types[] = {PrimitiveType::triangles,    PrimitiveType::triangle_strip,
                                 PrimitiveType::triangle_fan, PrimitiveType::lines,
                                 PrimitiveType::line_strip,   PrimitiveType::line_loop};
  // GL's table, 0-based, primitive by primitive, for 6 vertices.
  const std::vector<std::vector<int>> first = {{0, 3},    {0, 1, 2, 3},    {1, 2, 3, 4},
                                               {0, 2, 4}, {0, 1, 2, 3, 4}, {0, 1, 2, 3, 4, 5}};
  const std::vector<std::vector<int>> last = {{2, 5},    {2, 3, 4, 5},    {2, 3, 4, 5},
                                              {1, 3, 5}, {1, 2, 3, 4, 5}, {1, 2, 3, 4, 5, 0}};

  FrameState frame;
  frame.framebuffer.width = 64;
  frame.framebuffer.height = 64;
  std::vector<std::vector<glm::vec4>> positions;
  std::vector<std::vector<float>> tags;
  for (ProvokingVertex pv : {ProvokingVertex::first, ProvokingVertex::last}) {
    for (PrimitiveType t : types) {
      DrawState d;
      d.primitive = t;
      d.state.shading = Shading::flat;
      d.state.provoking_vertex = pv;
      frame.draws.push_back(d);
      positions.push_back(ring);
      tags.push_back(tag);
    }
  }
  // A triangle whose first vertex lies beyond the near plane: every piece of
  // it keeps vertex 0's varyings.
  DrawState clipped;
  clipped.state.shading = Shading::flat;
  clipped.state.provoking_vertex = ProvokingVertex::first;
  frame.draws.push_back(clipped);
  positions.push_back(
      {{0.0f, -0.5f, -3.0f, 1.0f}, {0.5f, 0.5f, 0.0f, 1.0f}, {-0.5f, 0.5f, 0.0f, 1.0f}});
  tags.push_back({7.0f, 8.0f, 9.0f});

  const std::vector<ClippedPrimitive> got = run_clipper(frame, positions, tags);
  size_t next = 0;
  for (uint32_t d = 0; d < 12; ++d) {
    const auto& want = d < 6 ? first[d] : last[d - 6];
    SCOPED_TRACE(testing::Message() << "draw " << d << " " << to_string(frame.draws[d].primitive)
                                    << " " << to_string(frame.draws[d].state.provoking_vertex));
    for (size_t k = 0; k < want.size(); ++k) {
      ASSERT_LT(next, got.size());
      const ClippedPrimitive& p = got[next++];
      EXPECT_EQ(p.draw_id, d);
      EXPECT_EQ(p.primitive_id, static_cast<int64_t>(k));
      EXPECT_EQ(p.flat_varyings[0], static_cast<float>(want[k])) << "primitive " << k;
    }
  }
  ASSERT_GE(got.size(), next + 2);  // the clipped triangle: at least 2 pieces
  for (; next < got.size(); ++next) {
    EXPECT_EQ(got[next].draw_id, 12u);
    EXPECT_EQ(got[next].flat_varyings[0], 7.0f);
  }
}

// The triangle a = (0, 0, 0, 1), b = (2, 0, -4, 2), c = (0, 1, 0, 1) is cut by
// the near plane on a -> b and b -> c. Varying 0 is 0 at a and c and 1 at b:
// linear in clip space it is x_clip / 2, so varying / w = x_ndc / 2 at every
// vertex (perspective); linear in window space it is x_ndc itself (screen),
// and then every vertex carries the weight 1 and the varying undivided. The
// cuts project to x_ndc = 0.5, where the two differ (1/3 against 0.5).
TEST(Clipper, ScreenInterpolationCutsAndWeightsLinearInWindowSpace) {
  FrameState frame;
  frame.framebuffer.width = 64;
  frame.framebuffer.height = 64;
  std::vector<std::vector<glm::vec4>> positions;
  std::vector<std::vector<float>> tags;
  for (Interpolation in : {Interpolation::perspective, Interpolation::screen}) {
    DrawState d;
    d.state.interpolation = in;
    frame.draws.push_back(d);
    positions.push_back({{0, 0, 0, 1}, {2, 0, -4, 2}, {0, 1, 0, 1}});
    tags.push_back({0.0f, 1.0f, 0.0f});
  }
  const std::vector<ClippedPrimitive> got = run_clipper(frame, positions, tags);
  ASSERT_EQ(got.size(), 4u);  // a quad each: 2 triangles
  int cut_vertices = 0;
  for (const ClippedPrimitive& p : got) {
    const bool screen = frame.draws[p.draw_id].state.interpolation == Interpolation::screen;
    SCOPED_TRACE(screen ? "screen" : "perspective");
    for (int i = 0; i < 3; ++i) {
      const ClippedVertex& v = p.v[i];
      const double xn = v.x / 32.0 - 1.0;
      if (std::fabs(xn - 0.5) < 1e-6) ++cut_vertices;
      if (screen) {
        EXPECT_EQ(v.inv_w, 1.0f);
        EXPECT_NEAR(v.varyings_over_w[0], xn, 1e-6) << "vertex " << i;
        EXPECT_EQ(v.varyings_over_w[3], 1.0f);
      } else {
        EXPECT_NEAR(v.varyings_over_w[0], xn / 2.0, 1e-6) << "vertex " << i;
      }
    }
  }
  EXPECT_GE(cut_vertices, 4);  // both cuts, in both draws
}

}  // namespace
}  // namespace gpusim
