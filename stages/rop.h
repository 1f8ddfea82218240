// Raster operations, one per unit (docs/pipeline-spec.md, section 12): the
// last stage, writing the colour buffer. A draw whose color_mask is all false
// changes nothing (and touches no memory). Otherwise, per pixel, with source
// s (the interpolated colour) and destination d (the stored colour decoded:
// v / 255 for rgba8, half -> float for rgba16f), for each enabled channel k:
//   out[k] = s[k] F_src(k) + d[k] F_dst(k)   add (subtract, reverse_subtract
//                                             likewise), or s[k] unblended,
// stored as nearbyint(clamp01(out) * 255) for rgba8 and half(out), unclamped,
// for rgba16f. Disabled channels keep their value. Every pixel reaching the
// ROP passed the depth test, so fragments_written counts the pixels of draws
// with at least one channel enabled (the golden model's definition).
//
// The colour buffer (frame.color_address, color_bytes_per_pixel(format)
// bytes per pixel, little endian: rgba8 bytes r, g, b, a; rgba16f four half
// bit patterns) is accessed through this unit's TileCache (hw/tile_cache.h,
// config.tile_cache_entries tiles), looked up once per stamp; the tile is
// read on a miss even when no pixel needs the old colour (no partial-tile
// tracking), except that with surfaces.skip_overwritten_fill a batch that
// covers every pixel (sample) of its one tile, unblended with all four
// channels enabled, allocates it without a read. The layout (tiled or not)
// and compression.colour are the cache's (hw/tile_cache.h). clear: a fast
// clear of every owned tile to the encoded clear_color.
//
// Multisampled frames (section 14): N colours per pixel, a pixel's samples
// adjacent (tiles N times larger); a pixel's colour is blended into and
// written to each sample of its mask (ShadedStampBatch::samples). With a
// resolve after it the ROP passes its control tokens on (`done`) instead of
// retiring them.
//
// Cost model, per token read at time t:
//   work:  busy = ii * stamps * ceil(N / samples_per_pass) (at least ii) + the
//          memory stall of the misses,
//          served one after another from t (a blocking cache), rounded up to
//          whole cycles.
//   clear: busy = ii.
//   end_of_frame: the last stamp's colour reaches the cache `latency` cycles
//          after it was accepted, so the write-back of every dirty or
//          still-cleared tile is issued at t + latency; the ROP is busy until
//          the last write completes (at least ii), then sets frame_done() and
//          notifies frame_done_event().
// ii and latency are config.stage("rop").
#pragma once

#include <cstdint>
#include <systemc>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"
#include "hw/tile_cache.h"
#include "hw/trace_probe.h"

namespace gpusim {

class Rop : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<ShadedStampBatch> in;
  // Bound only when a resolve follows (a multisampled or supersampled
  // frame): the control tokens, passed on once retired.
  sc_core::sc_port<FifoOutIf<ControlToken>, 1, sc_core::SC_ZERO_OR_MORE_BOUND> done;
  MemoryPort mem;

  Rop(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
      unsigned unit);
  // Its memory requests and its end of frame wait for the kernel; its
  // control tokens to the resolve go through a stamped FIFO (PipelineStage:
  // temporal decoupling).
  bool decouplable() const override { return true; }

  // True once an end_of_frame has been flushed to memory, until the next
  // token arrives; the event is notified (delta) when it becomes true.
  const sc_core::sc_event& frame_done_event() const { return m_frame_done_event; }
  bool frame_done() const { return m_frame_done; }

  // Testbench instrumentation, not hardware: when set, the primitive id of
  // every colour write is recorded at index y * width + x.
  void set_last_writer(std::vector<int64_t>* per_pixel) { m_last_writer = per_pixel; }
  // Tracing: every fragment received is reported to `probe` (nullptr: none).
  void set_fragment_probe(FragmentProbe* probe) override {
    if constexpr (kTraceHooks) m_probe = probe;  // a build without hooks ignores it
  }

  uint64_t fragments_written() const { return m_fragments_written; }
  uint64_t color_clears() const { return m_color_clears; }
  uint64_t samples_written() const { return m_samples_written; }

 private:
  void run();
  void reset_state() override;
  void blend(const ShadedStampBatch& batch, sc_core::sc_time& t);
  void check_pixel(int x, int y, const FramebufferDesc& fb) const;
  void forget_last_writers();
  // Calls write(colour, stored bytes) for every covered sample of the
  // batch, in order, with the checks, cache lookups, last-writer record and
  // trace around it; returns the number of colours (pixels) consumed.
  template <typename Write>
  size_t for_each_fragment(const ShadedStampBatch& batch, sc_core::sc_time& t, FragmentProbe* probe,
                           Write&& write);

  // log2 of the tile side and of the stamp width (powers of two): a stamp's
  // tile is its origin >> m_tile_shift, a mask bit's row is bit >> m_stamp_shift.
  const int m_tile_shift, m_stamp_shift;
  bool m_frame_done = false;
  sc_core::sc_event m_frame_done_event;
  std::vector<int64_t>* m_last_writer = nullptr;
  FragmentProbe* m_probe = nullptr;

  size_t m_clears_seen = 0;  // this frame's clear tokens so far (FrameState::clear)

  uint64_t& m_color_clears =
      m_stats.counter("color_clears", "clears", "colour clears executed (fast clears)");
  uint64_t& m_stamps = m_stats.counter("stamps", "stamps", "stamps received");
  uint64_t& m_fragments_in = m_stats.counter("fragments_in", "fragments", "pixels received");
  uint64_t& m_fragments_written =
      m_stats.counter("fragments_written", "fragments",
                      "pixels written: passed depth, at least one channel enabled");
  uint64_t& m_fragments_blended =
      m_stats.counter("fragments_blended", "fragments", "written with blending");
  uint64_t& m_samples_written = m_stats.counter(
      "samples_written", "samples", "samples written (the pixels' covered samples that passed)");
  uint64_t& m_memory_stall_cycles = m_stats.counter(
      "memory_stall_cycles", "cycles",
      "cycles of busy_cycles beyond ii per stamp or token: tile reads, or at end_of_frame "
      "the drain and write-back");
  uint64_t& m_frames = m_stats.counter("frames", "frames", "end_of_frame tokens flushed");
  TileCache m_cache;
  bool m_overwrite = false;  // this batch overwrites its whole tile (TileCache::lookup)
};

}  // namespace gpusim
