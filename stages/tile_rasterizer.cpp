#include "stages/tile_rasterizer.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "hw/fixed_point.h"

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

TileRasterizer::TileRasterizer(sc_core::sc_module_name name, const GpuConfig& config,
                               const FrameState& frame, unsigned unit)
    : PipelineStage(name, "tile_rasterizer", static_cast<int>(unit), config, frame,
                    "setup packets read", "stamp batches and control tokens written"),
      in("in"),
      out("out"),
      m_tile(static_cast<int>(config.tile_size)),
      m_stamp_w(static_cast<int>(config.stamp[0])),
      m_stamp_h(static_cast<int>(config.stamp[1])),
      m_stamp_pixels(stamp_pixels(config)),
      m_tile_shift(log2_side(config.tile_size)),
      m_stamp_w_shift(log2_side(config.stamp[0])),
      m_stamp_h_shift(log2_side(config.stamp[1])),
      m_full_mask(m_stamp_pixels == 64 ? ~uint64_t{0} : (uint64_t{1} << m_stamp_pixels) - 1) {
  if (unit >= config.units) {
    throw std::invalid_argument("TileRasterizer: unit " + std::to_string(unit) + " of " +
                                std::to_string(config.units));
  }
  SC_HAS_PROCESS(TileRasterizer);
  SC_THREAD(run);
}

void TileRasterizer::run() {
  for (;;) {
    SetupPacket p = receive(in);
    if (p.kind != PacketKind::work) {
      forward_control(out, p.kind);
      continue;
    }
    ++m_triangles;
    rasterize(p.triangle);
    // Cycles of trailing tiles that produced no batch.
    work(m_pending_cycles);
    m_pending_cycles = 0;
  }
}

void TileRasterizer::emit_batch(const std::shared_ptr<const RasterPrimitive>& tri) {
  work(m_pending_cycles);
  m_pending_cycles = 0;
  m_batch.kind = PacketKind::work;
  m_batch.triangle = tri;
  m_batch.depth.clear();
  // Moved in: m_batch comes back holding the slot's stale packet, whose
  // stamp buffer the next tile refills (hw/fifo.h).
  emit(out, std::move(m_batch));
}

void TileRasterizer::rasterize(const std::shared_ptr<const RasterPrimitive>& tri) {
  const RasterPrimitive& t = *tri;
  if (t.x0 > t.x1 || t.y0 > t.y1) return;
  const int sw = m_stamp_w, sh = m_stamp_h, ts = m_tile;
  const uint64_t ii = m_cost.ii;

  // Per-triangle constants: per-pixel steps (the offset table inside a stamp
  // is filled on first use, by coverage()), steps between stamps, and per
  // edge the offsets from a tile's origin pixel centre to its pixel centre of
  // largest / smallest E (chosen by the signs of a and b).
  std::array<EdgeValue, 3> step_x, step_y, tile_reach_max, tile_reach_min;
  const EdgeValue reach = EdgeValue{ts - 1} * kSubpixelOne;  // tile origin -> far pixel centre
  m_offset_valid = false;
  for (int k = 0; k < 3; ++k) {
    const EdgeEquation& e = t.edge[k];
    const EdgeValue a = e.a * kSubpixelOne, b = e.b * kSubpixelOne;
    m_pixel_dx[k] = a;
    m_pixel_dy[k] = b;
    step_x[k] = a * sw;
    step_y[k] = b * sh;
    tile_reach_max[k] = std::max<EdgeValue>(e.a, 0) * reach + std::max<EdgeValue>(e.b, 0) * reach;
    tile_reach_min[k] = std::min<EdgeValue>(e.a, 0) * reach + std::min<EdgeValue>(e.b, 0) * reach;
  }

  // Sizes are powers of two and coordinates non-negative: divisions are shifts.
  const int tx0 = t.x0 >> m_tile_shift, tx1 = t.x1 >> m_tile_shift;
  const int ty0 = t.y0 >> m_tile_shift, ty1 = t.y1 >> m_tile_shift;
  for (int ty = ty0; ty <= ty1; ++ty) {
    for (int tx = tx0; tx <= tx1; ++tx) {
      if (tile_owner(tx, ty, m_config.units) != m_unit) continue;
      ++m_tiles_visited;
      m_pending_cycles += 1;  // the tile test

      const int ox = tx * ts, oy = ty * ts;  // tile origin pixel
      std::array<EdgeValue, 3> e_tile;
      bool reject = false, accept = true;
      for (int k = 0; k < 3; ++k) {
        const EdgeEquation& e = t.edge[k];
        e_tile[k] = e.at(pixel_center(ox), pixel_center(oy));
        reject = reject || e_tile[k] + tile_reach_max[k] - e.bias < 0;
        accept = accept && e_tile[k] + tile_reach_min[k] - e.bias >= 0;
      }
      if (reject) {
        ++m_tiles_rejected;
        continue;
      }
      if (accept) ++m_tiles_accepted;

      // Stamps of the tile that intersect the box (the tile meets the box).
      const int px0 = std::max(ox, t.x0), px1 = std::min(ox + ts - 1, t.x1);
      const int py0 = std::max(oy, t.y0), py1 = std::min(oy + ts - 1, t.y1);
      const int si0 = (px0 - ox) >> m_stamp_w_shift, si1 = (px1 - ox) >> m_stamp_w_shift;
      const int sj0 = (py0 - oy) >> m_stamp_h_shift, sj1 = (py1 - oy) >> m_stamp_h_shift;
      std::array<EdgeValue, 3> e_row;
      for (int k = 0; k < 3; ++k) e_row[k] = e_tile[k] + si0 * step_x[k] + sj0 * step_y[k];

      m_batch.stamps.clear();
      for (int sj = sj0; sj <= sj1;
           ++sj, e_row[0] += step_y[0], e_row[1] += step_y[1], e_row[2] += step_y[2]) {
        const int sy = oy + sj * sh;
        const int jlo = std::max(0, t.y0 - sy), jhi = std::min(sh - 1, t.y1 - sy);
        std::array<EdgeValue, 3> e = e_row;
        for (int si = si0; si <= si1;
             ++si, e[0] += step_x[0], e[1] += step_x[1], e[2] += step_x[2]) {
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
          m_pending_cycles += ii;
          if (accept) {
            ++m_stamps_accepted;
            mask = box;
          } else {
            ++m_stamps_evaluated;
            mask = coverage(t, e, box);
          }
          if (mask == 0) continue;
          m_batch.stamps.push_back(Stamp{sx, sy, mask, e});
          ++m_stamps_emitted;
          // Full stamps need no count (popcount is a libgcc call on baseline x86-64).
          m_fragments += mask == m_full_mask ? static_cast<uint64_t>(m_stamp_pixels)
                                             : static_cast<uint64_t>(__builtin_popcountll(mask));
        }
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
uint64_t TileRasterizer::coverage(const RasterPrimitive& t, const std::array<EdgeValue, 3>& e,
                                  uint64_t box) {
  const EdgeValue t0 = t.edge[0].bias - e[0], t1 = t.edge[1].bias - e[1],
                  t2 = t.edge[2].bias - e[2];
  if (box != m_full_mask) {
    uint64_t cover = 0;
    for (uint64_t bits = box; bits != 0; bits &= bits - 1) {
      const int p = __builtin_ctzll(bits);
      const EdgeValue i = p & (m_stamp_w - 1), j = p >> m_stamp_w_shift;
      const bool in = i * m_pixel_dx[0] + j * m_pixel_dy[0] >= t0 &&
                      i * m_pixel_dx[1] + j * m_pixel_dy[1] >= t1 &&
                      i * m_pixel_dx[2] + j * m_pixel_dy[2] >= t2;
      cover |= static_cast<uint64_t>(in) << p;
    }
    return cover;
  }
  if (!m_offset_valid) {
    for (int k = 0; k < 3; ++k) {
      for (int p = 0; p < m_stamp_pixels; ++p) {
        const int i = p & (m_stamp_w - 1), j = p >> m_stamp_w_shift;
        m_offset[k][p] = i * m_pixel_dx[k] + j * m_pixel_dy[k];
      }
    }
    m_offset_valid = true;
  }
  const EdgeValue *o0 = m_offset[0].data(), *o1 = m_offset[1].data(), *o2 = m_offset[2].data();
  uint64_t cover = 0;
  for (int p = 0; p < m_stamp_pixels; ++p) {
    cover |= static_cast<uint64_t>((o0[p] >= t0) & (o1[p] >= t1) & (o2[p] >= t2)) << p;
  }
  return cover;
}

}  // namespace gpusim
