#include "stages/clipper.h"

#include <algorithm>
#include <cmath>

#include "hw/fixed_point.h"

namespace gpusim {
namespace {

// Plane 0 keeps w at or above 2^-32, so 1/w stays finite.
constexpr float kMinClipW = 0x1p-32f;

bool is_finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

}  // namespace

Clipper::Clipper(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame)
    : PipelineStage(name, "clipper", -1, config, frame, "batches and control tokens read",
                    "triangles and control tokens written"),
      in("in"),
      out("out"),
      m_cache(config.vertex_cache_entries) {
  const float width = static_cast<float>(frame.framebuffer.width);
  const float height = static_cast<float>(frame.framebuffer.height);
  const float sx = 2.0f * kGuardBandPixels / width;
  const float sy = 2.0f * kGuardBandPixels / height;
  m_gl = sx + 1.0f;
  m_gr = sx - 1.0f;
  m_gb = sy + 1.0f;
  m_gt = sy - 1.0f;
  m_half_width = 0.5f * width;
  m_half_height = 0.5f * height;
  // A triangle cut by all 7 planes has at most 10 vertices.
  m_poly.reserve(16);
  m_next.reserve(16);
  m_dist.reserve(16);
  m_window.reserve(16);
  m_out.reserve(4 * kVertexBatchSlots);
  SC_HAS_PROCESS(Clipper);
  SC_THREAD(run);
}

void Clipper::run() {
  for (;;) {
    const ShadedBatch batch = receive(in);
    m_out.clear();
    uint64_t busy = m_cost.ii;
    if (batch.kind == PacketKind::work) {
      busy = process_batch(batch);
    } else {
      ClippedPrimitive token;
      token.kind = batch.kind;
      m_out.push_back(token);
    }
    work(busy);
    for (const ClippedPrimitive& t : m_out) emit(out, t);
  }
}

uint64_t Clipper::process_batch(const ShadedBatch& batch) {
  const DrawState& draw = m_frame.draws.at(batch.draw_id);
  m_varying_count = draw.varyings.count;
  m_batch_triangles = 0;
  m_batch_extra = 0;
  Vertex v;
  for (uint32_t i = 0; i < batch.slot_count; ++i) {
    const VertexSlot& slot = batch.slots[i];
    switch (slot.kind) {
      case SlotKind::fetched:
        v.v = batch.vertices[slot.vertex];
        v.valid = is_finite(v.v.clip);
        if (slot.entry != kNoCacheEntry) {
          m_cache[slot.entry] = v;
          ++m_cache_writes;
        }
        break;
      case SlotKind::cached:
        v = m_cache[slot.entry];
        ++m_cache_reads;
        break;
      case SlotKind::invalid:
        v = Vertex{};
        break;
    }
    assemble(draw, batch.draw_id, batch.first_slot + i, v);
  }
  return uint64_t{m_cost.ii} * (m_batch_triangles + m_batch_extra);
}

void Clipper::assemble(const DrawState& draw, uint32_t draw_id, uint32_t slot, const Vertex& v) {
  switch (draw.primitive) {
    case PrimitiveType::triangles: {
      const uint32_t k = slot % 3;
      if (k < 2) {
        m_reg[k] = v;
      } else {
        process_triangle(draw_id, draw.first_primitive_id + slot / 3, m_reg[0], m_reg[1], v);
      }
      break;
    }
    case PrimitiveType::triangle_strip:
      if (slot >= 2) {
        // Triangle i = slot - 2 from the registers (v_i, v_i+1); odd ones
        // swap their first two vertices to keep the strip's winding.
        const uint32_t i = slot - 2;
        if (i % 2 == 0) {
          process_triangle(draw_id, draw.first_primitive_id + i, m_reg[0], m_reg[1], v);
        } else {
          process_triangle(draw_id, draw.first_primitive_id + i, m_reg[1], m_reg[0], v);
        }
        m_reg[0] = m_reg[1];
        m_reg[1] = v;
      } else {
        m_reg[slot] = v;
      }
      break;
    case PrimitiveType::triangle_fan:
      if (slot >= 2)
        process_triangle(draw_id, draw.first_primitive_id + (slot - 2), m_reg[0], m_reg[1], v);
      // Register 0 keeps the fan's centre; register 1 the last vertex.
      m_reg[slot == 0 ? 0 : 1] = v;
      break;
  }
}

// inline: called with a constant plane in unrolled loops, where the switch
// folds away (only this file uses it).
inline float Clipper::distance(int plane, const glm::vec4& c) const {
  switch (plane) {
    case 0:
      return c.w - kMinClipW;
    case 1:
      return c.z + c.w;
    case 2:
      return c.w - c.z;
    case 3:
      return c.x + m_gl * c.w;
    case 4:
      return m_gr * c.w - c.x;
    case 5:
      return c.y + m_gb * c.w;
    case 6:
      return m_gt * c.w - c.y;
  }
  return 0.0f;
}

ClippedVertex Clipper::to_window(const ShadedVertex& v) const {
  ClippedVertex w;
  const float q = 1.0f / v.clip.w;
  w.inv_w = q;
  w.x = (v.clip.x * q + 1.0f) * m_half_width;
  w.y = (v.clip.y * q + 1.0f) * m_half_height;
  w.z = (v.clip.z * q + 1.0f) * 0.5f;
  for (unsigned k = 0; k < m_varying_count; ++k) w.varyings_over_w[k] = v.varyings[k] * q;
  return w;
}

void Clipper::process_triangle(uint32_t draw_id, int64_t primitive_id, const Vertex& a,
                               const Vertex& b, const Vertex& c) {
  ++m_in;
  ++m_batch_triangles;
  if (!(a.valid && b.valid && c.valid)) {
    ++m_invalid;
    return;
  }
  ClippedPrimitive t;
  t.kind = PacketKind::work;
  t.primitive_kind = PrimitiveKind::triangle;
  t.vertex_count = vertex_count_of(PrimitiveKind::triangle);
  t.draw_id = draw_id;
  t.primitive_id = primitive_id;
  t.flat_varyings = c.v.varyings;  // the provoking vertex of the original triangle

  // Outcode test: inside every plane means no cut at all.
  bool inside = true;
  for (int plane = 0; plane < kPlanes && inside; ++plane) {
    inside = distance(plane, a.v.clip) >= 0.0f && distance(plane, b.v.clip) >= 0.0f &&
             distance(plane, c.v.clip) >= 0.0f;
  }
  if (inside) {
    t.v = {to_window(a.v), to_window(b.v), to_window(c.v)};
    m_out.push_back(t);
    ++m_after_clip;
    return;
  }

  m_poly.assign({a.v, b.v, c.v});
  clip_polygon();
  const size_t n = m_poly.size();
  if (n < 3) {
    ++m_clipped_away;
    return;
  }
  // A cut can land exactly on the original vertices; such a triangle counts
  // as not clipped, as the statistics define it.
  const bool unchanged = n == 3 && m_poly[0].clip == a.v.clip && m_poly[1].clip == b.v.clip &&
                         m_poly[2].clip == c.v.clip;
  if (!unchanged) ++m_clipped;
  m_window.clear();
  for (const ShadedVertex& p : m_poly) m_window.push_back(to_window(p));
  for (size_t i = 1; i + 1 < n; ++i) {
    t.v = {m_window[0], m_window[i], m_window[i + 1]};
    m_out.push_back(t);
    ++m_after_clip;
  }
  m_batch_extra += n - 3;
}

void Clipper::clip_polygon() {
  for (int plane = 0; plane < kPlanes && !m_poly.empty(); ++plane) {
    const size_t n = m_poly.size();
    m_dist.resize(n);
    bool all_inside = true;
    for (size_t i = 0; i < n; ++i) {
      m_dist[i] = distance(plane, m_poly[i].clip);
      all_inside = all_inside && m_dist[i] >= 0.0f;
    }
    if (all_inside) continue;
    m_next.clear();
    for (size_t i = 0; i < n; ++i) {
      const size_t j = i + 1 == n ? 0 : i + 1;
      const float di = m_dist[i], dj = m_dist[j];
      const bool in_i = di >= 0.0f, in_j = dj >= 0.0f;
      if (in_i) m_next.push_back(m_poly[i]);
      if (in_i == in_j) continue;
      // Cut from the endpoint nearer the plane (the inside one on a tie):
      // t stays small, and the cut depends only on the edge, so two
      // triangles sharing it cut it at the same point.
      const bool from_i = std::fabs(di) < std::fabs(dj) || (std::fabs(di) == std::fabs(dj) && in_i);
      const ShadedVertex& p = from_i ? m_poly[i] : m_poly[j];
      const ShadedVertex& q = from_i ? m_poly[j] : m_poly[i];
      const float dp = from_i ? di : dj;
      const float dq = from_i ? dj : di;
      const float t = dp / (dp - dq);
      // Every component, position and varyings alike, by the same formula.
      ShadedVertex v;
      for (int k = 0; k < 4; ++k) v.clip[k] = p.clip[k] + t * (q.clip[k] - p.clip[k]);
      for (unsigned k = 0; k < m_varying_count; ++k)
        v.varyings[k] = p.varyings[k] + t * (q.varyings[k] - p.varyings[k]);
      // Rounding can leave the cut at or below w = 0; keep 1/w finite. (As
      // std::max: a NaN w would stay NaN; finite inputs give none.)
      if (plane == 0) v.clip.w = std::max(v.clip.w, kMinClipW);
      m_next.push_back(v);
    }
    m_poly.swap(m_next);
  }
  if (m_poly.size() < 3) m_poly.clear();
}

}  // namespace gpusim
