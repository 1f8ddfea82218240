// Clipper: primitive assembly, the data half of the post-transform vertex
// cache, invalid-primitive removal, clipping, perspective divide and viewport
// (docs/pipeline-spec.md, sections 3 to 5), and polygon mode's facing
// decision (section 4d).
//
// - Assembly: each slot of a batch yields a vertex: a fetched slot's shaded
//   vertex (stored into its cache entry when it has one), a cached slot's
//   entry, or nothing for an invalid slot. Every primitive type is assembled
//   from two registers that carry over batch boundaries; a batch with
//   first_slot 0 starts a draw:
//     triangles: the triangle's first two vertices; strips: the last two
//     (odd triangles swap their first two vertices); fans: the first and the
//     last; lines: the line's first vertex; line strips: the previous
//     vertex; line loops: the previous vertex and the draw's first, which
//     closes the loop when the draw's last slot arrives (slot + 1 = the
//     draw's slot_count register, DrawBuffers); points need none.
//   Primitive k of a draw gets id first_primitive_id + k, counting every
//   assembled primitive, including the ones dropped below. A line carries
//   the Bresenham end flags of section 3: a strip's (and a loop's) lines
//   after the first clear draw_first, a loop's closing line clears both.
// - A primitive with an invalid vertex or a non-finite clip coordinate is
//   dropped (triangles_invalid, lines_invalid, points_invalid).
// - Triangles: all 7 plane distances of the 3 vertices are computed at once;
//   a triangle inside every plane (the common case) passes untouched.
//   Otherwise Sutherland-Hodgman runs plane by plane on a small polygon
//   buffer, cutting each edge from its endpoint nearer the plane, with the
//   plane-0 w floor; fewer than 3 vertices left is clipped away. The polygon
//   is split into the fan (p0, p_i, p_i+1).
// - Lines (section 4b): the 7 distances of both endpoints give the outcodes:
//   inside every plane passes untouched, both outside one plane is clipped
//   away. Otherwise the planes are walked in order and the outside endpoint
//   replaced by the cut, with the triangles' cut code (one function, so the
//   float operations are the same).
// - Points (section 4c): kept whole when the vertex is inside the view
//   volume (not the guard band), else dropped.
// - Polygon mode line or point (section 4d): the triangle is clipped as
//   above, each polygon vertex also carrying an edge flag (the edge from it
//   lies on the triangle's boundary). The polygon is mapped to window
//   coordinates and snapped, and its doubled area, the shoelace sum of the
//   snapped vertices (exactly the spec's fan sum in int64), decides
//   degenerate (zero) and culling here, since this is the last stage that
//   sees the whole polygon: triangles_degenerate and triangles_culled of the
//   clipper, which Gpu::pipeline_counts adds to setup's. A surviving one
//   (triangles_unfilled) becomes a line per flagged edge (draw_first set,
//   draw_last clear) or a point per flagged vertex, in polygon order, with
//   the triangle's primitive id. Lines carry the triangle's provoking
//   varyings; a point's flat varyings are the colour it shows (section 9):
//   the provoking vertex's with flat shading, else its own vertex's. These
//   triangles do not count in triangles_after_clip.
// - A cut vertex interpolates the clip position and every varying of the
//   draw (its VaryingLayout's count, whatever they mean) with the same
//   formula, in one loop. With screen interpolation a clipped primitive's
//   cut vertices then take the varyings affine in window space over the
//   original primitive, from the barycentrics of their projections
//   (section 4).
// - Viewport (sections 4 and 5): each draw has its viewport and depth range
//   (the render target's pixels), from which the clipper derives once per
//   batch the guard-band factors and the window transform's registers of
//   its draw (ViewportRegs).
// - Each vertex is divided by w once (q = 1/w) and mapped to window
//   coordinates, unsnapped; its varyings are multiplied by q for the
//   interpolator's perspective correction (screen interpolation: by 1, and
//   1/w is sent as 1). Every output is a ClippedPrimitive of kind triangle,
//   line or point carrying the provoking vertex's varyings of the assembled
//   primitive, for flat shading: the last vertex (a loop's closing line: the
//   draw's first), or under the first-vertex convention the first in API
//   order (a strip triangle's v_i, a fan triangle's v_i+1, a line's first).
//
// Cost model, per batch: busy = ii(clipper) x (primitives assembled + extra
// primitives), where a clipped triangle split into n > 1 triangles adds
// n - 1 extra, and a polygon-mode triangle drawn as n > 1 lines or points
// adds n - 1 extra (one per emitted primitive beyond the first; culled or
// degenerate ones cost their one). A line or a point costs one, clipped or
// not. Slots that complete no primitive cost nothing. The outputs are
// written after that and readable by setup latency(clipper) cycles later.
// Control tokens cost ii and are forwarded in order. No memory traffic: the
// cache data is on-chip storage of vertex_cache_entries shaded vertices.
#pragma once

#include <array>
#include <systemc>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "hw/pipeline_counts.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"
#include "hw/vertex_packets.h"

namespace gpusim {

class Clipper : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<ShadedBatch> in;
  FifoOutPort<ClippedPrimitive> out;

  Clipper(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);
  // Its only inputs and outputs are its FIFOs (PipelineStage: temporal decoupling).
  bool decouplable() const override { return true; }

  // Primitives of every kind assembled so far.
  uint64_t primitives_in() const { return m_in + m_lines_in + m_points_in; }
  // The golden model's counters this stage keeps (docs/pipeline-spec.md,
  // section 13). triangles_degenerate and triangles_culled are polygon
  // mode's only; setup adds its own.
  void add_pipeline_counts(PipelineCounts& c) const {
    c.triangles_in += m_in;
    c.triangles_invalid += m_invalid;
    c.triangles_clipped_away += m_clipped_away;
    c.triangles_clipped += m_clipped;
    c.triangles_after_clip += m_after_clip;
    c.triangles_degenerate += m_unfilled_degenerate;
    c.triangles_culled += m_unfilled_culled;
    c.triangles_unfilled += m_unfilled;
    c.lines_in += m_lines_in;
    c.lines_invalid += m_lines_invalid;
    c.lines_clipped_away += m_lines_clipped_away;
    c.lines_clipped += m_lines_clipped;
    c.points_in += m_points_in;
    c.points_invalid += m_points_invalid;
    c.points_clipped_away += m_points_clipped_away;
  }

 private:
  static constexpr int kPlanes = 7;

  // An assembly register: the vertex and whether a primitive may use it.
  struct Vertex {
    ShadedVertex v;
    bool valid = false;  // index in range and every clip coordinate finite
  };

  void run();
  void reset_state() override;
  // Cycles the batch costs; its output primitives are appended to m_out.
  uint64_t process_batch(const ShadedBatch& batch);
  void assemble(const DrawState& draw, uint32_t draw_id, uint32_t slot, const Vertex& v);
  // `provoking`: the vertex whose varyings flat shading shows (one of a, b, c).
  void process_triangle(uint32_t draw_id, int64_t primitive_id, const Vertex& a, const Vertex& b,
                        const Vertex& c, const Vertex& provoking);
  // Polygon mode line or point: the clipped polygon in m_poly (edge flags in
  // m_flags) as lines or points, after the facing decision.
  void draw_unfilled(ClippedPrimitive& t);
  // provoking_first: flat shading shows a's varyings, else b's.
  void process_line(uint32_t draw_id, int64_t primitive_id, const Vertex& a, const Vertex& b,
                    bool draw_first, bool draw_last, bool provoking_first);
  void process_point(uint32_t draw_id, int64_t primitive_id, const Vertex& a);
  // Sutherland-Hodgman on m_poly; leaves the clipped polygon there. With
  // kEdgeFlags, m_flags holds each vertex's edge flag and is clipped along.
  template <bool kEdgeFlags>
  void clip_polygon();
  // The point where the edge (i, j), exactly one endpoint inside `plane`
  // (distances di, dj), crosses it; the same for either order of i and j.
  ShadedVertex cut(int plane, const ShadedVertex& i, const ShadedVertex& j, float di,
                   float dj) const;
  // Screen interpolation (spec section 4): gives the clipped polygon's n
  // vertices the varyings of the primitive's `corners` (3, or a line's 2)
  // extended affinely over the window plane, where that is finite.
  void screen_varyings(ShadedVertex* poly, size_t n, const ShadedVertex* const* orig,
                       int corners) const;
  float distance(int plane, const glm::vec4& c) const;
  ClippedVertex to_window(const ShadedVertex& v) const;

  // The viewport registers of a draw, derived from its viewport and depth
  // range (spec sections 4 and 5) when a batch of it arrives: a handful of
  // float operations per batch, and nothing to go stale when a driver
  // reprograms the draws between frames.
  struct ViewportRegs {
    // Guard-band factors: x >= -gl * w, x <= gr * w, ...
    float gl = 0.0f, gr = 0.0f, gb = 0.0f, gt = 0.0f;
    float half_width = 0.0f, half_height = 0.0f;  // 0.5 * viewport side
    float x = 0.0f, y = 0.0f;                     // viewport origin
    float depth_near = 0.0f, depth_scale = 1.0f;  // n, f - n
  };
  ViewportRegs viewport_regs(const DrawState& d) const;
  ViewportRegs m_vp;  // the current batch's draw's

  std::vector<Vertex> m_cache;  // post-transform cache storage, indexed by entry
  // Assembly registers (see the header comment for what each type keeps).
  std::array<Vertex, 2> m_reg{};
  uint64_t m_batch_primitives = 0;  // assembled in the current batch, for the cost
  uint64_t m_batch_extra = 0;       // extra outputs of clipped and unfilled triangles
  // The current batch's draw registers.
  unsigned m_varying_count = 0;  // components in use
  const RenderState* m_state = nullptr;

  std::vector<ShadedVertex> m_poly, m_next;  // reused: no allocation per triangle
  std::vector<uint8_t> m_flags, m_next_flags;
  std::vector<float> m_dist;
  std::vector<ClippedVertex> m_window;
  std::vector<ClippedPrimitive> m_out;

  uint64_t& m_cache_writes =
      m_stats.counter("cache_writes", "vertices", "shaded vertices stored in the vertex cache");
  uint64_t& m_cache_reads = m_stats.counter("cache_reads", "vertices",
                                            "shaded vertices read from the vertex cache (hits)");
  uint64_t& m_in = m_stats.counter("triangles_in", "triangles", "triangles assembled");
  uint64_t& m_invalid = m_stats.counter("triangles_invalid", "triangles",
                                        "dropped: index out of range or non-finite position");
  uint64_t& m_clipped_away =
      m_stats.counter("triangles_clipped_away", "triangles", "nothing left inside the clip volume");
  uint64_t& m_clipped =
      m_stats.counter("triangles_clipped", "triangles", "cut by a plane, a part kept");
  uint64_t& m_after_clip =
      m_stats.counter("triangles_after_clip", "triangles", "filled triangles written to setup");
  uint64_t& m_unfilled_degenerate = m_stats.counter(
      "triangles_degenerate", "triangles", "polygon mode line or point: zero area after snapping");
  uint64_t& m_unfilled_culled = m_stats.counter("triangles_culled", "triangles",
                                                "polygon mode line or point: removed by culling");
  uint64_t& m_unfilled = m_stats.counter("triangles_unfilled", "triangles",
                                         "polygon mode line or point: drawn as lines or points");
  uint64_t& m_unfilled_lines =
      m_stats.counter("unfilled_lines", "lines", "lines written for polygon mode line (edges)");
  uint64_t& m_unfilled_points = m_stats.counter("unfilled_points", "points",
                                                "points written for polygon mode point (vertices)");
  uint64_t& m_lines_in = m_stats.counter("lines_in", "lines", "lines assembled");
  uint64_t& m_lines_invalid = m_stats.counter("lines_invalid", "lines",
                                              "dropped: index out of range or non-finite position");
  uint64_t& m_lines_clipped_away =
      m_stats.counter("lines_clipped_away", "lines", "nothing left inside the clip volume");
  uint64_t& m_lines_clipped =
      m_stats.counter("lines_clipped", "lines", "cut by a plane, a part kept");
  uint64_t& m_lines_out = m_stats.counter(
      "lines_out", "lines", "lines written to setup (assembled ones and polygon mode's)");
  uint64_t& m_points_in = m_stats.counter("points_in", "points", "points assembled");
  uint64_t& m_points_invalid = m_stats.counter(
      "points_invalid", "points", "dropped: index out of range or non-finite position");
  uint64_t& m_points_clipped_away =
      m_stats.counter("points_clipped_away", "points", "vertex outside the view volume");
  uint64_t& m_points_out = m_stats.counter(
      "points_out", "points", "points written to setup (assembled ones and polygon mode's)");
};

}  // namespace gpusim
