// Varyings beyond the colour through the stages that carry them without
// knowing what they mean: the clipper (interpolation at clip-plane cuts,
// division by w), primitive setup (the primitive kind it accepts) and the
// interpolator (perspective-correct, per pixel). The layouts hold a made-up
// varying next to the colour, before or after it, and one that fills the
// whole capacity.
//
// Every varying is an affine function of the vertex's clip-space position,
// so its correct value anywhere on a primitive is that function of the
// position there: at a cut vertex, of the cut's position (read back from its
// window coordinates); at a pixel, of the surface point seen through the
// pixel centre (the pixel's ray intersected with the triangle, in double).
// Neither uses the stages' formulas. The colour slot is also checked bit for
// bit against the golden model (clipper) and the spec's formula (interpolator).
// One sc_start per TEST: ctest runs each in its own process.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/pixel_formats.h"
#include "hw/vertex_packets.h"
#include "stages/clipper.h"
#include "stages/interpolator.h"
#include "stages/primitive_setup.h"
#include "testbench/golden/golden_model.h"

namespace gpusim {
namespace {

// Varying k at clip position c: 0.5 plus small, distinct slopes, so that for
// |x|, |y|, |z| <= w <= 2 every value stays inside (0, 1), where the
// interpolator's clamp of the colour it outputs changes nothing.
double affine(unsigned k, const glm::dvec4& c) {
  const double sx = 0.008 * (k + 1) * (k % 2 ? -1.0 : 1.0);
  const double sy = 0.04 - 0.005 * k;
  const double sz = 0.02 * (static_cast<double>(k % 4) - 1.5);
  const double sw = 0.03 * (static_cast<double>(k % 3) - 1.0);
  return 0.5 + sx * c.x + sy * c.y + sz * c.z + sw * c.w;
}

uint32_t bits(float f) {
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// Colour and a made-up 3-component varying: colour first or second.
VaryingLayout color_then_extra() {
  VaryingLayout l;
  l.count = 0;
  l.color = static_cast<uint8_t>(l.append(kColorComponents));
  l.append(3);
  return l;
}
VaryingLayout extra_then_color() {
  VaryingLayout l;
  l.count = 0;
  l.append(3);
  l.color = static_cast<uint8_t>(l.append(kColorComponents));
  return l;
}
// Every component in use, the colour last.
VaryingLayout full_capacity() {
  VaryingLayout l;
  l.count = 0;
  l.append(kMaxVaryings - kColorComponents);
  l.color = static_cast<uint8_t>(l.append(kColorComponents));
  return l;
}

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
// Clipper: triangles inside, across the near plane, across the right guard
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
    ShadedBatch b;
    b.kind = PacketKind::work;
    b.draw_id = d;
    b.first_slot = 0;
    b.slot_count = b.vertex_count = static_cast<uint32_t>(3 * triangles.size());
    for (uint32_t i = 0; i < b.slot_count; ++i) {
      b.slots[i] = {SlotKind::fetched, kNoCacheEntry, i};
      ShadedVertex& v = b.vertices[i];
      v.clip = triangles[i / 3][i % 3];
      for (unsigned k = 0; k < frame.draws[d].varyings.count; ++k)
        v.varyings[k] = static_cast<float>(affine(k, glm::dvec4(v.clip)));
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
    for (;;) got.push_back(out.read());
  });
  sc_core::sc_start();

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
  EXPECT_EQ(clipper.stats().to_json().at("triangles_clipped").get<uint64_t>(), 6u);
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
  std::vector<ShadedStampBatch> got;
  sc_core::sc_spawn([&] {
    for (const StampBatch& b : tokens) in.write(b);
  });
  sc_core::sc_spawn([&] {
    for (;;) got.push_back(out.read());
  });
  sc_core::sc_start();

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
