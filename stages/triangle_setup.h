// Triangle setup (docs/pipeline-spec.md, sections 6, 7, 8 and 10): snaps the
// clipper's window coordinates to the subpixel grid, computes twice the
// signed area, drops degenerate and culled triangles, turns clockwise
// triangles counter-clockwise, and derives what the rasterizer and the back
// end need once per triangle: the three edge equations with their fill-rule
// bias, the pixel bounding box clamped to the framebuffer and the polygon
// offset; the vertices' varyings (already divided by w) and the provoking
// vertex's flat varyings pass through unchanged. The result is shared
// read-only by every unit (shared_ptr). Only triangles are assembled today:
// a primitive of another kind is a model error (SC_REPORT_ERROR).
//
// Cost model: every input token (triangle or control token) read at time t
// occupies the stage for ii(triangle_setup) cycles, whether or not a triangle
// survives; its output, if any, is written at t + ii and readable from
// t + ii + latency(triangle_setup). No memory traffic.
//
// Triangles whose clamped bounding box is empty (entirely off screen, or too
// thin to contain a pixel centre's row or column) are counted in
// triangles_rasterized, as the golden model counts them, and also in
// triangles_offscreen; they are not sent on, since no unit has work for them.
#pragma once

#include <systemc>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"

namespace gpusim {

class TriangleSetup : public PipelineStage {
 public:
  FifoInPort<ClippedPrimitive> in;
  FifoOutPort<SetupPacket> out;

  TriangleSetup(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);

  // The golden model's setup counters (docs/pipeline-spec.md, section 13).
  nlohmann::json pipeline_counts() const {
    return {{"triangles_degenerate", m_degenerate},
            {"triangles_culled", m_culled},
            {"triangles_rasterized", m_rasterized}};
  }

 private:
  void run();
  // The setup of one triangle, without timing: nullptr when the triangle is
  // degenerate or culled (the reason goes to the counters). A RasterPrimitive
  // with an empty box (x0 > x1 or y0 > y1) is returned all the same.
  std::shared_ptr<RasterPrimitive> setup(const ClippedPrimitive& t);

  uint64_t& m_degenerate =
      m_stats.counter("triangles_degenerate", "triangles", "zero area after snapping, dropped");
  uint64_t& m_culled = m_stats.counter("triangles_culled", "triangles", "removed by face culling");
  uint64_t& m_rasterized = m_stats.counter("triangles_rasterized", "triangles",
                                           "set up for rasterization (incl. off screen)");
  uint64_t& m_offscreen =
      m_stats.counter("triangles_offscreen", "triangles",
                      "rasterized triangles whose box holds no pixel centre, not sent");
  uint64_t& m_swapped =
      m_stats.counter("triangles_swapped", "triangles", "clockwise, made counter-clockwise");
};

}  // namespace gpusim
