#include "stages/interpolator.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "hw/pixel_formats.h"

namespace gpusim {

namespace {

// Why a primitive whose last record is here went no further (traces): the
// depth test forwards a batch of stamps some of which passed.
constexpr const char* kFailed = "every fragment failed the depth test";

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  // Shades exactly the pixels that passed.
  const std::string dt = l.upstream("depth_test");
  l.equal("tokens_out", l.get("tokens_out"), "tokens_in", l.get("tokens_in"));
  l.equal("stamps", l.get("stamps"), dt + ".stamps_passed", l.stage(dt, "stamps_passed"));
  l.equal("fragments", l.get("fragments"), dt + ".fragments_passed",
          l.stage(dt, "fragments_passed"));
}

}  // namespace

const StageSpec& Interpolator::spec() {
  static const StageSpec s{
      "interpolator",
      StagePlacement::per_unit,
      /*optional=*/false,
      {/*ii=*/1, /*latency=*/6},
      "stamp",
      "perspective-correct interpolation: a reciprocal of 1/w then the attribute products",
      "stamp batches and control tokens read",
      "shaded batches and control tokens written",
      {"depth_to_interpolator"},
      &conserve,
      StageTrace{TraceItem::stamp_batch, {kFailed, kFailed, kFailed}, FragmentSite::none},
      {{"",
        "`ii` × stamps + lit pixels × (`lighting_cycles_per_pixel` + `lighting_cycles_per_light` × "
        "lights)",
        "Every kind; points and flat-shaded primitives take the flat varyings. The second term is "
        "the per-pixel lighting unit (Phong draws' triangles and lines only, spec 9b): it takes "
        "one pixel at a time after the interpolation lanes, paying per pixel for the "
        "renormalisation and clamp and per light for direction, attenuation, half vector and `pow` "
        "(defaults 1 and 2: 5 cycles a pixel under 2 lights). A frame without Phong draws pays "
        "nothing."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(Interpolator);

Interpolator::Interpolator(sc_core::sc_module_name name, const GpuConfig& config,
                           const FrameState& frame, unsigned unit)
    : PipelineStage(name, spec(), static_cast<int>(unit), config, frame),
      in("in"),
      out("out"),
      m_stamp_shift(log2_side(config.stamp[0])),
      m_stamp_pixels(static_cast<int>(config.stamp[0] * config.stamp[1])),
      m_lighting(frame) {
  SC_HAS_PROCESS(Interpolator);
  SC_THREAD(run);
}

void Interpolator::reset_state() {
  m_offset = {};
  m_step_x = m_step_y = {};
  m_offset_valid = false;
  m_lighting.reset();
}

void Interpolator::run() {
  // The frame's registers are final once the simulation runs.
  m_lighting_cycles_per_pixel_total =
      uint64_t{m_config.lighting_cycles_per_pixel} +
      uint64_t{m_config.lighting_cycles_per_light} * m_frame.lights.size();
  // One packet object each way: the FIFOs recycle their buffers (hw/fifo.h),
  // so no batch allocates.
  StampBatch batch;
  ShadedStampBatch result;
  for (;;) {
    receive(in, batch);
    result.kind = batch.kind;
    result.stamps.clear();
    result.samples.clear();
    // A work batch's colours are resized by shade(): the stale packet's
    // vector is only cut or extended, not cleared and refilled with zeros.
    if (batch.kind != PacketKind::work) {
      result.colors.clear();
      result.texcoords.clear();
      result.texcoord_derivatives.clear();
    }
    uint64_t cycles = m_cost.ii;
    if (batch.kind == PacketKind::work) {
      cycles = m_cost.ii * std::max<uint64_t>(batch.stamps.size(), 1);
      m_stamps += batch.stamps.size();
      const uint64_t lit_before = m_pixels_lit;
      shade(batch, result);
      // The lighting unit follows the interpolation lanes, one pixel at a
      // time: its cycles add to the batch's.
      cycles += (m_pixels_lit - lit_before) * m_lighting_cycles_per_pixel_total;
      result.stamps.swap(batch.stamps);
      result.samples.swap(batch.samples);  // multisampled: where each colour goes
      m_fragments += result.colors.size();
    }
    result.primitive.swap(batch.primitive);
    work(cycles);
    emit(out, std::move(result));
  }
}

void Interpolator::update_offsets(const RasterPrimitive& tri) {
  std::array<EdgeValue, 3> step_x, step_y;
  for (int k = 0; k < 3; ++k) {
    step_x[k] = tri.edge[k].a * kSubpixelOne;
    step_y[k] = tri.edge[k].b * kSubpixelOne;
  }
  // Consecutive batches are mostly one triangle's tiles: the table is kept
  // while the steps are the same (compared by value, not by triangle, so a
  // new triangle at a recycled address cannot reuse a stale table).
  if (m_offset_valid && step_x == m_step_x && step_y == m_step_y) return;
  m_step_x = step_x;
  m_step_y = step_y;
  const int w_mask = (1 << m_stamp_shift) - 1;
  for (int p = 0; p < m_stamp_pixels; ++p) {
    const EdgeValue i = p & w_mask, j = p >> m_stamp_shift;
    for (int k = 0; k < 3; ++k) m_offset[k][p] = i * step_x[k] + j * step_y[k];
  }
  m_offset_valid = true;
}

// Per-pixel edge offsets within a stamp, one table per edge.
struct EdgeOffsets {
  const EdgeValue *o0, *o1, *o2;
};

namespace {

#if defined(__SSE2__)
// Gouraud interpolation of a primitive whose draw has G groups of 4 varying
// components (count <= 4 G), writing one colour per covered pixel to `out`.
// Four components sit in the four lanes of one register: each lane performs
// the spec's operations in the spec's order (IEEE single, no contraction), so
// every component equals the scalar formula's bit for bit. Components past
// the count in the last group are 0 in the packet; their results go unused.
// G is a template parameter so the primitive's varyings stay in registers
// across its pixels. clamp01 is min(max(v, 0), 1) with maxps/minps taking
// the second operand when the first is NaN: NaN -> 0, -0 -> +0, as clamp01.
template <unsigned G>
void interpolate(const std::vector<Stamp>& stamps, const EdgeOffsets& o,
                 const RasterPrimitive& prim, unsigned color, glm::vec4* out) {
  __m128 vw[3][G];
  for (int i = 0; i < 3; ++i) {
    for (unsigned g = 0; g < G; ++g)
      vw[i][g] = _mm_loadu_ps(prim.varyings_over_w[i].data() + g * kVaryingGroup);
  }
  const std::array<float, 3>& q = prim.inv_w;
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  for (const Stamp& s : stamps) {
    const EdgeValue e0 = s.e[0], e1 = s.e[1], e2 = s.e[2];
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1) {
      const int idx = __builtin_ctzll(bits);
      const float f0 = static_cast<float>(e0 + o.o0[idx]);
      const float f1 = static_cast<float>(e1 + o.o1[idx]);
      const float f2 = static_cast<float>(e2 + o.o2[idx]);
      const float den = f0 * q[0] + f1 * q[1] + f2 * q[2];
      const __m128 m0 = _mm_set1_ps(f0), m1 = _mm_set1_ps(f1), m2 = _mm_set1_ps(f2);
      const __m128 d = _mm_set1_ps(den);
      __m128 v[G];
      for (unsigned g = 0; g < G; ++g) {
        const __m128 num =
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(m0, vw[0][g]), _mm_mul_ps(m1, vw[1][g])),
                       _mm_mul_ps(m2, vw[2][g]));
        v[g] = _mm_div_ps(num, d);
      }
      __m128 c;
      if constexpr (G == 1) {
        c = v[0];  // 4 components in all: they are the colour
      } else {
        alignas(16) float all[G * kVaryingGroup];
        for (unsigned g = 0; g < G; ++g) _mm_store_ps(all + g * kVaryingGroup, v[g]);
        c = _mm_loadu_ps(all + color);
      }
      _mm_storeu_ps(&(*out)[0], _mm_min_ps(_mm_max_ps(c, zero), one));
      ++out;
    }
  }
}
#endif

}  // namespace

void Interpolator::shade_phong(const std::vector<Stamp>& stamps, const EdgeOffsets& o,
                               const RasterPrimitive& prim, const VaryingLayout& layout,
                               glm::vec4* out) {
  m_lighting.load(prim.draw_id);
  const std::array<float, 3>& q = prim.inv_w;
  const float* vw0 = prim.varyings_over_w[0].data();
  const float* vw1 = prim.varyings_over_w[1].data();
  const float* vw2 = prim.varyings_over_w[2].data();
  // The interpolated normal (0-2) and eye position (3-5) of the pixel, each
  // by section 9's perspective-correct formula.
  const unsigned slot[6] = {layout.normal,   layout.normal + 1u, layout.normal + 2u,
                            layout.eye + 0u, layout.eye + 1u,    layout.eye + 2u};
  float v[6];
  for (const Stamp& s : stamps) {
    const EdgeValue e0 = s.e[0], e1 = s.e[1], e2 = s.e[2];
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1) {
      const int idx = __builtin_ctzll(bits);
      const float f0 = static_cast<float>(e0 + o.o0[idx]);
      const float f1 = static_cast<float>(e1 + o.o1[idx]);
      const float f2 = static_cast<float>(e2 + o.o2[idx]);
      const float den = f0 * q[0] + f1 * q[1] + f2 * q[2];
      for (int k = 0; k < 6; ++k) {
        const unsigned c = slot[k];
        v[k] = (f0 * vw0[c] + f1 * vw1[c] + f2 * vw2[c]) / den;
      }
      // Renormalised (a zero vector stays zero), then section 2's equation.
      const glm::vec3 n = LightingUnit::normalize(glm::vec3(v[0], v[1], v[2]));
      *out++ = m_lighting.shade(n, glm::vec3(v[3], v[4], v[5]));
    }
  }
}

void Interpolator::interpolate_texcoords(const std::vector<Stamp>& stamps,
                                         const RasterPrimitive& prim, unsigned slot, size_t n,
                                         std::vector<glm::vec2>& out,
                                         std::vector<glm::vec4>* derivatives) {
  out.resize(n);
  if (prim.primitive_kind == PrimitiveKind::point) {
    // A point samples at its vertex's coordinate (spec section 9c): no
    // change across its quads.
    out.assign(n, glm::vec2(prim.flat_varyings[slot], prim.flat_varyings[slot + 1]));
    if (derivatives) derivatives->assign(n, glm::vec4(0.0f));
    return;
  }
  if (derivatives) derivatives->resize(n);
  // Whatever the shading, by section 9's formula, as any varying.
  update_offsets(prim);
  const std::array<float, 3>& q = prim.inv_w;
  const float* vw0 = prim.varyings_over_w[0].data() + slot;
  const float* vw1 = prim.varyings_over_w[1].data() + slot;
  const float* vw2 = prim.varyings_over_w[2].data() + slot;
  const auto at = [&](EdgeValue e0, EdgeValue e1, EdgeValue e2) {
    const float f0 = static_cast<float>(e0);
    const float f1 = static_cast<float>(e1);
    const float f2 = static_cast<float>(e2);
    const float den = f0 * q[0] + f1 * q[1] + f2 * q[2];
    glm::vec2 tc;
    for (int k = 0; k < 2; ++k) tc[k] = (f0 * vw0[k] + f1 * vw1[k] + f2 * vw2[k]) / den;
    return tc;
  };
  const int w_mask = (1 << m_stamp_shift) - 1;
  size_t i = 0;
  for (const Stamp& s : stamps) {
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1, ++i) {
      const int idx = __builtin_ctzll(bits);
      out[i] = at(s.e[0] + m_offset[0][idx], s.e[1] + m_offset[1][idx], s.e[2] + m_offset[2][idx]);
      if (!derivatives) continue;
      // The pixel's 2x2 quad, from its lower-left pixel (even x and y) to
      // the right and upper neighbours, each stepped from the stamp's
      // origin whether or not it is covered or in the stamp: the same
      // exact edge values as at any pixel centre.
      const EdgeValue dx = ((s.x + (idx & w_mask)) & ~1) - s.x;
      const EdgeValue dy = ((s.y + (idx >> m_stamp_shift)) & ~1) - s.y;
      std::array<EdgeValue, 3> e00;
      for (int k = 0; k < 3; ++k) e00[k] = s.e[k] + dx * m_step_x[k] + dy * m_step_y[k];
      const glm::vec2 p00 = at(e00[0], e00[1], e00[2]);
      const glm::vec2 p10 = at(e00[0] + m_step_x[0], e00[1] + m_step_x[1], e00[2] + m_step_x[2]);
      const glm::vec2 p01 = at(e00[0] + m_step_y[0], e00[1] + m_step_y[1], e00[2] + m_step_y[2]);
      (*derivatives)[i] = glm::vec4(p10.x - p00.x, p10.y - p00.y, p01.x - p00.x, p01.y - p00.y);
    }
  }
}

void Interpolator::shade(const StampBatch& batch, ShadedStampBatch& result) {
  const RasterPrimitive& prim = *batch.primitive;
  const DrawState& draw = m_frame.draws.at(prim.draw_id);
  const RenderState& st = draw.state;
  const VaryingLayout& layout = draw.varyings;
  // Every layout holds the colour, inside its count (so a layout of one group
  // is the colour alone).
  assert(layout.color + kColorComponents <= layout.count && layout.count <= kMaxVaryings);
  // Full stamps need no count (popcount is a libgcc call on baseline x86-64).
  const uint64_t full = m_stamp_pixels == 64 ? ~uint64_t{0} : (uint64_t{1} << m_stamp_pixels) - 1;
  size_t n = 0;
  for (const Stamp& s : batch.stamps) {
    n += s.mask == full ? static_cast<size_t>(m_stamp_pixels)
                        : static_cast<size_t>(__builtin_popcountll(s.mask));
  }
  result.texcoord_derivatives.clear();
  if (layout.textured()) {
    interpolate_texcoords(
        batch.stamps, prim, layout.texcoord, n, result.texcoords,
        draw.texture.sampler.needs_lod() ? &result.texcoord_derivatives : nullptr);
    m_texcoords += n;
  } else {
    result.texcoords.clear();
  }
  if (st.shading == Shading::flat || prim.primitive_kind == PrimitiveKind::point) {
    // Every pixel takes the provoking vertex's varyings; the ROP its colour.
    // A point takes its vertex's values whatever the shading (spec section 9):
    // the clipper puts them in flat_varyings.
    const float* flat = prim.flat_varyings.data() + layout.color;
    result.colors.assign(n, glm::vec4(flat[0], flat[1], flat[2], flat[3]));
    m_flat_fragments += n;
    return;
  }
  // Sized once, written through a pointer: no capacity check per pixel (the
  // vector keeps its capacity and mostly its size across batches, so this
  // rarely allocates or zero-fills).
  result.colors.resize(n);
  glm::vec4* out = result.colors.data();

  // Pixel p of a stamp is at offset m_offset[k][p] = i * a_k * 256 +
  // j * b_k * 256 from the origin's edge value: the same exact int64 sum as
  // stepping per pixel, looked up instead of multiplied.
  update_offsets(prim);
  const EdgeOffsets o{m_offset[0].data(), m_offset[1].data(), m_offset[2].data()};
  if (layout.per_pixel_lighting()) {
    shade_phong(batch.stamps, o, prim, layout, out);
    m_pixels_lit += n;
    m_light_evaluations += n * m_frame.lights.size();
    return;
  }
#if defined(__SSE2__)
  switch (layout.groups()) {
    case 1:
      interpolate<1>(batch.stamps, o, prim, layout.color, out);
      break;
    case 2:
      interpolate<2>(batch.stamps, o, prim, layout.color, out);
      break;
    case 3:
      interpolate<3>(batch.stamps, o, prim, layout.color, out);
      break;
  }
  static_assert(kMaxVaryings == 3 * kVaryingGroup, "a case per group count");
#else
  const std::array<float, 3>& q = prim.inv_w;
  const float* vw0 = prim.varyings_over_w[0].data();
  const float* vw1 = prim.varyings_over_w[1].data();
  const float* vw2 = prim.varyings_over_w[2].data();
  Varyings v;  // the pixel's varyings
  for (const Stamp& s : batch.stamps) {
    const EdgeValue e0 = s.e[0], e1 = s.e[1], e2 = s.e[2];
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1) {
      const int idx = __builtin_ctzll(bits);
      const float f0 = static_cast<float>(e0 + o.o0[idx]);
      const float f1 = static_cast<float>(e1 + o.o1[idx]);
      const float f2 = static_cast<float>(e2 + o.o2[idx]);
      const float den = f0 * q[0] + f1 * q[1] + f2 * q[2];
      for (unsigned k = 0; k < layout.count; ++k)
        v[k] = (f0 * vw0[k] + f1 * vw1[k] + f2 * vw2[k]) / den;
      for (unsigned k = 0; k < kColorComponents; ++k) (*out)[k] = clamp01(v[layout.color + k]);
      ++out;
    }
  }
#endif
}

}  // namespace gpusim
