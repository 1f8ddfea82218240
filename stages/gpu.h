// The GPU: every stage instantiated and joined by bounded FIFOs, N raster
// units each with its own rasterizer, depth test, interpolator and ROP, and
// one memory shared by every client.
//
//   commands -> CommandProcessor -> VertexFetch -> VertexShader -> Clipper
//            -> PrimitiveSetup -> TileDistributor -+-> unit 0: TileRasterizer -> DepthTest
//                                                 |            -> Interpolator -> Rop
//                                                 +-> unit 1 ...
//   VertexFetch, every DepthTest and Rop -> Memory
//   multisampled or supersampled frames: every Rop -> Resolve -> Memory
//   hierarchical Z: each unit's DepthTest -> its TileRasterizer (a link)
//
// This file is instantiation and connections: the netlist they form
// (topology()) is what statistics, traces, the testbench's checkers
// (watchdog, conservation ledger, fault injection) and tools walk.
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
#include "hw/pipeline_counts.h"
#include "hw/trace_probe.h"
#include "stages/clipper.h"
#include "stages/command_processor.h"
#include "stages/depth_test.h"
#include "stages/interpolator.h"
#include "stages/primitive_setup.h"
#include "stages/resolve.h"
#include "stages/rop.h"
#include "stages/texture_unit.h"
#include "stages/tile_distributor.h"
#include "stages/tile_rasterizer.h"
#include "stages/topology.h"
#include "stages/vertex_fetch.h"
#include "stages/vertex_shader.h"

namespace gpusim {

class Gpu : public sc_core::sc_module {
 public:
  // The order in which the raster units are elaborated (and so the order in
  // which SystemC first runs their processes). Nothing the GPU computes may
  // depend on it; the determinism tests elaborate both ways.
  enum class UnitOrder { ascending, descending };

  // frame and config must outlive the GPU; memory_bytes sizes the memory.
  // `interposers` (optional) puts stages in the place of FIFOs (Topology).
  Gpu(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
      uint64_t memory_bytes, UnitOrder order = UnitOrder::ascending,
      const Interposers* interposers = nullptr);

  // The host writes commands here.
  Fifo<Command>& command_queue() { return *m_commands; }
  Memory& memory() { return m_memory; }
  const Memory& memory() const { return m_memory; }
  const Topology& topology() const { return m_topology; }
  Topology& topology() { return m_topology; }

  // Between frames, from a process (the testbench's host) at the new
  // frame's first instant, the previous frame complete and the kernel idle
  // but for the caller: every stage, FIFO and link and the memory's arbiter
  // and statistics as elaborated (Topology::reset), so that the next frame
  // has the cycles and statistics of a freshly elaborated GPU. The frame's
  // registers (the FrameState the GPU was made with) and the memory's
  // contents (Memory::reset_contents) are the caller's to load first. A
  // frame with another structure (needs_resolve()) needs another GPU.
  void reset();
  // Notified by reset() at once: observers (the watchdog) start over.
  const sc_core::sc_event& reset_event() const { return m_reset_event; }

  // Every unit has flushed its tiles after end_of_frame (and the resolve
  // has written the output image, when there is one).
  bool frame_done() const;
  // Notified whenever a unit (or the resolve) finishes its frame.
  const sc_core::sc_event_or_list& unit_done_events() const { return m_done_events; }
  // Testbench instrumentation: primitive id of the last colour write per pixel.
  void set_last_writer(std::vector<int64_t>* per_pixel);
  // Attaches a trace recorder before sc_start(): every FIFO gets its probe
  // (by its index in topology().trace_tables()), every depth test and ROP
  // the fragment probe. `probes` must outlive the simulation.
  void attach_trace(TraceProbes& probes);

  // Primitives the clipper has assembled so far (for progress lines).
  uint64_t primitives_assembled() const { return m_clipper.primitives_in(); }
  // Fragments so far, summed over the units: rasterized, passing the depth
  // test, written by the ROPs (pipeline_counts, progress lines).
  struct FragmentCounts {
    uint64_t generated = 0, passed_depth = 0, written = 0;
    uint64_t samples_generated = 0, samples_passed_depth = 0, samples_written = 0;
  };
  FragmentCounts fragment_counts() const;

  // Everything stats.json reports about the run: the GPU's stat group (the
  // frame's length, achieved against peak rates, per stage busy / stalled /
  // starved cycles and its own counters, per FIFO occupancy, per unit work,
  // memory traffic), the netlist's tables, and what every statistic means
  // ("descriptions"). `cycles` is the frame's length.
  nlohmann::json stats_json(uint64_t cycles);
  const StatGroup& stat_group() const { return m_stats; }
  // Pipeline counters comparable with the golden model's statistics.
  PipelineCounts pipeline_counts() const;

 private:
  void declare_stats();

  struct Unit {
    std::unique_ptr<TileRasterizer> rasterizer;
    std::unique_ptr<DepthTest> depth;
    std::unique_ptr<Interpolator> interpolator;
    std::unique_ptr<TextureUnit> texture;  // only when the frame has a textured draw
    std::unique_ptr<Rop> rop;
  };

  const GpuConfig& m_config;
  Memory m_memory;
  Topology m_topology;
  CommandProcessor m_command_processor;
  VertexFetch m_fetch;
  VertexShader m_shader;
  Clipper m_clipper;
  PrimitiveSetup m_setup;
  TileDistributor m_distributor;
  std::vector<Unit> m_units;
  std::unique_ptr<Resolve> m_resolve;  // only when the frame needs one
  Fifo<Command>* m_commands = nullptr;
  sc_core::sc_event_or_list m_done_events;
  sc_core::sc_event m_reset_event;
  uint64_t m_frame_cycles = 0;  // stats_json()'s
  StatGroup m_stats{"timing"};
};

}  // namespace gpusim
