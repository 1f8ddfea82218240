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

// A primitive leaving the clipper, before its vertices are filled in.
ClippedPrimitive work_primitive(PrimitiveKind kind, uint32_t draw_id, int64_t primitive_id,
                                const Varyings& flat) {
  ClippedPrimitive p;
  p.kind = PacketKind::work;
  p.primitive_kind = kind;
  p.vertex_count = vertex_count_of(kind);
  p.draw_id = draw_id;
  p.primitive_id = primitive_id;
  p.flat_varyings = flat;
  return p;
}

}  // namespace

namespace {

// Why a primitive whose last record is here went no further (traces).
constexpr const char* kDropped = "the clipper dropped it (a vertex not finite, or clipped away)";

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  const ConservationLedger::Frame& f = l.frame();
  // Per kind, primitives in = invalid + clipped away + survivors.
  // A filled triangle leaves as one triangle or more; a polygon-mode
  // one (line or point) is degenerate, culled or unfilled here, and
  // an unfilled one leaves as lines or points; an assembled line or
  // point leaves as itself.
  const auto survivors = [&l](const std::string& kind, uint64_t assembled) {
    const uint64_t in = l.get(kind + "_in");
    const uint64_t dropped = l.get(kind + "_invalid") + l.get(kind + "_clipped_away");
    l.equal(kind + "_in", in, kind + " assembled from the frame's draws", assembled);
    l.at_most(kind + "_invalid + " + kind + "_clipped_away", dropped, kind + "_in", in);
    return in >= dropped ? in - dropped : 0;
  };
  const uint64_t triangles = survivors("triangles", f.triangles);
  const uint64_t lines = survivors("lines", f.lines);
  const uint64_t points = survivors("points", f.points);
  const uint64_t after = l.get("triangles_after_clip");
  const uint64_t unfilled = l.get("triangles_unfilled");
  const uint64_t polygon_mode =
      l.get("triangles_degenerate") + l.get("triangles_culled") + unfilled;
  l.at_most("polygon-mode triangles (degenerate + culled + unfilled)", polygon_mode,
            "triangle survivors", triangles);
  const uint64_t filled = triangles >= polygon_mode ? triangles - polygon_mode : 0;
  l.at_most("filled survivors", filled, "triangles_after_clip", after);
  l.at_most("triangles_clipped", l.get("triangles_clipped"), "triangle survivors", triangles);
  l.at_most("lines_clipped", l.get("lines_clipped"), "line survivors", lines);
  const uint64_t lines_out = l.get("lines_out"), points_out = l.get("points_out");
  l.equal("lines_out", lines_out, "line survivors + unfilled_lines",
          lines + l.get("unfilled_lines"));
  l.equal("points_out", points_out, "point survivors + unfilled_points",
          points + l.get("unfilled_points"));
  if (unfilled == 0) {
    l.equal("unfilled_lines + unfilled_points", l.get("unfilled_lines") + l.get("unfilled_points"),
            "lines and points of triangles_unfilled", 0);
  }
  l.equal("cache_reads", l.get("cache_reads"), "vertex_fetch.cache_hits",
          l.stage("vertex_fetch", "cache_hits"));
  l.equal("tokens_in", l.get("tokens_in"), "vertex_fetch batches + control tokens",
          l.stage("vertex_fetch", "batches") + f.control);
  l.equal("tokens_out", l.get("tokens_out"),
          "triangles_after_clip + lines_out + points_out + control tokens",
          after + lines_out + points_out + f.control);
}

}  // namespace

const StageSpec& Clipper::spec() {
  static const StageSpec s{
      "clipper",
      StagePlacement::front_end,
      /*optional=*/false,
      {/*ii=*/2, /*latency=*/8},
      "primitive",
      "primitive assembly, clip-code test, perspective divide and viewport "
      "transform; a triangle that needs clipping pays per output triangle, "
      "one in polygon mode per line or point it becomes",
      "batches and control tokens read",
      "primitives and control tokens written",
      {"shader_to_clipper"},
      &conserve,
      StageTrace{TraceItem::slot_batch, {kDropped, kDropped, kDropped}, FragmentSite::none},
      {{"", "`ii` × (assembled primitives + extra primitives)",
        "A clipped triangle split into n triangles adds n − 1; a polygon-mode triangle drawn as n "
        "> 1 lines or points adds n − 1. A line or a point costs one, clipped or not."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(Clipper);

Clipper::Clipper(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame)
    : PipelineStage(name, spec(), -1, config, frame),
      in("in"),
      out("out"),
      m_cache(config.vertex_cache_entries) {
  // A triangle cut by all 7 planes has at most 10 vertices.
  m_poly.reserve(16);
  m_next.reserve(16);
  m_flags.reserve(16);
  m_next_flags.reserve(16);
  m_dist.reserve(16);
  m_window.reserve(16);
  m_out.reserve(4 * kVertexBatchSlots);
  SC_HAS_PROCESS(Clipper);
  SC_THREAD(run);
}

Clipper::ViewportRegs Clipper::viewport_regs(const DrawState& d) const {
  // The guard band keeps window x = (x/w + 1) * Vw/2 + Vx within [-L, L]
  // for -(2(L + Vx)/Vw + 1) <= x/w <= 2(L - Vx)/Vw - 1 (likewise y).
  const PixelRect r = viewport_of(d.state, m_frame.framebuffer.width, m_frame.framebuffer.height);
  ViewportRegs v;
  v.x = static_cast<float>(r.x);
  v.y = static_cast<float>(r.y);
  const float width = static_cast<float>(r.width), height = static_cast<float>(r.height);
  v.gl = 2.0f * (kGuardBandPixels + v.x) / width + 1.0f;
  v.gr = 2.0f * (kGuardBandPixels - v.x) / width - 1.0f;
  v.gb = 2.0f * (kGuardBandPixels + v.y) / height + 1.0f;
  v.gt = 2.0f * (kGuardBandPixels - v.y) / height - 1.0f;
  v.half_width = 0.5f * width;
  v.half_height = 0.5f * height;
  v.depth_near = d.state.depth_near;
  v.depth_scale = d.state.depth_far - d.state.depth_near;
  return v;
}

void Clipper::reset_state() {
  m_vp = ViewportRegs{};
  std::fill(m_cache.begin(), m_cache.end(), Vertex{});
  m_reg = {};
  m_batch_primitives = m_batch_extra = 0;
  m_varying_count = 0;
  m_state = nullptr;
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
  m_state = &draw.state;
  m_vp = viewport_regs(draw);
  m_batch_primitives = 0;
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
  return uint64_t{m_cost.ii} * (m_batch_primitives + m_batch_extra);
}

void Clipper::assemble(const DrawState& draw, uint32_t draw_id, uint32_t slot, const Vertex& v) {
  // Flat shading's provoking vertex (spec section 3): the incoming vertex
  // under the last-vertex convention; under the first-vertex one the
  // register holding the primitive's first vertex in API order.
  const bool first = draw.state.provoking_vertex == ProvokingVertex::first;
  switch (draw.primitive) {
    case PrimitiveType::triangles: {
      const uint32_t k = slot % 3;
      if (k < 2) {
        m_reg[k] = v;
      } else {
        process_triangle(draw_id, draw.first_primitive_id + slot / 3, m_reg[0], m_reg[1], v,
                         first ? m_reg[0] : v);
      }
      break;
    }
    case PrimitiveType::triangle_strip:
      if (slot >= 2) {
        // Triangle i = slot - 2 from the registers (v_i, v_i+1); odd ones
        // swap their first two vertices to keep the strip's winding.
        // Its first vertex in API order, v_i, is register 0 either way.
        const uint32_t i = slot - 2;
        const Vertex& provoking = first ? m_reg[0] : v;
        if (i % 2 == 0) {
          process_triangle(draw_id, draw.first_primitive_id + i, m_reg[0], m_reg[1], v, provoking);
        } else {
          process_triangle(draw_id, draw.first_primitive_id + i, m_reg[1], m_reg[0], v, provoking);
        }
        m_reg[0] = m_reg[1];
        m_reg[1] = v;
      } else {
        m_reg[slot] = v;
      }
      break;
    case PrimitiveType::triangle_fan:
      // Register 0 keeps the fan's centre; register 1 the last vertex, the
      // first-vertex convention's provoking vertex (v_i+1, not the centre).
      if (slot >= 2) {
        process_triangle(draw_id, draw.first_primitive_id + (slot - 2), m_reg[0], m_reg[1], v,
                         first ? m_reg[1] : v);
      }
      m_reg[slot == 0 ? 0 : 1] = v;
      break;
    case PrimitiveType::points:
      process_point(draw_id, draw.first_primitive_id + slot, v);
      break;
    case PrimitiveType::lines:
      if (slot % 2 == 0) {
        m_reg[0] = v;
      } else {
        process_line(draw_id, draw.first_primitive_id + slot / 2, m_reg[0], v, true, true, first);
      }
      break;
    case PrimitiveType::line_strip:
    case PrimitiveType::line_loop:
      // Line i = slot - 1 from register 0 (the previous vertex); lines after
      // the first share their first vertex with the previous line's last, so
      // Bresenham draws it once (draw_first clear).
      if (slot >= 1) {
        process_line(draw_id, draw.first_primitive_id + (slot - 1), m_reg[0], v, slot == 1, true,
                     first);
      } else if (draw.primitive == PrimitiveType::line_loop) {
        m_reg[1] = v;  // the loop's first vertex, kept until the draw's last slot
      }
      m_reg[0] = v;
      // The loop's closing line (n - 1, 0), id n - 1: both of its ends are
      // drawn by its neighbours. A draw's slot count is one of its registers.
      if (draw.primitive == PrimitiveType::line_loop && slot >= 1 &&
          slot + 1 == draw.buffers.slot_count) {
        process_line(draw_id, draw.first_primitive_id + slot, v, m_reg[1], false, false, first);
      }
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
      return c.x + m_vp.gl * c.w;
    case 4:
      return m_vp.gr * c.w - c.x;
    case 5:
      return c.y + m_vp.gb * c.w;
    case 6:
      return m_vp.gt * c.w - c.y;
  }
  return 0.0f;
}

ClippedVertex Clipper::to_window(const ShadedVertex& v) const {
  ClippedVertex w;
  const float q = 1.0f / v.clip.w;
  w.x = (v.clip.x * q + 1.0f) * m_vp.half_width + m_vp.x;
  w.y = (v.clip.y * q + 1.0f) * m_vp.half_height + m_vp.y;
  w.z = (v.clip.z * q + 1.0f) * 0.5f * m_vp.depth_scale + m_vp.depth_near;
  // Screen interpolation gives every vertex the weight 1: the interpolator's
  // perspective-correct formula then is affine in window space.
  if (m_state->interpolation == Interpolation::screen) {
    w.inv_w = 1.0f;
    for (unsigned k = 0; k < m_varying_count; ++k) w.varyings_over_w[k] = v.varyings[k];
  } else {
    w.inv_w = q;
    for (unsigned k = 0; k < m_varying_count; ++k) w.varyings_over_w[k] = v.varyings[k] * q;
  }
  return w;
}

void Clipper::process_triangle(uint32_t draw_id, int64_t primitive_id, const Vertex& a,
                               const Vertex& b, const Vertex& c, const Vertex& provoking) {
  ++m_in;
  ++m_batch_primitives;
  if (!(a.valid && b.valid && c.valid)) {
    ++m_invalid;
    return;
  }
  // Flat shading: the provoking vertex of the original triangle.
  ClippedPrimitive t =
      work_primitive(PrimitiveKind::triangle, draw_id, primitive_id, provoking.v.varyings);

  // Outcode test: inside every plane means no cut at all.
  bool inside = true;
  for (int plane = 0; plane < kPlanes && inside; ++plane) {
    inside = distance(plane, a.v.clip) >= 0.0f && distance(plane, b.v.clip) >= 0.0f &&
             distance(plane, c.v.clip) >= 0.0f;
  }
  const bool unfilled = m_state->polygon_mode != PolygonMode::fill;
  if (inside && unfilled) {
    m_poly.assign({a.v, b.v, c.v});
    m_flags.assign({1, 1, 1});
    draw_unfilled(t);
    return;
  }
  if (inside) {
    t.v = {to_window(a.v), to_window(b.v), to_window(c.v)};
    m_out.push_back(t);
    ++m_after_clip;
    return;
  }

  m_poly.assign({a.v, b.v, c.v});
  if (unfilled) {
    m_flags.assign({1, 1, 1});  // each original edge lies on the triangle
    clip_polygon<true>();
  } else {
    clip_polygon<false>();
  }
  const size_t n = m_poly.size();
  if (n < 3) {
    ++m_clipped_away;
    return;
  }
  if (m_state->interpolation == Interpolation::screen) {
    const ShadedVertex* const corners[3] = {&a.v, &b.v, &c.v};
    screen_varyings(m_poly.data(), n, corners, 3);
  }
  // A cut can land exactly on the original vertices; such a triangle counts
  // as not clipped, as the statistics define it.
  const bool unchanged = n == 3 && m_poly[0].clip == a.v.clip && m_poly[1].clip == b.v.clip &&
                         m_poly[2].clip == c.v.clip;
  if (!unchanged) ++m_clipped;
  if (unfilled) {
    draw_unfilled(t);
    return;
  }
  m_window.clear();
  for (const ShadedVertex& p : m_poly) m_window.push_back(to_window(p));
  for (size_t i = 1; i + 1 < n; ++i) {
    t.v = {m_window[0], m_window[i], m_window[i + 1]};
    m_out.push_back(t);
    ++m_after_clip;
  }
  m_batch_extra += n - 3;
}

void Clipper::draw_unfilled(ClippedPrimitive& t) {
  const size_t n = m_poly.size();
  m_window.clear();
  for (const ShadedVertex& p : m_poly) m_window.push_back(to_window(p));
  // Twice the polygon's signed area from its snapped vertices, by the
  // shoelace formula: integer arithmetic is exact, so it equals the spec's
  // sum of the fan triangles' area2. |X|, |Y| <= 2^24 (snapping saturates),
  // so each product is below 2^49 and 10 of them fit int64 easily.
  EdgeValue area2 = 0;
  Subpixel x0 = snap_to_subpixel(m_window[n - 1].x), y0 = snap_to_subpixel(m_window[n - 1].y);
  for (size_t i = 0; i < n; ++i) {
    const Subpixel x1 = snap_to_subpixel(m_window[i].x), y1 = snap_to_subpixel(m_window[i].y);
    area2 += EdgeValue{x0} * y1 - EdgeValue{x1} * y0;
    x0 = x1;
    y0 = y1;
  }
  if (area2 == 0) {
    ++m_unfilled_degenerate;
    return;
  }
  // Facing and culling on the whole polygon (spec section 7's rule).
  const bool front = (m_state->front_face == FrontFace::ccw) == (area2 > 0);
  if ((m_state->cull == CullMode::back && !front) || (m_state->cull == CullMode::front && front)) {
    ++m_unfilled_culled;
    return;
  }
  ++m_unfilled;
  const bool lines = m_state->polygon_mode == PolygonMode::line;
  t.primitive_kind = lines ? PrimitiveKind::line : PrimitiveKind::point;
  t.vertex_count = vertex_count_of(t.primitive_kind);
  // Every polygon vertex starts one edge: Bresenham draws each vertex once.
  t.draw_first = true;
  t.draw_last = false;
  // A point shows its flat varyings (spec section 9): the triangle's
  // provoking vertex's with flat shading, else its own vertex's.
  const bool own_varyings = !lines && m_state->shading != Shading::flat;
  uint64_t emitted = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!m_flags[i]) continue;
    t.v[0] = m_window[i];
    if (lines) t.v[1] = m_window[i + 1 == n ? 0 : i + 1];
    if (own_varyings) t.flat_varyings = m_poly[i].varyings;
    m_out.push_back(t);
    ++emitted;
  }
  if (lines) {
    m_lines_out += emitted;
    m_unfilled_lines += emitted;
  } else {
    m_points_out += emitted;
    m_unfilled_points += emitted;
  }
  if (emitted > 1) m_batch_extra += emitted - 1;
}

void Clipper::process_line(uint32_t draw_id, int64_t primitive_id, const Vertex& a, const Vertex& b,
                           bool draw_first, bool draw_last, bool provoking_first) {
  ++m_lines_in;
  ++m_batch_primitives;
  if (!(a.valid && b.valid)) {
    ++m_lines_invalid;
    return;
  }
  ShadedVertex p = a.v, q = b.v;
  // Outcodes: inside every plane passes untouched; both endpoints outside
  // one plane can have no part inside.
  bool inside = true, reject = false;
  for (int plane = 0; plane < kPlanes; ++plane) {
    const bool in_p = distance(plane, p.clip) >= 0.0f, in_q = distance(plane, q.clip) >= 0.0f;
    inside = inside && in_p && in_q;
    reject = reject || (!in_p && !in_q);
  }
  if (reject) {
    ++m_lines_clipped_away;
    return;
  }
  if (!inside) {
    // Plane by plane on the current endpoints: an earlier cut can leave
    // both outside a later plane.
    for (int plane = 0; plane < kPlanes; ++plane) {
      const float dp = distance(plane, p.clip), dq = distance(plane, q.clip);
      const bool in_p = dp >= 0.0f, in_q = dq >= 0.0f;
      if (in_p && in_q) continue;
      if (!in_p && !in_q) {
        ++m_lines_clipped_away;
        return;
      }
      const ShadedVertex v = cut(plane, p, q, dp, dq);
      (in_p ? q : p) = v;
    }
    ++m_lines_clipped;
    if (m_state->interpolation == Interpolation::screen) {
      ShadedVertex ends[2] = {p, q};
      const ShadedVertex* const corners[2] = {&a.v, &b.v};
      screen_varyings(ends, 2, corners, 2);
      p = ends[0];
      q = ends[1];
    }
  }
  // Flat shading: the provoking vertex, unclipped.
  ClippedPrimitive l = work_primitive(PrimitiveKind::line, draw_id, primitive_id,
                                      provoking_first ? a.v.varyings : b.v.varyings);
  l.v[0] = to_window(p);
  l.v[1] = to_window(q);
  l.draw_first = draw_first;
  l.draw_last = draw_last;
  m_out.push_back(l);
  ++m_lines_out;
}

void Clipper::process_point(uint32_t draw_id, int64_t primitive_id, const Vertex& a) {
  ++m_points_in;
  ++m_batch_primitives;
  if (!a.valid) {
    ++m_points_invalid;
    return;
  }
  // The view volume itself, not the guard band: a point is drawn whole or
  // not at all (spec section 4c).
  const glm::vec4& c = a.v.clip;
  const bool inside = c.w - kMinClipW >= 0.0f && c.x + c.w >= 0.0f && c.w - c.x >= 0.0f &&
                      c.y + c.w >= 0.0f && c.w - c.y >= 0.0f && c.z + c.w >= 0.0f &&
                      c.w - c.z >= 0.0f;
  if (!inside) {
    ++m_points_clipped_away;
    return;
  }
  ClippedPrimitive pt = work_primitive(PrimitiveKind::point, draw_id, primitive_id, a.v.varyings);
  pt.v[0] = to_window(a.v);
  m_out.push_back(pt);
  ++m_points_out;
}

ShadedVertex Clipper::cut(int plane, const ShadedVertex& i, const ShadedVertex& j, float di,
                          float dj) const {
  // Cut from the endpoint nearer the plane (the inside one on a tie): t
  // stays small, and the cut depends only on the edge, so two triangles
  // sharing it (or a line along it) cut it at the same point.
  const bool in_i = di >= 0.0f;
  const bool from_i = std::fabs(di) < std::fabs(dj) || (std::fabs(di) == std::fabs(dj) && in_i);
  const ShadedVertex& p = from_i ? i : j;
  const ShadedVertex& q = from_i ? j : i;
  const float dp = from_i ? di : dj;
  const float dq = from_i ? dj : di;
  const float t = dp / (dp - dq);
  ShadedVertex v;
  for (int k = 0; k < 4; ++k) v.clip[k] = p.clip[k] + t * (q.clip[k] - p.clip[k]);
  // Rounding can leave the cut at or below w = 0; keep 1/w finite. (As
  // std::max: a NaN w would stay NaN; finite inputs give none.)
  if (plane == 0) v.clip.w = std::max(v.clip.w, kMinClipW);
  for (unsigned k = 0; k < m_varying_count; ++k)
    v.varyings[k] = p.varyings[k] + t * (q.varyings[k] - p.varyings[k]);
  return v;
}

void Clipper::screen_varyings(ShadedVertex* poly, size_t n, const ShadedVertex* const* orig,
                              int corners) const {
  // The corners' projections (NDC): the varyings extended affinely over the
  // window plane through them (the viewport's scale cancels in the ratios).
  float px[3] = {}, py[3] = {};
  for (int i = 0; i < corners; ++i) {
    px[i] = orig[i]->clip.x / orig[i]->clip.w;
    py[i] = orig[i]->clip.y / orig[i]->clip.w;
  }
  const float d1x = px[1] - px[0], d1y = py[1] - py[0];
  const float d2x = corners == 3 ? px[2] - px[0] : 0.0f;
  const float d2y = corners == 3 ? py[2] - py[0] : 0.0f;
  const float den = d1x * d2y - d1y * d2x;
  const bool along_x = std::fabs(d1x) >= std::fabs(d1y);  // lines: the longer projected axis
  for (size_t i = 0; i < n; ++i) {
    ShadedVertex& v = poly[i];
    // A corner that survived keeps its own varyings (the first equal one).
    const ShadedVertex* same = nullptr;
    for (int c = 0; c < corners && same == nullptr; ++c) {
      if (v.clip == orig[c]->clip) same = orig[c];
    }
    if (same != nullptr) {
      v.varyings = same->varyings;
      continue;
    }
    const float ex = v.clip.x / v.clip.w - px[0], ey = v.clip.y / v.clip.w - py[0];
    if (corners == 2) {
      const float s = along_x ? ex / d1x : ey / d1y;
      if (!std::isfinite(s)) continue;  // the cut's perspective values stay
      for (unsigned k = 0; k < m_varying_count; ++k)
        v.varyings[k] = orig[0]->varyings[k] + s * (orig[1]->varyings[k] - orig[0]->varyings[k]);
    } else {
      const float b1 = (ex * d2y - ey * d2x) / den;
      const float b2 = (d1x * ey - d1y * ex) / den;
      if (!(std::isfinite(b1) && std::isfinite(b2))) continue;
      for (unsigned k = 0; k < m_varying_count; ++k) {
        const float v0 = orig[0]->varyings[k];
        v.varyings[k] = v0 + b1 * (orig[1]->varyings[k] - v0) + b2 * (orig[2]->varyings[k] - v0);
      }
    }
  }
}

template <bool kEdgeFlags>
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
    if (kEdgeFlags) m_next_flags.clear();
    for (size_t i = 0; i < n; ++i) {
      const size_t j = i + 1 == n ? 0 : i + 1;
      const float di = m_dist[i], dj = m_dist[j];
      const bool in_i = di >= 0.0f, in_j = dj >= 0.0f;
      if (in_i) {
        m_next.push_back(m_poly[i]);
        if (kEdgeFlags) m_next_flags.push_back(m_flags[i]);
      }
      if (in_i == in_j) continue;
      m_next.push_back(cut(plane, m_poly[i], m_poly[j], di, dj));
      // Leaving the inside, the edge from the cut runs along the plane;
      // entering, it is the rest of edge i.
      if (kEdgeFlags) m_next_flags.push_back(in_i ? 0 : m_flags[i]);
    }
    m_poly.swap(m_next);
    if (kEdgeFlags) m_flags.swap(m_next_flags);
  }
  if (m_poly.size() < 3) m_poly.clear();
}

}  // namespace gpusim
