// Tile rasterizer, one per unit: walks the unit's own screen tiles inside a
// primitive's pixel bounding box and emits the covered pixels as stamps
// (docs/pipeline-spec.md, sections 8, 8b, 8c; Mesa llvmpipe's hierarchical
// scheme). Triangles, diamond-exit lines and points take the tile walk
// below over the primitive's coverage edges (RasterPrimitive::coverage: 3
// for a triangle, 2 for a diamond-exit line, whose box already bounds its
// ends, 0 for a point, whose box is its square); Bresenham lines take the
// line walker described after it.
//
// Walk: tiles of config.tile_size in rows bottom-up, left to right, only
// those with tile_owner(tx, ty, units) == unit. Per tile, one test of the
// coverage edges at the tile's extreme pixel centres (chosen by the signs of a
// and b):
//   - reject: some edge's maximum over the tile's pixel centres is below its
//     bias: nothing covered, next tile;
//   - accept: every edge's minimum is >= its bias: every pixel centre of the
//     tile is covered, so its stamps inside the box are emitted without
//     per-pixel tests;
//   - otherwise the stamps (config.stamp = [w, h], aligned to the tile) that
//     intersect the box are evaluated, one stamp per cycle: the edge-function
//     core tests all w x h pixels against all three edges in parallel, from
//     the edge values at the stamp origin plus per-pixel offsets
//     i * a * 256 + j * b * 256 precomputed once per triangle.
// Edge values at stamp origins come by incremental stepping: E at the tile's
// origin pixel centre from the triangle's equation once per tile, then
// + a * (w * 256) per stamp to the right and + b * (h * 256) per stamp row
// (a tile cut by the box starts at its first stamp column and row inside the
// box: + i0 * a * (w * 256) + j0 * b * (h * 256)).
// Pixels outside the box (hence outside the draw rectangle: framebuffer,
// viewport and scissor, spec section 8d) are masked off; tiles wholly
// outside it are never visited.
// One StampBatch per (primitive, tile) holds the tile's non-empty stamps in
// walk order (rows bottom-up, left to right) with the raw interpolation
// values (RasterPrimitive::edge, no bias) at each stamp's origin pixel
// centre; tiles without coverage emit nothing. For a triangle they are the
// coverage edges' values the walk stepped; for a line or a point they are
// evaluated at the stamp's origin when it is emitted (a multiply-add per
// function, inside the stamp's ii).
//
// Line walker (Bresenham, spec section 8b): the integer midpoint algorithm
// from the end points' pixels, one step per pixel along the major axis M,
// the minor offset k kept by a decision variable d in (-2|dM|, 0]: per step
// d += 2|dN|, and d > 0 steps the minor axis (k += 1, d -= 2|dM|); a tie,
// d = 0, does not. Each step's pixel is replicated to the w pixels
// n - floor((w - 1) / 2) ... + w - 1 of the minor axis. The walk starts at
// the first drawn step whose major coordinate lies in the box (first end
// flag; k and d there in closed form, one division) and ends at the last
// (last end flag, box). It proceeds in spans, the steps of one tile column
// (x-major) or tile row (y-major). Per span, the unit tests whether it owns
// any tile the span can reach (minor range from the current pixel, widened
// by the span's length and the replication): if not, it jumps past the span
// (k and d in closed form again); if so, it walks every step of the span,
// keeps the pixels in its own tiles inside the box, and then emits one
// batch per tile, in increasing minor tile order, its stamps rows bottom-up,
// left to right.
//
// Bit widths: the box lies in the framebuffer (side <= 8192 pixels), so every
// tile and stamp the walk touches lies in [0, 8192 + 256) pixels: pixel
// centres are < 2^22 subpixels. Every value the stepping produces (tile
// origins, tile corners, stamp origins, pixels) is the exact equation
// a * px + b * py + c at such a point: |a|, |b| < 2^25 give products < 2^47,
// |c| < 2^50 (a line's band edge: < 2^50 + 2^40), so |E| < 2^52, and int64
// holds it with 11 bits to spare. The steps themselves are < 2^25 * 2^16 =
// 2^41. A line's or point's interpolation functions evaluated at a stamp
// origin are below 2^52 too (hw/fixed_point.h).
// The line walker's end point pixels lie within +-2^16 (snapped coordinates
// saturate at +-2^24 subpixels), so |dM|, |dN| < 2^17 and the decision
// variable and 2 i |dN| stay below 2^35: a 36-bit signed register.
//
// Multisampling (spec section 14; docs/architecture.md, "Multisampling and
// the resolve"): each coverage edge's offsets to the N sample points,
// a * dx_s + b * dy_s, are computed per primitive; the tile tests add their
// extremes, and a partial stamp tests each pixel at its N samples, emitting
// one sample mask per covered pixel (StampBatch::samples); accepted tiles emit
// full masks. Setup has widened the box and given lines and points four edges.
//
// Cost model (cycles) of the tile walk, per primitive: 1 per tile visited (the tile test),
// plus ii(rasterizer) per stamp evaluated in a partial tile and per stamp
// emitted from an accepted tile; stamps outside the box are never visited,
// rejected tiles cost only their test; tiles outside the box (outside the
// scissor or the viewport) cost nothing. With N samples per pixel every stamp
// takes passes = ceil(N / samples_per_pass) times ii. busy_cycles =
// tiles_visited + ii * passes * (stamps_evaluated + stamps_accepted) + ii *
// control tokens. With config.tile_test_overlap the tile test runs one tile
// ahead of the stamps (a coarse stage feeding the fine one): a tile that
// evaluates or emits any stamp costs only its stamps' cycles, and only tiles
// without one (rejected, culled, or whose box-clipped stamps are all empty
// before evaluation) pay the test's cycle.
// Timing: the unit waits the cycles of the tiles walked since its last
// output, then writes that tile's batch, readable latency(rasterizer) cycles
// later; cycles of trailing tiles without coverage are waited at the end of
// the triangle. So a triangle read at t whose last tile has coverage has its
// last batch readable at t + (its cycles) + latency when the output FIFO has
// room, and big triangles stream tile by tile.
// Line walker, per Bresenham line: 1 cycle to enter the walk, 1 per span
// tested (a jumped span costs only that), 1 per step walked in this unit's
// spans (all w replicated pixels of a step at once), and ii(rasterizer) per
// stamp emitted; a span's batches are written after its steps, each after
// the cycles before it. busy_cycles = lines_walked + line_spans +
// line_steps + ii * line_stamps (+ ii * control tokens). Every unit the
// distributor sends the line to walks it this way, skipping the spans of
// other units' tiles.
// A control token costs ii(rasterizer) and is forwarded with the latency.
// No memory traffic.
//
// Hierarchical Z (config.hierarchical_z, issue #11; off by default): per
// screen tile of this unit a block [min, max] of the stored depth values
// (the depth buffer's encoding, every sample), conservative: every stored
// value of the tile lies in it. Frame start: [0, 2^32 - 1] (unknown); a depth
// clear passing the unit sets every block to the clear value. Per triangle,
// its range P = hz_primitive_range() (hw/hierarchical_z.cpp: the vertices'
// window z widened by a rounding margin and the polygon offset, encoded;
// proved there to bound every value the depth test computes for it; the
// full range for a vertex depth or offset that is not finite or |z| >= 2^62,
// where that arithmetic can give NaN, stored as 0), and per
// tile the coverage test keeps, one HZ test against the block B:
//   less: cull if P.min >= B.max; lequal: P.min > B.max; greater:
//   P.max <= B.min; gequal: P.max < B.min; equal: P outside B; never:
//   always; always, notequal, depth test off, lines and points: never.
// A culled tile emits nothing. A depth-writing batch (depth test on, write
// on, func not never) widens its block first: less and lequal lower min to
// P.min, greater and gequal raise max to P.max, the others take the union
// (a line's or point's P is the full range); it carries the block's
// incremented sequence number (StampBatch::hz_seq). The depth test answers
// each such batch with the tile's exact range (stages/depth_test.h); an
// update is applied when it is visible (sent at t_u, visible once t_u +
// update_latency < sc_time_stamp() at a test; hw/hierarchical_z.h proves it
// independent of process order), in sending order, and only if it names the
// block's current sequence number (no depth-writing batch emitted since)
// and the current clear epoch (depth clears and frames passed); otherwise it
// is dropped. Updates are taken at each HZ test.
// Cost: the HZ test is a pipeline stage of access_latency cycles beside the
// tile test: every batch and control token leaves access_latency cycles
// later, and a culled tile costs its tile test (1 cycle) only; no stamps.
// Updates cost the rasterizer no cycles (a write port of their own).
// hz_fragments_culled counts the covered pixels of culled tiles (accepted
// tiles exactly, partial tiles through the coverage routine): a model-side
// count, no cycles. Storage: 2 x 32 bits per tile (unorm16 needs 2 x 16),
// plus a sequence number (16 bits suffice, hw/hierarchical_z.h): at 1080p
// with 16 x 16 tiles, 120 x 68 = 8160 blocks, 8160 x 80 bits = 79.7 KiB on
// chip for the GPU, a 1 / units share per unit.
#pragma once

#include <array>
#include <map>
#include <systemc>
#include <tuple>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/hierarchical_z.h"
#include "hw/packets.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"

namespace gpusim {

class TileRasterizer : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<SetupPacket> in;
  FifoOutPort<StampBatch> out;

  // Throws std::invalid_argument when a stamp holds more than 64 pixels (the
  // width of Stamp::mask), the tile is not a multiple of the stamp, or a side
  // is not a power of two (log2_side()).
  TileRasterizer(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
                 unsigned unit);

  // Hierarchical Z: the unit's update link from its depth test (the GPU
  // connects it when config.hierarchical_z.enabled; must outlive the unit).
  void set_hz_link(HzUpdateLink* link) { m_hz_link = link; }

  // Its inputs and outputs are its FIFOs and the update link, whose reads it
  // makes no earlier than the link's rule allows (hz_culls; temporal
  // decoupling, hw/pipeline_stage.h).
  bool decouplable() const override { return true; }

  uint64_t tiles_visited() const { return m_tiles_visited; }
  uint64_t stamps_emitted() const { return m_stamps_emitted; }
  uint64_t fragments() const { return m_fragments; }
  uint64_t samples() const { return m_samples_covered; }
  uint64_t hz_fragments_culled() const { return m_hz_fragments_culled; }
  uint64_t hz_samples_culled() const { return m_hz_samples_culled; }

 private:
  static constexpr int kMaxStampPixels = 64;

  void run();
  void reset_state() override;
  void rasterize(const std::shared_ptr<const RasterPrimitive>& tri);
  // The tile walk over N coverage edges (3 for a triangle, 2 for a
  // diamond-exit line, 0 for a point).
  template <int N>
  void rasterize_edges(const std::shared_ptr<const RasterPrimitive>& tri);
  // The edge-function core on one stamp: the pixels of `box` covered by the
  // primitive, from the raw coverage edge values `e` at the stamp's origin.
  template <int N>
  uint64_t coverage(const RasterPrimitive& t, const std::array<EdgeValue, N>& e, uint64_t box);
  // Multisampled: the same per sample; appends each covered pixel's sample
  // mask to m_batch.samples.
  template <int N>
  uint64_t sample_coverage(const RasterPrimitive& t, const std::array<EdgeValue, N>& e,
                           uint64_t box);
  // The Bresenham line walker.
  void walk_line(const std::shared_ptr<const RasterPrimitive>& tri);
  // The interpolation functions' values at stamp origin (sx, sy)'s centre.
  std::array<EdgeValue, 3> interpolation_at(const RasterPrimitive& t, int sx, int sy) const;
  // Waits the cycles walked since the last output, then writes m_batch (the
  // stamps of one tile) as the batch of `tri`.
  void emit_batch(const std::shared_ptr<const RasterPrimitive>& tri);
  // Hierarchical Z: a clear or end_of_frame passing (resets the blocks),
  // the test of one tile for the current primitive (applies the visible
  // updates first), and the widening of a block by a depth-writing batch.
  void hz_control(PacketKind kind);
  bool hz_culls(int tile);
  void hz_widen(int tile);

  const int m_tile;                // tile side, pixels
  const int m_stamp_w, m_stamp_h;  // stamp, pixels
  const int m_stamp_pixels;
  // log2 of the tile side and of the stamp's sides (all powers of two):
  // pixel p of a stamp is (p & (w - 1), p >> m_stamp_w_shift).
  const int m_tile_shift, m_stamp_w_shift, m_stamp_h_shift;
  const uint64_t m_full_mask;
  const unsigned m_owner;  // this unit, as tile_owner() names units

  // Per-triangle edge-core constants: the steps of each edge's value by one
  // pixel in x and in y (a * 256, b * 256), and the offset of pixel
  // p = j * w + i from the stamp origin, i * a * 256 + j * b * 256, per edge
  // (filled when the triangle's first whole stamp is evaluated).
  std::array<EdgeValue, RasterPrimitive::kMaxCoverageEdges> m_pixel_dx{}, m_pixel_dy{};
  std::array<std::array<EdgeValue, kMaxStampPixels>, RasterPrimitive::kMaxCoverageEdges> m_offset{};
  bool m_offset_valid = false;
  // Multisampling (spec section 14): samples per pixel, their offsets from
  // the pixel centre (read from the frame when the simulation starts), and
  // per primitive each coverage edge's offset to each sample,
  // a * dx_s + b * dy_s.
  unsigned m_samples = 1;
  uint16_t m_full_samples = 1;
  std::array<Subpixel, 16> m_sample_dx{}, m_sample_dy{};
  std::array<std::array<EdgeValue, 16>, RasterPrimitive::kMaxCoverageEdges> m_sample_offset{};
  uint64_t m_passes = 1;          // ceil(samples / samples_per_pass)
  uint64_t m_pending_cycles = 0;  // walked but not yet waited
  StampBatch m_batch;             // the tile's stamps; buffers recycled through the FIFO
  // The line walker's stamps of one span: (minor tile, stamp y, stamp x) ->
  // mask, so they leave tile by tile in walk order.
  std::map<std::tuple<int, int, int>, uint64_t> m_line_stamps;

  // Hierarchical Z (config.hierarchical_z): per screen tile (ty * tiles_x +
  // tx; only this unit's are used) the block's range and its sequence number,
  // the clear epoch (depth clears and frames passed), and per primitive its
  // range and what its depth state allows: culling and widening.
  const bool m_hz;
  const sc_core::sc_time m_hz_delay;  // access_latency cycles
  HzUpdateLink* m_hz_link = nullptr;
  int m_tiles_x = 0;
  std::vector<HzRange> m_hz_block;
  std::vector<uint32_t> m_hz_seq;
  uint32_t m_hz_epoch = 0;
  size_t m_clears_seen = 0;
  HzRange m_hz_prim;
  CompareFunc m_hz_func = CompareFunc::always;
  bool m_hz_cull = false, m_hz_write = false;

  uint64_t& m_triangles = m_stats.counter("triangles", "triangles", "triangles walked");
  uint64_t& m_lines = m_stats.counter("lines", "lines", "lines received (either rule)");
  uint64_t& m_points = m_stats.counter("points", "points", "points received");
  uint64_t& m_lines_walked = m_stats.counter(
      "lines_walked", "lines", "Bresenham lines with a drawn step in the box, walked");
  uint64_t& m_line_spans =
      m_stats.counter("line_spans", "spans", "line walker spans (one tile column or row) tested");
  uint64_t& m_line_spans_skipped = m_stats.counter(
      "line_spans_skipped", "spans", "line walker spans touching no tile of this unit, jumped");
  uint64_t& m_line_steps =
      m_stats.counter("line_steps", "steps", "line walker steps in this unit's spans");
  uint64_t& m_line_stamps_emitted =
      m_stats.counter("line_stamps", "stamps", "stamps the line walker built and emitted");
  uint64_t& m_tiles_visited =
      m_stats.counter("tiles_visited", "tiles", "own tiles in a triangle's box");
  uint64_t& m_tiles_rejected =
      m_stats.counter("tiles_rejected", "tiles", "tiles trivially rejected");
  uint64_t& m_tiles_accepted =
      m_stats.counter("tiles_accepted", "tiles", "tiles trivially accepted");
  uint64_t& m_stamps_evaluated =
      m_stats.counter("stamps_evaluated", "stamps", "stamps tested per pixel in partial tiles");
  uint64_t& m_stamps_accepted = m_stats.counter("stamps_accepted", "stamps",
                                                "stamps emitted from accepted tiles without tests");
  uint64_t& m_stamps_emitted =
      m_stats.counter("stamps_emitted", "stamps", "non-empty stamps written");
  // With hierarchical Z the pixels of culled tiles are not emitted (they are
  // in hz_fragments_culled); without, the description stays as it was.
  uint64_t& m_fragments =
      m_stats.counter("fragments", "fragments",
                      m_hz ? "covered pixels emitted (not those of tiles culled by hierarchical Z)"
                           : "covered pixels");
  uint64_t& m_samples_covered = m_stats.counter(
      "samples", "samples", "covered samples (one per covered pixel unless multisampled)");
  uint64_t& m_hz_tests = m_stats.counter(
      "hz_tests", "tests", "hierarchical Z tests: (triangle, tile) pairs the coverage test kept");
  uint64_t& m_hz_tiles_culled =
      m_stats.counter("hz_tiles_culled", "tiles",
                      "tiles of a triangle rejected by hierarchical Z: nothing emitted");
  uint64_t& m_hz_fragments_culled = m_stats.counter(
      "hz_fragments_culled", "fragments",
      "covered pixels of tiles rejected by hierarchical Z (a model count: no cycles)");
  uint64_t& m_hz_samples_culled = m_stats.counter(
      "hz_samples_culled", "samples",
      "covered samples of tiles rejected by hierarchical Z (one per pixel unless multisampled)");
  uint64_t& m_hz_updates_applied = m_stats.counter(
      "hz_updates_applied", "updates", "exact tile ranges from the depth test written to a block");
  uint64_t& m_hz_updates_dropped =
      m_stats.counter("hz_updates_dropped", "updates",
                      "depth test updates superseded by a later batch or a clear, not applied");
};

}  // namespace gpusim
