// Resolve (docs/pipeline-spec.md, section 14): the one stage after the
// units, present only in a multisampled or supersampled frame. Each ROP
// passes it its control tokens once their writes are done; when every unit's
// end_of_frame has arrived, the colour buffer holds the whole render target
// (N samples per pixel, k times the output on each side), and the resolve
// box-filters it into the output image at frame.resolve_address:
//   rgba8:   per channel, out = floor((2 sum + n) / (2 n)) over the n = k^2 N
//            stored bytes (exact integers: sum < 2^8 * 1024 = 2^18);
//   rgba16f: the n half values summed in float, rows, then columns, then
//            samples ascending, then divided by n and encoded (the spec's
//            order, so the bits equal the golden model's).
// The depth buffer is not resolved: the output's depth is sample 0 of each
// block's lower-left render-target pixel, which the testbench reads from
// the depth buffer as it is.
//
// Walk: the output in tiles of tile_size pixels, rows bottom-up, left to
// right. Per tile, the render-target rows it covers (k per output row, each
// k * tile_size * N samples, contiguous) are read as one group and waited
// for (a blocking unit, like the tile caches); with surfaces.tiled, the k x k
// render-target tiles it covers instead, each one block in bursts of at most
// surfaces.max_burst_bytes (as the tile caches move them; compressed tiles
// are read raw: the resolve does not see the ROPs' compression state); the tile is filtered at
// ii(resolve) per output stamp (config.stamp pixels) and sample pass
// (ceil(n / samples_per_pass)); its output rows are then written, posted.
// busy_cycles per tile = the read stall + ii * stamps * passes; after the
// last tile the resolve waits for its posted writes, then reports the frame
// done (frame_done(), frame_done_event()). A clear token costs ii.
// latency(resolve) is not used: nothing reads the resolve's output but the
// testbench, after the frame.
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
#include "hw/surface_layout.h"

namespace gpusim {

class Resolve : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  sc_core::sc_vector<FifoInPort<ControlToken>> in;  // one per unit
  MemoryPort mem;

  Resolve(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);

  const sc_core::sc_event& frame_done_event() const { return m_frame_done_event; }
  bool frame_done() const { return m_frame_done; }

 private:
  void run();
  void reset_state() override;
  // Filters output tile (tx, ty); returns its cycles, the read stall included.
  uint64_t resolve_tile(int tx, int ty);
  void read_tiles(int rx0, int ry0, int k, size_t row_bytes);

  bool m_frame_done = false;
  sc_core::sc_event m_frame_done_event;
  std::vector<uint8_t> m_rows;   // a tile's render-target rows
  std::vector<uint8_t> m_out;    // a tile's output rows
  SurfaceLayout m_surface;       // the colour buffer's (surfaces.tiled)
  std::vector<uint8_t> m_block;  // tiled: the render-target tiles as read

  uint64_t& m_tiles = m_stats.counter("tiles", "tiles", "output tiles filtered");
  uint64_t& m_pixels = m_stats.counter("pixels", "pixels", "output pixels written");
  uint64_t& m_samples =
      m_stats.counter("samples", "samples", "render-target samples read and averaged");
  uint64_t& m_memory_stall_cycles = m_stats.counter(
      "memory_stall_cycles", "cycles",
      "cycles of busy_cycles waiting for tile reads, and for the last writes at the end");
  uint64_t& m_frames = m_stats.counter("frames", "frames", "frames resolved");
};

}  // namespace gpusim
