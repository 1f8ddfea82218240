// The GPU: every stage instantiated and joined by bounded FIFOs, N raster
// units each with its own rasterizer, depth test, interpolator and ROP, and
// one memory shared by every client.
//
//   commands -> CommandProcessor -> VertexFetch -> VertexShader -> Clipper
//            -> TriangleSetup -> TileDistributor -+-> unit 0: TileRasterizer -> DepthTest
//                                                 |            -> Interpolator -> Rop
//                                                 +-> unit 1 ...
//   VertexFetch, every DepthTest and Rop -> Memory (TLM-2.0)
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <systemc>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "hw/vertex_packets.h"
#include "stages/clipper.h"
#include "stages/command_processor.h"
#include "stages/depth_test.h"
#include "stages/interpolator.h"
#include "stages/rop.h"
#include "stages/tile_distributor.h"
#include "stages/tile_rasterizer.h"
#include "stages/triangle_setup.h"
#include "stages/vertex_fetch.h"
#include "stages/vertex_shader.h"

namespace gpusim {

class Gpu : public sc_core::sc_module {
 public:
  // frame and config must outlive the GPU; memory_bytes sizes the memory.
  Gpu(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
      uint64_t memory_bytes);

  // The host writes commands here.
  Fifo<Command>& command_queue() { return m_commands; }
  Memory& memory() { return m_memory; }

  // Every unit has flushed its tiles after end_of_frame.
  bool frame_done() const;
  // Notified whenever a unit finishes its frame.
  const sc_core::sc_event_or_list& unit_done_events() const { return m_done_events; }
  // Testbench instrumentation: primitive id of the last colour write per pixel.
  void set_last_writer(std::vector<int64_t>* per_pixel);

  // Random stalls at every FIFO boundary (Fifo::inject_random_stalls), for
  // latency-insensitivity tests: results must not change.
  void inject_random_stalls(uint64_t seed, double probability, unsigned max_cycles);

  // Assembled triangles the clipper has taken in so far (for progress lines).
  uint64_t triangles_assembled() const;

  // Everything stats.json reports about the run: per stage busy / stalled /
  // starved cycles, per FIFO occupancy, per unit work, memory traffic,
  // achieved against peak rates. `cycles` is the frame's length.
  nlohmann::json stats_json(uint64_t cycles) const;
  // Pipeline counters comparable with the golden model's statistics.
  nlohmann::json pipeline_counts() const;

 private:
  struct Unit {
    std::unique_ptr<Fifo<SetupPacket>> jobs;
    std::unique_ptr<TileRasterizer> rasterizer;
    std::unique_ptr<Fifo<StampBatch>> stamps;
    std::unique_ptr<DepthTest> depth;
    std::unique_ptr<Fifo<StampBatch>> visible;
    std::unique_ptr<Interpolator> interpolator;
    std::unique_ptr<Fifo<ShadedStampBatch>> shaded;
    std::unique_ptr<Rop> rop;
  };

  const GpuConfig& m_config;
  const FrameState& m_frame;
  Memory m_memory;
  Fifo<Command> m_commands;
  CommandProcessor m_command_processor;
  Fifo<Command> m_command_to_fetch;
  VertexFetch m_fetch;
  Fifo<VertexBatch> m_fetch_to_shader;
  VertexShader m_shader;
  Fifo<ShadedBatch> m_shader_to_clipper;
  Clipper m_clipper;
  Fifo<ClippedTriangle> m_clipper_to_setup;
  TriangleSetup m_setup;
  Fifo<SetupPacket> m_setup_to_distributor;
  TileDistributor m_distributor;
  std::vector<Unit> m_units;
  sc_core::sc_event_or_list m_done_events;
};

}  // namespace gpusim
