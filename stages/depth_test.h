// Depth test, one per unit (docs/pipeline-spec.md, sections 9 to 11): early
// depth, since no shader can discard a fragment here. For every covered pixel
// of a stamp it rebuilds the edge values E1 and E2 by stepping from the stamp
// origin's (pixel (i, j): e_k + i * a_k * 256 + j * b_k * 256, exact int64),
// interpolates z = z0 + (f1 (z1 - z0) + f2 (z2 - z0)) / float(area2) with
// f_k = float(E_k), in that float order (exact for a triangle of constant
// depth), adds the triangle's polygon offset, encodes z in the buffer's
// format and compares it with the stored value; a passing value is stored
// when depth_write is on. Failing pixels leave the stamp's mask, empty stamps
// leave the batch, and an empty batch is not forwarded. The forwarded batch's
// `depth` vector stays empty: nothing after this stage needs z.
// depth_test off: every pixel passes, nothing is read or written. The depth
// buffer is not touched either when no stored value can matter (func never,
// or always without depth_write).
//
// Depth buffer access goes through this unit's TileCache (hw/tile_cache.h,
// config.tile_cache_entries tiles of frame.depth_address,
// depth_bytes_per_pixel(format) bytes per pixel), looked up once per stamp
// (a stamp lies inside one tile: the rasterizer aligns stamps to tiles).
// With surfaces.skip_overwritten_fill, a batch with func always and
// depth_write that covers every pixel (sample) of its one tile allocates it
// without a read; the layout and compression.depth are the cache's.
// clear: a fast clear of every tile this unit owns to
// encode_depth(clear_depth); cleared tiles reach memory when first evicted or
// at end_of_frame.
//
// Multisampled frames (section 14): the buffer holds N depths per pixel, a
// pixel's samples adjacent, so tiles are N times larger; each covered sample
// (StampBatch::samples) is interpolated at its own point (E1, E2 plus the
// sample's offset a * dx_s + b * dy_s), tested and stored, and a pixel goes
// on with the samples that passed.
//
// Cost model, per token read at time t:
//   work:  busy = ii * stamps * ceil(N / samples_per_pass) (at least ii) +
//          the memory stall: the misses of
//          the batch are served one after another (a blocking cache), each
//          request issued when the previous miss completed, starting at t;
//          the stall is the completion of the last one, rounded up to whole
//          cycles. The batch is written at t + busy, readable `latency`
//          cycles later.
//   clear: busy = ii; forwarded like a batch.
//   end_of_frame: the write-back of every dirty or still-cleared tile is
//          issued at t + latency (when the pipeline has drained); busy lasts
//          until the last write completes, at least ii; the token is then
//          forwarded, readable at once.
// ii and latency are config.stage("depth_test").
//
// Hierarchical Z (config.hierarchical_z.enabled; stages/tile_rasterizer.h):
// after a batch with hz_seq != 0 (one the rasterizer counted as depth
// writing), the tile's exact [min, max] over its pixels inside the
// framebuffer and all their samples is sent to the rasterizer, stamped with
// the time the batch is done and the clear epoch (depth clears and frames
// seen). It comes from per-stamp ranges kept beside the tile: the stamps the
// batch wrote are rescanned, all of them when the tile's are not known in
// this epoch (its first access after a clear or at frame start: a fill),
// then reduced. The reduction is off the batch's path: no cycles. Hardware
// keeps the stamp ranges per cache entry (tile_size^2 / stamp pixels x 2 x
// 32 bits: 1 Kbit for 16 x 16 tiles of 4 x 4 stamps); the model keeps them
// per screen tile, which gives the same values, since only this unit writes
// its tiles.
#pragma once

#include <array>
#include <systemc>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/hierarchical_z.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"
#include "hw/tile_cache.h"
#include "hw/trace_probe.h"

namespace gpusim {

class DepthTest : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<StampBatch> in;
  FifoOutPort<StampBatch> out;
  MemoryPort mem;

  DepthTest(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
            unsigned unit);
  // Its memory requests wait for the kernel and its hierarchical-Z updates
  // carry their stamps (PipelineStage: temporal decoupling).
  bool decouplable() const override { return true; }

  // Tracing: every tested fragment is reported to `probe` (nullptr: none).
  void set_fragment_probe(FragmentProbe* probe) override {
    if constexpr (kTraceHooks) m_probe = probe;  // a build without hooks ignores it
  }

  // Hierarchical Z: the link to this unit's rasterizer (the GPU connects it
  // when config.hierarchical_z.enabled; must outlive the unit).
  void set_hz_link(HzUpdateLink* link) { m_hz_link = link; }

  uint64_t fragments_passed() const { return m_fragments_passed; }
  uint64_t depth_clears() const { return m_depth_clears; }
  uint64_t samples_passed() const { return m_samples_passed; }

 private:
  void run();
  void reset_state() override;
  // Tests the batch's pixels, compacting its stamps in place; returns the
  // memory stall (local offset) through `t`.
  void test(StampBatch& batch, sc_core::sc_time& t);
  uint64_t stall_cycles(const sc_core::sc_time& t) const;
  // The per-fragment loop of test() for one depth format and, unless Func is
  // never (then read from `st`), one depth function.
  template <DepthFormat F>
  void test_format(StampBatch& batch, sc_core::sc_time& t, const RenderState& st,
                   FragmentProbe* probe);
  template <DepthFormat F, CompareFunc Func>
  void test_stamps(StampBatch& batch, sc_core::sc_time& t, const RenderState& st,
                   FragmentProbe* probe);
  // Multisampled (spec section 14): per covered sample, z from E1 and E2 at
  // the sample's point; a pixel survives with the samples that passed.
  template <DepthFormat F>
  void test_samples(StampBatch& batch, sc_core::sc_time& t, const RenderState& st,
                    FragmentProbe* probe);
  // Fills m_offset for the triangle's edge steps (kept while they are unchanged).
  void update_offsets(const RasterPrimitive& tri);
  // Hierarchical Z: the exact range of `tile` (held by cache entry `entry`)
  // after a batch, from the per-stamp ranges (the written stamps'
  // recomputed, or every stamp's when the tile's are not known this epoch).
  HzRange hz_tile_range(int tile, unsigned entry);
  // Notes a stamp at (x, y) the batch wrote.
  void hz_note(int x, int y);

  // log2 of the tile side and of the stamp width (powers of two): a stamp's
  // tile is its origin >> m_tile_shift, a mask bit's row is bit >> m_stamp_shift.
  const int m_tile_shift, m_stamp_shift;
  FragmentProbe* m_probe = nullptr;

  // Per-fragment setup hoisted to per triangle / per frame: the offsets of
  // E1 and E2 from a stamp's origin to its pixel p = j * w + i,
  // i * a_k * 256 + j * b_k * 256 (at most 64 pixels, the width of
  // Stamp::mask) for the edge steps m_step_x, m_step_y; and the byte offset
  // of pixel p from the stamp origin's inside a cached tile.
  std::array<std::array<EdgeValue, 64>, 2> m_offset{};
  std::array<EdgeValue, 2> m_step_x{}, m_step_y{};
  bool m_offset_valid = false;
  std::array<size_t, 64> m_pixel_offset{};

  size_t m_clears_seen = 0;  // this frame's clear tokens so far (FrameState::clear)

  // Hierarchical Z (null link: off). Per screen tile, per stamp of it, the
  // range of its stored values inside the framebuffer, valid when the tile's
  // m_hz_known equals the epoch + 1; the last cache entry looked up, and the
  // stamps (index in the tile) a batch wrote.
  HzUpdateLink* m_hz_link = nullptr;
  uint32_t m_hz_epoch = 0;  // depth clears and frames passed, as the rasterizer counts them
  int m_tiles_x = 0, m_stamps_x = 0, m_stamps_per_tile = 0;
  std::vector<HzRange> m_hz_stamp;
  std::vector<uint32_t> m_hz_known;
  unsigned m_hz_entry = 0;
  std::vector<int> m_hz_written;

  uint64_t& m_depth_clears =
      m_stats.counter("depth_clears", "clears", "depth clears executed (fast clears)");
  uint64_t& m_stamps = m_stats.counter("stamps", "stamps", "stamps tested");
  uint64_t& m_stamps_passed =
      m_stats.counter("stamps_passed", "stamps", "stamps with a pixel left");
  uint64_t& m_fragments_in = m_stats.counter("fragments_in", "fragments", "covered pixels tested");
  uint64_t& m_fragments_passed = m_stats.counter(
      "fragments_passed", "fragments", "pixels passing the depth test (all when it is off)");
  uint64_t& m_samples_passed =
      m_stats.counter("samples_passed", "samples",
                      "covered samples passing the depth test (one per pixel unless multisampled)");
  uint64_t& m_memory_stall_cycles = m_stats.counter(
      "memory_stall_cycles", "cycles",
      "cycles of busy_cycles beyond ii per stamp or token: tile reads, or at end_of_frame "
      "the drain and write-back");
  uint64_t& m_hz_updates_sent = m_stats.counter(
      "hz_updates_sent", "updates", "exact tile ranges sent to the rasterizer's hierarchical Z");
  TileCache m_cache;
  bool m_overwrite = false;  // this batch overwrites its whole tile (TileCache::lookup)
};

}  // namespace gpusim
