#include "stages/depth_test.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "hw/pixel_formats.h"
#include "hw/sample_pattern.h"

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

// encode_depth(F, z) for a format known at compile time. For the unorm
// formats, nearbyint(x) with x = double(clamp01(z)) * (2^n - 1) in [0, 2^24)
// is computed as (x + 2^52) - 2^52: the sum's ulp is 1, so it rounds x to the
// nearest integer, ties to even (the default rounding mode, which nearbyint
// also uses), and the difference is exact. Same value, without a libm call
// per fragment.
template <DepthFormat F>
DepthValue encode_depth_as(float z) {
  const float c = clamp01(z);
  if constexpr (F == DepthFormat::float32) {
    return bits_from_float(c);
  } else {
    constexpr double kRound = 4503599627370496.0;  // 2^52
    const double x = static_cast<double>(c) * unorm_depth_max(F);
    return static_cast<DepthValue>((x + kRound) - kRound);
  }
}

// test_stamps' template argument for "the render state's depth_func, read at
// run time": never is decided in test() without a loop, so it is free.
constexpr CompareFunc kAnyFunc = CompareFunc::never;

#if defined(__SSE2__)
constexpr uint8_t kBitCount4[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

// Four adjacent pixels of a stamp row in the four lanes of one register. Each
// lane performs the scalar path's operations in its order (IEEE single, no
// contraction; the int64 -> float conversions stay scalar, cvtsi2ss rounding
// as static_cast does), so every lane's value equals the scalar one bit for
// bit:
//   - clamp01 is min(max(z, 0), 1): maxps/minps return their second operand
//     when the first is NaN, so NaN -> 0 and -0 -> +0 as in clamp01;
//   - unorm: double(c) * (2^n - 1), then (x + 2^52) - 2^52 as in
//     encode_depth_as, converted exactly (an integer below 2^24);
//   - float32: the bits of c.
template <DepthFormat F>
__m128i encode_depth4(__m128 z) {
  const __m128 c = _mm_min_ps(_mm_max_ps(z, _mm_setzero_ps()), _mm_set1_ps(1.0f));
  if constexpr (F == DepthFormat::float32) {
    return _mm_castps_si128(c);
  } else {
    const __m128d max = _mm_set1_pd(unorm_depth_max(F));
    const __m128d round = _mm_set1_pd(4503599627370496.0);  // 2^52
    const __m128d lo = _mm_cvtps_pd(c), hi = _mm_cvtps_pd(_mm_movehl_ps(c, c));
    const __m128i qlo = _mm_cvttpd_epi32(_mm_sub_pd(_mm_add_pd(_mm_mul_pd(lo, max), round), round));
    const __m128i qhi = _mm_cvttpd_epi32(_mm_sub_pd(_mm_add_pd(_mm_mul_pd(hi, max), round), round));
    return _mm_unpacklo_epi64(qlo, qhi);
  }
}

// Four stored values, zero-extended to 32 bits, and back.
template <unsigned Bytes>
__m128i load_depth4(const uint8_t* p) {
  if constexpr (Bytes == 4) {
    return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
  } else {
    return _mm_unpacklo_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)),
                              _mm_setzero_si128());
  }
}

template <unsigned Bytes>
void store_depth4(uint8_t* p, __m128i v) {
  if constexpr (Bytes == 4) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(p), v);
  } else {
    // Sign-extending the low halves first makes packs_epi32 keep them as
    // they are (no saturation).
    const __m128i s = _mm_srai_epi32(_mm_slli_epi32(v, 16), 16);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(p), _mm_packs_epi32(s, s));
  }
}

// Lane mask of the 4 bits of m: lane i all ones iff bit i is set.
__m128i lane_mask(unsigned m) {
  const __m128i bit = _mm_setr_epi32(1, 2, 4, 8);
  return _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(static_cast<int>(m)), bit), bit);
}

// fragment func stored, per lane, as unsigned 32-bit integers (depth_compare):
// the sign bit flipped on both sides turns signed compares into unsigned ones.
template <CompareFunc Func>
__m128i depth_compare4(__m128i fragment, __m128i stored) {
  static_assert(Func == CompareFunc::less || Func == CompareFunc::lequal, "less or lequal");
  const __m128i sign = _mm_set1_epi32(static_cast<int>(0x80000000u));
  const __m128i f = _mm_xor_si128(fragment, sign), s = _mm_xor_si128(stored, sign);
  if constexpr (Func == CompareFunc::less) {
    return _mm_cmplt_epi32(f, s);
  } else {
    return _mm_andnot_si128(_mm_cmpgt_epi32(f, s), _mm_set1_epi32(-1));
  }
}
#endif

}  // namespace

namespace {

// Why a primitive whose last record is here went no further (traces).
constexpr const char* kFailed = "every fragment failed the depth test";

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  const ConservationLedger::Frame& f = l.frame();
  // Stamps and pixels in are the rasterizer's; the ones that fail are
  // dropped, so at most as many pass.
  const std::string tr = l.upstream("tile_rasterizer");
  l.equal("stamps", l.get("stamps"), tr + ".stamps_emitted", l.stage(tr, "stamps_emitted"));
  l.equal("fragments_in", l.get("fragments_in"), tr + ".fragments", l.stage(tr, "fragments"));
  l.at_most("fragments_passed", l.get("fragments_passed"), "fragments_in", l.get("fragments_in"));
  l.at_most("stamps_passed", l.get("stamps_passed"), "stamps", l.get("stamps"));
  // Every unit executes every depth clear on its own tiles.
  l.equal("depth_clears", l.get("depth_clears"), "depth clears in the frame", f.depth_clears);
  l.at_most("tokens_out", l.get("tokens_out"), "tokens_in", l.get("tokens_in"));
  l.at_most("control tokens", f.control, "tokens_out", l.get("tokens_out"));
}

}  // namespace

const StageSpec& DepthTest::spec() {
  static const StageSpec s{
      "depth_test",
      StagePlacement::per_unit,
      /*optional=*/false,
      {/*ii=*/1, /*latency=*/2},
      "stamp",
      "compare and merge; reading and writing depth go through the memory",
      "stamp batches and control tokens read",
      "stamp batches and control tokens forwarded",
      {"rasterizer_to_depth"},
      &conserve,
      StageTrace{TraceItem::stamp_batch, {kFailed, kFailed, kFailed}, FragmentSite::test},
      {{"", "`ii` × stamps + memory stall",
        "Blocking tile cache: misses are served one after another. At end of frame, the write-back "
        "starts `latency` after the token and the token leaves when it is done."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(DepthTest);

DepthTest::DepthTest(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
                     unsigned unit)
    : PipelineStage(name, spec(), static_cast<int>(unit), config, frame),
      in("in"),
      out("out"),
      mem("mem"),
      m_tile_shift(log2_side(config.tile_size)),
      m_stamp_shift(log2_side(config.stamp[0])),
      m_cache(mem, m_stats, config.tile_cache_entries) {
  SC_HAS_PROCESS(DepthTest);
  SC_THREAD(run);
}

uint64_t DepthTest::stall_cycles(const sc_core::sc_time& t) const {
  return (t.value() + m_cycle - 1) / m_cycle;
}

void DepthTest::reset_state() {
  m_offset = {};
  m_step_x = m_step_y = {};
  m_offset_valid = false;
  m_pixel_offset = {};
  m_clears_seen = 0;
  m_hz_epoch = 0;
  m_tiles_x = m_stamps_x = m_stamps_per_tile = 0;
  m_hz_stamp.clear();
  m_hz_known.clear();
  m_hz_entry = 0;
  m_hz_written.clear();
  m_cache.reset();
  m_overwrite = false;
}

void DepthTest::run() {
  // The frame's registers are final once the simulation runs.
  const FramebufferDesc& fb = m_frame.framebuffer;
  TileCache::Layout layout;
  layout.base = m_frame.depth_address;
  layout.width = fb.width;
  layout.height = fb.height;
  layout.bytes_per_pixel = depth_bytes_per_pixel(fb.depth_format) * fb.samples;
  layout.tile_size = m_config.tile_size;
  layout.units = m_config.units;
  layout.unit = m_unit;
  layout.set_surfaces(m_config, m_config.compression.depth);
  layout.codec_channel_bytes = depth_bytes_per_pixel(fb.depth_format);
  m_cache.configure(layout);
  attach_clock(mem);
  // Byte offset of stamp pixel p from the stamp origin's inside a tile (rows
  // of a tile are tile_size pixels apart, TileCache::pixel()).
  const unsigned stamp_w = m_config.stamp[0];
  for (unsigned p = 0; p < stamp_w * m_config.stamp[1]; ++p) {
    m_pixel_offset[p] =
        (static_cast<size_t>(p >> m_stamp_shift) * m_config.tile_size + (p & (stamp_w - 1))) *
        layout.bytes_per_pixel;
  }

  if (m_hz_link != nullptr) {
    if (decoupled()) m_hz_link->set_writer_clock(&local_clock());
    m_tiles_x = (fb.width + static_cast<int>(m_config.tile_size) - 1) >> m_tile_shift;
    const int tiles_y = (fb.height + static_cast<int>(m_config.tile_size) - 1) >> m_tile_shift;
    m_stamps_x = static_cast<int>(m_config.tile_size / m_config.stamp[0]);
    m_stamps_per_tile = m_stamps_x * static_cast<int>(m_config.tile_size / m_config.stamp[1]);
    m_hz_stamp.resize(static_cast<size_t>(m_tiles_x) * tiles_y * m_stamps_per_tile);
    m_hz_known.assign(static_cast<size_t>(m_tiles_x) * tiles_y, 0);
  }

  // Read into and written from one packet object: the FIFOs recycle its
  // buffers (hw/fifo.h), so no batch allocates.
  StampBatch batch;
  for (;;) {
    receive(in, batch);
    sc_core::sc_time t = sc_core::SC_ZERO_TIME;  // memory stall, local offset
    uint64_t cycles = m_cost.ii;
    sc_core::sc_time ready_after = m_latency;
    bool forward = true;
    int hz_tile = -1;
    uint32_t hz_seq = 0;
    switch (batch.kind) {
      case PacketKind::work:
        cycles = m_cost.ii * std::max<uint64_t>(batch.stamps.size(), 1) *
                 m_config.sample_passes(fb.samples);
        if (batch.hz_seq != 0 && m_hz_link != nullptr) {
          hz_seq = batch.hz_seq;
          hz_tile =
              (batch.stamps[0].y >> m_tile_shift) * m_tiles_x + (batch.stamps[0].x >> m_tile_shift);
          m_hz_written.clear();
        }
        test(batch, t);
        forward = !batch.stamps.empty();
        break;
      case PacketKind::clear: {
        const ClearState c = next_clear(m_clears_seen++);
        if (!c.depth) break;                                 // a colour clear: only forwarded
        std::vector<uint8_t> value(layout.bytes_per_pixel);  // every sample of a pixel
        const unsigned bytes = depth_bytes_per_pixel(fb.depth_format);
        for (unsigned s = 0; s < fb.samples; ++s) {
          store_depth(value.data() + s * bytes, bytes,
                      encode_depth(fb.depth_format, c.depth_value));
        }
        m_cache.clear(value.data());
        ++m_depth_clears;
        ++m_hz_epoch;
        break;
      }
      case PacketKind::end_of_frame:
        t = ready_after;
        m_cache.flush(t);
        ready_after = sc_core::SC_ZERO_TIME;
        m_clears_seen = 0;
        ++m_hz_epoch;
        break;
    }
    uint64_t stall = stall_cycles(t);
    if (batch.kind == PacketKind::end_of_frame) {
      // The flush overlaps the token's own ii.
      stall = stall > cycles ? stall - cycles : 0;
    }
    m_memory_stall_cycles += stall;
    work(cycles + stall);
    if (hz_seq != 0) {
      // The tile's exact range leaves when the batch is done; the reduction
      // over the stamp ranges is off the batch's path (no cycles).
      m_hz_link->send(HzUpdate{local_time(), static_cast<uint32_t>(hz_tile), hz_seq, m_hz_epoch,
                               hz_tile_range(hz_tile, m_hz_entry)});
      ++m_hz_updates_sent;
    }
    if (forward) emit_at(out, std::move(batch), local_time() + ready_after);
  }
}

void DepthTest::test(StampBatch& batch, sc_core::sc_time& t) {
  const RasterPrimitive& tri = *batch.primitive;
  const RenderState& st = m_frame.draws.at(tri.draw_id).state;
  const FramebufferDesc& fb = m_frame.framebuffer;
  const unsigned stamp_w = m_config.stamp[0];

  // Full stamps need no count (popcount is a libgcc call on baseline x86-64).
  const unsigned stamp_pixels = stamp_w * m_config.stamp[1];
  const uint64_t full = stamp_pixels == 64 ? ~uint64_t{0} : (uint64_t{1} << stamp_pixels) - 1;
  uint64_t fragments = 0;
  for (const Stamp& s : batch.stamps)
    fragments +=
        s.mask == full ? stamp_pixels : static_cast<uint64_t>(__builtin_popcountll(s.mask));
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
    uint64_t samples = fragments;
    if (!batch.samples.empty()) {
      samples = 0;
      for (const uint16_t m : batch.samples)
        samples += static_cast<uint64_t>(__builtin_popcount(m));
    }
    m_samples_passed += samples;
    m_stamps_passed += batch.stamps.size();
    if (probe) report_untested(depth_untested);
    return;
  }
  if (st.depth_func == CompareFunc::never) {
    if (probe) report_untested(depth_failed);
    batch.stamps.clear();
    batch.samples.clear();
    return;
  }

  // always with writes: every covered sample is written, no old value read.
  m_overwrite = st.depth_func == CompareFunc::always && st.depth_write &&
                m_cache.covers_tile(batch.stamps, batch.samples, fb.samples);
  if (fb.samples > 1) {
    switch (fb.depth_format) {
      case DepthFormat::unorm16:
        test_samples<DepthFormat::unorm16>(batch, t, st, probe);
        break;
      case DepthFormat::unorm24:
        test_samples<DepthFormat::unorm24>(batch, t, st, probe);
        break;
      case DepthFormat::float32:
        test_samples<DepthFormat::float32>(batch, t, st, probe);
        break;
    }
    return;
  }
  switch (fb.depth_format) {
    case DepthFormat::unorm16:
      test_format<DepthFormat::unorm16>(batch, t, st, probe);
      break;
    case DepthFormat::unorm24:
      test_format<DepthFormat::unorm24>(batch, t, st, probe);
      break;
    case DepthFormat::float32:
      test_format<DepthFormat::float32>(batch, t, st, probe);
      break;
  }
}

// The usual functions (less, GL's default, and lequal) get loops of their own
// with the comparison fixed; the others share one that switches per fragment.
template <DepthFormat F>
void DepthTest::test_format(StampBatch& batch, sc_core::sc_time& t, const RenderState& st,
                            FragmentProbe* probe) {
  switch (st.depth_func) {
    case CompareFunc::less:
      test_stamps<F, CompareFunc::less>(batch, t, st, probe);
      break;
    case CompareFunc::lequal:
      test_stamps<F, CompareFunc::lequal>(batch, t, st, probe);
      break;
    default:
      test_stamps<F, kAnyFunc>(batch, t, st, probe);
      break;
  }
}

void DepthTest::update_offsets(const RasterPrimitive& tri) {
  std::array<EdgeValue, 2> step_x, step_y;
  for (int k = 0; k < 2; ++k) {
    step_x[k] = tri.edge[k + 1].a * kSubpixelOne;
    step_y[k] = tri.edge[k + 1].b * kSubpixelOne;
  }
  // Consecutive batches are mostly one triangle's tiles: the table is kept
  // while the steps are the same (compared by value, not by triangle, so a
  // new triangle at a recycled address cannot reuse a stale table).
  if (m_offset_valid && step_x == m_step_x && step_y == m_step_y) return;
  m_step_x = step_x;
  m_step_y = step_y;
  const int stamp_pixels = static_cast<int>(m_config.stamp[0] * m_config.stamp[1]);
  const int w_mask = static_cast<int>(m_config.stamp[0] - 1);
  for (int p = 0; p < stamp_pixels; ++p) {
    const EdgeValue i = p & w_mask, j = p >> m_stamp_shift;
    for (int k = 0; k < 2; ++k) m_offset[k][static_cast<size_t>(p)] = i * step_x[k] + j * step_y[k];
  }
  m_offset_valid = true;
}

// The per-fragment loop for one depth format (a compile-time constant, so the
// encoding and the buffer access are specialised). Setup is hoisted out of the
// loop: E1 and E2 at pixel p are the stamp origin's plus m_offset (the same
// exact int64 sums as stepping), the pixel's bytes are at a per-stamp origin
// plus m_pixel_offset, and the framebuffer bounds are checked per pixel only
// for stamps reaching past it. The float operations are the spec's, in order.
template <DepthFormat F, CompareFunc Func>
void DepthTest::test_stamps(StampBatch& batch, sc_core::sc_time& t, const RenderState& st,
                            FragmentProbe* probe) {
  constexpr unsigned bytes = F == DepthFormat::unorm16 ? 2 : 4;
  [[maybe_unused]] constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  (void)probe;  // unused in a build without trace hooks
  const RasterPrimitive& tri = *batch.primitive;
  const FramebufferDesc& fb = m_frame.framebuffer;
  const unsigned stamp_w = m_config.stamp[0], stamp_h = m_config.stamp[1];
  const int tile = static_cast<int>(m_config.tile_size);
  const int w_mask = static_cast<int>(stamp_w - 1);
  const CompareFunc func = st.depth_func;
  const bool depth_write = st.depth_write;
  const bool has_offset = tri.has_depth_offset;
  const float z0 = tri.z[0], depth_offset = tri.depth_offset;
  const float area = static_cast<float>(tri.area2);
  const float dz1 = tri.z[1] - tri.z[0], dz2 = tri.z[2] - tri.z[0];  // spec section 9
  update_offsets(tri);
  const EdgeValue *o1 = m_offset[0].data(), *o2 = m_offset[1].data();
  [[maybe_unused]] const unsigned stamp_pixels = stamp_w * stamp_h;
  [[maybe_unused]] const bool rows_of_4 = stamp_w % 4 == 0;

  size_t kept = 0;
  for (size_t n = 0; n < batch.stamps.size(); ++n) {
    Stamp s = batch.stamps[n];
    const int tx = s.x >> m_tile_shift, ty = s.y >> m_tile_shift;
    if (s.x < 0 || s.y < 0 || s.x - tx * tile + static_cast<int>(stamp_w) > tile ||
        s.y - ty * tile + static_cast<int>(stamp_h) > tile) {
      SC_REPORT_ERROR("gpusim/depth_test",
                      (std::string(name()) + ": stamp at (" + std::to_string(s.x) + ", " +
                       std::to_string(s.y) + ") is not inside one tile")
                          .c_str());
    }
    const bool inside =
        s.x + static_cast<int>(stamp_w) <= fb.width && s.y + static_cast<int>(stamp_h) <= fb.height;
    const unsigned entry = m_cache.lookup(tx, ty, t, m_overwrite);
    m_hz_entry = entry;  // a batch's stamps share one tile, so one entry
    uint8_t* const origin = m_cache.pixel(entry, s.x, s.y);
    bool dirty = false;
    uint64_t passed = 0;
    bool vector_done = false;  // the stamp was tested four pixels at a time
#if defined(__SSE2__)
    // less and lequal, stamp rows of a multiple of 4 pixels (each group of
    // four lies in one row, adjacent in the tile), inside the framebuffer and
    // untraced: four pixels per register, uncovered lanes computed but
    // neither counted nor stored.
    if constexpr (Func != kAnyFunc) {
      if (rows_of_4 && inside && probe == nullptr) {
        const __m128 vz0 = _mm_set1_ps(z0), voffset = _mm_set1_ps(depth_offset);
        const __m128 vdz1 = _mm_set1_ps(dz1), vdz2 = _mm_set1_ps(dz2), varea = _mm_set1_ps(area);
        const EdgeValue e1 = s.e[1], e2 = s.e[2];
        uint64_t kept_mask = 0;
        for (unsigned p = 0; p < stamp_pixels; p += 4) {
          const unsigned covered = static_cast<unsigned>(s.mask >> p) & 15u;
          if (covered == 0) continue;
          const __m128 f1 =
              _mm_setr_ps(static_cast<float>(e1 + o1[p]), static_cast<float>(e1 + o1[p + 1]),
                          static_cast<float>(e1 + o1[p + 2]), static_cast<float>(e1 + o1[p + 3]));
          const __m128 f2 =
              _mm_setr_ps(static_cast<float>(e2 + o2[p]), static_cast<float>(e2 + o2[p + 1]),
                          static_cast<float>(e2 + o2[p + 2]), static_cast<float>(e2 + o2[p + 3]));
          __m128 z = _mm_add_ps(
              vz0, _mm_div_ps(_mm_add_ps(_mm_mul_ps(f1, vdz1), _mm_mul_ps(f2, vdz2)), varea));
          if (has_offset) z = _mm_add_ps(z, voffset);
          const __m128i fragment = encode_depth4<F>(z);
          uint8_t* const stored = origin + m_pixel_offset[p];
          const __m128i old = load_depth4<bytes>(stored);
          const unsigned pass = static_cast<unsigned>(_mm_movemask_ps(
                                    _mm_castsi128_ps(depth_compare4<Func>(fragment, old)))) &
                                covered;
          kept_mask |= uint64_t{pass} << p;
          passed += kBitCount4[pass];
          if (pass != 0 && depth_write) {
            const __m128i m = lane_mask(pass);
            store_depth4<bytes>(stored,
                                _mm_or_si128(_mm_and_si128(m, fragment), _mm_andnot_si128(m, old)));
            dirty = true;
          }
        }
        s.mask = kept_mask;
        vector_done = true;
      }
    }
#endif
    for (uint64_t bits = vector_done ? 0 : s.mask; bits != 0; bits &= bits - 1) {
      const int idx = __builtin_ctzll(bits);
      // The pixel's coordinates, needed only off the fast path.
      const auto pixel_x = [&] { return s.x + (idx & w_mask); };
      const auto pixel_y = [&] { return s.y + (idx >> m_stamp_shift); };
      if (!inside && (pixel_x() >= fb.width || pixel_y() >= fb.height)) {
        SC_REPORT_ERROR("gpusim/depth_test",
                        (std::string(name()) + ": pixel (" + std::to_string(pixel_x()) + ", " +
                         std::to_string(pixel_y()) + ") outside the framebuffer")
                            .c_str());
      }
      const float f1 = static_cast<float>(s.e[1] + o1[idx]);
      const float f2 = static_cast<float>(s.e[2] + o2[idx]);
      float z = z0 + (f1 * dz1 + f2 * dz2) / area;
      if (has_offset) z = z + depth_offset;
      const DepthValue fragment = encode_depth_as<F>(z);
      uint8_t* stored = origin + m_pixel_offset[static_cast<size_t>(idx)];
      const DepthValue old = load_depth(stored, bytes);
      const bool pass = depth_compare(Func == kAnyFunc ? func : Func, fragment, old);
      if constexpr (kTraceHooks) {
        if (probe) {
          const float value = decode_depth(F, fragment);
          probe->depth_tested(
              m_unit, DepthFragment{pixel_x(), pixel_y(), tri.primitive_id,
                                    pass ? depth_passed : depth_failed, value, decode_depth(F, old),
                                    pass && depth_write ? value : kNaN});
        }
      }
      if (pass) {
        ++passed;
        if (depth_write) {
          store_depth(stored, bytes, fragment);
          dirty = true;
        }
      } else {
        s.mask &= ~(uint64_t{1} << idx);
      }
    }
    if (dirty) {
      m_cache.mark_dirty(entry);
      if (m_hz_link != nullptr) hz_note(s.x, s.y);
    }
    m_fragments_passed += passed;
    m_samples_passed += passed;
    if (s.mask != 0) batch.stamps[kept++] = s;
  }
  batch.stamps.resize(kept);
  m_stamps_passed += kept;
}

template <DepthFormat F>
void DepthTest::test_samples(StampBatch& batch, sc_core::sc_time& t, const RenderState& st,
                             FragmentProbe* probe) {
  constexpr unsigned bytes = F == DepthFormat::unorm16 ? 2 : 4;  // per sample
  (void)probe;  // unused in a build without trace hooks
  const RasterPrimitive& tri = *batch.primitive;
  const FramebufferDesc& fb = m_frame.framebuffer;
  const unsigned samples = fb.samples;
  const int w_mask = static_cast<int>(m_config.stamp[0] - 1);
  const float z0 = tri.z[0];
  const float area = static_cast<float>(tri.area2);
  const float dz1 = tri.z[1] - tri.z[0], dz2 = tri.z[2] - tri.z[0];  // spec section 9
  update_offsets(tri);
  const EdgeValue *o1 = m_offset[0].data(), *o2 = m_offset[1].data();
  // E1 and E2 from the pixel centre to each sample point.
  std::array<EdgeValue, 16> s1{}, s2{};
  for (unsigned s = 0; s < samples; ++s) {
    const SampleOffset o = sample_offset(samples, s);
    s1[s] = tri.edge[1].a * o.dx + tri.edge[1].b * o.dy;
    s2[s] = tri.edge[2].a * o.dx + tri.edge[2].b * o.dy;
  }
  if (batch.samples.empty() && !batch.stamps.empty()) {
    SC_REPORT_ERROR("gpusim/depth_test",
                    (std::string(name()) + ": a multisampled batch without sample masks").c_str());
  }

  size_t kept = 0, in = 0, out = 0;  // stamps kept; sample masks read and kept
  for (size_t n = 0; n < batch.stamps.size(); ++n) {
    Stamp s = batch.stamps[n];
    const unsigned entry = m_cache.lookup(s.x >> m_tile_shift, s.y >> m_tile_shift, t, m_overwrite);
    m_hz_entry = entry;
    uint8_t* const origin = m_cache.pixel(entry, s.x, s.y);
    bool dirty = false;
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1) {
      const int idx = __builtin_ctzll(bits);
      const uint32_t covered = batch.samples[in++];
      uint8_t* const pixel = origin + m_pixel_offset[static_cast<size_t>(idx)];
      const EdgeValue e1 = s.e[1] + o1[idx], e2 = s.e[2] + o2[idx];
      uint32_t passed = 0;
      float first_z = 0.0f;
      DepthValue first_old = 0;
      for (uint32_t m = covered; m != 0; m &= m - 1) {
        const int k = __builtin_ctz(m);
        const float f1 = static_cast<float>(e1 + s1[static_cast<size_t>(k)]);
        const float f2 = static_cast<float>(e2 + s2[static_cast<size_t>(k)]);
        float z = z0 + (f1 * dz1 + f2 * dz2) / area;
        if (tri.has_depth_offset) z = z + tri.depth_offset;
        const DepthValue fragment = encode_depth_as<F>(z);
        uint8_t* stored = pixel + static_cast<size_t>(k) * bytes;
        const DepthValue old = load_depth(stored, bytes);
        if (m == covered) {
          first_z = decode_depth(F, fragment);
          first_old = old;
        }
        if (!depth_compare(st.depth_func, fragment, old)) continue;
        passed |= 1u << k;
        if (st.depth_write) {
          store_depth(stored, bytes, fragment);
          dirty = true;
        }
      }
      if constexpr (kTraceHooks) {
        if (probe) {
          // One record per pixel: its first covered sample's depths.
          constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
          probe->depth_tested(
              m_unit,
              DepthFragment{s.x + (idx & w_mask), s.y + (idx >> m_stamp_shift), tri.primitive_id,
                            passed ? depth_passed : depth_failed, first_z,
                            decode_depth(F, first_old), passed && st.depth_write ? first_z : kNaN});
        }
      }
      if (passed == 0) {
        s.mask &= ~(uint64_t{1} << idx);
        continue;
      }
      batch.samples[out++] = static_cast<uint16_t>(passed);
      ++m_fragments_passed;
      m_samples_passed += static_cast<uint64_t>(__builtin_popcount(passed));
    }
    if (dirty) {
      m_cache.mark_dirty(entry);
      if (m_hz_link != nullptr) hz_note(s.x, s.y);
    }
    if (s.mask != 0) batch.stamps[kept++] = s;
  }
  batch.stamps.resize(kept);
  batch.samples.resize(out);
  m_stamps_passed += kept;
}

void DepthTest::hz_note(int x, int y) {
  const int tile = static_cast<int>(m_config.tile_size);
  m_hz_written.push_back(((y & (tile - 1)) / static_cast<int>(m_config.stamp[1])) * m_stamps_x +
                         (x & (tile - 1)) / static_cast<int>(m_config.stamp[0]));
}

HzRange DepthTest::hz_tile_range(int tile, unsigned entry) {
  const FramebufferDesc& fb = m_frame.framebuffer;
  const unsigned bytes = depth_bytes_per_pixel(fb.depth_format);
  const int ts = static_cast<int>(m_config.tile_size);
  const int sw = static_cast<int>(m_config.stamp[0]), sh = static_cast<int>(m_config.stamp[1]);
  const int ox = (tile % m_tiles_x) * ts, oy = (tile / m_tiles_x) * ts;
  HzRange* const stamps = &m_hz_stamp[static_cast<size_t>(tile) * m_stamps_per_tile];
  // One stamp's range: its pixels inside the framebuffer, every sample. A
  // row's samples are contiguous in the tile (TileCache::pixel), so each row
  // is one run of values.
  const auto scan = [&](int k) {
    const int sx = ox + (k % m_stamps_x) * sw, sy = oy + (k / m_stamps_x) * sh;
    const int w = std::min(sx + sw, fb.width) - sx;  // none: a stamp right of the frame
    const size_t run = w > 0 ? static_cast<size_t>(w) * fb.samples : 0;
    HzRange r{~DepthValue{0}, 0};
    for (int y = sy; run != 0 && y < std::min(sy + sh, fb.height); ++y) {
      const uint8_t* p = m_cache.pixel(entry, sx, y);
      if (bytes == 4 && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__) {
        for (size_t i = 0; i < run; ++i) {
          uint32_t v;  // the host's order is the stored one: load_depth's value
          std::memcpy(&v, p + 4 * i, 4);
          r.min = std::min(r.min, v);
          r.max = std::max(r.max, v);
        }
      } else {
        for (size_t i = 0; i < run; ++i) {
          const DepthValue v = load_depth(p + i * bytes, bytes);
          r.min = std::min(r.min, v);
          r.max = std::max(r.max, v);
        }
      }
    }
    stamps[k] = r;
  };
  uint32_t& known = m_hz_known[static_cast<size_t>(tile)];
  if (known != m_hz_epoch + 1) {
    for (int k = 0; k < m_stamps_per_tile; ++k) scan(k);
    known = m_hz_epoch + 1;
  } else {
    for (const int k : m_hz_written) scan(k);
  }
  HzRange r{~DepthValue{0}, 0};
  for (int k = 0; k < m_stamps_per_tile; ++k) {
    r.min = std::min(r.min, stamps[k].min);
    r.max = std::max(r.max, stamps[k].max);
  }
  return r;
}

}  // namespace gpusim
