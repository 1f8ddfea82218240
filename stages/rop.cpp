#include "stages/rop.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

#if defined(__SSE2__)
// The rgba8 path with every channel enabled, the four channels in the four
// lanes of one register. Each lane performs the spec's operations in the
// spec's order (IEEE single, no contraction), so every stored byte equals
// the scalar path's:
//   - decode: float(v) / 255 (cvtdq2ps, divps);
//   - factors: the scalar factor() values, one vector per factor;
//   - encode: nearbyint(clamp01(v) * 255). clamp01 is min(max(v, 0), 1):
//     maxps/minps return their second operand when the first is NaN, so
//     NaN -> 0 and -0 -> +0 as in clamp01. The product lies in [0, 255],
//     where (x + 2^23) - 2^23 rounds to the nearest integer, ties to even,
//     exactly as nearbyint in the default rounding mode; the result is an
//     integer, converted exactly.
__m128 factor_vec(BlendFactor f, __m128 s, __m128 d, const glm::vec4& sv, float dw) {
  switch (f) {
    case BlendFactor::zero:
      return _mm_setzero_ps();
    case BlendFactor::one:
      return _mm_set1_ps(1.0f);
    case BlendFactor::src_color:
      return s;
    case BlendFactor::one_minus_src_color:
      return _mm_sub_ps(_mm_set1_ps(1.0f), s);
    case BlendFactor::dst_color:
      return d;
    case BlendFactor::one_minus_dst_color:
      return _mm_sub_ps(_mm_set1_ps(1.0f), d);
    case BlendFactor::src_alpha:
      return _mm_set1_ps(sv.w);
    case BlendFactor::one_minus_src_alpha:
      return _mm_set1_ps(1.0f - sv.w);
    case BlendFactor::dst_alpha:
      return _mm_set1_ps(dw);
    case BlendFactor::one_minus_dst_alpha:
      return _mm_set1_ps(1.0f - dw);
    case BlendFactor::src_alpha_saturate: {
      const float m = std::min(sv.w, 1.0f - dw);
      return _mm_setr_ps(m, m, m, 1.0f);
    }
  }
  return _mm_setzero_ps();
}

__m128 load_rgba8(const uint8_t* stored) {
  uint32_t packed;
  std::memcpy(&packed, stored, 4);
  const __m128i zero = _mm_setzero_si128();
  const __m128i bytes = _mm_cvtsi32_si128(static_cast<int>(packed));
  const __m128i words = _mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, zero), zero);
  return _mm_div_ps(_mm_cvtepi32_ps(words), _mm_set1_ps(255.0f));
}

void store_rgba8(__m128 v, uint8_t* stored) {
  const __m128 magic = _mm_set1_ps(8388608.0f);  // 2^23
  const __m128 c = _mm_min_ps(_mm_max_ps(v, _mm_setzero_ps()), _mm_set1_ps(1.0f));
  const __m128 r = _mm_sub_ps(_mm_add_ps(_mm_mul_ps(c, _mm_set1_ps(255.0f)), magic), magic);
  const __m128i q = _mm_cvttps_epi32(r);
  const __m128i b8 = _mm_packus_epi16(_mm_packs_epi32(q, q), _mm_setzero_si128());
  const uint32_t out = static_cast<uint32_t>(_mm_cvtsi128_si32(b8));
  std::memcpy(stored, &out, 4);
}

// Any blend state, the factors switched per pixel.
void blend_rgba8(const RenderState& st, const glm::vec4& src, uint8_t* stored) {
  const __m128 s = _mm_loadu_ps(&src[0]);
  const __m128 d = load_rgba8(stored);
  const float dw = _mm_cvtss_f32(_mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 3, 3, 3)));
  const __m128 a = _mm_mul_ps(s, factor_vec(st.blend_src, s, d, src, dw));
  const __m128 b = _mm_mul_ps(d, factor_vec(st.blend_dst, s, d, src, dw));
  __m128 v = s;
  switch (st.blend_equation) {
    case BlendEquation::add:
      v = _mm_add_ps(a, b);
      break;
    case BlendEquation::subtract:
      v = _mm_sub_ps(a, b);
      break;
    case BlendEquation::reverse_subtract:
      v = _mm_sub_ps(b, a);
      break;
  }
  store_rgba8(v, stored);
}

// The usual transparency state: s * s.a + d * (1 - s.a).
void blend_rgba8_alpha(const glm::vec4& src, uint8_t* stored) {
  const __m128 s = _mm_loadu_ps(&src[0]);
  const __m128 d = load_rgba8(stored);
  const __m128 a = _mm_mul_ps(s, _mm_set1_ps(src.w));
  const __m128 b = _mm_mul_ps(d, _mm_set1_ps(1.0f - src.w));
  store_rgba8(_mm_add_ps(a, b), stored);
}
#endif

}  // namespace

namespace {

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  const ConservationLedger::Frame& f = l.frame();
  // Retires every token, or with a resolve after it passes the control
  // tokens on; writes at most the pixels it received.
  const std::string ip = l.upstream("interpolator");
  if (l.outputs().empty()) {
    l.equal("tokens_out", l.get("tokens_out"), "tokens_in", l.get("tokens_in"));
  } else {
    l.equal("tokens_out", l.get("tokens_out"), "control tokens", f.control);
  }
  l.equal("stamps", l.get("stamps"), ip + ".stamps", l.stage(ip, "stamps"));
  l.equal("fragments_in", l.get("fragments_in"), ip + ".fragments", l.stage(ip, "fragments"));
  l.at_most("fragments_written", l.get("fragments_written"), "fragments_in", l.get("fragments_in"));
  l.equal("frames", l.get("frames"), "frames run", 1);
  l.equal("color_clears", l.get("color_clears"), "colour clears in the frame", f.color_clears);
  l.at_most("samples_written", l.get("samples_written"), "fragments_written x 16",
            16 * l.get("fragments_written"));
  l.at_most("fragments_written", l.get("fragments_written"), "samples_written",
            l.get("samples_written"));
}

}  // namespace

const StageSpec& Rop::spec() {
  static const StageSpec s{
      "rop",
      StagePlacement::per_unit,
      /*optional=*/false,
      {/*ii=*/1, /*latency=*/4},
      "stamp",
      "blend and colour mask; reading and writing colour go through the memory",
      "shaded batches and control tokens read",
      "tokens retired (their writes done or posted)",
      {"interpolator_to_rop"},
      &conserve,
      StageTrace{TraceItem::stamp_batch, {"", "", ""}, FragmentSite::write},
      {{"", "`ii` × stamps + memory stall",
        "Like the depth test; at end of frame it reports the unit done when its write-back "
        "completes (with a resolve: it passes the token to the resolve instead)."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(Rop);

Rop::Rop(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
         unsigned unit)
    : PipelineStage(name, spec(), static_cast<int>(unit), config, frame),
      in("in"),
      done("done"),
      mem("mem"),
      m_tile_shift(log2_side(config.tile_size)),
      m_stamp_shift(log2_side(config.stamp[0])),
      m_cache(mem, m_stats, config.tile_cache_entries) {
  SC_HAS_PROCESS(Rop);
  SC_THREAD(run);
}

void Rop::reset_state() {
  m_frame_done = false;
  m_clears_seen = 0;
  m_cache.reset();
  m_overwrite = false;
}

void Rop::run() {
  // The frame's registers are final once the simulation runs.
  const FramebufferDesc& fb = m_frame.framebuffer;
  TileCache::Layout layout;
  layout.base = m_frame.color_address;
  layout.width = fb.width;
  layout.height = fb.height;
  layout.bytes_per_pixel = color_bytes_per_pixel(fb.color_format) * fb.samples;
  layout.tile_size = m_config.tile_size;
  layout.units = m_config.units;
  layout.unit = m_unit;
  layout.set_surfaces(m_config, m_config.compression.colour);
  layout.codec_channels = 4;
  layout.codec_channel_bytes = color_bytes_per_pixel(fb.color_format) / 4;
  m_cache.configure(layout);
  attach_clock(mem);

  const unsigned bytes = color_bytes_per_pixel(fb.color_format);  // per sample
  // A stamp of N samples per pixel takes ceil(N / samples_per_pass) passes.
  const uint64_t passes = m_config.sample_passes(fb.samples);

  // Read into one packet object: the FIFO recycles its buffers (hw/fifo.h).
  ShadedStampBatch batch;
  for (;;) {
    receive(in, batch);
    m_frame_done = false;
    sc_core::sc_time t = sc_core::SC_ZERO_TIME;  // memory stall, local offset
    uint64_t cycles = m_cost.ii;
    switch (batch.kind) {
      case PacketKind::work:
        cycles = m_cost.ii * std::max<uint64_t>(batch.stamps.size(), 1) * passes;
        blend(batch, t);
        break;
      case PacketKind::clear: {
        const ClearState c = next_clear(m_clears_seen++);
        if (!c.color) break;                                 // a depth clear: nothing to do here
        std::vector<uint8_t> value(layout.bytes_per_pixel);  // every sample of a pixel
        const bool half = fb.color_format == ColorFormat::rgba16f;
        for (unsigned s = 0; s < fb.samples; ++s) {
          for (int k = 0; k < 4; ++k) {
            store_channel(value.data() + s * bytes, half, k,
                          encode_color(fb.color_format, c.color_value[k]));
          }
        }
        m_cache.clear(value.data());
        forget_last_writers();
        ++m_color_clears;
        break;
      }
      case PacketKind::end_of_frame:
        t = m_latency;
        m_cache.flush(t);
        m_clears_seen = 0;
        break;
    }
    uint64_t stall = (t.value() + m_cycle - 1) / m_cycle;
    // end_of_frame: the write-back overlaps the token's own ii.
    if (batch.kind == PacketKind::end_of_frame) stall = stall > cycles ? stall - cycles : 0;
    m_memory_stall_cycles += stall;
    work(cycles + stall);
    if (done.size() == 0) {
      retire();
    } else if (batch.kind != PacketKind::work) {
      // To the resolve, readable once this token's writes are done.
      emit_at(done, ControlToken{batch.kind}, local_time());
    }
    if (batch.kind == PacketKind::end_of_frame) {
      sync_with_kernel();  // the frame's end is seen at the kernel's time
      ++m_frames;
      m_frame_done = true;
      m_frame_done_event.notify(sc_core::SC_ZERO_TIME);
    }
  }
}

// Testbench instrumentation: the pixels of this unit's tiles were cleared, so
// no primitive wrote them since.
void Rop::forget_last_writers() {
  if (!m_last_writer) return;
  const FramebufferDesc& fb = m_frame.framebuffer;
  const int tile = static_cast<int>(m_config.tile_size);
  for (int y = 0; y < fb.height; ++y) {
    for (int x = 0; x < fb.width; ++x) {
      if (tile_owner(x / tile, y / tile, m_config.units) == static_cast<unsigned>(m_unit))
        (*m_last_writer)[static_cast<size_t>(y) * fb.width + x] = -1;
    }
  }
}

// A stamp's pixels outside the framebuffer are a model bug: checked once per
// stamp, and per pixel only for a stamp that reaches past the framebuffer.
void Rop::check_pixel(int x, int y, const FramebufferDesc& fb) const {
  if (x >= fb.width || y >= fb.height) {
    SC_REPORT_ERROR("gpusim/rop", (std::string(name()) + ": pixel (" + std::to_string(x) + ", " +
                                   std::to_string(y) + ") outside the framebuffer")
                                      .c_str());
  }
}

void Rop::blend(const ShadedStampBatch& batch, sc_core::sc_time& t) {
  const RasterPrimitive& tri = *batch.primitive;
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
  // Unblended with every channel enabled: no old colour read.
  m_overwrite = !st.blend && mask[0] && mask[1] && mask[2] && mask[3] &&
                m_cache.covers_tile(batch.stamps, batch.samples, fb.samples);
  size_t c = 0;  // colours consumed
#if defined(__SSE2__)
  // rgba8 with every channel enabled (the common case): one register per
  // pixel, the blend state's branches taken once per batch.
  if (!half && mask[0] && mask[1] && mask[2] && mask[3]) {
    if (!st.blend) {
      c = for_each_fragment(batch, t, probe, [](const glm::vec4& src, uint8_t* stored) {
        store_rgba8(_mm_loadu_ps(&src[0]), stored);
      });
    } else if (st.blend_src == BlendFactor::src_alpha &&
               st.blend_dst == BlendFactor::one_minus_src_alpha &&
               st.blend_equation == BlendEquation::add) {
      c = for_each_fragment(batch, t, probe, [](const glm::vec4& src, uint8_t* stored) {
        blend_rgba8_alpha(src, stored);
      });
    } else {
      c = for_each_fragment(batch, t, probe, [&st](const glm::vec4& src, uint8_t* stored) {
        blend_rgba8(st, src, stored);
      });
    }
  } else
#endif
  {
    c = for_each_fragment(batch, t, probe, [&](const glm::vec4& src, uint8_t* stored) {
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
    });
  }
  if (c != batch.colors.size()) {
    SC_REPORT_ERROR("gpusim/rop",
                    (std::string(name()) + ": more colours than covered pixels").c_str());
  }
  m_fragments_written += c;
  if (st.blend) m_fragments_blended += c;
}

// The walk over a batch's covered pixels, shared by every blend path:
// `write(colour, stored bytes)` is inlined into it (a lambda or function, not
// a std::function). Per stamp: the tile check, one cache lookup and the
// stamp origin's address; per pixel, a table lookup gives its bytes, and the
// framebuffer bounds are checked only for stamps reaching past it. Returns
// the number of colours consumed.
template <typename Write>
size_t Rop::for_each_fragment(const ShadedStampBatch& batch, sc_core::sc_time& t,
                              FragmentProbe* probe, Write&& write) {
  (void)probe;  // unused in a build without trace hooks
  const RasterPrimitive& tri = *batch.primitive;
  const FramebufferDesc& fb = m_frame.framebuffer;
  const ColorFormat format = fb.color_format;
  const bool half = format == ColorFormat::rgba16f;
  const unsigned stamp_w = m_config.stamp[0], stamp_h = m_config.stamp[1];
  const int tile = static_cast<int>(m_config.tile_size);
  const int w_mask = static_cast<int>(stamp_w - 1);
  const size_t sample_bytes = color_bytes_per_pixel(format);
  const size_t bpp = sample_bytes * fb.samples;  // a pixel's samples are adjacent
  // Byte offset of stamp pixel p from the stamp origin's inside a tile:
  // rows of the tile are tile_size pixels apart (TileCache::pixel()).
  std::array<size_t, 64> offset;
  for (int p = 0; p < static_cast<int>(stamp_w * stamp_h); ++p) {
    offset[static_cast<size_t>(p)] =
        (static_cast<size_t>(p >> m_stamp_shift) * static_cast<size_t>(tile) +
         static_cast<size_t>(p & w_mask)) *
        bpp;
  }
  std::vector<int64_t>* const last_writer = m_last_writer;
  const glm::vec4* const colors = batch.colors.data();
  const size_t n_colors = batch.colors.size();
  // Multisampled: the samples each colour goes to (none: the pixel's one).
  const uint16_t* const sample_masks = batch.samples.empty() ? nullptr : batch.samples.data();
  if (sample_masks != nullptr && batch.samples.size() != n_colors) {
    SC_REPORT_ERROR("gpusim/rop",
                    (std::string(name()) + ": a sample mask per colour expected").c_str());
  }
  uint64_t samples = 0;
  // Single-sampled, untraced, no last-writer record: a stamp inside the
  // framebuffer takes the loop without per-pixel checks below.
  const bool plain = sample_masks == nullptr && last_writer == nullptr && probe == nullptr;
  const unsigned stamp_pixels = stamp_w * stamp_h;
  const uint64_t full = stamp_pixels == 64 ? ~uint64_t{0} : (uint64_t{1} << stamp_pixels) - 1;

  size_t c = 0;  // index into batch.colors
  for (const Stamp& s : batch.stamps) {
    const int tx = s.x >> m_tile_shift, ty = s.y >> m_tile_shift;
    if (s.x < 0 || s.y < 0 || s.x - tx * tile + static_cast<int>(stamp_w) > tile ||
        s.y - ty * tile + static_cast<int>(stamp_h) > tile) {
      SC_REPORT_ERROR("gpusim/rop", (std::string(name()) + ": stamp at (" + std::to_string(s.x) +
                                     ", " + std::to_string(s.y) + ") is not inside one tile")
                                        .c_str());
    }
    const bool inside =
        s.x + static_cast<int>(stamp_w) <= fb.width && s.y + static_cast<int>(stamp_h) <= fb.height;
    const unsigned entry = m_cache.lookup(tx, ty, t, m_overwrite);
    m_cache.mark_dirty(entry);
    uint8_t* const origin = m_cache.pixel(entry, s.x, s.y);
    if (plain && inside) {
      // Nothing to check or record per pixel: the colour count once per stamp.
      const size_t covered = s.mask == full ? static_cast<size_t>(stamp_pixels)
                                            : static_cast<size_t>(__builtin_popcountll(s.mask));
      if (covered <= n_colors - c) {
        if (s.mask == full) {
          for (unsigned p = 0; p < stamp_pixels; ++p) write(colors[c + p], origin + offset[p]);
        } else {
          const glm::vec4* src = colors + c;
          for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1)
            write(*src++, origin + offset[static_cast<size_t>(__builtin_ctzll(bits))]);
        }
        c += covered;
        continue;
      }
    }
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1, ++c) {
      if (c >= n_colors) {
        SC_REPORT_ERROR("gpusim/rop",
                        (std::string(name()) + ": fewer colours than covered pixels").c_str());
      }
      const int idx = __builtin_ctzll(bits);
      if (!inside) check_pixel(s.x + (idx & w_mask), s.y + (idx >> m_stamp_shift), fb);
      uint8_t* stored = origin + offset[static_cast<size_t>(idx)];
      if (sample_masks == nullptr) {
        write(colors[c], stored);
      } else {
        const uint32_t covered = sample_masks[c];
        for (uint32_t m = covered; m != 0; m &= m - 1)
          write(colors[c], stored + static_cast<size_t>(__builtin_ctz(m)) * sample_bytes);
        samples += static_cast<uint64_t>(__builtin_popcount(covered));
        stored += static_cast<size_t>(__builtin_ctz(covered)) * sample_bytes;  // traced below
      }
      if (last_writer) {
        const int x = s.x + (idx & w_mask), y = s.y + (idx >> m_stamp_shift);
        (*last_writer)[static_cast<size_t>(y) * fb.width + x] = tri.primitive_id;
      }
      if constexpr (kTraceHooks) {
        if (probe) {
          const int x = s.x + (idx & w_mask), y = s.y + (idx >> m_stamp_shift);
          RopFragment f{x, y, tri.primitive_id, rop_written, {}};
          for (int k = 0; k < 4; ++k)
            f.value[k] = decode_color(format, load_channel(stored, half, k));
          probe->rop_wrote(m_unit, f);
        }
      }
    }
  }
  m_samples_written += sample_masks == nullptr ? c : samples;
  return c;
}

}  // namespace gpusim
