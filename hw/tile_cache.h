// A raster unit's cache of framebuffer tiles, holding their data: the depth
// test keeps depth tiles in one, the ROP colour tiles in another. A unit owns
// its screen tiles exclusively (tile_owner()), so no other cache ever holds
// the same bytes and the caches need no coherence protocol.
//
// Organisation: `entries` tiles, fully associative, least recently used
// replaced (an invalid entry first), write-back. The tag lookup is modelled by
// a table from screen tile to entry, which is what a CAM over the entries'
// tags answers in one cycle. A tile's data is tile_size x tile_size pixels;
// tiles on the framebuffer's right and top edges use only the part inside it.
//
// Memory traffic. Linear surfaces (Layout::surface not tiled): a tile moves
// as one request per pixel row (the buffer is row-major, row 0 at the
// bottom, so a tile row is contiguous), every row of a transfer issued at
// the same local time offset: the bus streams them back to back and the
// memory latency is paid once per tile. Tiled surfaces (hw/surface_layout.h):
// a tile is one contiguous block of w * h * bytes_per_pixel bytes (its part
// inside the framebuffer), moved as one transfer split into bursts of at
// most Layout::max_burst_bytes, all issued at the same offset. The requests
// of one miss, or of one flush, are one group on the memory's arbiter
// (hw/memory.h): issued together, then one MemoryPort::wait_round() (a
// delta, no simulated time) tells when they complete.
//   - Miss: the victim's tile is written back if it is dirty (posted: the
//     stage does not wait for it, but it is issued first, so the arbiter
//     grants it the bus first), then the new tile is read; the caller waits
//     for the last read. A miss on a cleared tile reads nothing and so does
//     not wait for the round at all: its write-back's completion is
//     collected by the next round the cache waits for.
//   - No fill (Layout::skip_overwritten_fill): a miss the caller says will be
//     overwritten entirely (lookup's `overwrite`: every pixel and sample of
//     the tile inside the framebuffer written, old values unused) allocates
//     without reading, like a cleared tile.
//   - Fast clear: clear() drops every entry without writing it back and marks
//     every owned tile "cleared" (one flag per tile, as a fast-clear table in
//     hardware). The first access to a cleared tile fills an entry with the
//     clear value instead of reading memory; the entry is dirty, since memory
//     does not hold the cleared data yet.
//   - flush(): writes back every dirty entry (which stays cached, now clean)
//     and every owned tile still marked cleared, so that memory holds the
//     whole buffer; the caller waits for the last write, and for every write
//     posted earlier.
//   - Compression (Layout::compress, tiled only): an on-chip table keeps each
//     tile's state: CLEARED (the fast-clear flag), COMPRESSED (with its
//     encoded size) or UNCOMPRESSED. Every write-back goes through the
//     compressor (hw/tile_codec.h), computed once per write-back: it leaves
//     compressor_latency cycles after it would have, moving the encoded size
//     when that is smaller than the tile, else the raw tile; a fill of a
//     COMPRESSED tile reads the encoded size and the data is usable
//     decompressor_latency cycles after it arrives. The memory keeps the
//     decoded bytes (written and read untimed, MemoryPort::debug_*): only
//     the traffic and the time change.
//
// Counters (added to the owner's StatGroup): cache_hits, cache_misses (tiles
// read from memory), cache_clear_fills (tiles filled from the clear value),
// cache_overwrite_allocs (misses allocated without a read, no-fill path);
// every lookup is exactly one of the four. cache_writebacks (tiles written
// back on eviction or flush, cleared tiles included), bytes_read,
// bytes_written (bytes moved: encoded sizes for compressed tiles);
// compression: tiles_compressed, tiles_uncompressed (write-backs encoded /
// stored raw), compression_bytes_saved, compressed_fills,
// compressor_busy_cycles, decompressor_busy_cycles.
#pragma once

#include <cstdint>
#include <systemc>
#include <vector>

#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "hw/stats.h"
#include "hw/surface_layout.h"

namespace gpusim {

class TileCache {
 public:
  // Where the buffer lives and which tiles this cache serves.
  struct Layout {
    uint64_t base = 0;  // address of pixel (0, 0)
    int width = 0, height = 0;
    unsigned bytes_per_pixel = 4;
    unsigned tile_size = 16;
    unsigned units = 1;  // tiles with tile_owner(tx, ty, units) == unit
    unsigned unit = 0;
    // Surfaces and compression (GpuConfig::surfaces, GpuConfig::compression).
    bool tiled = false;
    unsigned max_burst_bytes = 1024;
    bool skip_overwritten_fill = false;
    bool compress = false;        // needs tiled
    unsigned codec_channels = 1;  // tile_codec.h's view of a sample
    unsigned codec_channel_bytes = 4;
    unsigned granule = 32;  // bus bytes per cycle: encoded sizes round up to it
    unsigned compressor_latency = 0, decompressor_latency = 0;  // cycles
    sc_core::sc_time cycle = sc_core::sc_time(1, sc_core::SC_NS);

    // The surface and compression fields from the configuration; `compress`
    // is the buffer's compression.depth or compression.colour.
    void set_surfaces(const GpuConfig& c, bool compress_buffer) {
      tiled = c.surfaces.tiled;
      max_burst_bytes = c.surfaces.max_burst_bytes;
      skip_overwritten_fill = c.surfaces.skip_overwritten_fill;
      compress = compress_buffer;
      granule = c.memory.bytes_per_cycle;
      compressor_latency = c.compression.compressor_latency;
      decompressor_latency = c.compression.decompressor_latency;
      cycle = c.cycle();
    }
  };

  // Counters are registered in `stats`; `mem` and `stats` must outlive the
  // cache. Nothing is allocated until configure().
  TileCache(MemoryPort& mem, StatGroup& stats, unsigned entries);

  // Sets the buffer and drops every entry and clear flag (without writing
  // anything back). Tile data is allocated lazily, per entry on first use.
  void configure(const Layout& layout);
  // Between frames: every entry empty and unused, no write outstanding, as
  // constructed (configure() follows).
  void reset();
  const Layout& layout() const { return m_layout; }

  // The entry holding tile (tx, ty), loading it on a miss. `t` is the caller's
  // local time offset from now: requests are issued at t, and on a miss t
  // advances to when the tile's data has arrived. `overwrite`: the caller
  // will write every pixel (sample) of the tile and never read the old ones,
  // so with skip_overwritten_fill a miss reads nothing. A tile this unit does
  // not own is a model bug (SC_REPORT_ERROR).
  unsigned lookup(int tx, int ty, sc_core::sc_time& t, bool overwrite = false);

  // Pixel (x, y) of the tile held by `entry` (x, y are framebuffer pixels
  // inside that tile): bytes_per_pixel bytes, little endian.
  uint8_t* pixel(unsigned entry, int x, int y) {
    Entry& e = m_entries[entry];
    return e.data.data() +
           (static_cast<size_t>(y - e.y0) * m_layout.tile_size + static_cast<size_t>(x - e.x0)) *
               m_layout.bytes_per_pixel;
  }
  void mark_dirty(unsigned entry) { m_entries[entry].dirty = true; }

  // Whether a batch's covered pixels (`sample_masks` empty) or samples (one
  // mask per covered pixel, `samples` per pixel) are every one of a single
  // tile's inside the framebuffer: the lookup's `overwrite` when the writes
  // are unconditional. A batch's stamps never cover a pixel twice. Only
  // counted when skip_overwritten_fill is on (false otherwise).
  bool covers_tile(const std::vector<Stamp>& stamps, const std::vector<uint16_t>& sample_masks,
                   unsigned samples) const;

  // Fast clear of every owned tile to `value` (bytes_per_pixel bytes); no
  // memory traffic until the tiles are touched or flushed.
  void clear(const uint8_t* value);

  // Writes back every dirty entry and every tile still marked cleared,
  // issuing the writes at local offset `t`; t advances to when the last of
  // them, and of every write posted before, has completed.
  void flush(sc_core::sc_time& t);

 private:
  struct Entry {
    bool valid = false;
    bool dirty = false;
    int tile = -1;       // screen tile index ty * tiles_x + tx
    int x0 = 0, y0 = 0;  // the tile's lower-left pixel
    uint64_t last_use = 0;
    std::vector<uint8_t> data;  // tile_size^2 pixels, rows bottom-up
  };

  // Issues the requests moving the tile's part inside the framebuffer, at
  // local offset t (their completion comes from the port's next round).
  // Returns the decompressor latency a fill must add (zero otherwise).
  sc_core::sc_time transfer(bool write, int tile, uint8_t* data, sc_core::sc_time t);
  void fill_clear(Entry& e);
  unsigned choose_victim() const;
  bool owned(int tx, int ty) const {
    return static_cast<unsigned>(tx + ty) % m_layout.units == m_layout.unit;
  }

  MemoryPort& m_mem;
  Layout m_layout;
  int m_tiles_x = 0, m_tiles_y = 0;
  std::vector<Entry> m_entries;
  std::vector<int32_t> m_entry_of_tile;  // per screen tile: entry index or -1
  std::vector<uint8_t> m_cleared;        // per screen tile: holds the clear value, not in memory
  std::vector<uint8_t> m_clear_value;    // one pixel
  SurfaceLayout m_surface;
  std::vector<uint32_t> m_encoded;  // per screen tile: encoded bytes in memory, 0 = raw
  std::vector<uint8_t> m_stage;     // a tile packed as its block (w pixels a row)
  uint64_t m_tick = 0;
  sc_core::sc_time m_writes_done;  // absolute completion time of the last posted write

  uint64_t& m_hits;
  uint64_t& m_misses;
  uint64_t& m_clear_fills;
  uint64_t& m_writebacks;
  uint64_t& m_bytes_read;
  uint64_t& m_bytes_written;
  uint64_t& m_overwrite_allocs;
  uint64_t& m_tiles_compressed;
  uint64_t& m_tiles_uncompressed;
  uint64_t& m_bytes_saved;
  uint64_t& m_compressed_fills;
  uint64_t& m_compressor_busy;
  uint64_t& m_decompressor_busy;
};

}  // namespace gpusim
