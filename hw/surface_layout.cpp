#include "hw/surface_layout.h"

#include <algorithm>

#include "hw/packets.h"

namespace gpusim {

SurfaceLayout::SurfaceLayout(bool tiled, int width, int height, unsigned bytes_per_pixel,
                             unsigned tile_size, unsigned units)
    : m_tiled(tiled),
      m_width(width),
      m_height(height),
      m_bpp(bytes_per_pixel),
      m_tile(static_cast<int>(tile_size)) {
  m_tiles_x = (width + m_tile - 1) / m_tile;
  m_tiles_y = (height + m_tile - 1) / m_tile;
  if (!tiled) return;
  const size_t tiles = static_cast<size_t>(m_tiles_x) * static_cast<size_t>(m_tiles_y);
  m_block_offset.assign(tiles, 0);
  // Each unit's full tiles in raster order, then dealt round-robin.
  std::vector<std::vector<size_t>> full(units);
  for (int ty = 0; ty < m_tiles_y; ++ty) {
    for (int tx = 0; tx < m_tiles_x; ++tx) {
      if (tile_width(tx) == m_tile && tile_height(ty) == m_tile)
        full[tile_owner(tx, ty, units)].push_back(static_cast<size_t>(ty) * m_tiles_x + tx);
    }
  }
  const uint64_t full_bytes = static_cast<uint64_t>(m_tile) * static_cast<uint64_t>(m_tile) * m_bpp;
  uint64_t next = 0;
  size_t longest = 0;
  for (const auto& f : full) longest = std::max(longest, f.size());
  for (size_t k = 0; k < longest; ++k) {
    for (const auto& f : full) {
      if (k >= f.size()) continue;
      m_block_offset[f[k]] = next;
      next += full_bytes;
    }
  }
  // The partial edge tiles, packed, in raster order.
  for (int ty = 0; ty < m_tiles_y; ++ty) {
    for (int tx = 0; tx < m_tiles_x; ++tx) {
      const int w = tile_width(tx), h = tile_height(ty);
      if (w == m_tile && h == m_tile) continue;
      m_block_offset[static_cast<size_t>(ty) * m_tiles_x + tx] = next;
      next += static_cast<uint64_t>(w) * static_cast<uint64_t>(h) * m_bpp;
    }
  }
}

int SurfaceLayout::tile_width(int tx) const {
  return std::min(m_tile, m_width - tx * m_tile);
}

int SurfaceLayout::tile_height(int ty) const {
  return std::min(m_tile, m_height - ty * m_tile);
}

uint64_t SurfaceLayout::pixel_offset(int x, int y) const {
  if (!m_tiled) {
    return (static_cast<uint64_t>(y) * static_cast<uint64_t>(m_width) + static_cast<uint64_t>(x)) *
           m_bpp;
  }
  const int tx = x / m_tile, ty = y / m_tile;
  const uint64_t i =
      static_cast<uint64_t>(y - ty * m_tile) * static_cast<uint64_t>(tile_width(tx)) +
      static_cast<uint64_t>(x - tx * m_tile);
  return tile_offset(tx, ty) + i * m_bpp;
}

}  // namespace gpusim
