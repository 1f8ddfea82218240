#include "testbench/driver/painter_sort.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "testbench/golden/golden_model.h"

namespace gpusim::painter {
namespace {

// A vertex within this NDC distance of a plane counts as lying on it, so
// triangles of one mesh that share a vertex or an edge are not taken for
// ones that cross each other's plane. NDC spans [-1, 1]; double rounding of
// the plane through three float vertices is some 1e-15 there.
constexpr double kPlaneEpsilon = 1.0 / (1 << 23);

bool is_finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// Sides of a triangle's vertices relative to a plane: +1 behind, -1 in
// front, 0 on it (within kPlaneEpsilon).
std::array<int, 3> sides(const SortTriangle& t, const SortTriangle& plane) {
  std::array<int, 3> s{};
  for (int i = 0; i < 3; ++i) {
    const double f = plane_side(plane, t.ndc[i]);
    s[i] = f > kPlaneEpsilon ? 1 : f < -kPlaneEpsilon ? -1 : 0;
  }
  return s;
}

// A polygon vertex while cutting: clip position and colour in double.
struct CutVertex {
  glm::dvec4 clip, color;
};

// Sutherland-Hodgman on both sides at once: the vertices with side >= 0 go
// to `pos`, those with side <= 0 to `neg`, and an edge whose ends lie
// strictly on opposite sides is cut where the clip-linear `dist` is zero.
// Each cut vertex is computed once and given to both pieces, so the pieces
// share their new edge exactly and the fill rule draws its pixels once.
void cut(const std::vector<CutVertex>& poly, const std::vector<double>& dist,
         const std::vector<int>& side, std::vector<CutVertex>& neg, std::vector<CutVertex>& pos) {
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    if (side[i] >= 0) pos.push_back(poly[i]);
    if (side[i] <= 0) neg.push_back(poly[i]);
    if (side[i] * side[j] < 0) {
      const double t = dist[i] / (dist[i] - dist[j]);
      const CutVertex v{poly[i].clip + t * (poly[j].clip - poly[i].clip),
                        poly[i].color + t * (poly[j].color - poly[i].color)};
      pos.push_back(v);
      neg.push_back(v);
    }
  }
}

// The sort's geometry of a piece is the exact (double) one, while what is
// submitted is rounded to float: a piece then lies on the plane that cut it
// to within double rounding (far below kPlaneEpsilon) and is not cut again
// by the same plane for the float rounding of its new vertices.
SortTriangle make_exact_triangle(const std::array<glm::dvec4, 3>& clip,
                                 const std::array<glm::dvec4, 3>& color) {
  SortTriangle t;
  t.min = glm::dvec3(std::numeric_limits<double>::infinity());
  t.max = -t.min;
  for (int i = 0; i < 3; ++i) {
    t.clip[i] = glm::vec4(clip[i]);
    t.color[i] = glm::vec4(color[i]);
    t.ndc[i] = glm::dvec3(clip[i]) / clip[i].w;
    t.min = glm::min(t.min, t.ndc[i]);
    t.max = glm::max(t.max, t.ndc[i]);
  }
  glm::dvec3 n = glm::cross(t.ndc[1] - t.ndc[0], t.ndc[2] - t.ndc[0]);
  const double len = glm::length(n);
  n = len > 0.0 ? n / len : glm::dvec3(0.0);
  if (n.z < 0.0) n = -n;
  t.n = n;
  t.d = -glm::dot(n, t.ndc[0]);
  return t;
}

// A convex polygon as a fan of triangles (0, i, i + 1), which keeps its
// winding; fewer than 3 vertices give none.
std::vector<SortTriangle> fan(const std::vector<CutVertex>& poly, const SortTriangle& from) {
  std::vector<SortTriangle> out;
  for (size_t i = 1; i + 1 < poly.size(); ++i) {
    SortTriangle t = make_exact_triangle({poly[0].clip, poly[i].clip, poly[i + 1].clip},
                                         {poly[0].color, poly[i].color, poly[i + 1].color});
    t.draw = from.draw;
    t.order = from.order;
    out.push_back(t);
  }
  return out;
}

std::vector<CutVertex> polygon_of(const SortTriangle& t) {
  std::vector<CutVertex> poly;
  for (int i = 0; i < 3; ++i) poly.push_back({glm::dvec4(t.clip[i]), glm::dvec4(t.color[i])});
  return poly;
}

// List order: a is drawn after b. The farther triangle (larger max z) is
// drawn first; of two equally far, the later in API order, so that at an
// exact tie the earlier one ends on top, as under a `less` depth test.
bool drawn_after(const SortTriangle& a, const SortTriangle& b) {
  if (a.max.z != b.max.z) return a.max.z < b.max.z;
  return a.order < b.order;
}

// Inserts t among list[0, end) (kept in drawn_after order).
void insert_sorted(std::vector<SortTriangle>& list, size_t end, const SortTriangle& t) {
  const auto at = std::upper_bound(list.begin(), list.begin() + static_cast<std::ptrdiff_t>(end), t,
                                   drawn_after);
  list.insert(at, t);
}

bool straddles(const SortTriangle& t, const SortTriangle& plane) {
  const std::array<int, 3> s = sides(t, plane);
  return std::count(s.begin(), s.end(), 1) > 0 && std::count(s.begin(), s.end(), -1) > 0;
}

// The draws whose triangles are sorted: filled, opaque, z-buffered
// triangles with every colour channel written, a depth range that increases
// (the sort takes larger NDC z as farther, which a reversed or empty range
// contradicts), lit per vertex (a Phong draw submitted pre-lit would turn
// Gouraud), and with perspective interpolation unless flat shaded (a
// split's new vertex carries a clip-linear colour, which screen
// interpolation would not give it; flat colours are constant). Anything
// else keeps its own state and is drawn after the sorted ones of its
// stretch.
bool sortable(const Draw& d) {
  const RenderState& s = d.state;
  return primitive_kind_of(d.primitive) == PrimitiveKind::triangle &&
         s.polygon_mode == PolygonMode::fill && !s.blend && s.depth_test &&
         (s.depth_func == CompareFunc::less || s.depth_func == CompareFunc::lequal) &&
         s.color_mask == std::array<bool, 4>{true, true, true, true} &&
         s.depth_near < s.depth_far && !golden::lit_per_pixel(d) &&
         (s.interpolation == Interpolation::perspective || s.shading == Shading::flat);
}

// The viewport transform a draw gets in the models: viewport and depth
// range, the viewport scaled by the supersampling factor k.
golden::ViewportTransform transform_of(const RenderState& s, int width, int height, int k) {
  RenderState scaled_state = s;
  if (s.viewport) scaled_state.viewport = scaled(*s.viewport, k);
  return {viewport_of(scaled_state, width, height), s.depth_near, s.depth_far};
}

bool same_space(const golden::ViewportTransform& a, const golden::ViewportTransform& b) {
  return a.rect == b.rect && a.near == b.near && a.far == b.far;
}

}  // namespace

SortTriangle make_triangle(const std::array<glm::vec4, 3>& clip,
                           const std::array<glm::vec4, 3>& color) {
  return make_exact_triangle({glm::dvec4(clip[0]), glm::dvec4(clip[1]), glm::dvec4(clip[2])},
                             {glm::dvec4(color[0]), glm::dvec4(color[1]), glm::dvec4(color[2])});
}

double plane_side(const SortTriangle& t, const glm::dvec3& p) {
  return glm::dot(t.n, p) + t.d;
}

bool depth_extents_disjoint(const SortTriangle& p, const SortTriangle& q) {
  return q.max.z <= p.min.z;
}
bool x_extents_disjoint(const SortTriangle& p, const SortTriangle& q) {
  return p.max.x <= q.min.x || q.max.x <= p.min.x;
}
bool y_extents_disjoint(const SortTriangle& p, const SortTriangle& q) {
  return p.max.y <= q.min.y || q.max.y <= p.min.y;
}

// An edge-on plane (n.z = 0) has no front or back as seen by the viewer:
// only a triangle lying in it is on both sides.
bool entirely_behind(const SortTriangle& t, const SortTriangle& plane) {
  const std::array<int, 3> s = sides(t, plane);
  const bool on = s == std::array<int, 3>{0, 0, 0};
  if (plane.n.z == 0.0) return on;
  return std::count(s.begin(), s.end(), -1) == 0;
}
bool entirely_in_front(const SortTriangle& t, const SortTriangle& plane) {
  const std::array<int, 3> s = sides(t, plane);
  const bool on = s == std::array<int, 3>{0, 0, 0};
  if (plane.n.z == 0.0) return on;
  return std::count(s.begin(), s.end(), 1) == 0;
}

// Separating axes: two convex polygons' interiors are disjoint exactly when
// the normal of one of their edges separates them. Touching along an axis
// (a shared edge) counts as disjoint: the fill rule gives a pixel on a
// shared edge to one triangle only.
bool projections_overlap(const SortTriangle& p, const SortTriangle& q) {
  const SortTriangle* tri[2] = {&p, &q};
  for (const SortTriangle* e : tri) {
    for (int i = 0; i < 3; ++i) {
      const glm::dvec3& a = e->ndc[i];
      const glm::dvec3& b = e->ndc[(i + 1) % 3];
      const glm::dvec2 axis(a.y - b.y, b.x - a.x);
      double lo[2], hi[2];
      for (int k = 0; k < 2; ++k) {
        lo[k] = std::numeric_limits<double>::infinity();
        hi[k] = -lo[k];
        for (const glm::dvec3& v : tri[k]->ndc) {
          const double x = axis.x * v.x + axis.y * v.y;
          lo[k] = std::min(lo[k], x);
          hi[k] = std::max(hi[k], x);
        }
      }
      if (hi[0] <= lo[1] || hi[1] <= lo[0]) return false;
    }
  }
  return true;
}

Decision decide(const SortTriangle& p, const SortTriangle& q) {
  if (depth_extents_disjoint(p, q)) return Decision::depth_extents;
  if (x_extents_disjoint(p, q)) return Decision::x_extents;
  if (y_extents_disjoint(p, q)) return Decision::y_extents;
  if (entirely_behind(p, q)) return Decision::p_behind_q_plane;
  if (entirely_in_front(q, p)) return Decision::q_in_front_p_plane;
  if (!projections_overlap(p, q)) return Decision::projections;
  return Decision::ambiguous;
}

// The cut is made in clip space: the plane n . p + d = 0 of NDC points is
// n.x X + n.y Y + n.z Z + d W = 0 in clip coordinates (multiplied by W > 0),
// a linear function, so cutting an edge at the parameter where it is zero
// and interpolating position and colour linearly gives exactly the point
// and the colour that the rasterizer's perspective-correct interpolation
// gives there; NDC-linear interpolation would bend the colours.
SplitResult split(const SortTriangle& t, const SortTriangle& by) {
  const std::array<int, 3> s3 = sides(t, by);
  std::vector<double> dist(3);
  for (int i = 0; i < 3; ++i) {
    const glm::dvec4 c(t.clip[i]);
    dist[i] = by.n.x * c.x + by.n.y * c.y + by.n.z * c.z + by.d * c.w;
  }
  std::vector<CutVertex> neg, pos;
  cut(polygon_of(t), dist, {s3.begin(), s3.end()}, neg, pos);
  return {fan(pos, t), fan(neg, t)};
}

std::vector<SortTriangle> sort(std::vector<SortTriangle> list, Stats& stats) {
  // `list` holds the triangles not yet drawn, the next to draw at the back.
  std::stable_sort(list.begin(), list.end(), drawn_after);
  stats.triangles_sorted += list.size();
  // A bound on splitting, so that no arrangement (or rounding) can make the
  // sort run away: beyond it, undecided pairs stay in depth order.
  const uint64_t split_budget = 4 * list.size() + 64;
  std::vector<SortTriangle> out;
  out.reserve(list.size());
  while (!list.empty()) {
    const size_t head = list.size() - 1;
    bool restart = false;
    for (size_t k = head; k-- > 0 && !restart;) {
      const SortTriangle& p = list[head];
      const SortTriangle& q = list[k];
      ++stats.comparisons;
      switch (decide(p, q)) {
        case Decision::depth_extents:
          // Every later q is nearer still: the list is in depth order.
          ++stats.decided_depth_extents;
          k = 0;
          continue;
        case Decision::x_extents:
          ++stats.decided_x_extents;
          continue;
        case Decision::y_extents:
          ++stats.decided_y_extents;
          continue;
        case Decision::p_behind_q_plane:
          ++stats.decided_p_behind_q_plane;
          continue;
        case Decision::q_in_front_p_plane:
          ++stats.decided_q_in_front_p_plane;
          continue;
        case Decision::projections:
          ++stats.decided_projections;
          continue;
        case Decision::ambiguous:
          break;
      }
      ++stats.ambiguous;
      // The same tests with the roles swapped: may q be drawn before p?
      const bool q_first = entirely_behind(q, p) || entirely_in_front(p, q);
      if (q_first && !q.moved) {
        SortTriangle moved = q;
        moved.moved = true;
        list.erase(list.begin() + static_cast<std::ptrdiff_t>(k));
        list.push_back(moved);
        ++stats.swaps;
        restart = true;
        break;
      }
      // q was moved ahead once already (a cycle), or neither plane separates
      // the two (they interpenetrate): cut one by the other's plane.
      if (q_first) ++stats.cycles;
      if (stats.splits < split_budget) {
        if (straddles(p, q)) {
          const SplitResult r = split(p, q);
          list.pop_back();
          for (const auto* side : {&r.behind, &r.in_front})
            for (const SortTriangle& t : *side) insert_sorted(list, list.size(), t);
          ++stats.splits;
          restart = true;
          break;
        }
        if (straddles(q, p)) {
          const SplitResult r = split(q, p);
          const SortTriangle keep_head = list[head];
          list.erase(list.begin() + static_cast<std::ptrdiff_t>(k));
          list.pop_back();
          for (const auto* side : {&r.behind, &r.in_front})
            for (const SortTriangle& t : *side) insert_sorted(list, list.size(), t);
          list.push_back(keep_head);
          ++stats.splits;
          restart = true;
          break;
        }
      }
      // No plane of the pair cuts the other: leave them in depth order.
      ++stats.unresolved;
    }
    if (!restart) {
      out.push_back(list.back());
      list.pop_back();
    }
  }
  stats.triangles_out += out.size();
  return out;
}

nlohmann::json Stats::to_json() const {
  return {{"draws_sorted", draws_sorted},
          {"draws_passed", draws_passed},
          {"triangles_in", triangles_in},
          {"triangles_dropped", triangles_dropped},
          {"triangles_near_clipped", triangles_near_clipped},
          {"triangles_sorted", triangles_sorted},
          {"comparisons", comparisons},
          {"decided_depth_extents", decided_depth_extents},
          {"decided_x_extents", decided_x_extents},
          {"decided_y_extents", decided_y_extents},
          {"decided_p_behind_q_plane", decided_p_behind_q_plane},
          {"decided_q_in_front_p_plane", decided_q_in_front_p_plane},
          {"decided_projections", decided_projections},
          {"ambiguous", ambiguous},
          {"swaps", swaps},
          {"cycles", cycles},
          {"splits", splits},
          {"unresolved", unresolved},
          {"triangles_out", triangles_out},
          {"draws_out", draws_out}};
}

namespace {

// The draws [begin, end) of one stretch of the draw list between clears,
// appended to `out`: the sorted triangles as clip-space draws, then the
// passed draws in API order.
void paint_stretch(const Scene& scene, const std::vector<Draw>& draws, uint32_t begin, uint32_t end,
                   uint64_t& order, Stats& stats, std::vector<Draw>& out) {
  const FramebufferDesc& fb = scene.framebuffer;
  // The render target, as the models size it (supersampled frames are larger).
  const int k = static_cast<int>(fb.supersample);
  const int width = fb.width * k, height = fb.height * k;

  std::vector<const Draw*> passed;
  std::vector<SortTriangle> triangles;
  // The sort compares NDC positions, which only map to the same pixels and
  // depths under one viewport transform: the stretch's first sortable draw
  // fixes it, and sortable draws under another are passed.
  std::optional<golden::ViewportTransform> space;
  for (uint32_t di = begin; di < end; ++di) {
    const Draw& d = draws[di];
    const golden::ViewportTransform vp = transform_of(d.state, width, height, k);
    const bool sorts = sortable(d);
    if (sorts && !space) space = vp;
    if (!sorts || !same_space(*space, vp)) {
      passed.push_back(&d);
      ++stats.draws_passed;
      continue;
    }
    ++stats.draws_sorted;
    const golden::GuardBand gb = golden::guard_band_for(vp.rect);
    // The spec's vertex stage (docs/pipeline-spec.md, section 2): the
    // driver submits what the models would have computed.
    std::vector<golden::ShadedVertex> shaded(d.positions.size());
    for (uint32_t i = 0; i < shaded.size(); ++i) shaded[i] = golden::shade_vertex(scene, d, i);
    const auto assembled = golden::assemble_triangles(d.primitive, d.vertex_count());
    for (uint32_t ti = 0; ti < assembled.size(); ++ti) {
      const auto& slots = assembled[ti];
      ++stats.triangles_in;
      ++order;
      std::array<golden::ShadedVertex, 3> v;
      bool valid = true;
      for (int j = 0; j < 3; ++j) {
        const uint32_t index = d.indices.empty() ? slots[j] : d.indices[slots[j]];
        valid = valid && index < shaded.size() && is_finite(shaded[index].clip);
        if (valid) v[j] = shaded[index];
      }
      if (!valid) {
        ++stats.triangles_dropped;
        continue;
      }
      // A flat-shaded triangle takes its provoking vertex's colour (spec
      // section 3): all three carry it, so every piece and every
      // convention of the submitted `triangles` draw keeps it.
      if (d.state.shading == Shading::flat) {
        const glm::vec4 c =
            v[golden::provoking_position(d.primitive, ti, d.state.provoking_vertex)].color;
        v[0].color = v[1].color = v[2].color = c;
      }
      bool inside = true;
      for (int plane = 0; plane < golden::kClipPlaneCount; ++plane) {
        for (int j = 0; j < 3; ++j)
          inside = inside && golden::clip_distance(plane, v[j].clip, gb) >= 0.0f;
      }
      if (inside) {
        // Unclipped, the models take exactly this area and facing (spec
        // section 7) in the draw's viewport: a triangle they would drop is
        // not sorted.
        const EdgeValue area2 =
            golden::signed_area2(golden::to_window(v[0], vp, d.state.interpolation),
                                 golden::to_window(v[1], vp, d.state.interpolation),
                                 golden::to_window(v[2], vp, d.state.interpolation));
        const bool front = (d.state.front_face == FrontFace::ccw) == (area2 > 0);
        if (area2 == 0 || (d.state.cull == CullMode::back && !front) ||
            (d.state.cull == CullMode::front && front)) {
          ++stats.triangles_dropped;
          continue;
        }
      }
      std::vector<CutVertex> poly;
      for (int j = 0; j < 3; ++j) poly.push_back({glm::dvec4(v[j].clip), glm::dvec4(v[j].color)});
      // The sort divides by w: cut away what lies behind the near plane (and
      // w <= 0) first, as the clipper would (spec section 4).
      bool clipped = false;
      for (int plane = 0; plane < 2 && !poly.empty(); ++plane) {
        std::vector<double> dist;
        std::vector<int> side;
        for (const CutVertex& c : poly) {
          dist.push_back(plane == 0 ? c.clip.w - golden::kMinClipW : c.clip.z + c.clip.w);
          side.push_back(dist.back() > 0.0 ? 1 : dist.back() < 0.0 ? -1 : 0);
        }
        if (std::count(side.begin(), side.end(), -1) == 0) continue;
        // A vertex exactly on the plane divides by w = kMinClipW or lies on
        // the near plane: both are finite.
        std::vector<CutVertex> neg, pos;
        cut(poly, dist, side, neg, pos);
        poly = pos.size() >= 3 ? pos : std::vector<CutVertex>{};
        clipped = true;
      }
      if (clipped) ++stats.triangles_near_clipped;
      if (poly.empty()) {
        ++stats.triangles_dropped;
        continue;
      }
      SortTriangle base;
      base.draw = di;
      base.order = order;
      if (!clipped) {
        SortTriangle t =
            make_triangle({v[0].clip, v[1].clip, v[2].clip}, {v[0].color, v[1].color, v[2].color});
        t.draw = di;
        t.order = order;
        triangles.push_back(t);
      } else {
        for (const SortTriangle& t : fan(poly, base)) triangles.push_back(t);
      }
    }
  }

  const std::vector<SortTriangle> sorted = sort(std::move(triangles), stats);
  // Consecutive triangles of one draw become one clip-space draw.
  for (size_t i = 0; i < sorted.size();) {
    const Draw& from = draws[sorted[i].draw];
    Draw d;
    d.name = from.name + " (painter)";
    d.primitive = PrimitiveType::triangles;
    d.lighting = false;
    d.state = from.state;
    // Back to front needs no depth test; "always" (GL's only way to write
    // depth without testing) keeps the draw's depth writes, so the depth
    // buffer ends as the z-buffer's would and later depth-tested draws
    // (the passed ones) are hidden as before.
    d.state.depth_func = CompareFunc::always;
    for (const uint32_t source = sorted[i].draw; i < sorted.size() && sorted[i].draw == source;
         ++i) {
      for (int j = 0; j < 3; ++j) {
        d.positions.push_back(sorted[i].clip[j]);
        d.colors.push_back(sorted[i].color[j]);
      }
    }
    out.push_back(std::move(d));
  }
  for (const Draw* d : passed) out.push_back(*d);
}

}  // namespace

std::optional<Stats> apply_visibility(Scene& scene) {
  if (scene.visibility != Visibility::painter) return std::nullopt;
  Stats stats;
  std::vector<Draw> draws = std::move(scene.draws);
  scene.draws.clear();
  const uint32_t count = static_cast<uint32_t>(draws.size());
  // A clear in the draw list (spec section 15) divides it into stretches:
  // nothing drawn before a clear may be sorted after it, so each stretch is
  // sorted on its own, and each clear moves to where its stretch begins in
  // the rewritten list.
  std::vector<uint32_t> bounds{0, count};
  for (const ClearState& c : scene.clears) bounds.push_back(std::min(c.before_draw, count));
  std::sort(bounds.begin(), bounds.end());
  bounds.erase(std::unique(bounds.begin(), bounds.end()), bounds.end());
  std::map<uint32_t, uint32_t> rewritten;  // a stretch's first draw: old index -> new
  uint64_t order = 0;
  for (size_t i = 0; i + 1 < bounds.size(); ++i) {
    rewritten[bounds[i]] = static_cast<uint32_t>(scene.draws.size());
    paint_stretch(scene, draws, bounds[i], bounds[i + 1], order, stats, scene.draws);
  }
  rewritten[count] = static_cast<uint32_t>(scene.draws.size());
  for (ClearState& c : scene.clears) c.before_draw = rewritten.at(std::min(c.before_draw, count));
  stats.draws_out = scene.draws.size();
  return stats;
}

}  // namespace gpusim::painter
