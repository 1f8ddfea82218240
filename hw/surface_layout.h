// Where a framebuffer surface's pixels live in GPU memory (the colour and
// depth buffers; bytes_per_pixel counts every sample of a pixel). Two layouts
// of the same width * height * bytes_per_pixel bytes, so the buffers occupy
// exactly what they did row-major (docs/architecture.md, "Memory"):
//   - linear (surfaces.tiled false): row-major, row 0 at the bottom.
//   - tiled: every screen tile one contiguous block, its pixels row-major
//     inside it (w pixels a row for a tile w pixels wide). Full tiles come
//     first, each tile_size^2 * bytes_per_pixel bytes, so with the buffer
//     aligned to that size they stay aligned; the partial tiles on the right
//     and top edges follow, packed. Full tiles are ordered unit-interleaved:
//     the first full tile of unit 0 (tile_owner), of unit 1, ..., then the
//     second of each, ... (a unit with no tile left is skipped). With
//     memory.interleave_bytes = a tile's bytes and C channels, block b is on
//     channel b % C: a unit's consecutive tiles are `units` channels apart,
//     so C = units gives each unit a channel of its own (no unit queues
//     behind another) and C a multiple of units spreads a unit over C/units.
// Pure arithmetic, no SystemC: the tile caches, the resolve and the
// testbench's readout (gpu_run.cpp) all use it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gpusim {

class SurfaceLayout {
 public:
  SurfaceLayout() = default;
  SurfaceLayout(bool tiled, int width, int height, unsigned bytes_per_pixel, unsigned tile_size,
                unsigned units);

  bool tiled() const { return m_tiled; }
  int tiles_x() const { return m_tiles_x; }
  int tiles_y() const { return m_tiles_y; }
  uint64_t size() const {
    return static_cast<uint64_t>(m_width) * static_cast<uint64_t>(m_height) * m_bpp;
  }
  // The part of tile (tx, ty) inside the surface: w x h pixels.
  int tile_width(int tx) const;
  int tile_height(int ty) const;
  // Tiled: byte offset of tile (tx, ty)'s block from the surface's base.
  uint64_t tile_offset(int tx, int ty) const {
    return m_block_offset[static_cast<size_t>(ty) * static_cast<size_t>(m_tiles_x) +
                          static_cast<size_t>(tx)];
  }
  // Byte offset of pixel (x, y) from the base, in either layout.
  uint64_t pixel_offset(int x, int y) const;

 private:
  bool m_tiled = false;
  int m_width = 0, m_height = 0;
  unsigned m_bpp = 0;
  int m_tile = 16;
  int m_tiles_x = 0, m_tiles_y = 0;
  std::vector<uint64_t> m_block_offset;  // per screen tile (ty * tiles_x + tx); tiled only
};

}  // namespace gpusim
