// Tile distributor: sends each set-up primitive (triangle, line or point) to
// the raster units that own at least one screen tile its pixel bounding box
// touches (tile_owner() in hw/packets.h; setup has clamped the box to the
// draw rectangle, so a scissor or a viewport keeps units whose tiles lie
// outside it idle), once per unit, in increasing unit
// order; control tokens go to every unit, so each unit sees the same order of
// clears, primitives and ends of frame. A line's box is a rectangle around
// it, so a long diagonal line goes to units whose tiles in the box it misses;
// their rasterizers reject those tiles (or jump those spans) at their cost.
// The counters keep the name triangles_sent for every kind.
//
// Cost model: a primitive read at time t occupies the stage for
// ii(tile_distributor) x (units it is sent to) cycles (one handoff per unit
// per cycle at ii 1; a primitive sent nowhere still takes ii); a control token
// takes ii once (one broadcast). Outputs are written at t + busy and readable
// latency(tile_distributor) cycles later. A full unit FIFO blocks the
// distributor (head of line). No memory traffic.
#pragma once

#include <systemc>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"

namespace gpusim {

class TileDistributor : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<SetupPacket> in;
  sc_core::sc_vector<FifoOutPort<SetupPacket>> out;  // one per unit

  TileDistributor(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);
  // Its only inputs and outputs are its FIFOs (PipelineStage: temporal decoupling).
  bool decouplable() const override { return true; }

 private:
  void run();
  void reset_state() override;
  // targets[u]: unit u owns a tile of the triangle's box; returns how many do.
  unsigned target_units(const RasterPrimitive& t, std::vector<bool>& targets) const;

  const int m_tile_shift;  // log2(tile_size): a pixel's tile is x >> m_tile_shift
  std::vector<bool> m_targets;

  uint64_t& m_triangles_sent = m_stats.counter("triangles_sent", "triangles",
                                               "(triangle, unit) pairs sent, summed over units");
  std::vector<uint64_t*> m_unit_triangles;  // triangles_sent_unit<u>
};

}  // namespace gpusim
