#include "hw/tile_cache.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "hw/tile_codec.h"

namespace gpusim {

TileCache::TileCache(MemoryPort& mem, StatGroup& stats, unsigned entries)
    : m_mem(mem),
      m_entries(std::max(entries, 1u)),
      m_hits(stats.counter("cache_hits", "tiles", "tile lookups that found the tile cached")),
      m_misses(
          stats.counter("cache_misses", "tiles", "tile lookups that read the tile from memory")),
      m_clear_fills(stats.counter("cache_clear_fills", "tiles",
                                  "tile lookups filled from the fast-clear value, no read")),
      m_writebacks(stats.counter("cache_writebacks", "tiles", "tiles written back to memory")),
      m_bytes_read(stats.counter("bytes_read", "bytes", "bytes read from memory")),
      m_bytes_written(stats.counter("bytes_written", "bytes", "bytes written to memory")),
      m_overwrite_allocs(stats.counter(
          "cache_overwrite_allocs", "tiles",
          "tile misses allocated without a read: the batch overwrites the whole tile")),
      m_tiles_compressed(
          stats.counter("tiles_compressed", "tiles", "write-backs that moved the encoded tile")),
      m_tiles_uncompressed(stats.counter("tiles_uncompressed", "tiles",
                                         "write-backs through the compressor stored raw")),
      m_bytes_saved(stats.counter("compression_bytes_saved", "bytes",
                                  "bytes not moved thanks to compression, reads and writes")),
      m_compressed_fills(
          stats.counter("compressed_fills", "tiles", "tile misses that read an encoded tile")),
      m_compressor_busy(stats.counter("compressor_busy_cycles", "cycles",
                                      "cycles the compressor spent on write-backs")),
      m_decompressor_busy(stats.counter("decompressor_busy_cycles", "cycles",
                                        "cycles the decompressor spent on fills")) {}

void TileCache::configure(const Layout& layout) {
  m_layout = layout;
  const int t = static_cast<int>(layout.tile_size);
  m_tiles_x = (layout.width + t - 1) / t;
  m_tiles_y = (layout.height + t - 1) / t;
  for (Entry& e : m_entries) {
    e.valid = false;
    e.dirty = false;
  }
  m_entry_of_tile.assign(static_cast<size_t>(m_tiles_x) * m_tiles_y, -1);
  m_cleared.assign(m_entry_of_tile.size(), 0);
  m_clear_value.assign(layout.bytes_per_pixel, 0);
  m_surface = SurfaceLayout(layout.tiled, layout.width, layout.height, layout.bytes_per_pixel,
                            layout.tile_size, layout.units);
  m_encoded.assign(m_entry_of_tile.size(), 0);
}

void TileCache::reset() {
  for (Entry& e : m_entries) e = Entry{};
  m_tick = 0;
  m_writes_done = sc_core::SC_ZERO_TIME;
}

unsigned TileCache::lookup(int tx, int ty, sc_core::sc_time& t, bool overwrite) {
  const int tile = ty * m_tiles_x + tx;
  const int32_t hit = m_entry_of_tile[static_cast<size_t>(tile)];
  if (hit >= 0) {
    ++m_hits;
    m_entries[static_cast<size_t>(hit)].last_use = ++m_tick;
    return static_cast<unsigned>(hit);
  }
  if (tx < 0 || ty < 0 || tx >= m_tiles_x || ty >= m_tiles_y || !owned(tx, ty)) {
    SC_REPORT_ERROR(
        "gpusim/tile_cache",
        ("tile (" + std::to_string(tx) + ", " + std::to_string(ty) +
         ") is outside the framebuffer or not owned by unit " + std::to_string(m_layout.unit))
            .c_str());
  }

  const unsigned index = choose_victim();
  Entry& e = m_entries[index];
  if (e.valid) {
    if (e.dirty) {
      // Posted: the stage does not wait for it, but it is issued before the
      // fill, so at the same arrival the arbiter grants it first.
      transfer(true, e.tile, e.data.data(), t);
      ++m_writebacks;
    }
    m_entry_of_tile[static_cast<size_t>(e.tile)] = -1;
  }
  const size_t tile_bytes =
      static_cast<size_t>(m_layout.tile_size) * m_layout.tile_size * m_layout.bytes_per_pixel;
  if (e.data.size() != tile_bytes) e.data.assign(tile_bytes, 0);
  e.valid = true;
  e.tile = tile;
  e.x0 = tx * static_cast<int>(m_layout.tile_size);
  e.y0 = ty * static_cast<int>(m_layout.tile_size);
  e.last_use = ++m_tick;
  if (m_cleared[static_cast<size_t>(tile)]) {
    // No read, so nothing to wait for: a write-back posted above is
    // collected by the next wait_round().
    m_cleared[static_cast<size_t>(tile)] = 0;
    fill_clear(e);
    e.dirty = true;
    ++m_clear_fills;
  } else if (overwrite && m_layout.skip_overwritten_fill) {
    // The caller writes every byte that matters before anything reads it.
    e.dirty = true;
    ++m_overwrite_allocs;
  } else {
    const sc_core::sc_time decode = transfer(false, tile, e.data.data(), t);
    // The data is in the entry already; the round says when it arrived.
    const MemoryCompletion done = m_mem.wait_round();
    m_writes_done = std::max(m_writes_done, done.writes);
    t = done.reads + decode - m_mem.now();
    e.dirty = false;
    ++m_misses;
  }
  m_entry_of_tile[static_cast<size_t>(tile)] = static_cast<int32_t>(index);
  return index;
}

bool TileCache::covers_tile(const std::vector<Stamp>& stamps,
                            const std::vector<uint16_t>& sample_masks, unsigned samples) const {
  if (!m_layout.skip_overwritten_fill || stamps.empty()) return false;
  const int size = static_cast<int>(m_layout.tile_size);
  const int tx = stamps.front().x / size, ty = stamps.front().y / size;
  uint64_t covered = 0;
  for (const Stamp& s : stamps) {
    if (s.x / size != tx || s.y / size != ty) return false;
    if (sample_masks.empty()) covered += static_cast<uint64_t>(__builtin_popcountll(s.mask));
  }
  if (!sample_masks.empty()) {
    samples = std::max(samples, 1u);
    for (const uint16_t m : sample_masks) covered += static_cast<uint64_t>(__builtin_popcount(m));
  } else {
    samples = 1;
  }
  return covered == static_cast<uint64_t>(m_surface.tile_width(tx)) *
                        static_cast<uint64_t>(m_surface.tile_height(ty)) * samples;
}

void TileCache::clear(const uint8_t* value) {
  std::memcpy(m_clear_value.data(), value, m_layout.bytes_per_pixel);
  for (Entry& e : m_entries) {
    if (e.valid) m_entry_of_tile[static_cast<size_t>(e.tile)] = -1;
    e.valid = false;
    e.dirty = false;
  }
  for (int ty = 0; ty < m_tiles_y; ++ty) {
    for (int tx = 0; tx < m_tiles_x; ++tx) {
      if (owned(tx, ty)) m_cleared[static_cast<size_t>(ty) * m_tiles_x + tx] = 1;
    }
  }
}

void TileCache::flush(sc_core::sc_time& t) {
  const sc_core::sc_time issue = t;
  for (Entry& e : m_entries) {
    if (!e.valid || !e.dirty) continue;
    transfer(true, e.tile, e.data.data(), issue);
    e.dirty = false;
    ++m_writebacks;
  }
  // Tiles never touched since the clear: written from one scratch tile
  // (each write copies its bytes when issued).
  std::vector<uint8_t> scratch;
  for (size_t tile = 0; tile < m_cleared.size(); ++tile) {
    if (!m_cleared[tile]) continue;
    if (scratch.empty()) {
      Entry tmp;
      tmp.data.resize(static_cast<size_t>(m_layout.tile_size) * m_layout.tile_size *
                      m_layout.bytes_per_pixel);
      fill_clear(tmp);
      scratch.swap(tmp.data);
    }
    transfer(true, static_cast<int>(tile), scratch.data(), issue);
    m_cleared[tile] = 0;
    ++m_writebacks;
  }
  // One round for the whole flush; it also returns any write-back posted
  // earlier and not yet collected.
  m_writes_done = std::max(m_writes_done, m_mem.wait_round().writes);
  const sc_core::sc_time now = m_mem.now();
  t = std::max(issue, m_writes_done > now ? m_writes_done - now : sc_core::SC_ZERO_TIME);
}

sc_core::sc_time TileCache::transfer(bool write, int tile, uint8_t* data, sc_core::sc_time t) {
  const int size = static_cast<int>(m_layout.tile_size);
  const int tx = tile % m_tiles_x, ty = tile / m_tiles_x;
  const int x0 = tx * size;
  const int y0 = ty * size;
  const int w = std::min(size, m_layout.width - x0);
  const int h = std::min(size, m_layout.height - y0);
  const uint64_t bpp = m_layout.bytes_per_pixel;
  const uint64_t len = static_cast<uint64_t>(w) * bpp;
  const size_t stride = static_cast<size_t>(size) * bpp;
  if (!m_layout.tiled) {
    for (int r = 0; r < h; ++r) {
      const uint64_t addr =
          m_layout.base + (static_cast<uint64_t>(y0 + r) * static_cast<uint64_t>(m_layout.width) +
                           static_cast<uint64_t>(x0)) *
                              bpp;
      uint8_t* row = data + static_cast<size_t>(r) * stride;
      if (write) {
        m_mem.write(addr, row, len, t);
      } else {
        m_mem.read(addr, row, len, t);
      }
    }
    (write ? m_bytes_written : m_bytes_read) += len * static_cast<uint64_t>(h);
    return sc_core::SC_ZERO_TIME;
  }

  // Tiled: the block is the tile's rows of w pixels back to back; the
  // entry's rows are tile_size pixels apart, so a partial tile is packed.
  const uint64_t addr = m_layout.base + m_surface.tile_offset(tx, ty);
  const uint64_t bytes = len * static_cast<uint64_t>(h);
  uint8_t* block = data;
  if (w != size) {
    m_stage.resize(bytes);
    block = m_stage.data();
    if (write) {
      for (int r = 0; r < h; ++r)
        std::memcpy(block + r * len, data + static_cast<size_t>(r) * stride, len);
    }
  }
  uint64_t moved = bytes;
  sc_core::sc_time decode = sc_core::SC_ZERO_TIME;
  uint32_t& encoded = m_encoded[static_cast<size_t>(tile)];
  if (write && m_layout.compress) {
    // The compressor sees the tile once, as it leaves.
    encoded = encoded_tile_bytes(block, bytes, m_layout.codec_channels,
                                 m_layout.codec_channel_bytes, m_layout.granule);
    t += m_layout.cycle * m_layout.compressor_latency;
    m_compressor_busy += m_layout.compressor_latency;
    if (encoded != 0) {
      moved = encoded;
      ++m_tiles_compressed;
      m_mem.debug_write(addr, block, bytes);  // the decoded bytes
    } else {
      ++m_tiles_uncompressed;
    }
  } else if (!write && encoded != 0) {
    moved = encoded;
    decode = m_layout.cycle * m_layout.decompressor_latency;
    m_decompressor_busy += m_layout.decompressor_latency;
    ++m_compressed_fills;
  }
  m_bytes_saved += bytes - moved;
  const uint64_t burst = m_layout.max_burst_bytes;
  for (uint64_t off = 0; off < moved; off += burst) {
    const uint64_t n = std::min(burst, moved - off);
    if (write) {
      m_mem.write(addr + off, block + off, n, t);
    } else {
      m_mem.read(addr + off, block + off, n, t);
    }
  }
  if (!write && moved != bytes) m_mem.debug_read(addr, block, bytes);  // the decoded bytes
  if (!write && block != data) {
    for (int r = 0; r < h; ++r)
      std::memcpy(data + static_cast<size_t>(r) * stride, block + r * len, len);
  }
  (write ? m_bytes_written : m_bytes_read) += moved;
  return decode;
}

void TileCache::fill_clear(Entry& e) {
  const size_t bpp = m_layout.bytes_per_pixel;
  for (size_t p = 0; p + bpp <= e.data.size(); p += bpp) {
    std::memcpy(e.data.data() + p, m_clear_value.data(), bpp);
  }
}

unsigned TileCache::choose_victim() const {
  unsigned best = 0;
  for (unsigned i = 0; i < m_entries.size(); ++i) {
    if (!m_entries[i].valid) return i;
    if (m_entries[i].last_use < m_entries[best].last_use) best = i;
  }
  return best;
}

}  // namespace gpusim
