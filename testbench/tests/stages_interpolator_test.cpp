// The interpolator (stages/interpolator.h) alone, fed stamp batches made
// here, against the spec's formula (docs/pipeline-spec.md, section 9):
// - colours per pixel of random flat and Gouraud triangles, set up and
//   cut into stamps with the golden model's functions
//   (testbench/tests/back_end_input.h), evaluated with golden edge functions
//   at each pixel centre (no stepping), bit for bit;
// - every varying of a layout (testbench/tests/varying_layouts.h: a made-up
//   varying next to the colour, one that fills the capacity, this file also
//   checking the layouts), perspective-correct: one triangle in perspective
//   drawn once per colour slot position, each value against the affine
//   function of the surface point seen through the pixel centre (the
//   pixel's ray intersected with the triangle, in double), and bit for bit
//   against the spec's formula.
// One sc_start per TEST: ctest runs each in its own process.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/pixel_formats.h"
#include "hw/vertex_packets.h"
#include "stages/interpolator.h"
#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"
#include "testbench/tests/back_end_input.h"
#include "testbench/tests/stage_host.h"
#include "testbench/tests/varying_layouts.h"

namespace gpusim {
namespace {

using namespace test;

// The bits of `f`, to compare floats exactly.
uint32_t bits(float f) {
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// ---------------------------------------------------------------------------
// The interpolator's colours, per pixel, against the spec's formula evaluated
// with golden edge functions at each pixel centre (no stepping).

TEST(Interpolator, ColoursEqualTheSpecPerPixel) {
  GpuConfig cfg = config(1, 16, 4, 2, 4, 4);
  Scene scene = make_scene(64, 48, ColorFormat::rgba16f, DepthFormat::unorm24);
  Rng rng(600);
  for (int d = 0; d < 20; ++d) {
    RenderState st;
    st.shading = d % 4 == 0 ? Shading::flat : Shading::gouraud;
    add_random_draw(scene, rng, 15, st, 0.0, nullptr);
  }
  const FrameState frame = frame_state(scene);
  UnitTokens tokens = front_end(scene, cfg);
  Fifo<StampBatch> in("in", 4);
  Fifo<ShadedStampBatch> out("out", 4);
  Interpolator interpolator("interpolator", cfg, frame, 0);
  interpolator.in(in);
  interpolator.out(out);
  feed(in, tokens[0]);
  Sink<ShadedStampBatch> sink(out, cfg.cycle());
  sc_core::sc_start();
  const std::vector<ShadedStampBatch>& got = sink.items;

  ASSERT_EQ(got.size(), tokens[0].size());
  uint64_t pixels = 0, flat = 0;
  for (size_t n = 0; n < got.size(); ++n) {
    const StampBatch& b = tokens[0][n];
    const ShadedStampBatch& s = got[n];
    ASSERT_EQ(s.kind, b.kind);
    ASSERT_EQ(s.stamps, b.stamps);
    if (b.kind != PacketKind::work) continue;
    const RasterPrimitive& t = *b.primitive;
    const auto v = window_vertices(t);
    const bool is_flat = scene.draws[t.draw_id].state.shading == Shading::flat;
    size_t c = 0;
    for (const Stamp& st : b.stamps) {
      for (int bit = 0; bit < 64; ++bit) {
        if (!(st.mask >> bit & 1)) continue;
        const int x = st.x + bit % 4, y = st.y + bit / 4;
        glm::vec4 want(t.flat_varyings[0], t.flat_varyings[1], t.flat_varyings[2],
                       t.flat_varyings[3]);
        if (!is_flat) {
          const float f0 = static_cast<float>(
              golden::edge_function(v[1], v[2], pixel_center(x), pixel_center(y)));
          const float f1 = static_cast<float>(
              golden::edge_function(v[2], v[0], pixel_center(x), pixel_center(y)));
          const float f2 = static_cast<float>(
              golden::edge_function(v[0], v[1], pixel_center(x), pixel_center(y)));
          const float den = f0 * v[0].inv_w + f1 * v[1].inv_w + f2 * v[2].inv_w;
          for (int k = 0; k < 4; ++k) {
            want[k] = clamp01((f0 * v[0].color_over_w[k] + f1 * v[1].color_over_w[k] +
                               f2 * v[2].color_over_w[k]) /
                              den);
          }
        }
        ASSERT_LT(c, s.colors.size());
        EXPECT_EQ(std::memcmp(&s.colors[c], &want, sizeof want), 0)
            << "triangle " << t.primitive_id << " pixel (" << x << ", " << y << ")";
        ++c;
        ++pixels;
        flat += is_flat;
      }
    }
    EXPECT_EQ(c, s.colors.size());
  }
  EXPECT_GT(pixels, 2000u);
  EXPECT_GT(flat, 200u);
  EXPECT_EQ(interpolator.stats().to_json().at("fragments").get<uint64_t>(), pixels);
  EXPECT_EQ(interpolator.stats().to_json().at("flat_fragments").get<uint64_t>(), flat);
}

// ---------------------------------------------------------------------------
// The layouts of varying_layouts.h (hw/varying_layout.h's VaryingLayout::append)
// hold what the next test assumes.

TEST(VaryingLayouts, MadeUpVaryingsTakeTheirComponents) {
  EXPECT_EQ(color_then_extra().count, 7);
  EXPECT_EQ(color_then_extra().color, 0);
  EXPECT_EQ(color_then_extra().groups(), 2u);
  EXPECT_EQ(extra_then_color().color, 3);
  EXPECT_EQ(full_capacity().count, kMaxVaryings);
  EXPECT_EQ(full_capacity().color, kMaxVaryings - kColorComponents);
  EXPECT_EQ(full_capacity().groups(), kMaxVaryings / kVaryingGroup);
}

// ---------------------------------------------------------------------------
// Interpolator: one triangle in perspective (w = 0.5, 1, 2) under layouts of
// 7 and 12 (the capacity) components. The interpolator outputs the 4 components at the
// layout's colour slot, so the test draws the triangle once per colour slot
// position, 0 to count - 4, and sees every component.

struct Corner {
  double x, y;  // window, pixels, on the subpixel grid
  double z;     // NDC
  double w;
};

TEST(Interpolator, InterpolatesEveryVaryingPerspectiveCorrect) {
  constexpr int kSize = 32;
  constexpr double kHalf = kSize / 2.0;
  // Counter-clockwise (y up); window positions exact in float and subpixels.
  const std::array<Corner, 3> corners = {{
      {1.5, 2.25, -0.5, 0.5},
      {30.0, 5.5, 0.25, 1.0},
      {9.75, 29.0, 0.75, 2.0},
  }};
  std::array<glm::dvec4, 3> clip;
  for (int i = 0; i < 3; ++i) {
    const Corner& c = corners[i];
    clip[i] = glm::dvec4((c.x / kHalf - 1.0) * c.w, (c.y / kHalf - 1.0) * c.w, c.z * c.w, c.w);
  }

  FrameState frame;
  frame.framebuffer.width = kSize;
  frame.framebuffer.height = kSize;
  struct DrawCase {
    VaryingLayout layout;
    Shading shading;
  };
  std::vector<DrawCase> cases;
  for (const VaryingLayout& base : {color_then_extra(), full_capacity()}) {
    for (unsigned slot = 0; slot + kColorComponents <= base.count; ++slot) {
      VaryingLayout l = base;
      l.color = static_cast<uint8_t>(slot);
      cases.push_back({l, Shading::gouraud});
    }
  }
  cases.push_back({color_then_extra(), Shading::flat});
  cases.push_back({extra_then_color(), Shading::flat});
  for (const DrawCase& c : cases) {
    DrawState d;
    d.varyings = c.layout;
    d.state.shading = c.shading;
    frame.draws.push_back(d);
  }

  // The vertices' varyings as float, as the vertex shader holds them.
  std::array<Varyings, 3> vary{};
  for (int i = 0; i < 3; ++i) {
    for (unsigned k = 0; k < kMaxVaryings; ++k) vary[i][k] = static_cast<float>(affine(k, clip[i]));
  }

  GpuConfig config;
  config.stamp = {4, 4};
  std::vector<StampBatch> tokens;
  std::vector<std::shared_ptr<RasterPrimitive>> prims;
  for (uint32_t d = 0; d < frame.draws.size(); ++d) {
    const unsigned count = frame.draws[d].varyings.count;
    auto p = std::make_shared<RasterPrimitive>();
    p->draw_id = d;
    p->primitive_id = d;
    for (int i = 0; i < 3; ++i) {
      p->x[i] = static_cast<Subpixel>(corners[i].x * kSubpixelOne);
      p->y[i] = static_cast<Subpixel>(corners[i].y * kSubpixelOne);
      p->inv_w[i] = static_cast<float>(1.0 / corners[i].w);  // powers of two: exact
      for (unsigned k = 0; k < count; ++k) p->varyings_over_w[i][k] = vary[i][k] * p->inv_w[i];
    }
    for (unsigned k = 0; k < count; ++k) p->flat_varyings[k] = vary[2][k];
    p->area2 = (EdgeValue{p->x[1]} - p->x[0]) * (EdgeValue{p->y[2]} - p->y[0]) -
               (EdgeValue{p->y[1]} - p->y[0]) * (EdgeValue{p->x[2]} - p->x[0]);
    ASSERT_GT(p->area2, 0);
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const EdgeValue dx = EdgeValue{p->x[j]} - p->x[i], dy = EdgeValue{p->y[j]} - p->y[i];
      p->edge[k] = {-dy, dx, dy * p->x[i] - dx * p->y[i], (dy < 0 || (dy == 0 && dx > 0)) ? 0 : 1};
    }
    p->x0 = p->y0 = 0;
    p->x1 = p->y1 = kSize - 1;
    StampBatch b;
    b.primitive = p;
    for (int sy = 0; sy < kSize; sy += 4) {
      for (int sx = 0; sx < kSize; sx += 4) {
        Stamp s;
        s.x = sx;
        s.y = sy;
        for (int k = 0; k < 3; ++k) s.e[k] = p->edge[k].at(pixel_center(sx), pixel_center(sy));
        for (int bit = 0; bit < 16; ++bit) {
          const Subpixel px = pixel_center(sx + bit % 4), py = pixel_center(sy + bit / 4);
          bool covered = true;
          for (int k = 0; k < 3; ++k) covered = covered && p->edge[k].at(px, py) >= p->edge[k].bias;
          if (covered) s.mask |= uint64_t{1} << bit;
        }
        if (s.mask) b.stamps.push_back(s);
      }
    }
    prims.push_back(p);
    tokens.push_back(b);
  }
  StampBatch eof;
  eof.kind = PacketKind::end_of_frame;
  tokens.push_back(eof);

  Fifo<StampBatch> in("in", 4);
  Fifo<ShadedStampBatch> out("out", 4);
  Interpolator interpolator("interpolator", config, frame, 0);
  interpolator.in(in);
  interpolator.out(out);
  feed(in, tokens);
  Sink<ShadedStampBatch> sink(out, config.cycle());
  sc_core::sc_start();
  const std::vector<ShadedStampBatch>& got = sink.items;

  ASSERT_EQ(got.size(), tokens.size());
  uint64_t pixels = 0;
  double worst = 0.0;
  for (uint32_t d = 0; d < frame.draws.size(); ++d) {
    const VaryingLayout& layout = frame.draws[d].varyings;
    const bool flat = frame.draws[d].state.shading == Shading::flat;
    SCOPED_TRACE(testing::Message() << "draw " << d << ": " << layout << (flat ? ", flat" : ""));
    const RasterPrimitive& p = *prims[d];
    const ShadedStampBatch& s = got[d];
    ASSERT_EQ(s.stamps, tokens[d].stamps);
    size_t n = 0;
    for (const Stamp& st : s.stamps) {
      for (int bit = 0; bit < 16; ++bit) {
        if (!(st.mask >> bit & 1)) continue;
        const int x = st.x + bit % 4, y = st.y + bit / 4;
        ASSERT_LT(n, s.colors.size());
        const glm::vec4 c = s.colors[n++];
        ++pixels;
        if (flat) {
          for (unsigned j = 0; j < kColorComponents; ++j)
            EXPECT_EQ(bits(c[j]), bits(vary[2][layout.color + j]));
          continue;
        }
        // The surface point under the pixel centre: P = sum l_i clip_i with
        // sum l_i = 1 and P.x / P.w, P.y / P.w at the centre's NDC.
        const double nx = (x + 0.5) / kHalf - 1.0, ny = (y + 0.5) / kHalf - 1.0;
        double m[3][3];
        for (int i = 0; i < 3; ++i) {
          m[0][i] = clip[i].x - nx * clip[i].w;
          m[1][i] = clip[i].y - ny * clip[i].w;
          m[2][i] = 1.0;
        }
        auto det = [](const double a[3][3]) {
          return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        };
        const double dm = det(m);
        std::array<double, 3> l;
        for (int i = 0; i < 3; ++i) {
          double mi[3][3];
          std::memcpy(mi, m, sizeof m);
          mi[0][i] = 0.0, mi[1][i] = 0.0, mi[2][i] = 1.0;  // Cramer: right-hand side (0, 0, 1)
          l[i] = det(mi) / dm;
        }
        // The spec's formula for each component, in float, for the bits.
        std::array<float, 3> f;
        for (int k = 0; k < 3; ++k)
          f[k] = static_cast<float>(p.edge[k].at(pixel_center(x), pixel_center(y)));
        const float den = f[0] * p.inv_w[0] + f[1] * p.inv_w[1] + f[2] * p.inv_w[2];
        for (unsigned j = 0; j < kColorComponents; ++j) {
          const unsigned k = layout.color + j;
          double expected = 0.0;
          for (int i = 0; i < 3; ++i) expected += l[i] * vary[i][k];
          EXPECT_NEAR(c[j], expected, 2e-6) << "pixel (" << x << ", " << y << ") component " << k;
          worst = std::max(worst, std::fabs(c[j] - expected));
          const float spec =
              clamp01((f[0] * p.varyings_over_w[0][k] + f[1] * p.varyings_over_w[1][k] +
                       f[2] * p.varyings_over_w[2][k]) /
                      den);
          EXPECT_EQ(bits(c[j]), bits(spec)) << "pixel (" << x << ", " << y << ") component " << k;
        }
      }
    }
    EXPECT_EQ(n, s.colors.size());
  }
  // Every draw covers the triangle's pixels: about 370 of the 1024.
  size_t covered = 0;
  for (const Stamp& st : tokens[0].stamps) covered += __builtin_popcountll(st.mask);
  EXPECT_GT(covered, 300u);
  EXPECT_EQ(pixels, covered * frame.draws.size());
  EXPECT_LT(worst, 2e-6);
}

}  // namespace
}  // namespace gpusim
