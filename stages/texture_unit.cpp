#include "stages/texture_unit.h"

#include <algorithm>
#include <cmath>

#include "hw/pixel_formats.h"

namespace gpusim {
namespace {

// Conservation (testbench/sim/conservation.h): textures exactly the pixels
// the interpolator gave a texture coordinate, and passes every stamp on.
void conserve(ConservationLedger& l) {
  const std::string ip = l.upstream("interpolator");
  l.equal("tokens_out", l.get("tokens_out"), "tokens_in", l.get("tokens_in"));
  l.equal("fragments", l.get("fragments"), ip + ".texcoords", l.stage(ip, "texcoords"));
  l.equal("texels", l.get("texels"), "nearest_samples + 4 x bilinear_samples",
          l.get("nearest_samples") + 4 * l.get("bilinear_samples"));
  l.equal("fragments + two_level_fragments", l.get("fragments") + l.get("two_level_fragments"),
          "nearest_samples + bilinear_samples",
          l.get("nearest_samples") + l.get("bilinear_samples"));
}

// A texel index wrapped onto a side of `size` texels.
int32_t wrap(int64_t i, int32_t size, TextureWrap mode) {
  if (mode == TextureWrap::repeat) {
    if ((size & (size - 1)) == 0) return static_cast<int32_t>(i & (size - 1));
    const int64_t r = i % size;
    return static_cast<int32_t>(r < 0 ? r + size : r);
  }
  return static_cast<int32_t>(std::clamp<int64_t>(i, 0, size - 1));
}

// NEAREST along one axis. A subnormal coordinate is 0 (the datapath flushes
// them); REPEAT on a side that is not a power of two scales the coordinate's
// fraction, kept below 1.
int32_t nearest_axis(float s, int32_t size, TextureWrap mode) {
  if (std::fpclassify(s) == FP_SUBNORMAL) s = 0.0f;
  if (mode == TextureWrap::repeat && (size & (size - 1)) != 0) {
    const float f = std::min(s - std::floor(s), kBelowOne);
    return static_cast<int32_t>(f * static_cast<float>(size));
  }
  return wrap(static_cast<int64_t>(std::floor(s * static_cast<float>(size))), size, mode);
}

// LINEAR along one axis: the 24.8 texel coordinate, split.
struct AxisTexels {
  int32_t i0, i1;
  unsigned weight;
};
AxisTexels linear_axis(float s, int32_t size, TextureWrap mode) {
  if (mode == TextureWrap::repeat && (size & (size - 1)) != 0) s -= std::floor(s);
  const int64_t u =
      static_cast<int64_t>(std::nearbyint(s * static_cast<float>(size) * 256.0f)) - 128;
  return {wrap(u >> 8, size, mode), wrap((u >> 8) + 1, size, mode),
          static_cast<unsigned>(u & 0xff)};
}

// Where a pixel samples (spec section 9c): magnified (level 0, the MAG
// filter) or minified, at `level` and, with weight > 0, level + 1 too.
struct LevelPick {
  bool minified = false;
  unsigned level = 0;
  unsigned weight = 0;  // 8 bits, of level + 1
};
// The level of detail from the quad's derivatives d = (ds/dx, dt/dx, ds/dy,
// dt/dy): rho^2 in texels of level 0, lod = 0.5 log2(rho^2) by the
// exponent-plus-mantissa approximation, biased and clamped; minified iff
// lod > 0. *_MIPMAP_LINEAR: level floor(lod), weight of the next
// trunc(fract(lod) 256); *_MIPMAP_NEAREST: rho^2's exponent + 1 halved when
// no bias or clamp applies, else lod rounded half to even; both clamped to
// the chain.
LevelPick pick_level(const TextureBinding& b, const glm::vec4& d) {
  const TextureSampler& sm = b.sampler;
  LevelPick pick;
  const float w = static_cast<float>(b.levels[0].width);
  const float h = static_cast<float>(b.levels[0].height);
  const float dsdx = d[0] * w, dtdx = d[1] * h, dsdy = d[2] * w, dtdy = d[3] * h;
  const float rho2 = std::max(dsdx * dsdx + dtdx * dtdx, dsdy * dsdy + dtdy * dtdy);
  if (!(rho2 > 0.0f)) return pick;
  int e = 0;
  const float mantissa = 2.0f * std::frexp(rho2, &e);  // rho2 = mantissa 2^(e - 1)
  const int exponent = e - 1;
  float lod = 0.5f * (static_cast<float>(exponent - 1) + mantissa) + sm.lod_bias;
  lod = std::min(std::max(lod, sm.min_lod), sm.max_lod);
  if (!(lod > 0.0f)) return pick;
  pick.minified = true;
  if (!uses_mipmaps(sm.min_filter)) return pick;
  const unsigned last = static_cast<unsigned>(b.levels.size() - 1);
  if (blends_levels(sm.min_filter)) {
    const float whole = std::floor(lod);
    pick.level = static_cast<unsigned>(whole);
    pick.weight = static_cast<unsigned>(static_cast<int>((lod - whole) * 256.0f));
    if (pick.level >= last) pick.level = last, pick.weight = 0;
  } else {
    const long level = sm.plain_lod() ? (exponent + 1) >> 1 : std::lrint(lod);
    pick.level = static_cast<unsigned>(std::clamp<long>(level, 0, last));
  }
  return pick;
}

// v0 + (w (v1 - v0) + 128) >> 8: the filter's 8.8 lerp, rounded.
uint8_t lerp(uint8_t v0, uint8_t v1, unsigned w) {
  return static_cast<uint8_t>(v0 + ((static_cast<int>(w) * (v1 - v0) + 128) >> 8));
}

// GL 1.5's texture environment (tables 3.22 and 3.23) for a texture of base
// format `base`: the filtered texel ct (each channel / 255) and the
// fragment's colour cf.
glm::vec4 environment(const TextureEnv& env, BaseFormat base, const Texel& texel,
                      const glm::vec4& cf) {
  const glm::vec4 ct(texel_value(texel[0]), texel_value(texel[1]), texel_value(texel[2]),
                     texel_value(texel[3]));
  const bool color = base != BaseFormat::alpha;
  const bool alpha = base == BaseFormat::alpha || base == BaseFormat::luminance_alpha ||
                     base == BaseFormat::intensity || base == BaseFormat::rgba;
  const bool intensity = base == BaseFormat::intensity;
  glm::vec4 r = cf;
  for (int c = 0; c < 3; ++c) {
    switch (env.mode) {
      case TextureEnvMode::replace:
        if (color) r[c] = ct[c];
        break;
      case TextureEnvMode::modulate:
        if (color) r[c] = cf[c] * ct[c];
        break;
      case TextureEnvMode::decal:
        if (base == BaseFormat::rgb) r[c] = ct[c];
        if (base == BaseFormat::rgba) r[c] = cf[c] * (1.0f - ct[3]) + ct[c] * ct[3];
        break;
      case TextureEnvMode::blend:
        if (color) r[c] = cf[c] * (1.0f - ct[c]) + env.color[c] * ct[c];
        break;
      case TextureEnvMode::add:
        if (color) r[c] = cf[c] + ct[c];
        break;
    }
  }
  switch (env.mode) {
    case TextureEnvMode::replace:
      if (alpha) r[3] = ct[3];
      break;
    case TextureEnvMode::modulate:
      if (alpha) r[3] = cf[3] * ct[3];
      break;
    case TextureEnvMode::decal:
      break;
    case TextureEnvMode::blend:
      if (intensity) {
        r[3] = cf[3] * (1.0f - ct[3]) + env.color[3] * ct[3];
      } else if (alpha) {
        r[3] = cf[3] * ct[3];
      }
      break;
    case TextureEnvMode::add:
      if (intensity) {
        r[3] = cf[3] + ct[3];
      } else if (alpha) {
        r[3] = cf[3] * ct[3];
      }
      break;
  }
  for (int c = 0; c < 4; ++c) r[c] = clamp01(r[c]);
  return r;
}

}  // namespace

const StageSpec& TextureUnit::spec() {
  static const StageSpec s{
      "texture_unit",
      StagePlacement::per_unit,
      /*optional=*/true,
      {/*ii=*/1, /*latency=*/8},
      "stamp",
      "passes a stamp a cycle; texturing filters a pixel a cycle (a bilinear sample), after "
      "address, cache tag and a fragment FIFO (8 cycles of latency, as ATTILA's address and "
      "filter ALUs, 6 + 4, less the overlap)",
      "shaded batches and control tokens read",
      "textured batches and control tokens written",
      {"interpolator_to_texture"},
      &conserve,
      StageTrace{TraceItem::stamp_batch, {"", "", ""}, FragmentSite::none},
      {{"", "`ii` × stamps (at least `ii`)", "Untextured batches and control tokens pass through."},
       {"textured batch", "max(`ii` × stamps, the address stage's pixels and waits)",
        "A pixel a cycle through address and filter, a pass per mipmap level it reads; misses go "
        "to memory as soon as their pixel is addressed, up to texture.prefetch_fragments pixels "
        "ahead of the filter, across batches; the batch leaves `latency` after its last pass "
        "(stages/texture_unit.h)."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(TextureUnit);

TextureUnit::TextureUnit(sc_core::sc_module_name name, const GpuConfig& config,
                         const FrameState& frame, unsigned unit)
    : PipelineStage(name, spec(), static_cast<int>(unit), config, frame),
      in("in"),
      out("out"),
      mem("mem"),
      m_cache(config.texture) {
  SC_HAS_PROCESS(TextureUnit);
  SC_THREAD(run);
}

void TextureUnit::reset_state() {
  m_cache.reset();
  m_filter_free = 0;
  m_filter_starts.clear();
  m_last_ready = sc_core::SC_ZERO_TIME;
}

void TextureUnit::run() {
  attach_clock(mem);
  ShadedStampBatch batch;
  for (;;) {
    receive(in, batch);
    uint64_t cycles = m_cost.ii * std::max<uint64_t>(batch.stamps.size(), 1);
    sc_core::sc_time filtered = sc_core::SC_ZERO_TIME;  // when the filter is done with it
    if (batch.kind == PacketKind::work && !batch.texcoords.empty()) {
      const TextureBinding& binding = m_frame.draws.at(batch.primitive->draw_id).texture;
      const Timing t = texture(batch, binding);
      cycles = std::max(cycles, t.address_cycles);
      filtered = t.filtered;
      batch.texcoords.clear();
    }
    work(cycles);
    // In order: no token leaves before the filter has finished the ones
    // before it.
    m_last_ready = std::max({local_time() + m_latency, filtered + m_latency, m_last_ready});
    emit_at(out, std::move(batch), m_last_ready);
  }
}

TextureUnit::Timing TextureUnit::texture(ShadedStampBatch& batch, const TextureBinding& binding) {
  const TextureSampler& sampler = binding.sampler;
  const unsigned bytes = texel_bytes(binding.format);
  const unsigned line_bytes = m_cache.line_bytes();
  const size_t n = batch.texcoords.size();
  const uint64_t start = mem.now().value();
  const uint64_t depth = m_config.texture.prefetch_fragments;

  // Per pixel: the cycle it is addressed, its filter's first cycle and its
  // passes (one a level), from `start`.
  std::vector<uint64_t> address(n), filter(n), passes(n);
  std::vector<Texel> filtered(n);
  m_fills.clear();
  // At most 2 levels x 4 texels x 2 lines a pixel: no reallocation while a
  // round is unresolved (the arbiter holds pointers to the sinks).
  m_fills.reserve(n * 16);
  m_pixels.resize(n);

  // Lines filled in this round: slot -> fill index (the fill's arrival is
  // known once its round is resolved).
  std::vector<std::pair<uint32_t, int32_t>> in_flight;
  const auto arrival = [&](const Footprint& p) {
    uint64_t ready = p.ready;
    for (int32_t f : p.fill) {
      if (f >= 0) {
        ready = std::max<uint64_t>(ready, m_fills[static_cast<size_t>(f)].done.reads.value());
      }
    }
    return ready;
  };
  // One texel of a level through the cache: a miss is filled at cycle `at`;
  // the pixel `p` notes what it waits for.
  const auto texel = [&](const TextureLevel& level, int32_t x, int32_t y, uint64_t at, Footprint& p,
                         unsigned& waits) {
    const uint64_t addr =
        level.address + (uint64_t(y) * uint64_t(level.width) + uint64_t(x)) * bytes;
    uint8_t raw[4];
    // A texel's bytes (3 of them may straddle two lines), line by line.
    for (uint64_t a = addr; a < addr + bytes;) {
      const TextureCache::Lookup line = m_cache.lookup(a);
      const uint64_t line_start = a & ~uint64_t{line_bytes - 1};
      int32_t fill = -1;
      if (!line.hit) {
        ++m_misses;
        fill = static_cast<int32_t>(m_fills.size());
        m_fills.emplace_back();
        mem.read_tracked(line_start, m_cache.data(line.slot), line_bytes, clock_cycles(at),
                         m_fills.back());
        in_flight.emplace_back(line.slot, fill);
      } else {
        ++m_hits;
        const auto it = std::find_if(in_flight.rbegin(), in_flight.rend(),
                                     [&](const auto& f) { return f.first == line.slot; });
        if (it != in_flight.rend()) {
          fill = it->second;
        } else {
          p.ready = std::max(p.ready, m_cache.ready(line.slot));
        }
      }
      if (fill >= 0 &&
          std::find(p.fill.begin(), p.fill.begin() + waits, fill) == p.fill.begin() + waits) {
        p.fill[waits++] = fill;
      }
      const uint64_t end = std::min<uint64_t>(addr + bytes, line_start + line_bytes);
      std::copy(m_cache.data(line.slot) + (a - line_start),
                m_cache.data(line.slot) + (end - line_start), raw + (a - addr));
      a = end;
    }
    ++m_texels;
    return expand_texel(binding.format, raw);
  };
  // One level filtered at (s, t).
  const auto sample_level = [&](const TextureLevel& level, bool bilinear, const glm::vec2& st,
                                uint64_t at, Footprint& p, unsigned& waits) {
    if (!bilinear) {
      ++m_nearest;
      return texel(level, nearest_axis(st.x, level.width, sampler.wrap_s),
                   nearest_axis(st.y, level.height, sampler.wrap_t), at, p, waits);
    }
    ++m_bilinear;
    const AxisTexels x = linear_axis(st.x, level.width, sampler.wrap_s);
    const AxisTexels y = linear_axis(st.y, level.height, sampler.wrap_t);
    const Texel t00 = texel(level, x.i0, y.i0, at, p, waits);
    const Texel t10 = texel(level, x.i1, y.i0, at, p, waits);
    const Texel t01 = texel(level, x.i0, y.i1, at, p, waits);
    const Texel t11 = texel(level, x.i1, y.i1, at, p, waits);
    Texel out;
    for (int c = 0; c < 4; ++c) {
      out[c] = lerp(lerp(t00[c], t10[c], x.weight), lerp(t01[c], t11[c], x.weight), y.weight);
    }
    return out;
  };

  // The filter's state left by the batches before, in cycles from `start`:
  // when it is free, and when each of the last D pixels started.
  const auto from_start = [&](uint64_t t) {
    return t > start ? (t - start + m_cycle - 1) / m_cycle : uint64_t{0};
  };
  const uint64_t filter_free = from_start(m_filter_free);
  // The cycle pixel i's fragment FIFO entry is free: pixel i - D's filter
  // start, in this batch or an earlier one.
  const auto entry_free = [&](size_t i) {
    if (i >= depth) return filter[i - depth];
    const size_t back = depth - i;
    if (back > m_filter_starts.size()) return uint64_t{0};
    return from_start(m_filter_starts[m_filter_starts.size() - back]);
  };
  size_t next_address = 0, next_filter = 0;
  while (next_filter < n) {
    // Address as far as the fragment FIFO allows: pixel i needs pixel
    // i - D's filter cycle, known once that pixel's fills have arrived.
    for (; next_address < n && (next_address < depth || next_address - depth < next_filter);
         ++next_address) {
      const size_t i = next_address;
      const uint64_t at = std::max(i == 0 ? uint64_t{0} : address[i - 1] + 1, entry_free(i));
      address[i] = at;
      Footprint& p = m_pixels[i];
      p.fill.fill(-1);
      p.ready = 0;
      unsigned waits = 0;
      const LevelPick pick = batch.texcoord_derivatives.empty()
                                 ? LevelPick{}
                                 : pick_level(binding, batch.texcoord_derivatives[i]);
      const bool bilinear = (pick.minified ? level_filter(sampler.min_filter)
                                           : sampler.mag_filter) == TextureFilter::linear;
      const glm::vec2& st = batch.texcoords[i];
      const Texel t0 = sample_level(binding.levels[pick.level], bilinear, st, at, p, waits);
      passes[i] = 1;
      filtered[i] = t0;
      if (pick.weight > 0) {
        // The second level: a second pass through the filter.
        const Texel t1 = sample_level(binding.levels[pick.level + 1], bilinear, st, at, p, waits);
        for (int c = 0; c < 4; ++c) filtered[i][c] = lerp(t0[c], t1[c], pick.weight);
        passes[i] = 2;
        ++m_two_level;
      }
    }
    // The fills issued so far complete in this delta's round.
    mem.wait_round();
    for (; next_filter < next_address; ++next_filter) {
      const size_t i = next_filter;
      const uint64_t ready = arrival(m_pixels[i]);
      const uint64_t lines = from_start(ready);
      const uint64_t free =
          std::max(i == 0 ? filter_free : filter[i - 1] + passes[i - 1], address[i] + 1);
      filter[i] = std::max(free, lines);
      m_memory_stall_cycles += filter[i] - free;  // the filter waiting for fills
    }
    // The lines filled in this round are present from their fills' arrival.
    for (const auto& [slot, fill] : in_flight) {
      m_cache.ready(slot) = m_fills[static_cast<size_t>(fill)].done.reads.value();
    }
    in_flight.clear();
  }
  const BaseFormat base = base_format(binding.format);
  for (size_t i = 0; i < n; ++i) {
    batch.colors[i] = environment(binding.env, base, filtered[i], batch.colors[i]);
  }
  m_fragments += n;
  // What the next batch finds: the filter's last pass, and the last D
  // pixels' filter starts (the fragment FIFO's entries they free).
  m_filter_free = start + (filter[n - 1] + passes[n - 1]) * m_cycle;
  for (size_t i = n > depth ? n - depth : 0; i < n; ++i) {
    m_filter_starts.push_back(start + filter[i] * m_cycle);
  }
  while (m_filter_starts.size() > depth) m_filter_starts.pop_front();
  return {address[n - 1] + 1, sc_core::sc_time::from_value(m_filter_free)};
}

}  // namespace gpusim
