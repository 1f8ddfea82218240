#include "stages/interpolator.h"

#include <algorithm>
#include <array>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "hw/pixel_formats.h"

namespace gpusim {

Interpolator::Interpolator(sc_core::sc_module_name name, const GpuConfig& config,
                           const FrameState& frame, unsigned unit)
    : sc_core::sc_module(name),
      in("in"),
      out("out"),
      m_config(config),
      m_frame(frame),
      m_unit(unit),
      m_cost(config.stage("interpolator")),
      m_cycle(config.cycle().value()),
      m_latency(clock_cycles(m_cost.latency)),
      m_stamp_shift(log2_side(config.stamp[0])),
      m_stamp_pixels(static_cast<int>(config.stamp[0] * config.stamp[1])) {
  SC_HAS_PROCESS(Interpolator);
  SC_THREAD(run);
}

void Interpolator::run() {
  // One packet object each way: the FIFOs recycle their buffers (hw/fifo.h),
  // so no batch allocates.
  StampBatch batch;
  ShadedStampBatch result;
  for (;;) {
    in->read(batch);
    ++m_tokens_in;
    result.kind = batch.kind;
    result.stamps.clear();
    // A work batch's colours are resized by shade(): the stale packet's
    // vector is only cut or extended, not cleared and refilled with zeros.
    if (batch.kind != PacketKind::work) result.colors.clear();
    uint64_t cycles = m_cost.ii;
    if (batch.kind == PacketKind::work) {
      cycles = m_cost.ii * std::max<uint64_t>(batch.stamps.size(), 1);
      m_stamps += batch.stamps.size();
      shade(batch, result);
      result.stamps.swap(batch.stamps);
      m_fragments += result.colors.size();
    }
    result.triangle.swap(batch.triangle);
    m_busy_cycles += cycles;
    sc_core::wait(clock_cycles(cycles));
    out->write(std::move(result), sc_core::sc_time_stamp() + m_latency);
    ++m_tokens_out;
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

void Interpolator::shade(const StampBatch& batch, ShadedStampBatch& result) {
  const RasterPrimitive& prim = *batch.triangle;
  const DrawState& draw = m_frame.draws.at(prim.draw_id);
  const RenderState& st = draw.state;
  const VaryingLayout& layout = draw.varyings;
  // Full stamps need no count (popcount is a libgcc call on baseline x86-64).
  const uint64_t full = m_stamp_pixels == 64 ? ~uint64_t{0} : (uint64_t{1} << m_stamp_pixels) - 1;
  size_t n = 0;
  for (const Stamp& s : batch.stamps) {
    n += s.mask == full ? static_cast<size_t>(m_stamp_pixels)
                        : static_cast<size_t>(__builtin_popcountll(s.mask));
  }
  if (st.shading == Shading::flat) {
    // Every pixel takes the provoking vertex's varyings; the ROP its colour.
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
  const EdgeValue *o0 = m_offset[0].data(), *o1 = m_offset[1].data(), *o2 = m_offset[2].data();
  const std::array<float, 3>& q = prim.inv_w;
  const float* vw0 = prim.varyings_over_w[0].data();
  const float* vw1 = prim.varyings_over_w[1].data();
  const float* vw2 = prim.varyings_over_w[2].data();
  const unsigned color = layout.color;
#if defined(__SSE2__)
  // Four components in the four lanes of one register, a group at a time
  // over the draw's groups (components past `count` in the last group are 0
  // in the packet and their results unused): each lane performs the spec's
  // operations in the spec's order (IEEE single, no contraction), so the
  // results equal the scalar ones bit for bit. clamp01 is min(max(v, 0), 1)
  // with maxps/minps taking the second operand when the first is NaN:
  // NaN -> 0, -0 -> +0, as clamp01.
  const unsigned group_end = layout.groups() * kVaryingGroup;
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
#else
  const unsigned count = layout.count;
#endif
  alignas(16) Varyings v;  // the pixel's varyings
  for (const Stamp& s : batch.stamps) {
    const EdgeValue e0 = s.e[0], e1 = s.e[1], e2 = s.e[2];
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1) {
      const int idx = __builtin_ctzll(bits);
      const float f0 = static_cast<float>(e0 + o0[idx]);
      const float f1 = static_cast<float>(e1 + o1[idx]);
      const float f2 = static_cast<float>(e2 + o2[idx]);
      const float den = f0 * q[0] + f1 * q[1] + f2 * q[2];
#if defined(__SSE2__)
      const __m128 m0 = _mm_set1_ps(f0), m1 = _mm_set1_ps(f1), m2 = _mm_set1_ps(f2);
      const __m128 d = _mm_set1_ps(den);
      for (unsigned g = 0; g < group_end; g += kVaryingGroup) {
        const __m128 num = _mm_add_ps(_mm_add_ps(_mm_mul_ps(m0, _mm_loadu_ps(vw0 + g)),
                                                 _mm_mul_ps(m1, _mm_loadu_ps(vw1 + g))),
                                      _mm_mul_ps(m2, _mm_loadu_ps(vw2 + g)));
        _mm_store_ps(&v[g], _mm_div_ps(num, d));
      }
      const __m128 c = _mm_loadu_ps(&v[color]);
      _mm_storeu_ps(&(*out)[0], _mm_min_ps(_mm_max_ps(c, zero), one));
#else
      for (unsigned k = 0; k < count; ++k) v[k] = (f0 * vw0[k] + f1 * vw1[k] + f2 * vw2[k]) / den;
      for (unsigned k = 0; k < kColorComponents; ++k) (*out)[k] = clamp01(v[color + k]);
#endif
      ++out;
    }
  }
}

}  // namespace gpusim
