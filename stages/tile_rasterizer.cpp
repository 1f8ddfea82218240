#include "stages/tile_rasterizer.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

#include "hw/fixed_point.h"
#include "hw/sample_pattern.h"

namespace gpusim {
namespace {

int stamp_pixels(const GpuConfig& c) {
  const unsigned n = c.stamp[0] * c.stamp[1];
  if (c.stamp[0] == 0 || c.stamp[1] == 0 || n > 64 || c.tile_size % c.stamp[0] != 0 ||
      c.tile_size % c.stamp[1] != 0) {
    throw std::invalid_argument("TileRasterizer: stamp " + std::to_string(c.stamp[0]) + "x" +
                                std::to_string(c.stamp[1]) + " must hold at most 64 pixels" +
                                " and divide tile_size " + std::to_string(c.tile_size));
  }
  return static_cast<int>(n);
}

}  // namespace

namespace {

// Why a point or line whose last record is here went no further (traces).
constexpr const char* kNoPixel = "no pixel of it was covered in any tile";

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  const ConservationLedger::Frame& f = l.frame();
  // The line walker's stamps (line_stamps) are emitted as it builds them.
  l.at_most("stamps_emitted", l.get("stamps_emitted"),
            "stamps_evaluated + stamps_accepted + line_stamps",
            l.get("stamps_evaluated") + l.get("stamps_accepted") + l.get("line_stamps"));
  l.at_most("control tokens", f.control, "tokens_out", l.get("tokens_out"));
}

}  // namespace

const StageSpec& TileRasterizer::spec() {
  static const StageSpec s{
      "tile_rasterizer",
      StagePlacement::per_unit,
      /*optional=*/false,
      {/*ii=*/1, /*latency=*/2},
      "stamp",
      "one stamp of edge functions per cycle per unit (a Bresenham line: one "
      "step per cycle, docs/architecture.md)",
      "setup packets read",
      "stamp batches and control tokens written",
      {"distributor_to_rasterizer"},
      &conserve,
      StageTrace{TraceItem::tile_job,
                 {kNoPixel, kNoPixel, "no pixel centre of it was covered in any tile"},
                 FragmentSite::none},
      {{"",
        "1 per tile visited + `ii` per stamp evaluated or emitted; with `tile_test_overlap` (the "
        "default) the test of a tile that evaluates any stamp is hidden behind its stamps",
        "Per tile, one test of the coverage edges (a triangle's three, a diamond-exit line's two, "
        "a point's none) at the tile's extreme pixel centres rejects or accepts it whole; an "
        "accepted tile emits its stamps at `ii` each without per-pixel tests; a partial tile "
        "evaluates every stamp inside the box at `ii` each, all pixels of the stamp against all "
        "edges at once. The unit waits the cycles walked since its last output and then writes "
        "that tile's batch, so large triangles stream tile by tile."},
       {"Bresenham line",
        "1 to enter + 1 per span tested + 1 per step walked + `ii` per stamp emitted",
        "The line walker (below): a span is the line's steps in one tile column (x-major) or row "
        "(y-major); a span reaching none of the unit's tiles is jumped for its test cycle alone; "
        "the steps of the others cost a cycle each, all `w` replicated pixels at once. A span's "
        "batches (one per tile) leave after its steps."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(TileRasterizer);

TileRasterizer::TileRasterizer(sc_core::sc_module_name name, const GpuConfig& config,
                               const FrameState& frame, unsigned unit)
    : PipelineStage(name, spec(), static_cast<int>(unit), config, frame),
      in("in"),
      out("out"),
      m_tile(static_cast<int>(config.tile_size)),
      m_stamp_w(static_cast<int>(config.stamp[0])),
      m_stamp_h(static_cast<int>(config.stamp[1])),
      m_stamp_pixels(stamp_pixels(config)),
      m_tile_shift(log2_side(config.tile_size)),
      m_stamp_w_shift(log2_side(config.stamp[0])),
      m_stamp_h_shift(log2_side(config.stamp[1])),
      m_full_mask(m_stamp_pixels == 64 ? ~uint64_t{0} : (uint64_t{1} << m_stamp_pixels) - 1),
      m_owner(unit),
      m_hz(config.hierarchical_z.enabled),
      m_hz_delay(clock_cycles(config.hierarchical_z.access_latency)) {
  if (unit >= config.units) {
    throw std::invalid_argument("TileRasterizer: unit " + std::to_string(unit) + " of " +
                                std::to_string(config.units));
  }
  SC_HAS_PROCESS(TileRasterizer);
  SC_THREAD(run);
}

void TileRasterizer::reset_state() {
  m_pixel_dx = m_pixel_dy = {};
  m_offset = {};
  m_offset_valid = false;
  m_samples = 1;
  m_full_samples = 1;
  m_sample_dx = m_sample_dy = {};
  m_sample_offset = {};
  m_passes = 1;
  m_pending_cycles = 0;
  m_batch = StampBatch{};
  m_line_stamps.clear();
  m_tiles_x = 0;
  m_hz_block.clear();
  m_hz_seq.clear();
  m_hz_epoch = 0;
  m_clears_seen = 0;
  m_hz_prim = HzRange{};
  m_hz_func = CompareFunc::always;
  m_hz_cull = m_hz_write = false;
}

void TileRasterizer::run() {
  // The frame's registers are final once the simulation runs.
  m_samples = m_frame.framebuffer.samples;
  m_full_samples = static_cast<uint16_t>((1u << m_samples) - 1);
  m_passes = m_config.sample_passes(m_samples);
  for (unsigned i = 0; i < m_samples; ++i) {
    const SampleOffset o = sample_offset(m_samples, i);
    m_sample_dx[i] = o.dx;
    m_sample_dy[i] = o.dy;
  }
  if (m_hz) {
    const FramebufferDesc& fb = m_frame.framebuffer;
    m_tiles_x = (fb.width + m_tile - 1) >> m_tile_shift;
    const size_t tiles =
        static_cast<size_t>(m_tiles_x) * ((fb.height + m_tile - 1) >> m_tile_shift);
    m_hz_block.assign(tiles, HzRange{});  // the buffer's contents are unknown
    m_hz_seq.assign(tiles, 0);
  }
  for (;;) {
    SetupPacket p = receive(in);
    if (p.kind != PacketKind::work) {
      if (!m_hz) {
        forward_control(out, p.kind);
        continue;
      }
      hz_control(p.kind);
      // As forward_control, through the HZ stage's latency like the batches.
      work(m_cost.ii);
      StampBatch token{};
      token.kind = p.kind;
      emit_at(out, std::move(token), local_time() + m_latency + m_hz_delay);
      continue;
    }
    rasterize(p.primitive);
    // Cycles of trailing tiles that produced no batch.
    work(m_pending_cycles);
    m_pending_cycles = 0;
  }
}

void TileRasterizer::emit_batch(const std::shared_ptr<const RasterPrimitive>& tri) {
  work(m_pending_cycles);
  m_pending_cycles = 0;
  m_batch.kind = PacketKind::work;
  m_batch.primitive = tri;
  m_batch.hz_seq = 0;
  if (!m_hz) {
    // Moved in: m_batch comes back holding the slot's stale packet, whose
    // stamp buffer the next tile refills (hw/fifo.h).
    emit(out, std::move(m_batch));
    return;
  }
  if (m_hz_write) {
    // A batch's stamps lie in one tile.
    const int tile =
        (m_batch.stamps[0].y >> m_tile_shift) * m_tiles_x + (m_batch.stamps[0].x >> m_tile_shift);
    hz_widen(tile);
    m_batch.hz_seq = ++m_hz_seq[static_cast<size_t>(tile)];
  }
  emit_at(out, std::move(m_batch), local_time() + m_latency + m_hz_delay);
}

void TileRasterizer::hz_control(PacketKind kind) {
  if (kind == PacketKind::clear) {
    const ClearState c = next_clear(m_clears_seen++);
    if (!c.depth) return;
    const DepthValue v = encode_depth(m_frame.framebuffer.depth_format, c.depth_value);
    std::fill(m_hz_block.begin(), m_hz_block.end(), HzRange{v, v});
  } else {
    m_clears_seen = 0;
    std::fill(m_hz_block.begin(), m_hz_block.end(), HzRange{});
  }
  ++m_hz_epoch;  // the depth test counts the same tokens: older updates are dropped
}

// A depth-writing batch can move the tile's values only towards the
// primitive's range, and only in the direction the compare function passes.
void TileRasterizer::hz_widen(int tile) {
  HzRange& b = m_hz_block[static_cast<size_t>(tile)];
  switch (m_hz_func) {
    case CompareFunc::less:
    case CompareFunc::lequal:
      b.min = std::min(b.min, m_hz_prim.min);
      break;
    case CompareFunc::greater:
    case CompareFunc::gequal:
      b.max = std::max(b.max, m_hz_prim.max);
      break;
    default:
      b.min = std::min(b.min, m_hz_prim.min);
      b.max = std::max(b.max, m_hz_prim.max);
      break;
  }
}

bool TileRasterizer::hz_culls(int tile) {
  if (m_hz_link != nullptr) {
    const sc_core::sc_time now = local_time();
    if (decoupled()) {
      // Every update visible at `now` was stamped before now - latency.
      // Unless the link says they have all been sent, the stage waits for
      // the kernel to get there (then they have, and one stamped at it is
      // not visible).
      const sc_core::sc_time& latency = m_hz_link->latency();
      if (now > latency && !m_hz_link->sent_before(now - latency)) {
        sc_core::wait(now - latency - sc_core::sc_time_stamp());
      }
    }
    m_hz_link->take_visible(now, [&](const HzUpdate& u) {
      // Exact only if it describes the last depth-writing batch emitted to
      // the block in this epoch: every earlier one has then been tested too.
      if (u.epoch == m_hz_epoch && u.seq == m_hz_seq[u.tile]) {
        m_hz_block[u.tile] = u.range;
        ++m_hz_updates_applied;
      } else {
        ++m_hz_updates_dropped;
      }
    });
  }
  ++m_hz_tests;
  const HzRange& b = m_hz_block[static_cast<size_t>(tile)];
  const HzRange& p = m_hz_prim;
  switch (m_hz_func) {
    case CompareFunc::never:
      return true;
    case CompareFunc::less:
      return p.min >= b.max;
    case CompareFunc::lequal:
      return p.min > b.max;
    case CompareFunc::greater:
      return p.max <= b.min;
    case CompareFunc::gequal:
      return p.max < b.min;
    case CompareFunc::equal:
      return p.max < b.min || p.min > b.max;
    default:
      return false;
  }
}

void TileRasterizer::rasterize(const std::shared_ptr<const RasterPrimitive>& tri) {
  const RasterPrimitive& t = *tri;
  switch (t.primitive_kind) {
    case PrimitiveKind::triangle:
      ++m_triangles;
      break;
    case PrimitiveKind::line:
      ++m_lines;
      break;
    case PrimitiveKind::point:
      ++m_points;
      break;
  }
  if (t.x0 > t.x1 || t.y0 > t.y1) return;
  if (m_hz) {
    // What the primitive's depth state lets hierarchical Z do (the depth
    // test's own cases, stages/depth_test.h): cull with a function that can
    // fail against a range (triangles only: hz_primitive_range), widen for a
    // batch that can store.
    const RenderState& st = m_frame.draws.at(t.draw_id).state;
    m_hz_func = st.depth_test ? st.depth_func : CompareFunc::always;
    m_hz_cull = t.primitive_kind == PrimitiveKind::triangle && m_hz_func != CompareFunc::always &&
                m_hz_func != CompareFunc::notequal;
    m_hz_write = st.depth_test && st.depth_write && m_hz_func != CompareFunc::never;
    if (m_hz_cull || m_hz_write) {
      m_hz_prim = hz_primitive_range(t, m_frame.framebuffer.depth_format);
    }
  }
  if (t.line_rule == LineRule::bresenham) {
    walk_line(tri);
    return;
  }
  // The edge core has four edge units; a multisampled line or point uses them
  // all (its rectangle or square), a triangle three, a diamond-exit line two
  // (its band), a single-sampled point none (its square is the box). One
  // instantiation per count keeps the triangle path's loops fixed at three.
  switch (t.coverage_count) {
    case 4:
      rasterize_edges<4>(tri);
      break;
    case 3:
      rasterize_edges<3>(tri);
      break;
    case 2:
      rasterize_edges<2>(tri);
      break;
    case 0:
      rasterize_edges<0>(tri);
      break;
    default:
      SC_REPORT_ERROR("gpusim/tile_rasterizer",
                      (std::string(name()) + ": unsupported coverage edge count " +
                       std::to_string(unsigned{t.coverage_count}))
                          .c_str());
  }
}

// Lines and points: the stamp carries the interpolation functions' values at
// its origin pixel centre (what the back end steps from), which differ from
// the coverage edges'. One multiply-add per function per emitted stamp.
std::array<EdgeValue, 3> TileRasterizer::interpolation_at(const RasterPrimitive& t, int sx,
                                                          int sy) const {
  const Subpixel px = pixel_center(sx), py = pixel_center(sy);
  return {t.edge[0].at(px, py), t.edge[1].at(px, py), t.edge[2].at(px, py)};
}

namespace {

// ceil(n / d) for d > 0.
int64_t ceil_div(int64_t n, int64_t d) {
  return n >= 0 ? (n + d - 1) / d : -((-n) / d);
}

}  // namespace

// The Bresenham walker (docs/pipeline-spec.md, section 8b). Major axis M,
// minor axis N; step i in [0, m] is at major ma + sm i and minor na + sn k_i
// with k_i = ceil((2 i |dN| - |dM|) / (2 |dM|)), kept incrementally by the
// decision variable d_i = 2 i |dN| - |dM| - 2 k_i |dM| in (-2|dM|, 0]:
// d += 2|dN| per step, and when d > 0, k += 1 and d -= 2|dM| (a tie, d = 0,
// does not step the minor axis). The walk is cut into spans of the major
// axis, one tile column (row) each; see the cost model in the header.
void TileRasterizer::walk_line(const std::shared_ptr<const RasterPrimitive>& tri) {
  const RasterPrimitive& t = *tri;
  const int64_t ddx = int64_t{t.ib_x} - t.ia_x, ddy = int64_t{t.ib_y} - t.ia_y;
  const bool x_major = std::llabs(ddx) >= std::llabs(ddy);
  const int64_t dm = x_major ? ddx : ddy, dn = x_major ? ddy : ddx;
  const int64_t adm = std::llabs(dm), adn = std::llabs(dn);
  const int64_t sm = dm < 0 ? -1 : 1, sn = dn < 0 ? -1 : 1;
  const int64_t ma = x_major ? t.ia_x : t.ia_y, na = x_major ? t.ia_y : t.ia_x;
  const int64_t w = t.width, lo = (w - 1) / 2;
  // The box along each axis (inside the framebuffer).
  const int64_t box_m0 = x_major ? t.x0 : t.y0, box_m1 = x_major ? t.x1 : t.y1;
  const int64_t box_n0 = x_major ? t.y0 : t.x0, box_n1 = x_major ? t.y1 : t.x1;
  // Steps drawn: the end flags (m = 0: one pixel, drawn only if both are set).
  int64_t i_first = t.draw_first ? 0 : 1, i_last = t.draw_last ? adm : adm - 1;
  if (adm == 0) i_last = t.draw_first && t.draw_last ? 0 : -1;
  // Only steps whose major coordinate lies in the box can produce a pixel.
  if (sm > 0) {
    i_first = std::max(i_first, box_m0 - ma);
    i_last = std::min(i_last, box_m1 - ma);
  } else {
    i_first = std::max(i_first, ma - box_m1);
    i_last = std::min(i_last, ma - box_m0);
  }
  if (i_first > i_last) return;  // no drawn step in the box: nothing to walk
  ++m_lines_walked;

  const int ts = m_tile, sw = m_stamp_w, sh = m_stamp_h;
  const uint64_t ii = m_cost.ii;
  // Entering the walk at step i_first: k and d in closed form (a division,
  // once per line; 1 cycle).
  auto state_at = [&](int64_t i, int64_t& k, int64_t& d) {
    if (adm == 0) {
      k = 0;
      d = 0;
      return;
    }
    k = ceil_div(2 * i * adn - adm, 2 * adm);
    d = 2 * i * adn - adm - 2 * k * adm;
  };
  int64_t k, d;
  state_at(i_first, k, d);
  m_pending_cycles += 1;

  int64_t i = i_first;
  while (i <= i_last) {
    // The span: the steps whose major coordinate lies in this tile column.
    const int64_t m = ma + sm * i;
    const int64_t mt = m >> m_tile_shift;
    const int64_t span_end_m = sm > 0 ? (mt + 1) * ts - 1 : mt * ts;
    const int64_t i_end = std::min(i_last, sm > 0 ? span_end_m - ma : ma - span_end_m);
    const int64_t steps = i_end - i + 1;
    // The minor tiles the span can reach: from the current minor pixel,
    // at most `steps - 1` further, widened by the replication.
    const int64_t n_now = na + sn * k;
    const int64_t n_far = n_now + sn * (steps - 1);
    const int64_t n_min = std::max(box_n0, std::min(n_now, n_far) - lo);
    const int64_t n_max = std::min(box_n1, std::max(n_now, n_far) - lo + w - 1);
    bool mine = false;
    for (int64_t nt = n_min >> m_tile_shift; n_min <= n_max && nt <= n_max >> m_tile_shift && !mine;
         ++nt) {
      const int tx = static_cast<int>(x_major ? mt : nt), ty = static_cast<int>(x_major ? nt : mt);
      mine = tile_owner(tx, ty, m_config.units) == m_owner;
    }
    ++m_line_spans;
    m_pending_cycles += 1;  // the span test
    if (!mine) {
      // None of the span's tiles is this unit's: jump past it in closed form.
      ++m_line_spans_skipped;
      i = i_end + 1;
      if (i <= i_last) state_at(i, k, d);
      continue;
    }
    // Walk the span, 1 cycle per step, collecting the unit's pixels into
    // stamps, keyed by (minor tile, stamp row, stamp column).
    m_line_stamps.clear();
    for (; i <= i_end; ++i) {
      ++m_line_steps;
      m_pending_cycles += 1;
      const int64_t pm = ma + sm * i, pn = na + sn * k;
      for (int64_t j = std::max(pn - lo, box_n0); j <= std::min(pn - lo + w - 1, box_n1); ++j) {
        const int x = static_cast<int>(x_major ? pm : j), y = static_cast<int>(x_major ? j : pm);
        if (tile_owner(x >> m_tile_shift, y >> m_tile_shift, m_config.units) != m_owner) continue;
        const int sx = x & ~(sw - 1), sy = y & ~(sh - 1);
        const int tile_n = static_cast<int>(j >> m_tile_shift);
        const int bit = (y - sy) * sw + (x - sx);
        m_line_stamps[std::make_tuple(tile_n, sy, sx)] |= uint64_t{1} << bit;
      }
      if (adm > 0) {
        d += 2 * adn;
        if (d > 0) {
          ++k;
          d -= 2 * adm;
        }
      }
    }
    // One batch per tile, tiles in minor order, stamps in rows bottom-up,
    // left to right; ii per stamp emitted.
    m_batch.stamps.clear();
    m_batch.samples.clear();
    bool open = false;
    int current_tile = 0;
    for (const auto& [key, mask] : m_line_stamps) {
      const int tile_n = std::get<0>(key);
      if (open && tile_n != current_tile) {
        emit_batch(tri);
        m_batch.stamps.clear();  // the FIFO handed back a stale packet
        m_batch.samples.clear();
      }
      open = true;
      current_tile = tile_n;
      const int sy = std::get<1>(key), sx = std::get<2>(key);
      m_pending_cycles += ii;
      m_batch.stamps.push_back(Stamp{sx, sy, mask, interpolation_at(t, sx, sy)});
      ++m_stamps_emitted;
      ++m_line_stamps_emitted;
      m_fragments += static_cast<uint64_t>(__builtin_popcountll(mask));
      m_samples_covered += static_cast<uint64_t>(__builtin_popcountll(mask));
    }
    if (open) emit_batch(tri);
  }
}

template <int N>
void TileRasterizer::rasterize_edges(const std::shared_ptr<const RasterPrimitive>& tri) {
  const RasterPrimitive& t = *tri;
  const int sw = m_stamp_w, sh = m_stamp_h, ts = m_tile;
  const uint64_t ii = m_cost.ii;

  // Per-triangle constants: per-pixel steps (the offset table inside a stamp
  // is filled on first use, by coverage()), steps between stamps, and per
  // edge the offsets from a tile's origin pixel centre to its pixel centre of
  // largest / smallest E (chosen by the signs of a and b).
  std::array<EdgeValue, N> step_x, step_y, tile_reach_max, tile_reach_min;
  const EdgeValue reach = EdgeValue{ts - 1} * kSubpixelOne;  // tile origin -> far pixel centre
  m_offset_valid = false;
  for (int k = 0; k < N; ++k) {
    const EdgeEquation& e = t.coverage[k];
    const EdgeValue a = e.a * kSubpixelOne, b = e.b * kSubpixelOne;
    m_pixel_dx[k] = a;
    m_pixel_dy[k] = b;
    step_x[k] = a * sw;
    step_y[k] = b * sh;
    tile_reach_max[k] = std::max<EdgeValue>(e.a, 0) * reach + std::max<EdgeValue>(e.b, 0) * reach;
    tile_reach_min[k] = std::min<EdgeValue>(e.a, 0) * reach + std::min<EdgeValue>(e.b, 0) * reach;
    if (m_samples > 1) {
      // The tile test covers every sample point: the extremes of the
      // samples' offsets widen each edge's range.
      EdgeValue lo = 0, hi = 0;
      for (unsigned s = 0; s < m_samples; ++s) {
        const EdgeValue o = e.a * m_sample_dx[s] + e.b * m_sample_dy[s];
        m_sample_offset[k][s] = o;
        lo = s == 0 ? o : std::min(lo, o);
        hi = s == 0 ? o : std::max(hi, o);
      }
      tile_reach_max[k] += hi;
      tile_reach_min[k] += lo;
    }
  }

  // Sizes are powers of two and coordinates non-negative: divisions are shifts.
  const int tx0 = t.x0 >> m_tile_shift, tx1 = t.x1 >> m_tile_shift;
  const int ty0 = t.y0 >> m_tile_shift, ty1 = t.y1 >> m_tile_shift;
  for (int ty = ty0; ty <= ty1; ++ty) {
    for (int tx = tx0; tx <= tx1; ++tx) {
      if (tile_owner(tx, ty, m_config.units) != m_owner) continue;
      ++m_tiles_visited;
      // The tile test; overlapped with the stamps when config.tile_test_overlap
      // and the tile evaluates any (taken back below).
      m_pending_cycles += 1;
      const uint64_t cycles_before_stamps = m_pending_cycles;

      const int ox = tx * ts, oy = ty * ts;  // tile origin pixel
      std::array<EdgeValue, N> e_tile;
      bool reject = false, accept = true;
      for (int k = 0; k < N; ++k) {
        const EdgeEquation& e = t.coverage[k];
        e_tile[k] = e.at(pixel_center(ox), pixel_center(oy));
        reject = reject || e_tile[k] + tile_reach_max[k] - e.bias < 0;
        accept = accept && e_tile[k] + tile_reach_min[k] - e.bias >= 0;
      }
      if (reject) {
        ++m_tiles_rejected;
        continue;
      }
      // Stamps of the tile that intersect the box (the tile meets the box).
      const int px0 = std::max(ox, t.x0), px1 = std::min(ox + ts - 1, t.x1);
      const int py0 = std::max(oy, t.y0), py1 = std::min(oy + ts - 1, t.y1);
      // Hierarchical Z, in the tile test's cycle: a culled tile emits nothing.
      // Its covered pixels are counted by the walk below for
      // hz_fragments_culled, a model-side count that costs no cycles.
      const bool culled = N == 3 && m_hz_cull && hz_culls(ty * m_tiles_x + tx);
      if (culled) {
        ++m_hz_tiles_culled;
        if (accept) {
          m_hz_fragments_culled += static_cast<uint64_t>(px1 - px0 + 1) * (py1 - py0 + 1);
          m_hz_samples_culled += static_cast<uint64_t>(px1 - px0 + 1) * (py1 - py0 + 1) * m_samples;
          continue;
        }
      }
      if (accept) ++m_tiles_accepted;

      const int si0 = (px0 - ox) >> m_stamp_w_shift, si1 = (px1 - ox) >> m_stamp_w_shift;
      const int sj0 = (py0 - oy) >> m_stamp_h_shift, sj1 = (py1 - oy) >> m_stamp_h_shift;
      std::array<EdgeValue, N> e_row;
      for (int k = 0; k < N; ++k) e_row[k] = e_tile[k] + si0 * step_x[k] + sj0 * step_y[k];

      m_batch.stamps.clear();
      m_batch.samples.clear();
      for (int sj = sj0; sj <= sj1; ++sj) {
        const int sy = oy + sj * sh;
        const int jlo = std::max(0, t.y0 - sy), jhi = std::min(sh - 1, t.y1 - sy);
        std::array<EdgeValue, N> e = e_row;
        for (int si = si0; si <= si1; ++si) {
          const std::array<EdgeValue, N> e_here = e;  // at this stamp's origin
          for (int k = 0; k < N; ++k) e[k] += step_x[k];
          const int sx = ox + si * sw;
          const int ilo = std::max(0, t.x0 - sx), ihi = std::min(sw - 1, t.x1 - sx);
          // Pixels inside the box (the box is inside the framebuffer).
          uint64_t box = m_full_mask;
          if (ilo > 0 || ihi < sw - 1 || jlo > 0 || jhi < sh - 1) {
            const uint64_t row = ((uint64_t{2} << ihi) - 1) & ~((uint64_t{1} << ilo) - 1);
            box = 0;
            for (int j = jlo; j <= jhi; ++j) box |= row << (j * sw);
          }
          uint64_t mask;
          if (culled) {
            const uint64_t samples_before = m_samples_covered;
            mask = m_samples > 1 ? sample_coverage<N>(t, e_here, box) : coverage<N>(t, e_here, box);
            const uint64_t covered = static_cast<uint64_t>(__builtin_popcountll(mask));
            m_hz_fragments_culled += covered;
            m_hz_samples_culled += m_samples > 1 ? m_samples_covered - samples_before : covered;
            m_samples_covered = samples_before;
            m_batch.samples.clear();
            continue;
          }
          m_pending_cycles += ii * m_passes;
          if (accept) {
            ++m_stamps_accepted;
            mask = box;
            if (m_samples > 1) {
              for (uint64_t bits = box; bits != 0; bits &= bits - 1)
                m_batch.samples.push_back(m_full_samples);
              m_samples_covered += static_cast<uint64_t>(__builtin_popcountll(box)) * m_samples;
            }
          } else {
            ++m_stamps_evaluated;
            mask = m_samples > 1 ? sample_coverage<N>(t, e_here, box) : coverage<N>(t, e_here, box);
          }
          if (mask == 0) continue;
          if constexpr (N == 3) {
            m_batch.stamps.push_back(Stamp{sx, sy, mask, e_here});
          } else {
            m_batch.stamps.push_back(Stamp{sx, sy, mask, interpolation_at(t, sx, sy)});
          }
          ++m_stamps_emitted;
          // Full stamps need no count (popcount is a libgcc call on baseline x86-64).
          const uint64_t covered = mask == m_full_mask
                                       ? static_cast<uint64_t>(m_stamp_pixels)
                                       : static_cast<uint64_t>(__builtin_popcountll(mask));
          m_fragments += covered;
          if (m_samples == 1) m_samples_covered += covered;
        }
        for (int k = 0; k < N; ++k) e_row[k] += step_y[k];
      }
      if (m_config.tile_test_overlap && m_pending_cycles != cycles_before_stamps) {
        m_pending_cycles -= 1;
      }
      if (!m_batch.stamps.empty()) emit_batch(tri);
    }
  }
}

// The hardware tests all w x h pixels against all three edges in parallel and
// masks the result with the box. Pixels outside the box cannot survive the
// mask, so the model evaluates only the box's: all of them through the
// offset table when the box is the whole stamp, else one by one (a small
// triangle's box holds a few pixels). Either way a pixel is covered iff
// E + offset - bias >= 0 for every edge, in exact integers.
template <int N>
uint64_t TileRasterizer::coverage(const RasterPrimitive& t, const std::array<EdgeValue, N>& e,
                                  uint64_t box) {
  std::array<EdgeValue, N> th;  // E + offset - bias >= 0 <=> offset >= bias - E
  for (int k = 0; k < N; ++k) th[k] = t.coverage[k].bias - e[k];
  if (box != m_full_mask) {
    uint64_t cover = 0;
    for (uint64_t bits = box; bits != 0; bits &= bits - 1) {
      const int p = __builtin_ctzll(bits);
      const EdgeValue i = p & (m_stamp_w - 1), j = p >> m_stamp_w_shift;
      bool in = true;
      for (int k = 0; k < N; ++k) in = in && i * m_pixel_dx[k] + j * m_pixel_dy[k] >= th[k];
      cover |= static_cast<uint64_t>(in) << p;
    }
    return cover;
  }
  if (!m_offset_valid) {
    for (int k = 0; k < N; ++k) {
      for (int p = 0; p < m_stamp_pixels; ++p) {
        const int i = p & (m_stamp_w - 1), j = p >> m_stamp_w_shift;
        m_offset[k][p] = i * m_pixel_dx[k] + j * m_pixel_dy[k];
      }
    }
    m_offset_valid = true;
  }
  uint64_t cover = 0;
  if constexpr (N == 3) {
    const EdgeValue *o0 = m_offset[0].data(), *o1 = m_offset[1].data(), *o2 = m_offset[2].data();
    const EdgeValue t0 = th[0], t1 = th[1], t2 = th[2];
    for (int p = 0; p < m_stamp_pixels; ++p) {
      cover |= static_cast<uint64_t>((o0[p] >= t0) & (o1[p] >= t1) & (o2[p] >= t2)) << p;
    }
  } else {
    for (int p = 0; p < m_stamp_pixels; ++p) {
      bool in = true;
      for (int k = 0; k < N; ++k) in = in && m_offset[k][p] >= th[k];
      cover |= static_cast<uint64_t>(in) << p;
    }
  }
  return cover;
}

template <int N>
uint64_t TileRasterizer::sample_coverage(const RasterPrimitive& t,
                                         const std::array<EdgeValue, N>& e, uint64_t box) {
  uint64_t cover = 0;
  for (uint64_t bits = box; bits != 0; bits &= bits - 1) {
    const int p = __builtin_ctzll(bits);
    const EdgeValue i = p & (m_stamp_w - 1), j = p >> m_stamp_w_shift;
    std::array<EdgeValue, N> at;  // E - bias at the pixel centre
    for (int k = 0; k < N; ++k)
      at[k] = e[k] + i * m_pixel_dx[k] + j * m_pixel_dy[k] - t.coverage[k].bias;
    uint32_t samples = 0;
    for (unsigned s = 0; s < m_samples; ++s) {
      bool in = true;
      for (int k = 0; k < N; ++k) in = in && at[k] + m_sample_offset[k][s] >= 0;
      samples |= static_cast<uint32_t>(in) << s;
    }
    if (samples == 0) continue;
    cover |= uint64_t{1} << p;
    m_batch.samples.push_back(static_cast<uint16_t>(samples));
    m_samples_covered += static_cast<uint64_t>(__builtin_popcount(samples));
  }
  return cover;
}

}  // namespace gpusim
