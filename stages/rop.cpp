#include "stages/rop.h"

#include <algorithm>
#include <array>
#include <limits>
#include <string>

#include "hw/pixel_formats.h"

namespace gpusim {
namespace {

// Channel k of a stored pixel, as ColorChannel (unorm8 value or half bits).
ColorChannel load_channel(const uint8_t* p, bool half, int k) {
  if (!half) return p[k];
  return static_cast<ColorChannel>(p[2 * k] | p[2 * k + 1] << 8);
}

void store_channel(uint8_t* p, bool half, int k, ColorChannel v) {
  if (!half) {
    p[k] = static_cast<uint8_t>(v);
  } else {
    p[2 * k] = static_cast<uint8_t>(v);
    p[2 * k + 1] = static_cast<uint8_t>(v >> 8);
  }
}

float factor(BlendFactor f, const glm::vec4& s, const glm::vec4& d, int k) {
  switch (f) {
    case BlendFactor::zero:
      return 0.0f;
    case BlendFactor::one:
      return 1.0f;
    case BlendFactor::src_color:
      return s[k];
    case BlendFactor::one_minus_src_color:
      return 1.0f - s[k];
    case BlendFactor::dst_color:
      return d[k];
    case BlendFactor::one_minus_dst_color:
      return 1.0f - d[k];
    case BlendFactor::src_alpha:
      return s.w;
    case BlendFactor::one_minus_src_alpha:
      return 1.0f - s.w;
    case BlendFactor::dst_alpha:
      return d.w;
    case BlendFactor::one_minus_dst_alpha:
      return 1.0f - d.w;
    case BlendFactor::src_alpha_saturate:
      return k < 3 ? std::min(s.w, 1.0f - d.w) : 1.0f;
  }
  return 0.0f;
}

}  // namespace

Rop::Rop(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
         unsigned unit)
    : sc_core::sc_module(name),
      in("in"),
      mem("mem"),
      m_config(config),
      m_frame(frame),
      m_unit(unit),
      m_cost(config.stage("rop")),
      m_cycle(config.cycle().value()),
      m_latency(clock_cycles(m_cost.latency)),
      m_tile_shift(log2_side(config.tile_size)),
      m_stamp_shift(log2_side(config.stamp[0])),
      m_cache(mem, m_stats, config.tile_cache_entries) {
  SC_HAS_PROCESS(Rop);
  SC_THREAD(run);
}

void Rop::run() {
  // The frame's registers are final once the simulation runs.
  const FramebufferDesc& fb = m_frame.framebuffer;
  TileCache::Layout layout;
  layout.base = m_frame.color_address;
  layout.width = fb.width;
  layout.height = fb.height;
  layout.bytes_per_pixel = color_bytes_per_pixel(fb.color_format);
  layout.tile_size = m_config.tile_size;
  layout.units = m_config.units;
  layout.unit = m_unit;
  m_cache.configure(layout);

  // Read into one packet object: the FIFO recycles its buffers (hw/fifo.h).
  ShadedStampBatch batch;
  for (;;) {
    in->read(batch);
    ++m_tokens_in;
    m_frame_done = false;
    sc_core::sc_time t = sc_core::SC_ZERO_TIME;  // memory stall, local offset
    uint64_t cycles = m_cost.ii;
    switch (batch.kind) {
      case PacketKind::work:
        cycles = m_cost.ii * std::max<uint64_t>(batch.stamps.size(), 1);
        blend(batch, t);
        break;
      case PacketKind::clear: {
        uint8_t value[8];
        const bool half = fb.color_format == ColorFormat::rgba16f;
        for (int k = 0; k < 4; ++k) {
          store_channel(value, half, k, encode_color(fb.color_format, fb.clear_color[k]));
        }
        m_cache.clear(value);
        break;
      }
      case PacketKind::end_of_frame:
        t = m_latency;
        m_cache.flush(t);
        break;
    }
    uint64_t stall = (t.value() + m_cycle - 1) / m_cycle;
    // end_of_frame: the write-back overlaps the token's own ii.
    if (batch.kind == PacketKind::end_of_frame) stall = stall > cycles ? stall - cycles : 0;
    m_memory_stall_cycles += stall;
    m_busy_cycles += cycles + stall;
    sc_core::wait(clock_cycles(cycles + stall));
    ++m_tokens_out;
    if (batch.kind == PacketKind::end_of_frame) {
      ++m_frames;
      m_frame_done = true;
      m_frame_done_event.notify(sc_core::SC_ZERO_TIME);
    }
  }
}

void Rop::blend(const ShadedStampBatch& batch, sc_core::sc_time& t) {
  const RasterTriangle& tri = *batch.triangle;
  const RenderState& st = m_frame.draws.at(tri.draw_id).state;
  const FramebufferDesc& fb = m_frame.framebuffer;
  m_stamps += batch.stamps.size();
  m_fragments_in += batch.colors.size();
  // Tracing: the probe is read once per batch (one branch per fragment when
  // none is set; none in a build without trace hooks, where it stays null).
  FragmentProbe* const probe = m_probe;
  const std::array<bool, 4>& mask = st.color_mask;
  if (!(mask[0] || mask[1] || mask[2] || mask[3])) {
    if (probe) {
      constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
      for_each_covered_pixel(batch.stamps, m_config.stamp[0], m_stamp_shift, [&](int x, int y) {
        probe->rop_wrote(m_unit,
                         RopFragment{x, y, tri.primitive_id, rop_masked, {kNaN, kNaN, kNaN, kNaN}});
      });
    }
    return;
  }

  const ColorFormat format = fb.color_format;
  const bool half = format == ColorFormat::rgba16f;
  const unsigned stamp_w = m_config.stamp[0];
  const int tile = static_cast<int>(m_config.tile_size);

  size_t c = 0;  // index into batch.colors
  for (const Stamp& s : batch.stamps) {
    const int tx = s.x >> m_tile_shift, ty = s.y >> m_tile_shift;
    if (s.x < 0 || s.y < 0 || s.x - tx * tile + static_cast<int>(stamp_w) > tile ||
        s.y - ty * tile + static_cast<int>(m_config.stamp[1]) > tile) {
      SC_REPORT_ERROR("gpusim/rop", (std::string(name()) + ": stamp at (" + std::to_string(s.x) +
                                     ", " + std::to_string(s.y) + ") is not inside one tile")
                                        .c_str());
    }
    const unsigned entry = m_cache.lookup(tx, ty, t);
    m_cache.mark_dirty(entry);
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1, ++c) {
      if (c >= batch.colors.size()) {
        SC_REPORT_ERROR("gpusim/rop",
                        (std::string(name()) + ": fewer colours than covered pixels").c_str());
      }
      const int idx = __builtin_ctzll(bits);
      const int x = s.x + (idx & static_cast<int>(stamp_w - 1)), y = s.y + (idx >> m_stamp_shift);
      if (x >= fb.width || y >= fb.height) {
        SC_REPORT_ERROR("gpusim/rop", (std::string(name()) + ": pixel (" + std::to_string(x) +
                                       ", " + std::to_string(y) + ") outside the framebuffer")
                                          .c_str());
      }
      const glm::vec4& src = batch.colors[c];
      uint8_t* stored = m_cache.pixel(entry, x, y);
      glm::vec4 dst(0.0f);
      if (st.blend) {
        for (int k = 0; k < 4; ++k) dst[k] = decode_color(format, load_channel(stored, half, k));
      }
      for (int k = 0; k < 4; ++k) {
        if (!mask[k]) continue;
        float v = src[k];
        if (st.blend) {
          const float a = src[k] * factor(st.blend_src, src, dst, k);
          const float b = dst[k] * factor(st.blend_dst, src, dst, k);
          switch (st.blend_equation) {
            case BlendEquation::add:
              v = a + b;
              break;
            case BlendEquation::subtract:
              v = a - b;
              break;
            case BlendEquation::reverse_subtract:
              v = b - a;
              break;
          }
        }
        // encode_color clamps rgba8; rgba16f keeps the value unclamped.
        store_channel(stored, half, k, encode_color(format, v));
      }
      if (m_last_writer) (*m_last_writer)[static_cast<size_t>(y) * fb.width + x] = tri.primitive_id;
      if constexpr (kTraceHooks) {
        if (probe) {
          RopFragment f{x, y, tri.primitive_id, rop_written, {}};
          for (int k = 0; k < 4; ++k)
            f.value[k] = decode_color(format, load_channel(stored, half, k));
          probe->rop_wrote(m_unit, f);
        }
      }
    }
  }
  if (c != batch.colors.size()) {
    SC_REPORT_ERROR("gpusim/rop",
                    (std::string(name()) + ": more colours than covered pixels").c_str());
  }
  m_fragments_written += c;
  if (st.blend) m_fragments_blended += c;
}

}  // namespace gpusim
