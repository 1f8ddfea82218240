// Clipper: primitive assembly, the data half of the post-transform vertex
// cache, invalid-triangle removal, clipping, perspective divide and viewport
// (docs/pipeline-spec.md, sections 3 to 5).
//
// - Assembly: each slot of a batch yields a vertex: a fetched slot's shaded
//   vertex (stored into its cache entry when it has one), a cached slot's
//   entry, or nothing for an invalid slot. Lists, strips (odd triangles swap
//   their first two vertices) and fans are assembled from a few registers
//   that carry over batch boundaries; a batch with first_slot 0 starts a draw.
//   Triangle k of a draw gets primitive id first_primitive_id + k, counting
//   every assembled triangle, including the ones dropped below.
// - A triangle with an invalid vertex or a non-finite clip coordinate is
//   dropped (triangles_invalid).
// - Clipping: all 7 plane distances of the 3 vertices are computed at once;
//   a triangle inside every plane (the common case) passes untouched.
//   Otherwise Sutherland-Hodgman runs plane by plane on a small polygon
//   buffer, cutting each edge from its endpoint nearer the plane, with the
//   plane-0 w floor; fewer than 3 vertices left is clipped away. The polygon
//   is split into the fan (p0, p_i, p_i+1).
// - A cut vertex interpolates the clip position and every varying of the
//   draw (its VaryingLayout's count, whatever they mean) with the same
//   formula, in one loop.
// - Each vertex is divided by w once (q = 1/w) and mapped to window
//   coordinates, unsnapped; its varyings are multiplied by q for the
//   interpolator's perspective correction. Every output triangle is a
//   ClippedPrimitive of kind triangle carrying the provoking (third) vertex's
//   varyings of the original triangle, for flat shading.
//
// Cost model, per batch: busy = ii(clipper) x (triangles assembled + extra
// triangles), where a clipped triangle split into n > 1 triangles adds n - 1
// extra. Slots that complete no triangle cost nothing. The output triangles
// are written after that and readable by setup latency(clipper) cycles later.
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
#include "hw/pipeline_stage.h"
#include "hw/stats.h"
#include "hw/vertex_packets.h"

namespace gpusim {

class Clipper : public PipelineStage {
 public:
  FifoInPort<ShadedBatch> in;
  FifoOutPort<ClippedPrimitive> out;

  Clipper(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);

  uint64_t triangles_in() const { return m_in; }
  // The golden model's clipping counters (docs/pipeline-spec.md, section 13).
  nlohmann::json pipeline_counts() const {
    return {{"triangles_in", m_in},
            {"triangles_invalid", m_invalid},
            {"triangles_clipped_away", m_clipped_away},
            {"triangles_clipped", m_clipped},
            {"triangles_after_clip", m_after_clip}};
  }

 private:
  static constexpr int kPlanes = 7;

  // An assembly register: the vertex and whether a triangle may use it.
  struct Vertex {
    ShadedVertex v;
    bool valid = false;  // index in range and every clip coordinate finite
  };

  void run();
  // Cycles the batch costs; its output triangles are appended to m_out.
  uint64_t process_batch(const ShadedBatch& batch);
  void assemble(const DrawState& draw, uint32_t draw_id, uint32_t slot, const Vertex& v);
  void process_triangle(uint32_t draw_id, int64_t primitive_id, const Vertex& a, const Vertex& b,
                        const Vertex& c);
  // Sutherland-Hodgman on m_poly; leaves the clipped polygon there.
  void clip_polygon();
  float distance(int plane, const glm::vec4& c) const;
  ClippedVertex to_window(const ShadedVertex& v) const;

  // Guard-band factors (spec section 4): x >= -m_gl * w, x <= m_gr * w, ...
  float m_gl = 0.0f, m_gr = 0.0f, m_gb = 0.0f, m_gt = 0.0f;
  float m_half_width = 0.0f, m_half_height = 0.0f;

  std::vector<Vertex> m_cache;  // post-transform cache storage, indexed by entry
  // Assembly registers: lists keep the triangle's first two vertices, strips
  // the last two, fans the first and the last.
  std::array<Vertex, 2> m_reg{};
  uint64_t m_batch_triangles = 0;  // assembled in the current batch, for the cost
  uint64_t m_batch_extra = 0;      // extra output triangles of clipped ones
  unsigned m_varying_count = 0;    // components in use in the current batch's draw

  std::vector<ShadedVertex> m_poly, m_next;  // reused: no allocation per triangle
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
      m_stats.counter("triangles_after_clip", "triangles", "triangles written to setup");
};

}  // namespace gpusim
