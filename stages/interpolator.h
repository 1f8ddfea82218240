// Interpolator, one per unit (docs/pipeline-spec.md, section 9): the
// varyings of every pixel that survived the depth test, and from them the
// colour the ROP consumes. Gouraud shading is perspective-correct: with
// f_k = float(E_k), the edge values rebuilt by stepping from the stamp
// origin's (pixel (i, j): e_k + i * a_k * 256 + j * b_k * 256, exact int64),
//   den  = f0 q0 + f1 q1 + f2 q2      (q = 1/w; 1 with screen interpolation)
//   v[k] = (f0 vw0[k] + f1 vw1[k] + f2 vw2[k]) / den      (vw = varyings / w)
// evaluated in float in exactly that order, for every component k below the
// draw's VaryingLayout count, in one loop whatever the components mean. The
// pixel's colour is clamp01 of the four components at the layout's colour
// slot. Flat shading takes the provoking vertex's varyings (flat_varyings)
// unchanged instead, and so does every point, whatever the shading (its
// vertex's colour, unchanged). A line is interpolated by the same formula
// with its parameter along it as the edge values (E2 = 0, vertices
// (a, b, a): setup's interpolation functions, hw/packets.h).
//
// Phong shading (section 9b): a draw whose layout holds a normal (a lit
// draw with shading "phong", hw/draw_state.h) has its triangles' and lines'
// pixels lit by the per-pixel lighting unit: the normal and eye position
// interpolated as above, the normal renormalised, section 2's equation with
// the draw's material and the frame's lights. Its points and flat primitives
// keep their vertex's colour. The unit sits inside the interpolator, not in
// a stage of its own, because its inputs are the interpolated varyings,
// which never leave this stage (only colours go to the ROP): a separate
// stage would need a packet of 6 more floats per pixel. It is always
// present and costs nothing in a draw that is not lit per pixel.
//
// Output: the batch's stamps unchanged and one colour per covered pixel,
// stamp order, then mask bit order. Only the colour leaves, and in a
// textured draw the texture coordinate (s, t) of each pixel (section 9c:
// interpolated as any varying, whatever the shading; a point's is its
// vertex's), which the texture unit consumes.
//
// Cost model, per token read at time t: busy = ii * stamps (at least ii for
// any token, control tokens included), plus, for a batch lit per pixel,
// pixels * (lighting_cycles_per_pixel + lighting_cycles_per_light * lights):
// the lighting unit takes one pixel at a time after the interpolation lanes
// (hw/gpu_config.h). A frame without Phong draws pays nothing for it. The
// result is written at t + busy, readable `latency` cycles later. ii and
// latency are config.stage("interpolator"). No memory traffic.
#pragma once

#include <array>
#include <systemc>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/lighting_unit.h"
#include "hw/packets.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"

namespace gpusim {

struct EdgeOffsets;

class Interpolator : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<StampBatch> in;
  FifoOutPort<ShadedStampBatch> out;

  Interpolator(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
               unsigned unit);
  // Its only inputs and outputs are its FIFOs (PipelineStage: temporal decoupling).
  bool decouplable() const override { return true; }

 private:
  void run();
  void reset_state() override;
  void shade(const StampBatch& batch, ShadedStampBatch& result);
  // Fills m_offset for the triangle's edge steps (kept while they are unchanged).
  void update_offsets(const RasterPrimitive& tri);
  // Section 9c: the texture coordinate of every covered pixel, from the
  // varyings at `slot` (the layout's texcoord), into `out` (n pixels); with
  // `derivatives`, each pixel's derivatives over its 2x2 quad there too.
  void interpolate_texcoords(const std::vector<Stamp>& stamps, const RasterPrimitive& prim,
                             unsigned slot, size_t n, std::vector<glm::vec2>& out,
                             std::vector<glm::vec4>* derivatives);
  // Phong (section 9b): the lit colour of every covered pixel to `out`.
  void shade_phong(const std::vector<Stamp>& stamps, const EdgeOffsets& o,
                   const RasterPrimitive& prim, const VaryingLayout& layout, glm::vec4* out);

  const int m_stamp_shift;  // log2 of the stamp width: a mask bit's row is bit >> shift
  const int m_stamp_pixels;

  // Per-pixel edge offsets inside a stamp, i * a_k * 256 + j * b_k * 256 for
  // pixel p = j * w + i (at most 64 pixels, the width of Stamp::mask), for the
  // edge steps m_step_x, m_step_y: per-triangle setup hoisted out of the
  // per-pixel loop.
  std::array<std::array<EdgeValue, 64>, 3> m_offset{};
  std::array<EdgeValue, 3> m_step_x{}, m_step_y{};
  bool m_offset_valid = false;

  uint64_t m_lighting_cycles_per_pixel_total = 0;  // per lit pixel, all lights (the frame's)
  LightingUnit m_lighting;  // the per-pixel lighting unit, loaded per lit draw

  uint64_t& m_stamps = m_stats.counter("stamps", "stamps", "stamps interpolated");
  uint64_t& m_fragments = m_stats.counter("fragments", "fragments", "pixels given a colour");
  uint64_t& m_flat_fragments =
      m_stats.counter("flat_fragments", "fragments",
                      "pixels of flat-shaded primitives and of points (no interpolation)");
  uint64_t& m_pixels_lit =
      m_stats.counter("pixels_lit", "fragments", "pixels lit per pixel (Phong shading)");
  uint64_t& m_texcoords = m_stats.counter("texcoords", "fragments",
                                          "pixels given a texture coordinate (textured draws)");
  uint64_t& m_light_evaluations = m_stats.counter("light_evaluations", "evaluations",
                                                  "lights evaluated for pixels lit per pixel");
};

}  // namespace gpusim
