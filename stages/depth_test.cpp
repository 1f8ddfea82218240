#include "stages/depth_test.h"

#include <algorithm>
#include <limits>
#include <string>

#include "hw/pixel_formats.h"

namespace gpusim {
namespace {

DepthValue load_depth(const uint8_t* p, unsigned bytes) {
  DepthValue v = DepthValue{p[0]} | DepthValue{p[1]} << 8;
  if (bytes == 4) v |= DepthValue{p[2]} << 16 | DepthValue{p[3]} << 24;
  return v;
}

void store_depth(uint8_t* p, unsigned bytes, DepthValue v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
  if (bytes == 4) {
    p[2] = static_cast<uint8_t>(v >> 16);
    p[3] = static_cast<uint8_t>(v >> 24);
  }
}

}  // namespace

DepthTest::DepthTest(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
                     unsigned unit)
    : sc_core::sc_module(name),
      in("in"),
      out("out"),
      mem("mem"),
      m_config(config),
      m_frame(frame),
      m_unit(unit),
      m_cost(config.stage("depth_test")),
      m_cycle(config.cycle().value()),
      m_latency(clock_cycles(m_cost.latency)),
      m_tile_shift(log2_side(config.tile_size)),
      m_stamp_shift(log2_side(config.stamp[0])),
      m_cache(mem, m_stats, config.tile_cache_entries) {
  SC_HAS_PROCESS(DepthTest);
  SC_THREAD(run);
}

uint64_t DepthTest::stall_cycles(const sc_core::sc_time& t) const {
  return (t.value() + m_cycle - 1) / m_cycle;
}

void DepthTest::run() {
  // The frame's registers are final once the simulation runs.
  const FramebufferDesc& fb = m_frame.framebuffer;
  TileCache::Layout layout;
  layout.base = m_frame.depth_address;
  layout.width = fb.width;
  layout.height = fb.height;
  layout.bytes_per_pixel = depth_bytes_per_pixel(fb.depth_format);
  layout.tile_size = m_config.tile_size;
  layout.units = m_config.units;
  layout.unit = m_unit;
  m_cache.configure(layout);

  // Read into and written from one packet object: the FIFOs recycle its
  // buffers (hw/fifo.h), so no batch allocates.
  StampBatch batch;
  for (;;) {
    in->read(batch);
    ++m_tokens_in;
    sc_core::sc_time t = sc_core::SC_ZERO_TIME;  // memory stall, local offset
    uint64_t cycles = m_cost.ii;
    sc_core::sc_time ready_after = m_latency;
    bool forward = true;
    switch (batch.kind) {
      case PacketKind::work:
        cycles = m_cost.ii * std::max<uint64_t>(batch.stamps.size(), 1);
        test(batch, t);
        forward = !batch.stamps.empty();
        break;
      case PacketKind::clear: {
        uint8_t value[4];
        store_depth(value, layout.bytes_per_pixel, encode_depth(fb.depth_format, fb.clear_depth));
        m_cache.clear(value);
        break;
      }
      case PacketKind::end_of_frame:
        t = ready_after;
        m_cache.flush(t);
        ready_after = sc_core::SC_ZERO_TIME;
        break;
    }
    uint64_t stall = stall_cycles(t);
    if (batch.kind == PacketKind::end_of_frame) {
      // The flush overlaps the token's own ii.
      stall = stall > cycles ? stall - cycles : 0;
    }
    m_memory_stall_cycles += stall;
    m_busy_cycles += cycles + stall;
    sc_core::wait(clock_cycles(cycles + stall));
    if (forward) {
      out->write(std::move(batch), sc_core::sc_time_stamp() + ready_after);
      ++m_tokens_out;
    }
  }
}

void DepthTest::test(StampBatch& batch, sc_core::sc_time& t) {
  const RasterTriangle& tri = *batch.triangle;
  const RenderState& st = m_frame.draws.at(tri.draw_id).state;
  const FramebufferDesc& fb = m_frame.framebuffer;
  const unsigned stamp_w = m_config.stamp[0];
  const int tile = static_cast<int>(m_config.tile_size);

  uint64_t fragments = 0;
  for (const Stamp& s : batch.stamps)
    fragments += static_cast<uint64_t>(__builtin_popcountll(s.mask));
  m_stamps += batch.stamps.size();
  m_fragments_in += fragments;

  // Tracing: the probe is read once per batch, so an untraced run pays one
  // branch per fragment (none in a build without trace hooks, where the
  // per-fragment call is compiled out and the probe stays null). Fragments
  // the fast paths below decide without computing z are reported with NaN
  // depths.
  FragmentProbe* const probe = m_probe;
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const auto report_untested = [&](uint8_t outcome) {
    for_each_covered_pixel(batch.stamps, stamp_w, m_stamp_shift, [&](int x, int y) {
      probe->depth_tested(m_unit, DepthFragment{x, y, tri.primitive_id, outcome, kNaN, kNaN, kNaN});
    });
  };

  // No stored value can change the outcome: no memory access.
  if (!st.depth_test || (st.depth_func == CompareFunc::always && !st.depth_write)) {
    m_fragments_passed += fragments;
    m_stamps_passed += batch.stamps.size();
    if (probe) report_untested(depth_untested);
    return;
  }
  if (st.depth_func == CompareFunc::never) {
    if (probe) report_untested(depth_failed);
    batch.stamps.clear();
    return;
  }

  const DepthFormat format = fb.depth_format;
  const unsigned bytes = depth_bytes_per_pixel(format);
  const float area = static_cast<float>(tri.area2);
  const float dz1 = tri.z[1] - tri.z[0], dz2 = tri.z[2] - tri.z[0];  // spec section 9
  // Steps of the edge functions by one pixel in x and in y.
  std::array<EdgeValue, 3> step_x, step_y;
  for (int k = 0; k < 3; ++k) {
    step_x[k] = tri.edge[k].a * kSubpixelOne;
    step_y[k] = tri.edge[k].b * kSubpixelOne;
  }

  size_t kept = 0;
  for (size_t n = 0; n < batch.stamps.size(); ++n) {
    Stamp s = batch.stamps[n];
    const int tx = s.x >> m_tile_shift, ty = s.y >> m_tile_shift;
    if (s.x < 0 || s.y < 0 || s.x - tx * tile + static_cast<int>(stamp_w) > tile ||
        s.y - ty * tile + static_cast<int>(m_config.stamp[1]) > tile) {
      SC_REPORT_ERROR("gpusim/depth_test",
                      (std::string(name()) + ": stamp at (" + std::to_string(s.x) + ", " +
                       std::to_string(s.y) + ") is not inside one tile")
                          .c_str());
    }
    const unsigned entry = m_cache.lookup(tx, ty, t);
    bool dirty = false;
    uint64_t passed = 0;
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1) {
      const int idx = __builtin_ctzll(bits);
      const int i = idx & static_cast<int>(stamp_w - 1), j = idx >> m_stamp_shift;
      const int x = s.x + i, y = s.y + j;
      if (x >= fb.width || y >= fb.height) {
        SC_REPORT_ERROR("gpusim/depth_test",
                        (std::string(name()) + ": pixel (" + std::to_string(x) + ", " +
                         std::to_string(y) + ") outside the framebuffer")
                            .c_str());
      }
      const float f1 = static_cast<float>(s.e[1] + i * step_x[1] + j * step_y[1]);
      const float f2 = static_cast<float>(s.e[2] + i * step_x[2] + j * step_y[2]);
      float z = tri.z[0] + (f1 * dz1 + f2 * dz2) / area;
      if (tri.has_depth_offset) z = z + tri.depth_offset;
      const DepthValue fragment = encode_depth(format, z);
      uint8_t* stored = m_cache.pixel(entry, x, y);
      const DepthValue old = load_depth(stored, bytes);
      const bool pass = depth_compare(st.depth_func, fragment, old);
      if constexpr (kTraceHooks) {
        if (probe) {
          const float value = decode_depth(format, fragment);
          probe->depth_tested(
              m_unit,
              DepthFragment{x, y, tri.primitive_id, pass ? depth_passed : depth_failed, value,
                            decode_depth(format, old), pass && st.depth_write ? value : kNaN});
        }
      }
      if (pass) {
        ++passed;
        if (st.depth_write) {
          store_depth(stored, bytes, fragment);
          dirty = true;
        }
      } else {
        s.mask &= ~(uint64_t{1} << idx);
      }
    }
    if (dirty) m_cache.mark_dirty(entry);
    m_fragments_passed += passed;
    if (s.mask != 0) batch.stamps[kept++] = s;
  }
  batch.stamps.resize(kept);
  m_stamps_passed += kept;
}

}  // namespace gpusim
