// The clipper (stages/clipper.h): primitive assembly, clipping, the
// perspective divide and viewport, and polygon mode (docs/pipeline-spec.md,
// sections 3 to 5).
//
// Alone, fed shaded batches written here: its provoking vertex under both
// conventions (section 3), expected by hand from the OpenGL specification's
// table (4.6 core, table 13.2), and its screen interpolation at cuts and
// division (sections 4 and 5), where the cut varyings are an analytic
// function of the cut's window position; and every varying of a layout
// (testbench/tests/varying_layouts.h: a made-up varying next to the colour,
// one that fills the capacity) carried and interpolated at clip-plane cuts,
// each an affine function of the clip position, the colour bit for bit
// against the golden model.
//
// In the front-end bench (testbench/tests/front_end_bench.h; the fetch and
// the shader pass clip-space positions and colours through): lines, line
// strips and loops, points and polygon mode (sections 3, 4b, 4c, 4d) against
// expectations derived here from the spec's text, by hand and for random
// primitives. One sc_start per TEST: ctest runs each in its own process.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/vertex_packets.h"
#include "stages/clipper.h"
#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"
#include "testbench/tests/front_end_bench.h"
#include "testbench/tests/stage_host.h"
#include "testbench/tests/varying_layouts.h"

namespace gpusim {
namespace {

using namespace test;

// ---------------------------------------------------------------------------
// The clipper alone.

// A batch of draw d's slots [0, count), every one fetched into the vertex
// of its number.
ShadedBatch fetched_batch(uint32_t d, uint32_t count) {
  ShadedBatch b;
  b.kind = PacketKind::work;
  b.draw_id = d;
  b.first_slot = 0;
  b.slot_count = b.vertex_count = count;
  for (uint32_t i = 0; i < count; ++i) b.slots[i] = {SlotKind::fetched, kNoCacheEntry, i};
  return b;
}

// Runs a clipper over `batches` and the end of the frame; returns all it
// wrote, and its statistics through `stats` when given.
std::vector<ClippedPrimitive> clip(const FrameState& frame, std::vector<ShadedBatch> batches,
                                   nlohmann::json* stats = nullptr) {
  ShadedBatch eof;
  eof.kind = PacketKind::end_of_frame;
  batches.push_back(eof);
  const GpuConfig config;
  Fifo<ShadedBatch> in("in", 4);
  Fifo<ClippedPrimitive> out("out", 4);
  Clipper clipper("clipper", config, frame);
  clipper.in(in);
  clipper.out(out);
  feed(in, std::move(batches));
  Sink<ClippedPrimitive> sink(out, config.cycle());
  sc_core::sc_start();
  if (stats != nullptr) *stats = clipper.stats().to_json();
  return sink.items;
}

// Runs a clipper over one batch per draw (slot i of a draw holds vertex
// positions[d][i], every slot fetched) and returns what it wrote before the
// end of the frame.
std::vector<ClippedPrimitive> run_clipper(FrameState& frame,
                                          const std::vector<std::vector<glm::vec4>>& positions,
                                          const std::vector<std::vector<float>>& tags) {
  std::vector<ShadedBatch> batches;
  for (uint32_t d = 0; d < frame.draws.size(); ++d) {
    frame.draws[d].buffers.slot_count = static_cast<uint32_t>(positions[d].size());
    ShadedBatch b = fetched_batch(d, static_cast<uint32_t>(positions[d].size()));
    for (uint32_t i = 0; i < b.slot_count; ++i) {
      b.vertices[i].clip = positions[d][i];
      b.vertices[i].varyings[0] = tags[d][i];
      b.vertices[i].varyings[3] = 1.0f;
    }
    batches.push_back(b);
  }
  std::vector<ClippedPrimitive> got = clip(frame, batches);
  got.erase(std::find_if(got.begin(), got.end(),
                         [](const ClippedPrimitive& p) { return p.kind != PacketKind::work; }),
            got.end());
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

// ---------------------------------------------------------------------------
// Every varying of the layout: triangles inside, across the near plane, across the right guard
// band and the far plane, and across near and far in perspective; draw 0
// with colour + made-up varying, draw 1 at full capacity.

TEST(Clipper, CarriesAndInterpolatesEveryVaryingOfTheLayout) {
  FrameState frame;
  frame.framebuffer.width = 64;
  frame.framebuffer.height = 64;
  frame.draws.resize(2);
  frame.draws[0].varyings = color_then_extra();
  frame.draws[1].varyings = full_capacity();
  const std::vector<std::array<glm::vec4, 3>> triangles = {
      {{{-0.5f, -0.5f, 0.0f, 1.0f}, {1.0f, -0.5f, 0.5f, 2.0f}, {0.0f, 0.25f, -0.25f, 0.5f}}},
      {{{-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, -3.0f, 1.0f}}},
      {{{-0.5f, -0.5f, 0.0f, 1.0f}, {3000.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.8f, 2.0f, 1.0f}}},
      {{{-0.4f, -0.6f, 0.2f, 0.5f}, {0.6f, -0.5f, -1.5f, 0.7f}, {-0.3f, 0.9f, 3.0f, 1.5f}}},
  };

  std::vector<ShadedBatch> batches;
  for (uint32_t d = 0; d < frame.draws.size(); ++d) {
    ShadedBatch b = fetched_batch(d, static_cast<uint32_t>(3 * triangles.size()));
    for (uint32_t i = 0; i < b.slot_count; ++i) {
      ShadedVertex& v = b.vertices[i];
      v.clip = triangles[i / 3][i % 3];
      for (unsigned k = 0; k < frame.draws[d].varyings.count; ++k)
        v.varyings[k] = static_cast<float>(affine(k, glm::dvec4(v.clip)));
    }
    batches.push_back(b);
  }
  nlohmann::json stats;
  const std::vector<ClippedPrimitive> got = clip(frame, batches, &stats);

  const golden::GuardBand gb = golden::guard_band_for(64, 64);
  const float half = 32.0f;
  size_t next = 0;
  uint64_t cut_vertices = 0;
  for (uint32_t d = 0; d < frame.draws.size(); ++d) {
    const VaryingLayout& layout = frame.draws[d].varyings;
    for (size_t t = 0; t < triangles.size(); ++t) {
      SCOPED_TRACE(testing::Message() << "draw " << d << " triangle " << t);
      const ShadedVertex* src = &batches[d].vertices[3 * t];
      // The golden model clips position and colour; the fan's vertex count
      // and the colour components must match it bit for bit.
      std::array<golden::ShadedVertex, 3> tri;
      for (int i = 0; i < 3; ++i) {
        tri[i].clip = src[i].clip;
        for (unsigned c = 0; c < kColorComponents; ++c)
          tri[i].color[c] = src[i].varyings[layout.color + c];
      }
      const std::vector<golden::ShadedVertex> poly = golden::clip_triangle(tri, gb);
      ASSERT_GE(poly.size(), 3u);
      double vmax = 0.0;  // the varyings' magnitude, for the tolerance
      for (int i = 0; i < 3; ++i) {
        for (unsigned k = 0; k < layout.count; ++k)
          vmax = std::max(vmax, std::fabs(double{src[i].varyings[k]}));
      }
      for (size_t f = 1; f + 1 < poly.size(); ++f) {
        ASSERT_LT(next, got.size());
        const ClippedPrimitive& p = got[next++];
        ASSERT_EQ(p.kind, PacketKind::work);
        EXPECT_EQ(p.primitive_kind, PrimitiveKind::triangle);
        EXPECT_EQ(p.vertex_count, 3);
        EXPECT_EQ(p.draw_id, d);
        // Flat shading: the original provoking vertex's varyings, all of them.
        EXPECT_EQ(p.flat_varyings, src[2].varyings);
        const size_t corner[3] = {0, f, f + 1};
        for (int i = 0; i < 3; ++i) {
          const ClippedVertex& v = p.v[i];
          const golden::WindowVertex want = golden::to_window(poly[corner[i]], 64, 64);
          EXPECT_EQ(bits(v.inv_w), bits(want.inv_w));
          EXPECT_EQ(bits(v.z), bits(want.z));
          for (unsigned c = 0; c < kColorComponents; ++c) {
            EXPECT_EQ(bits(v.varyings_over_w[layout.color + c]), bits(want.color_over_w[c]))
                << "vertex " << i << " colour " << c;
          }
          // The vertex's clip position, read back from its window
          // coordinates; each varying is its affine function of it, times 1/w.
          const double w = 1.0 / double{v.inv_w};
          const glm::dvec4 pos((v.x / half - 1.0) * w, (v.y / half - 1.0) * w,
                               (2.0 * v.z - 1.0) * w, w);
          const bool original = std::any_of(
              src, src + 3, [&](const ShadedVertex& s) { return s.clip == poly[corner[i]].clip; });
          cut_vertices += !original;
          for (unsigned k = 0; k < kMaxVaryings; ++k) {
            const float g = v.varyings_over_w[k];
            if (k >= layout.count) {
              EXPECT_EQ(g, 0.0f) << "vertex " << i << " unused component " << k;
              continue;
            }
            const double expected = affine(k, pos) * v.inv_w;
            const double tolerance = 4e-6 * (1.0 + vmax) * std::max(1.0, double{v.inv_w});
            EXPECT_NEAR(g, expected, tolerance) << "vertex " << i << " component " << k;
            if (original) {
              // Untouched by a cut: exactly varying * (1/w).
              const ShadedVertex& s = *std::find_if(src, src + 3, [&](const ShadedVertex& s) {
                return s.clip == poly[corner[i]].clip;
              });
              EXPECT_EQ(bits(g), bits(s.varyings[k] * v.inv_w));
            }
          }
        }
      }
    }
  }
  ASSERT_EQ(got.size(), next + 1);
  EXPECT_EQ(got.back().kind, PacketKind::end_of_frame);
  EXPECT_GE(cut_vertices, 12u);
  EXPECT_EQ(stats.at("triangles_clipped").get<uint64_t>(), 6u);
}

// ---------------------------------------------------------------------------
// In the front-end bench: points, lines and polygon mode, against
// expectations derived here from the spec (sections 3, 4b, 4c, 4d): draws in
// clip space (identity matrices, so the vertex shader passes positions and
// colours through) on a 128 x 128 framebuffer, where x_w = (x / w + 1) * 64, so vertices at
// multiples of 1/64 map to exact window coordinates.

constexpr int kSide = 128;

// Vertex i's colour: distinct and exact, to tell provoking vertices apart.
glm::vec4 color_of(size_t i) {
  return {static_cast<float>(i) / 64.0f, 0.5f, 0.25f, 1.0f};
}

Draw clip_space_draw(PrimitiveType primitive, const std::vector<glm::vec4>& positions) {
  Draw d;
  d.primitive = primitive;
  d.positions = positions;
  for (size_t i = 0; i < positions.size(); ++i) d.colors.push_back(color_of(i));
  return d;
}

Scene clip_space_scene(std::vector<Draw> draws) {
  Scene s;
  s.framebuffer.width = kSide;
  s.framebuffer.height = kSide;
  s.draws = std::move(draws);
  return s;
}

// Runs the front end on `scene`; returns the work primitives it wrote and
// the clipper's counters.
struct FrontEndRun {
  std::vector<ClippedPrimitive> prims;
  nlohmann::json clipper;
};
FrontEndRun run_front_end(const Scene& scene, const GpuConfig& config = GpuConfig{}) {
  const LoadedFrame frame = load_frame(scene);
  FrontEndBench bench("bench", config, frame);
  sc_core::sc_start();
  FrontEndRun r;
  for (const ClippedPrimitive& p : bench.got) {
    if (p.kind == PacketKind::work) r.prims.push_back(p);
  }
  r.clipper = bench.clipper.stats().to_json();
  return r;
}

TEST(FrontEndLines, StripOfNVerticesGivesNMinusOneLines) {
  // 37 slots: the strip crosses a batch boundary (32 slots). A triangle
  // list of 2 triangles before it: its lines are numbered from 2.
  std::vector<glm::vec4> tri(6, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  std::vector<glm::vec4> strip;
  for (size_t i = 0; i < 37; ++i) strip.push_back(strip_vertex(i));
  const FrontEndRun r =
      run_front_end(clip_space_scene({clip_space_draw(PrimitiveType::triangles, tri),
                                      clip_space_draw(PrimitiveType::line_strip, strip)}));
  // The two triangles are degenerate but the clipper passes them on.
  ASSERT_EQ(r.prims.size(), 2u + 36u);
  for (size_t i = 0; i < 36; ++i) {
    const ClippedPrimitive& l = r.prims[2 + i];
    SCOPED_TRACE("line " + std::to_string(i));
    EXPECT_EQ(l.primitive_kind, PrimitiveKind::line);
    EXPECT_EQ(l.vertex_count, 2);
    EXPECT_EQ(l.draw_id, 1u);
    EXPECT_EQ(l.primitive_id, static_cast<int64_t>(2 + i));
    EXPECT_EQ(l.draw_first, i == 0);  // later lines share their first vertex
    EXPECT_TRUE(l.draw_last);
    EXPECT_EQ(l.v[0].x, 8.0f + i);
    EXPECT_EQ(l.v[1].x, 9.0f + i);
    EXPECT_EQ(l.v[0].y, i % 2 ? 80.0f : 48.0f);
    EXPECT_EQ(l.v[1].inv_w, 1.0f);
    EXPECT_TRUE(holds_color(l.v[1].varyings_over_w, color_of(i + 1)));
    EXPECT_TRUE(holds_color(l.flat_varyings, color_of(i + 1)));  // the last vertex
  }
  EXPECT_EQ(r.clipper.at("lines_in"), 36u);
  EXPECT_EQ(r.clipper.at("lines_out"), 36u);
  EXPECT_EQ(r.clipper.at("lines_clipped"), 0u);
  EXPECT_EQ(r.clipper.at("triangles_in"), 2u);
}

TEST(FrontEndLines, ListsAndLoops) {
  // lines of 5 slots: 2 lines, the partial last one ignored, both ends drawn.
  // line_loop of 33 slots (across a batch boundary): 33 lines, the closing
  // one (32, 0) with both flags clear and vertex 0's colour. Loops of 1 and
  // 2 slots: none, and (0, 1), (1, 0).
  std::vector<glm::vec4> v;
  for (size_t i = 0; i < 33; ++i) v.push_back(strip_vertex(i));
  const std::vector<glm::vec4> five(v.begin(), v.begin() + 5);
  const std::vector<glm::vec4> one(v.begin(), v.begin() + 1);
  const std::vector<glm::vec4> two(v.begin(), v.begin() + 2);
  const FrontEndRun r = run_front_end(clip_space_scene(
      {clip_space_draw(PrimitiveType::lines, five), clip_space_draw(PrimitiveType::line_loop, v),
       clip_space_draw(PrimitiveType::line_loop, one),
       clip_space_draw(PrimitiveType::line_loop, two)}));
  ASSERT_EQ(r.prims.size(), 2u + 33u + 0u + 2u);
  for (size_t i = 0; i < 2; ++i) {
    const ClippedPrimitive& l = r.prims[i];
    EXPECT_EQ(l.primitive_id, static_cast<int64_t>(i));
    EXPECT_EQ(l.v[0].x, 8.0f + 2 * i);
    EXPECT_EQ(l.v[1].x, 9.0f + 2 * i);
    EXPECT_TRUE(l.draw_first && l.draw_last);
    EXPECT_TRUE(holds_color(l.flat_varyings, color_of(2 * i + 1)));
  }
  for (size_t i = 0; i < 33; ++i) {
    const ClippedPrimitive& l = r.prims[2 + i];
    SCOPED_TRACE("loop line " + std::to_string(i));
    EXPECT_EQ(l.draw_id, 1u);
    EXPECT_EQ(l.primitive_id, static_cast<int64_t>(2 + i));
    const size_t a = i, b = (i + 1) % 33;
    EXPECT_EQ(l.v[0].x, 8.0f + a);
    EXPECT_EQ(l.v[1].x, 8.0f + b);
    EXPECT_EQ(l.draw_first, i == 0);
    EXPECT_EQ(l.draw_last, i != 32);
    EXPECT_TRUE(holds_color(l.flat_varyings, color_of(b)));
  }
  const ClippedPrimitive& p = r.prims[35];
  const ClippedPrimitive& q = r.prims[36];
  EXPECT_EQ(p.draw_id, 3u);
  EXPECT_EQ(p.primitive_id, 2 + 33 + 0);
  EXPECT_EQ(q.primitive_id, 2 + 33 + 1);
  EXPECT_TRUE(p.draw_first && p.draw_last);
  EXPECT_TRUE(!q.draw_first && !q.draw_last);
  EXPECT_EQ(q.v[0].x, 9.0f);
  EXPECT_EQ(q.v[1].x, 8.0f);
  EXPECT_TRUE(holds_color(q.flat_varyings, color_of(0)));
  EXPECT_EQ(r.clipper.at("lines_in"), 37u);
}

TEST(FrontEndLines, IndexedLinesWithAnInvalidIndexAreDropped) {
  // Indices 0 1 | 1 9 | 2 3: the second line's vertex 9 does not exist. A
  // loop over 0 1 9 2: lines (0 1), (1 9) and (9 2) invalid, (2 0) closes.
  std::vector<glm::vec4> v;
  for (size_t i = 0; i < 4; ++i) v.push_back(strip_vertex(i));
  Draw lines = clip_space_draw(PrimitiveType::lines, v);
  lines.indices = {0, 1, 1, 9, 2, 3};
  Draw loop = clip_space_draw(PrimitiveType::line_loop, v);
  loop.indices = {0, 1, 9, 2};
  const FrontEndRun r = run_front_end(clip_space_scene({lines, loop}));
  ASSERT_EQ(r.prims.size(), 4u);
  EXPECT_EQ(r.prims[0].primitive_id, 0);
  EXPECT_EQ(r.prims[1].primitive_id, 2);
  EXPECT_EQ(r.prims[2].primitive_id, 3);  // the loop's first line
  EXPECT_EQ(r.prims[3].primitive_id, 6);  // its closing line (2, 0)
  EXPECT_EQ(r.prims[3].v[0].x, 10.0f);
  EXPECT_EQ(r.prims[3].v[1].x, 8.0f);
  EXPECT_EQ(r.clipper.at("lines_in"), 7u);
  EXPECT_EQ(r.clipper.at("lines_invalid"), 3u);
}

TEST(FrontEndLines, LineCrossingTheNearPlaneIsCutOnIt) {
  // Line 0: a = (0.5, 0.25, -2, 1) has z + w = -1, b = (-0.5, 0, 0, 1) has
  // z + w = 1: equal distances, so the cut starts from the inside endpoint
  // b, t = 1 / (1 - -1) = 0.5 exactly, and the new a is the midpoint
  // (0, 0.125, -1, 1), colour midway: window (64, 72, z 0).
  // Line 1: a = (0.5, 0, -3, 1) (z + w = -2), b = (0, 0, 0.5, 1) (1.5): the
  // cut starts from b, nearer: t = 1.5 / 3.5 = 3/7, the plane z = -w at
  // x = 3/14 (the analytic crossing, to float rounding).
  Draw d = clip_space_draw(PrimitiveType::lines, {{0.5f, 0.25f, -2.0f, 1.0f},
                                                  {-0.5f, 0.0f, 0.0f, 1.0f},
                                                  {0.5f, 0.0f, -3.0f, 1.0f},
                                                  {0.0f, 0.0f, 0.5f, 1.0f}});
  const FrontEndRun r = run_front_end(clip_space_scene({d}));
  ASSERT_EQ(r.prims.size(), 2u);
  const ClippedPrimitive& l = r.prims[0];
  EXPECT_EQ(l.v[0].x, 64.0f);
  EXPECT_EQ(l.v[0].y, 72.0f);
  EXPECT_EQ(l.v[0].z, 0.0f);
  EXPECT_EQ(l.v[0].inv_w, 1.0f);
  EXPECT_TRUE(holds_color(l.v[0].varyings_over_w, 0.5f * (color_of(0) + color_of(1))));
  EXPECT_EQ(l.v[1].x, 32.0f);  // b untouched
  EXPECT_EQ(l.v[1].z, 0.5f);
  EXPECT_TRUE(holds_color(l.flat_varyings, color_of(1)));
  EXPECT_TRUE(l.draw_first && l.draw_last);  // clipping keeps the flags
  const ClippedPrimitive& m = r.prims[1];
  EXPECT_NEAR(m.v[0].z, 0.0f, 1e-6f);  // on the near plane: z_w = 0
  EXPECT_NEAR(m.v[0].x, (3.0f / 14.0f + 1.0f) * 64.0f, 1e-4f);
  EXPECT_EQ(m.v[1].x, 64.0f);
  EXPECT_EQ(m.v[1].z, 0.75f);
  EXPECT_EQ(r.clipper.at("lines_clipped"), 2u);
  EXPECT_EQ(r.clipper.at("lines_clipped_away"), 0u);
}

TEST(FrontEndLines, LinesWithNothingInsideAreClippedAway) {
  // Both ends behind the eye (w < 0): the outcodes share plane 0. Then a
  // line from outside the left guard band to outside the bottom one, the
  // outcodes disjoint: for 128 pixels the band is x >= -513 w, y >= -513 w;
  // the line x + y = -1100 passes the corner (-513, -513) at y = -587 after
  // the left cut, so the bottom plane finds both ends outside.
  Draw d = clip_space_draw(PrimitiveType::lines, {{0.0f, 0.0f, 0.0f, -1.0f},
                                                  {0.5f, 0.2f, 0.1f, -2.0f},
                                                  {-1100.0f, 0.0f, 0.0f, 1.0f},
                                                  {0.0f, -1100.0f, 0.0f, 1.0f}});
  const FrontEndRun r = run_front_end(clip_space_scene({d}));
  EXPECT_EQ(r.prims.size(), 0u);
  EXPECT_EQ(r.clipper.at("lines_in"), 2u);
  EXPECT_EQ(r.clipper.at("lines_clipped_away"), 2u);
  EXPECT_EQ(r.clipper.at("lines_clipped"), 0u);
}

TEST(FrontEndPoints, OutsideTheFrustumDroppedOnTheEdgeKept) {
  // Kept: inside; x = w (the right edge); z = -w (the near plane); y = -w.
  // Dropped: x > w (inside the guard band, but a point is not clipped
  // there), w < 0, z > w.
  Draw d = clip_space_draw(PrimitiveType::points, {{0.25f, 0.5f, 0.0f, 1.0f},
                                                   {2.0f, 0.0f, 0.0f, 2.0f},
                                                   {0.0f, 0.0f, -1.0f, 1.0f},
                                                   {0.0f, -1.0f, 0.0f, 1.0f},
                                                   {1.0f + 1.0f / 64.0f, 0.0f, 0.0f, 1.0f},
                                                   {0.0f, 0.0f, 0.0f, -1.0f},
                                                   {0.0f, 0.0f, 1.5f, 1.0f}});
  const FrontEndRun r = run_front_end(clip_space_scene({d}));
  ASSERT_EQ(r.prims.size(), 4u);
  const int64_t ids[4] = {0, 1, 2, 3};
  const float xs[4] = {80.0f, 128.0f, 64.0f, 64.0f};
  const float ys[4] = {96.0f, 64.0f, 64.0f, 0.0f};
  for (size_t i = 0; i < 4; ++i) {
    const ClippedPrimitive& p = r.prims[i];
    EXPECT_EQ(p.primitive_kind, PrimitiveKind::point);
    EXPECT_EQ(p.vertex_count, 1);
    EXPECT_EQ(p.primitive_id, ids[i]);
    EXPECT_EQ(p.v[0].x, xs[i]);
    EXPECT_EQ(p.v[0].y, ys[i]);
    EXPECT_TRUE(holds_color(p.flat_varyings, color_of(i)));
  }
  EXPECT_EQ(r.prims[1].v[0].inv_w, 0.5f);
  EXPECT_EQ(r.prims[2].v[0].z, 0.0f);
  EXPECT_EQ(r.clipper.at("points_in"), 7u);
  EXPECT_EQ(r.clipper.at("points_clipped_away"), 3u);
  EXPECT_EQ(r.clipper.at("points_out"), 4u);
}

// One triangle per draw in polygon mode `mode`, cull mode `cull`.
Draw unfilled(PolygonMode mode, CullMode cull, const std::vector<glm::vec4>& v) {
  Draw d = clip_space_draw(PrimitiveType::triangles, v);
  d.state.polygon_mode = mode;
  d.state.cull = cull;
  return d;
}

// kCcw (front_end_bench.h) clockwise.
const std::vector<glm::vec4> kCw = {kCcw[0], kCcw[2], kCcw[1]};

TEST(FrontEndPolygonMode, LineModeDrawsTheEdgesOfSurvivingTriangles) {
  // CCW (window (32, 32), (96, 32), (64, 96)), cull back: 3 lines (v0 v1),
  // (v1 v2), (v2 v0), each with its first end only, the triangle's id and
  // its provoking colour (v2). The same triangle clockwise with cull back: culled.
  // A collinear one: degenerate. The clockwise one without culling: 3 lines.
  const FrontEndRun r = run_front_end(clip_space_scene(
      {unfilled(PolygonMode::line, CullMode::back, kCcw),
       unfilled(PolygonMode::line, CullMode::back, kCw),
       unfilled(PolygonMode::line, CullMode::none, {kCcw[0], kCcw[1], {1.5f, -0.5f, 0.0f, 1.0f}}),
       unfilled(PolygonMode::line, CullMode::none, kCw)}));
  ASSERT_EQ(r.prims.size(), 6u);
  const float x[3] = {32.0f, 96.0f, 64.0f}, y[3] = {32.0f, 32.0f, 96.0f};
  for (size_t i = 0; i < 3; ++i) {
    const ClippedPrimitive& l = r.prims[i];
    EXPECT_EQ(l.primitive_kind, PrimitiveKind::line);
    EXPECT_EQ(l.vertex_count, 2);
    EXPECT_EQ(l.primitive_id, 0);
    EXPECT_TRUE(l.draw_first);
    EXPECT_FALSE(l.draw_last);
    EXPECT_EQ(l.v[0].x, x[i]);
    EXPECT_EQ(l.v[0].y, y[i]);
    EXPECT_EQ(l.v[1].x, x[(i + 1) % 3]);
    EXPECT_EQ(l.v[1].y, y[(i + 1) % 3]);
    EXPECT_TRUE(holds_color(l.v[0].varyings_over_w, color_of(i)));
    EXPECT_TRUE(holds_color(l.flat_varyings, color_of(2)));
  }
  // The clockwise one: its own vertex order, (v0 v1) = (32, 32) -> (64, 96).
  EXPECT_EQ(r.prims[3].primitive_id, 3);
  EXPECT_EQ(r.prims[3].v[1].x, 64.0f);
  EXPECT_EQ(r.clipper.at("triangles_in"), 4u);
  EXPECT_EQ(r.clipper.at("triangles_unfilled"), 2u);
  EXPECT_EQ(r.clipper.at("triangles_culled"), 1u);
  EXPECT_EQ(r.clipper.at("triangles_degenerate"), 1u);
  EXPECT_EQ(r.clipper.at("triangles_after_clip"), 0u);
  EXPECT_EQ(r.clipper.at("unfilled_lines"), 6u);
  EXPECT_EQ(r.clipper.at("lines_in"), 0u);  // not assembled lines
}

TEST(FrontEndPolygonMode, TheClippedEdgeIsNotDrawn) {
  // v2 behind the near plane (z + w = -2): the polygon is v0, v1, the cut c1
  // on (v1 v2) where the edge leaves (its flag clear: the edge from it runs
  // along the plane), the cut c2 on (v2 v0) where it enters (v2's flag,
  // set). Line mode draws (v0 v1), (v1 c1), (c2 v0); point mode v0, v1, c2.
  // Each cut starts from the inside endpoint (distance 1 against 2), t =
  // 1/3: c1 = (1/3, -1/6), c2 = (-1/3, -1/6), window (85.33, 53.33) and
  // (42.67, 53.33), on the near plane (z_w = 0).
  const std::vector<glm::vec4> v = {kCcw[0], kCcw[1], {0.0f, 0.5f, -3.0f, 1.0f}};
  const FrontEndRun r =
      run_front_end(clip_space_scene({unfilled(PolygonMode::line, CullMode::back, v),
                                      unfilled(PolygonMode::point, CullMode::back, v)}));
  ASSERT_EQ(r.prims.size(), 6u);
  const float third = 64.0f / 3.0f;
  const ClippedPrimitive& a = r.prims[0];
  const ClippedPrimitive& b = r.prims[1];
  const ClippedPrimitive& c = r.prims[2];
  EXPECT_EQ(a.v[0].x, 32.0f);
  EXPECT_EQ(a.v[1].x, 96.0f);
  EXPECT_EQ(b.v[0].x, 96.0f);
  EXPECT_NEAR(b.v[1].x, 64.0f + third, 1e-4f);
  EXPECT_NEAR(b.v[1].y, 64.0f - third / 2, 1e-4f);
  EXPECT_NEAR(b.v[1].z, 0.0f, 1e-6f);
  EXPECT_NEAR(c.v[0].x, 64.0f - third, 1e-4f);
  EXPECT_NEAR(c.v[0].z, 0.0f, 1e-6f);
  EXPECT_EQ(c.v[1].x, 32.0f);
  for (const ClippedPrimitive* l : {&a, &b, &c}) {
    EXPECT_EQ(l->primitive_kind, PrimitiveKind::line);
    EXPECT_TRUE(holds_color(l->flat_varyings, color_of(2)));  // v2, though clipped off
  }
  for (size_t i = 3; i < 6; ++i) EXPECT_EQ(r.prims[i].primitive_kind, PrimitiveKind::point);
  EXPECT_EQ(r.prims[3].v[0].x, 32.0f);
  EXPECT_EQ(r.prims[4].v[0].x, 96.0f);
  EXPECT_NEAR(r.prims[5].v[0].x, 64.0f - third, 1e-4f);
  EXPECT_EQ(r.prims[5].primitive_id, 1);
  EXPECT_EQ(r.clipper.at("triangles_clipped"), 2u);
  EXPECT_EQ(r.clipper.at("triangles_unfilled"), 2u);
  EXPECT_EQ(r.clipper.at("unfilled_lines"), 3u);
  EXPECT_EQ(r.clipper.at("unfilled_points"), 3u);
  EXPECT_EQ(r.clipper.at("points_out"), 3u);
  EXPECT_EQ(r.clipper.at("points_in"), 0u);
}

TEST(FrontEndPolygonMode, ATriangleEnclosingTheGuardBandHasNoEdgeLeft) {
  // The guard band of 128 pixels is -513 w <= x, y <= 511 w: this triangle
  // contains it, so the clipped polygon is the band's square, every edge
  // along a plane, and line mode draws nothing, though the triangle is
  // unfilled (not culled or degenerate).
  const FrontEndRun r = run_front_end(clip_space_scene({unfilled(PolygonMode::line, CullMode::back,
                                                                 {{-5000.0f, -5000.0f, 0.0f, 1.0f},
                                                                  {5000.0f, -5000.0f, 0.0f, 1.0f},
                                                                  {0.0f, 5000.0f, 0.0f, 1.0f}})}));
  EXPECT_EQ(r.prims.size(), 0u);
  EXPECT_EQ(r.clipper.at("triangles_unfilled"), 1u);
  EXPECT_EQ(r.clipper.at("triangles_clipped"), 1u);
}

TEST(FrontEndPolygonMode, AVertexOnAPlaneIsDrawnTwiceInPointMode) {
  // Section 4d taken literally: v2 lies on the near plane (z + w = 0), v1
  // behind it. The edge (v1 v2) enters the inside at v2 itself: the cut
  // starts from v2 (distance 0), t = 0, and the new vertex, equal to v2,
  // takes v1's flag (set); v2 keeps its own. Polygon v0, c1 (leaving, clear),
  // c' = v2, v2: the points v0, v2, v2; the lines (v0 c1), (v2 v2) of zero
  // length, (v2 v0).
  const std::vector<glm::vec4> v = {kCcw[0], {0.5f, -0.5f, -3.0f, 1.0f}, {0.0f, 0.5f, -1.0f, 1.0f}};
  const FrontEndRun r =
      run_front_end(clip_space_scene({unfilled(PolygonMode::point, CullMode::none, v),
                                      unfilled(PolygonMode::line, CullMode::none, v)}));
  ASSERT_EQ(r.prims.size(), 6u);
  EXPECT_EQ(r.prims[0].v[0].x, 32.0f);
  for (size_t i : {1, 2}) {
    EXPECT_EQ(r.prims[i].v[0].x, 64.0f);
    EXPECT_EQ(r.prims[i].v[0].y, 96.0f);
    EXPECT_EQ(r.prims[i].v[0].z, 0.0f);
  }
  EXPECT_EQ(r.prims[4].v[0], r.prims[4].v[1]);
  EXPECT_EQ(r.prims[5].v[1].x, 32.0f);
}

TEST(FrontEndPolygonMode, PointModeDrawsTheVertices) {
  // A point shows its flat varyings (section 9): with Gouraud shading its
  // own vertex's colour, with flat shading the triangle's provoking one.
  Draw flat = unfilled(PolygonMode::point, CullMode::front, kCw);
  flat.state.shading = Shading::flat;
  const FrontEndRun r =
      run_front_end(clip_space_scene({unfilled(PolygonMode::point, CullMode::front, kCw), flat}));
  ASSERT_EQ(r.prims.size(), 6u);
  const float x[3] = {32.0f, 64.0f, 96.0f};
  for (size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(r.prims[i].primitive_kind, PrimitiveKind::point);
    EXPECT_EQ(r.prims[i].v[0].x, x[i % 3]);
    EXPECT_TRUE(holds_color(r.prims[i].flat_varyings, color_of(i < 3 ? i : 2)));
  }
}

// Random lines, strips, loops and points (vertices of every kind that
// random_clip_vertex makes: near and far, guard band, w around 0, behind the
// eye, huge) against the rules of sections 3, 4b and 4c written out here
// from the spec's text, on golden::clip_distance and golden::to_window.

struct ExpectedLinePoint {
  uint32_t draw_id = 0;
  int64_t primitive_id = 0;
  std::vector<golden::ShadedVertex> v;  // clipped, 1 or 2
  glm::vec4 flat_color{0.0f};
  bool first = true, last = true;
};

struct ExpectedLinesPoints {
  std::vector<ExpectedLinePoint> prims;
  uint64_t lines_in = 0, lines_invalid = 0, lines_away = 0, lines_clipped = 0;
  uint64_t points_in = 0, points_invalid = 0, points_away = 0;
};

// Section 4b: false when nothing is left; `clipped` when step 2 ran.
bool spec_clip_line(golden::ShadedVertex& a, golden::ShadedVertex& b, const golden::GuardBand& gb,
                    bool& clipped) {
  clipped = false;
  bool accept = true;
  for (int p = 0; p < golden::kClipPlaneCount; ++p) {
    const float da = golden::clip_distance(p, a.clip, gb),
                db = golden::clip_distance(p, b.clip, gb);
    if (da < 0.0f && db < 0.0f) return false;
    accept = accept && da >= 0.0f && db >= 0.0f;
  }
  if (accept) return true;
  for (int p = 0; p < golden::kClipPlaneCount; ++p) {
    const float da = golden::clip_distance(p, a.clip, gb),
                db = golden::clip_distance(p, b.clip, gb);
    if (da >= 0.0f && db >= 0.0f) continue;
    if (da < 0.0f && db < 0.0f) return false;
    golden::ShadedVertex& out = da < 0.0f ? a : b;
    const golden::ShadedVertex in = da < 0.0f ? b : a;
    const float d_out = da < 0.0f ? da : db, d_in = da < 0.0f ? db : da;
    // From the endpoint nearer the plane, the inside one on a tie.
    const bool from_in = std::fabs(d_in) <= std::fabs(d_out);
    const golden::ShadedVertex& s = from_in ? in : out;
    const golden::ShadedVertex& e = from_in ? out : in;
    const float ds = from_in ? d_in : d_out, de = from_in ? d_out : d_in;
    const float t = ds / (ds - de);
    golden::ShadedVertex v;
    for (int k = 0; k < 4; ++k) {
      v.clip[k] = s.clip[k] + t * (e.clip[k] - s.clip[k]);
      v.color[k] = s.color[k] + t * (e.color[k] - s.color[k]);
    }
    if (p == 0 && v.clip.w < golden::kMinClipW) v.clip.w = golden::kMinClipW;
    out = v;
  }
  clipped = true;
  return true;
}

ExpectedLinesPoints expected_lines_points(const Scene& scene) {
  ExpectedLinesPoints e;
  const golden::GuardBand gb =
      golden::guard_band_for(scene.framebuffer.width, scene.framebuffer.height);
  int64_t id = 0;
  for (uint32_t d = 0; d < scene.draws.size(); ++d) {
    const Draw& draw = scene.draws[d];
    const uint32_t n = static_cast<uint32_t>(draw.vertex_count());
    // Slot -> vertex, or nothing when invalid (index or non-finite clip).
    const auto vertex = [&](uint32_t slot, golden::ShadedVertex& out) {
      const uint32_t vi = draw.indices.empty() ? slot : draw.indices[slot];
      if (vi >= draw.positions.size()) return false;
      out = golden::shade_vertex(scene, draw, vi);
      return finite4(out.clip);
    };
    if (draw.primitive == PrimitiveType::points) {
      for (uint32_t i = 0; i < n; ++i, ++id) {
        ++e.points_in;
        golden::ShadedVertex v;
        if (!vertex(i, v)) {
          ++e.points_invalid;
          continue;
        }
        const glm::vec4& c = v.clip;
        if (!(c.w - golden::kMinClipW >= 0.0f && c.x + c.w >= 0.0f && c.w - c.x >= 0.0f &&
              c.y + c.w >= 0.0f && c.w - c.y >= 0.0f && c.z + c.w >= 0.0f && c.w - c.z >= 0.0f)) {
          ++e.points_away;
          continue;
        }
        e.prims.push_back({d, id, {v}, v.color, true, true});
      }
      continue;
    }
    // Section 3's table.
    std::vector<std::array<uint32_t, 2>> lines;
    std::vector<std::pair<bool, bool>> flags;
    if (draw.primitive == PrimitiveType::lines) {
      for (uint32_t i = 0; 2 * i + 1 < n; ++i) {
        lines.push_back({2 * i, 2 * i + 1});
        flags.push_back({true, true});
      }
    } else {
      for (uint32_t i = 0; i + 1 < n; ++i) {
        lines.push_back({i, i + 1});
        flags.push_back({i == 0, true});
      }
      if (draw.primitive == PrimitiveType::line_loop && n >= 2) {
        lines.push_back({n - 1, 0});
        flags.push_back({false, false});
      }
    }
    for (size_t i = 0; i < lines.size(); ++i, ++id) {
      ++e.lines_in;
      golden::ShadedVertex a, b;
      if (!vertex(lines[i][0], a) || !vertex(lines[i][1], b)) {
        ++e.lines_invalid;
        continue;
      }
      const glm::vec4 flat = b.color;
      bool clipped = false;
      if (!spec_clip_line(a, b, gb, clipped)) {
        ++e.lines_away;
        continue;
      }
      if (clipped) ++e.lines_clipped;
      e.prims.push_back({d, id, {a, b}, flat, flags[i].first, flags[i].second});
    }
  }
  return e;
}

TEST(FrontEndLines, RandomLinesAndPointsFollowTheSpec) {
  std::mt19937 rng(11);
  Scene s;
  s.framebuffer.width = 256;
  s.framebuffer.height = 192;
  s.draws.push_back(random_draw(rng, PrimitiveType::lines, 400, true, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::line_strip, 131, true, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::line_loop, 97, false, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::points, 300, true, 0));
  Draw indexed = random_draw(rng, PrimitiveType::line_loop, 60, true, 150);
  indexed.indices[7] = 60;      // out of range
  indexed.indices[149] = 1000;  // the loop's last slot: its last two lines invalid
  s.draws.push_back(indexed);
  Draw points = random_draw(rng, PrimitiveType::points, 50, true, 90);
  points.indices[40] = 77;
  s.draws.push_back(points);
  s.draws.push_back(random_draw(rng, PrimitiveType::line_strip, 33, true, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::line_loop, 2, true, 0));
  const ExpectedLinesPoints want = expected_lines_points(s);
  EXPECT_GT(want.lines_clipped, 50u);
  EXPECT_GT(want.lines_away, 50u);
  EXPECT_GT(want.points_away, 50u);
  EXPECT_GT(want.lines_invalid, 3u);

  const FrontEndRun r = run_front_end(s, config_with(16, 2));
  ASSERT_EQ(r.prims.size(), want.prims.size());
  const float half_w = 0.5f * s.framebuffer.width, half_h = 0.5f * s.framebuffer.height;
  int failures = 0;
  for (size_t i = 0; i < want.prims.size() && failures < 5; ++i) {
    const ClippedPrimitive& g = r.prims[i];
    const ExpectedLinePoint& w = want.prims[i];
    bool ok = g.draw_id == w.draw_id && g.primitive_id == w.primitive_id &&
              g.vertex_count == w.v.size() &&
              g.primitive_kind == (w.v.size() == 1 ? PrimitiveKind::point : PrimitiveKind::line) &&
              holds_color(g.flat_varyings, w.flat_color);
    if (w.v.size() == 2) ok = ok && g.draw_first == w.first && g.draw_last == w.last;
    for (size_t k = 0; k < w.v.size(); ++k) {
      const golden::WindowVertex wv =
          golden::to_window(w.v[k], s.framebuffer.width, s.framebuffer.height);
      const float x = (w.v[k].clip.x * wv.inv_w + 1.0f) * half_w;
      const float y = (w.v[k].clip.y * wv.inv_w + 1.0f) * half_h;
      ok = ok && bits(g.v[k].x) == bits(x) && bits(g.v[k].y) == bits(y) &&
           bits(g.v[k].z) == bits(wv.z) && bits(g.v[k].inv_w) == bits(wv.inv_w) &&
           holds_color(g.v[k].varyings_over_w, wv.color_over_w);
    }
    if (!ok) {
      ++failures;
      ADD_FAILURE() << "primitive " << i << " (prim " << w.primitive_id << "): " << g;
    }
  }
  EXPECT_EQ(r.clipper.at("lines_in"), want.lines_in);
  EXPECT_EQ(r.clipper.at("lines_invalid"), want.lines_invalid);
  EXPECT_EQ(r.clipper.at("lines_clipped_away"), want.lines_away);
  EXPECT_EQ(r.clipper.at("lines_clipped"), want.lines_clipped);
  EXPECT_EQ(r.clipper.at("points_in"), want.points_in);
  EXPECT_EQ(r.clipper.at("points_invalid"), want.points_invalid);
  EXPECT_EQ(r.clipper.at("points_clipped_away"), want.points_away);
}

}  // namespace
}  // namespace gpusim
