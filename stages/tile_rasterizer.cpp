#include "stages/tile_rasterizer.h"

#include <algorithm>
#include <bitset>
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
    : sc_core::sc_module(name),
      in("in"),
      out("out"),
      m_config(config),
      m_frame(frame),
      m_unit(unit),
      m_cost(config.stage("rasterizer")),
      m_tile(static_cast<int>(config.tile_size)),
      m_stamp_w(static_cast<int>(config.stamp[0])),
      m_stamp_h(static_cast<int>(config.stamp[1])),
      m_stamp_pixels(stamp_pixels(config)),
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
    SetupPacket p = in->read();
    ++m_tokens_in;
    if (p.kind != PacketKind::work) {
      sc_core::wait(m_config.cycles(m_cost.ii));
      m_busy_cycles += m_cost.ii;
      StampBatch b;
      b.kind = p.kind;
      out->write(b, sc_core::sc_time_stamp() + m_config.cycles(m_cost.latency));
      ++m_tokens_out;
      continue;
    }
    ++m_triangles;
    rasterize(p.triangle);
    // Cycles of trailing tiles that produced no batch.
    if (m_pending_cycles > 0) {
      sc_core::wait(m_config.cycles(m_pending_cycles));
      m_busy_cycles += m_pending_cycles;
      m_pending_cycles = 0;
    }
  }
}

void TileRasterizer::emit_batch() {
  sc_core::wait(m_config.cycles(m_pending_cycles));
  m_busy_cycles += m_pending_cycles;
  m_pending_cycles = 0;
  out->write(m_batch, sc_core::sc_time_stamp() + m_config.cycles(m_cost.latency));
  ++m_tokens_out;
}

void TileRasterizer::rasterize(const std::shared_ptr<const RasterTriangle>& tri) {
  const RasterTriangle& t = *tri;
  if (t.x0 > t.x1 || t.y0 > t.y1) return;
  const int sw = m_stamp_w, sh = m_stamp_h, ts = m_tile;
  const uint64_t ii = m_cost.ii;

  // Per-triangle constants: per-pixel offsets inside a stamp, steps between
  // stamps, and per edge the offsets from a tile's origin pixel centre to its
  // pixel centre of largest / smallest E (chosen by the signs of a and b).
  std::array<EdgeValue, 3> step_x, step_y, tile_reach_max, tile_reach_min;
  const EdgeValue reach = EdgeValue{ts - 1} * kSubpixelOne;  // tile origin -> far pixel centre
  for (int k = 0; k < 3; ++k) {
    const EdgeEquation& e = t.edge[k];
    const EdgeValue a = e.a * kSubpixelOne, b = e.b * kSubpixelOne;
    for (int j = 0; j < sh; ++j) {
      for (int i = 0; i < sw; ++i) m_offset[k][j * sw + i] = i * a + j * b;
    }
    step_x[k] = a * sw;
    step_y[k] = b * sh;
    tile_reach_max[k] = std::max<EdgeValue>(e.a, 0) * reach + std::max<EdgeValue>(e.b, 0) * reach;
    tile_reach_min[k] = std::min<EdgeValue>(e.a, 0) * reach + std::min<EdgeValue>(e.b, 0) * reach;
  }

  m_batch.kind = PacketKind::work;
  m_batch.triangle = tri;
  m_batch.depth.clear();

  const int tx0 = t.x0 / ts, tx1 = t.x1 / ts, ty0 = t.y0 / ts, ty1 = t.y1 / ts;
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
      const int si0 = (px0 - ox) / sw, si1 = (px1 - ox) / sw;
      const int sj0 = (py0 - oy) / sh, sj1 = (py1 - oy) / sh;
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
            // All pixels against all edges: E + offset - bias >= 0.
            const EdgeValue t0 = t.edge[0].bias - e[0], t1 = t.edge[1].bias - e[1],
                            t2 = t.edge[2].bias - e[2];
            const EdgeValue *o0 = m_offset[0].data(), *o1 = m_offset[1].data(),
                            *o2 = m_offset[2].data();
            uint64_t cover = 0;
            for (int p = 0; p < m_stamp_pixels; ++p) {
              cover |= static_cast<uint64_t>((o0[p] >= t0) & (o1[p] >= t1) & (o2[p] >= t2)) << p;
            }
            mask = cover & box;
          }
          if (mask == 0) continue;
          m_batch.stamps.push_back(Stamp{sx, sy, mask, e});
          ++m_stamps_emitted;
          m_fragments += static_cast<uint64_t>(std::bitset<64>(mask).count());
        }
      }
      if (!m_batch.stamps.empty()) emit_batch();
    }
  }
  m_batch.triangle.reset();
}

}  // namespace gpusim
