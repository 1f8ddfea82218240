// Primitive setup (docs/pipeline-spec.md, sections 6 to 10, 8b, 8c): snaps
// the clipper's window coordinates to the subpixel grid and derives, once
// per primitive, what the rasterizer and the back end need (RasterPrimitive,
// hw/packets.h). The result is shared read-only by every unit (shared_ptr).
//
// Triangles: twice the signed area; degenerate and culled triangles are
// dropped; clockwise ones are turned counter-clockwise; the three edge
// equations with their fill-rule bias (interpolation and coverage alike), the
// pixel bounding box clamped to the draw rectangle (the framebuffer, the
// draw's viewport and its scissor: section 8d) and the polygon offset.
// Every primitive's box is clamped so: the scissor and the viewport bound
// are nothing but this clamp, and the distributor and the rasterizers,
// which only ever look inside the box, never spend a cycle outside it. The
// vertices' varyings (already divided by w) and the provoking vertex's flat
// varyings pass through unchanged.
//
// Lines (a, b): the interpolation functions of section 9 (E0 = L2 - T,
// E1 = T, E2 = 0, area2 = L2, vertices (a, b, a)); no polygon offset.
// - Diamond exit: a zero-length line is dropped (lines_degenerate). Otherwise
//   a parallelogram: two coverage edges bound the band of w pixel centres per
//   major column, -128 w |dm| < s D < 128 w |dm| with the ties of section
//   8b's integer form, and the pixel box bounds the major axis to the first
//   and last column (row) the line produces. Setup decides those two with
//   the end test on the offset segment (end points moved by -128 (w - 1) in
//   the minor axis): per end, one candidate column beside the end point,
//   whose band pixel is found among 7 candidate rows by the band test (no
//   division), and whose diamond is tested against the end point. The minor
//   range of the box is the band pixels of the two end columns, plus w - 1.
// - Bresenham: the end points' pixels, the width and the end flags for the
//   rasterizer's line walker, and a box holding every pixel it can produce.
// Points: the square of section 8c (F, X0, Y0, rounded half away from zero)
// is the pixel box itself, with no coverage edge; interpolation E0 = 1,
// area2 = 1, so depth is the vertex's z exactly, and the interpolator gives
// the flat varyings.
// Multisampled frames (section 14): boxes hold every pixel with a sample
// point inside the primitive's subpixel box (the pattern's reach from the
// centre widens it); every line, whatever its rule, is a rectangle of four
// coverage edges (the corners from the width in float, snapped half away
// from zero), and a point's square is four axis-aligned edges.
//
// Cost model: every input token (primitive of any kind, or control token)
// read at time t occupies the stage for ii(primitive_setup) cycles, whether or
// not it survives; its output, if any, is written at t + ii and readable from
// t + ii + latency(primitive_setup). A line's end tests (a handful of
// multiply-adds per end) are part of that ii. No memory traffic.
//
// Primitives whose clamped box is empty (entirely off screen or outside the
// viewport or scissor, too thin to contain a pixel centre's row or column,
// or a line producing no column)
// are counted as rasterized, as the golden model counts them, and also in
// triangles_offscreen, lines_offscreen or points_offscreen; they are not
// sent on, since no unit has work for them.
#pragma once

#include <systemc>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/pipeline_counts.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"

namespace gpusim {

class PrimitiveSetup : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<ClippedPrimitive> in;
  FifoOutPort<SetupPacket> out;

  PrimitiveSetup(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);
  // Its only inputs and outputs are its FIFOs (PipelineStage: temporal decoupling).
  bool decouplable() const override { return true; }

  // The golden model's setup counters (docs/pipeline-spec.md, section 13).
  void add_pipeline_counts(PipelineCounts& c) const {
    c.triangles_degenerate += m_degenerate;
    c.triangles_culled += m_culled;
    c.triangles_rasterized += m_rasterized;
    c.triangles_offscreen += m_offscreen;
    c.lines_degenerate += m_lines_degenerate;
    c.lines_rasterized += m_lines_rasterized;
    c.points_rasterized += m_points_rasterized;
  }

 private:
  void run();
  void reset_state() override;
  // The setup of one triangle, without timing: nullptr when the triangle is
  // degenerate or culled (the reason goes to the counters). A RasterPrimitive
  // with an empty box (x0 > x1 or y0 > y1) is returned all the same.
  std::shared_ptr<RasterPrimitive> setup(const ClippedPrimitive& t);
  std::shared_ptr<RasterPrimitive> setup_triangle(const ClippedPrimitive& t);
  std::shared_ptr<RasterPrimitive> setup_line(const ClippedPrimitive& t);
  std::shared_ptr<RasterPrimitive> setup_point(const ClippedPrimitive& t);
  // Multisampled (spec section 14): a line's rectangle, its four edges and box.
  void setup_line_rectangle(RasterPrimitive& t, float width) const;
  // The pixel box of the subpixel box [x0, x1] x [y0, y1] of sample points:
  // every pixel with a sample inside, clamped to the draw rectangle.
  void set_sample_box(RasterPrimitive& t, int64_t x0, int64_t x1, int64_t y0, int64_t y1) const;
  // The draw rectangle of a draw (spec section 8d): the render target's
  // pixels inside its viewport and scissor. Every pixel box is clamped to
  // it, so the distributor and the rasterizers never see the pixels around.
  PixelBounds bounds_of(uint32_t draw_id) const {
    return draw_bounds(m_frame.draws[draw_id].state, m_frame.framebuffer.width,
                       m_frame.framebuffer.height);
  }
  // Sets the edge from (xa, ya) to (xb, yb) with section 8's fill rule.
  static EdgeEquation edge_between(int64_t xa, int64_t ya, int64_t xb, int64_t yb);

  // The sample pattern's reach from the pixel centre (subpixels), read from
  // the frame when the simulation starts.
  unsigned m_samples = 1;
  int64_t m_reach_x0 = 0, m_reach_x1 = 0, m_reach_y0 = 0, m_reach_y1 = 0;

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
  uint64_t& m_lines_degenerate = m_stats.counter(
      "lines_degenerate", "lines", "diamond-exit lines of zero length after snapping, dropped");
  uint64_t& m_lines_rasterized =
      m_stats.counter("lines_rasterized", "lines", "set up for rasterization (incl. off screen)");
  uint64_t& m_lines_bresenham =
      m_stats.counter("lines_bresenham", "lines", "rasterized lines left to the line walker");
  uint64_t& m_lines_offscreen = m_stats.counter(
      "lines_offscreen", "lines", "rasterized lines whose box holds no pixel, not sent");
  uint64_t& m_points_rasterized =
      m_stats.counter("points_rasterized", "points", "set up for rasterization (incl. off screen)");
  uint64_t& m_points_offscreen = m_stats.counter(
      "points_offscreen", "points", "rasterized points whose square holds no pixel, not sent");
};

}  // namespace gpusim
