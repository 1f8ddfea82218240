#include "stages/interpolator.h"

#include <algorithm>
#include <array>

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
      m_stamp_shift(log2_side(config.stamp[0])) {
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
    result.colors.clear();
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

void Interpolator::shade(const StampBatch& batch, ShadedStampBatch& result) {
  const RasterTriangle& tri = *batch.triangle;
  const RenderState& st = m_frame.draws.at(tri.draw_id).state;
  if (st.shading == Shading::flat) {
    size_t n = 0;
    for (const Stamp& s : batch.stamps) n += static_cast<size_t>(__builtin_popcountll(s.mask));
    result.colors.assign(n, tri.flat_color);
    m_flat_fragments += n;
    return;
  }

  const unsigned stamp_w = m_config.stamp[0];
  std::array<EdgeValue, 3> step_x, step_y;
  for (int k = 0; k < 3; ++k) {
    step_x[k] = tri.edge[k].a * kSubpixelOne;
    step_y[k] = tri.edge[k].b * kSubpixelOne;
  }
  const std::array<float, 3>& q = tri.inv_w;
  const std::array<glm::vec4, 3>& cw = tri.color_over_w;
  for (const Stamp& s : batch.stamps) {
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1) {
      const int idx = __builtin_ctzll(bits);
      const int i = idx & static_cast<int>(stamp_w - 1), j = idx >> m_stamp_shift;
      const float f0 = static_cast<float>(s.e[0] + i * step_x[0] + j * step_y[0]);
      const float f1 = static_cast<float>(s.e[1] + i * step_x[1] + j * step_y[1]);
      const float f2 = static_cast<float>(s.e[2] + i * step_x[2] + j * step_y[2]);
      const float den = f0 * q[0] + f1 * q[1] + f2 * q[2];
      glm::vec4 c;
      for (int k = 0; k < 4; ++k) {
        const float num = f0 * cw[0][k] + f1 * cw[1][k] + f2 * cw[2][k];
        c[k] = clamp01(num / den);
      }
      result.colors.push_back(c);
    }
  }
}

}  // namespace gpusim
