#include "stages/primitive_setup.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <new>
#include <sstream>
#include <utility>
#include <vector>

#include "hw/fixed_point.h"
#include "hw/pixel_formats.h"
#include "hw/sample_pattern.h"

namespace gpusim {
namespace {

// The storage of a RasterPrimitive (with its shared_ptr control block) comes
// back to a free list when the last unit releases the primitive, and the next
// setup takes it from there: past the first few hundred primitives (as many
// as the FIFOs and the units hold at once) setup allocates nothing, where
// make_shared cost a malloc and a free per primitive. The list is one per
// block type, shared by every PrimitiveSetup of the process (single-threaded
// like the simulation), and lives as long as the process: a primitive may
// outlive the stage that made it (a packet still in a FIFO at teardown).
template <typename T>
struct RecyclingAllocator {
  using value_type = T;
  RecyclingAllocator() = default;
  template <typename U>
  RecyclingAllocator(const RecyclingAllocator<U>&) {}  // NOLINT: rebinding is implicit
  T* allocate(std::size_t n) {
    std::vector<void*>& list = free_list();
    if (n == 1 && !list.empty()) {
      void* block = list.back();
      list.pop_back();
      return static_cast<T*>(block);
    }
    return static_cast<T*>(::operator new(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t n) {
    if (n == 1) {
      free_list().push_back(p);
    } else {
      ::operator delete(p);
    }
  }
  static std::vector<void*>& free_list() {
    static auto* list = new std::vector<void*>;  // never freed: see above
    return *list;
  }
  template <typename U>
  bool operator==(const RecyclingAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const RecyclingAllocator<U>&) const {
    return false;
  }
};

std::shared_ptr<RasterPrimitive> new_primitive() {
  return std::allocate_shared<RasterPrimitive>(RecyclingAllocator<RasterPrimitive>{});
}

// Spec section 10, in the written float order (the build forbids FMA).
float polygon_offset(const RasterPrimitive& t, const RenderState& st, DepthFormat fmt) {
  const float s = 1.0f / static_cast<float>(kSubpixelOne);
  const float dx1 = static_cast<float>(t.x[1] - t.x[0]) * s;
  const float dy1 = static_cast<float>(t.y[1] - t.y[0]) * s;
  const float dx2 = static_cast<float>(t.x[2] - t.x[0]) * s;
  const float dy2 = static_cast<float>(t.y[2] - t.y[0]) * s;
  const float dz1 = t.z[1] - t.z[0];
  const float dz2 = t.z[2] - t.z[0];
  const float a = static_cast<float>(t.area2) * (s * s);
  const float dzdx = (dz1 * dy2 - dz2 * dy1) / a;
  const float dzdy = (dz2 * dx1 - dz1 * dx2) / a;
  const float m = std::max(std::fabs(dzdx), std::fabs(dzdy));
  const float max_z = std::max({std::fabs(t.z[0]), std::fabs(t.z[1]), std::fabs(t.z[2])});
  return st.offset_factor * m + st.offset_units * min_resolvable_depth(fmt, max_z);
}

int64_t ceil_div_subpixel(int64_t v) {
  return -static_cast<int64_t>(floor_div_subpixel(-v));
}

// A diamond-exit line in major / minor coordinates (x / y for an x-major
// line, y / x for a y-major one), for setup's band and end tests
// (docs/pipeline-spec.md, section 8b, "Consequences"). All integers are
// exact in int64: coordinates < 2^25 in magnitude, products < 2^50.
struct MajorLine {
  bool x_major;
  int64_t ma, na, mb, nb;  // end points (major, minor), subpixels
  int64_t dm, dn;          // mb - ma, nb - na; dm != 0
  int64_t s;               // sign(dm)
  int64_t adm;             // |dm|
  bool low_tie, high_tie;  // whether s D = -128 w |dm| (+128 w |dm|) counts
  int64_t w;

  // s * D at the centre (cm, cn), major / minor subpixels, of the line
  // offset by `shift` subpixels in the minor axis.
  int64_t sd(int64_t cm, int64_t cn, int64_t shift) const {
    return (cn - (na + shift)) * adm - (cm - ma) * s * dn;
  }
  // Width-1 band test of the offset line (shift = -128 (w - 1)).
  bool in_band1(int64_t cm, int64_t cn) const {
    const int64_t v = sd(cm, cn, -128 * (w - 1)), h = 128 * adm;
    return (v > -h && v < h) || (v == -h && low_tie) || (v == h && high_tie);
  }
  // The minor pixel of the offset line's band in major column m, searched
  // among the few rows around `near_n` (a minor coordinate of the line near
  // that column: within 2 pixels, |slope| <= 1); no division.
  int64_t band_pixel(int64_t m, int64_t near_n) const {
    const int64_t cm = 256 * m + 128;
    const int64_t n0 = floor_div_subpixel(near_n - 128 * (w - 1));
    for (int64_t n = n0 - 3; n <= n0 + 3; ++n) {
      if (in_band1(cm, 256 * n + 128)) return n;
    }
    SC_REPORT_ERROR("gpusim/primitive_setup", "diamond-exit line: no band pixel near its end");
    return n0;
  }
  // Whether the offset end point (pm, pn) perturbed by -(eps, eps^2) lies in
  // the diamond of the pixel (m, n): |u| + |v| < 128, or = 128 with u > 0,
  // u and v along x and y whatever the major axis.
  bool end_in_diamond(int64_t pm, int64_t pn, int64_t m, int64_t n) const {
    const int64_t dmaj = pm - (256 * m + 128);
    const int64_t dmin = pn - 128 * (w - 1) - (256 * n + 128);
    const int64_t u = x_major ? dmaj : dmin, v = x_major ? dmin : dmaj;
    const int64_t d = std::llabs(u) + std::llabs(v);
    return d < 128 || (d == 128 && u > 0);
  }
};

}  // namespace

namespace {

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  const ConservationLedger::Frame& f = l.frame();
  // Primitives in = the clipper's outputs. Triangles in = degenerate
  // + culled + rasterized (setup's own counters: polygon mode's are
  // the clipper's); lines in = degenerate + rasterized; points in =
  // rasterized. The rasterized ones leave unless their box holds no
  // pixel. Line and point counters are read when the clipper wrote
  // lines or points.
  const std::string cl = l.upstream("clipper");
  const uint64_t after = l.stage(cl, "triangles_after_clip");
  const uint64_t lines = l.stage(cl, "lines_out");
  const uint64_t points = l.stage(cl, "points_out");
  const uint64_t rasterized = l.get("triangles_rasterized");
  const uint64_t offscreen = l.get("triangles_offscreen");
  l.equal("tokens_in", l.get("tokens_in"),
          cl + ".triangles_after_clip + lines_out + points_out + control tokens",
          after + lines + points + f.control);
  l.equal(cl + ".triangles_after_clip", after,
          "triangles_degenerate + triangles_culled + triangles_rasterized",
          l.get("triangles_degenerate") + l.get("triangles_culled") + rasterized);
  l.at_most("triangles_offscreen", offscreen, "triangles_rasterized", rasterized);
  uint64_t sent = rasterized >= offscreen ? rasterized - offscreen : 0;
  if (lines > 0) {
    const uint64_t lr = l.get("lines_rasterized"), lo = l.get("lines_offscreen");
    l.equal(cl + ".lines_out", lines, "lines_degenerate + lines_rasterized",
            l.get("lines_degenerate") + lr);
    l.at_most("lines_offscreen", lo, "lines_rasterized", lr);
    sent += lr >= lo ? lr - lo : 0;
  }
  if (points > 0) {
    const uint64_t pr = l.get("points_rasterized"), po = l.get("points_offscreen");
    l.equal(cl + ".points_out", points, "points_rasterized", pr);
    l.at_most("points_offscreen", po, "points_rasterized", pr);
    sent += pr >= po ? pr - po : 0;
  }
  l.equal("tokens_out", l.get("tokens_out"), "primitives rasterized - offscreen + control tokens",
          sent + f.control);
}

}  // namespace

const StageSpec& PrimitiveSetup::spec() {
  static const StageSpec s{
      "primitive_setup",
      StagePlacement::front_end,
      /*optional=*/false,
      {/*ii=*/4, /*latency=*/16},
      "primitive",
      "edge equations, fill-rule bias, attribute plane equations (one reciprocal of the area); a "
      "line's band edges and end tests, a point's square",
      "primitives and control tokens read",
      "setup packets written",
      {"clipper_to_setup"},
      &conserve,
      StageTrace{TraceItem::primitive,
                 {"setup dropped it (nothing of it on screen)",
                  "setup dropped it (zero length, or nothing of it on screen)",
                  "setup dropped it (degenerate, culled, or no pixel centre on screen)"},
                 FragmentSite::none},
      {{"", "`ii` per input token",
        "Every kind: a triangle whether or not it survives culling, a line (its end tests "
        "included), a point."}},
      {"triangle_setup"}};
  return s;
}
GPUSIM_REGISTER_STAGE(PrimitiveSetup);

PrimitiveSetup::PrimitiveSetup(sc_core::sc_module_name name, const GpuConfig& config,
                               const FrameState& frame)
    : PipelineStage(name, spec(), -1, config, frame), in("in"), out("out") {
  SC_HAS_PROCESS(PrimitiveSetup);
  SC_THREAD(run);
}

std::shared_ptr<RasterPrimitive> PrimitiveSetup::setup(const ClippedPrimitive& in) {
  const uint8_t n = vertex_count_of(in.primitive_kind);
  if (in.vertex_count != n) {
    std::ostringstream msg;
    msg << name() << ": cannot set up a " << in.primitive_kind << " of "
        << unsigned{in.vertex_count} << " vertices (primitive " << in.primitive_id << ")";
    SC_REPORT_ERROR("gpusim/primitive_setup", msg.str().c_str());
    return nullptr;
  }
  switch (in.primitive_kind) {
    case PrimitiveKind::triangle:
      return setup_triangle(in);
    case PrimitiveKind::line:
      return setup_line(in);
    case PrimitiveKind::point:
      return setup_point(in);
  }
  return nullptr;
}

std::shared_ptr<RasterPrimitive> PrimitiveSetup::setup_triangle(const ClippedPrimitive& in_tri) {
  std::array<Subpixel, 3> x, y;
  for (int i = 0; i < 3; ++i) {
    x[i] = snap_to_subpixel(in_tri.v[i].x);
    y[i] = snap_to_subpixel(in_tri.v[i].y);
  }
  // |deltas| < 2^25, so each product < 2^50: exact in int64.
  const EdgeValue area2 = (EdgeValue{x[1]} - x[0]) * (EdgeValue{y[2]} - y[0]) -
                          (EdgeValue{y[1]} - y[0]) * (EdgeValue{x[2]} - x[0]);
  if (area2 == 0) {
    ++m_degenerate;
    return nullptr;
  }
  const RenderState& st = m_frame.draws.at(in_tri.draw_id).state;
  const bool ccw = area2 > 0;
  const bool front = (st.front_face == FrontFace::ccw) == ccw;
  if ((st.cull == CullMode::back && !front) || (st.cull == CullMode::front && front)) {
    ++m_culled;
    return nullptr;
  }
  ++m_rasterized;

  auto t = new_primitive();
  t->draw_id = in_tri.draw_id;
  t->primitive_kind = PrimitiveKind::triangle;
  t->vertex_count = vertex_count_of(PrimitiveKind::triangle);
  t->primitive_id = in_tri.primitive_id;
  t->flat_varyings = in_tri.flat_varyings;
  // Clockwise: swap v1 and v2 (with their attributes) so that area2 > 0.
  const std::array<int, 3> order = ccw ? std::array<int, 3>{0, 1, 2} : std::array<int, 3>{0, 2, 1};
  if (!ccw) ++m_swapped;
  for (int i = 0; i < 3; ++i) {
    const ClippedVertex& v = in_tri.v[order[i]];
    t->x[i] = x[order[i]];
    t->y[i] = y[order[i]];
    t->z[i] = v.z;
    t->inv_w[i] = v.inv_w;
    t->varyings_over_w[i] = v.varyings_over_w;
  }
  t->area2 = ccw ? area2 : -area2;

  // Edge k runs from vertex k+1 to vertex k+2. The fill rule is applied here,
  // once, as a bias: left edges (dy < 0) and bottom edges (dy == 0, dx > 0)
  // own the pixel centres exactly on them.
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const EdgeValue dx = EdgeValue{t->x[j]} - t->x[i];
    const EdgeValue dy = EdgeValue{t->y[j]} - t->y[i];
    EdgeEquation& e = t->edge[k];
    e.a = -dy;
    e.b = dx;
    e.c = dy * t->x[i] - dx * t->y[i];
    e.bias = (dy < 0 || (dy == 0 && dx > 0)) ? 0 : 1;
  }
  // The rasterizer tests the same three edges.
  std::copy(t->edge.begin(), t->edge.end(), t->coverage.begin());
  t->coverage_count = 3;

  if (st.offset_factor != 0.0f || st.offset_units != 0.0f) {
    t->has_depth_offset = true;
    t->depth_offset = polygon_offset(*t, st, m_frame.framebuffer.depth_format);
  }

  // Pixels whose centres (256 i + 128), or samples, lie within the
  // vertices' box, clamped to the framebuffer (spec sections 8 and 14).
  const int64_t min_x = std::min({t->x[0], t->x[1], t->x[2]});
  const int64_t max_x = std::max({t->x[0], t->x[1], t->x[2]});
  const int64_t min_y = std::min({t->y[0], t->y[1], t->y[2]});
  const int64_t max_y = std::max({t->y[0], t->y[1], t->y[2]});
  set_sample_box(*t, min_x, max_x, min_y, max_y);
  return t;
}

void PrimitiveSetup::set_sample_box(RasterPrimitive& t, int64_t x0, int64_t x1, int64_t y0,
                                    int64_t y1) const {
  const PixelBounds r = bounds_of(t.draw_id);
  // Pixel i has a sample at 256 i + 128 + d for each offset d of the pattern.
  t.x0 = std::max(r.x0, -floor_div_subpixel(-(x0 - kSubpixelHalf - m_reach_x1)));
  t.x1 = std::min(r.x1, floor_div_subpixel(x1 - kSubpixelHalf - m_reach_x0));
  t.y0 = std::max(r.y0, -floor_div_subpixel(-(y0 - kSubpixelHalf - m_reach_y1)));
  t.y1 = std::min(r.y1, floor_div_subpixel(y1 - kSubpixelHalf - m_reach_y0));
}

EdgeEquation PrimitiveSetup::edge_between(int64_t xa, int64_t ya, int64_t xb, int64_t yb) {
  const EdgeValue dx = xb - xa, dy = yb - ya;
  return EdgeEquation{-dy, dx, dy * xa - dx * ya, (dy < 0 || (dy == 0 && dx > 0)) ? 0 : 1};
}

void PrimitiveSetup::setup_line_rectangle(RasterPrimitive& t, float width) const {
  // Half the width along the left normal (-dy, dx), in float, snapped:
  // corners A - o, B - o, B + o, A + o, counter-clockwise.
  const int64_t xa = t.x[0], ya = t.y[0], xb = t.x[1], yb = t.y[1];
  const int64_t dx = xb - xa, dy = yb - ya;
  const float half = (width * 128.0f) / std::sqrt(static_cast<float>(dx * dx + dy * dy));
  const int64_t ox = round_half_away(static_cast<float>(-dy) * half);
  const int64_t oy = round_half_away(static_cast<float>(dx) * half);
  const std::array<int64_t, 4> cx{xa - ox, xb - ox, xb + ox, xa + ox};
  const std::array<int64_t, 4> cy{ya - oy, yb - oy, yb + oy, ya + oy};
  for (int k = 0; k < 4; ++k)
    t.coverage[k] = edge_between(cx[k], cy[k], cx[(k + 1) % 4], cy[(k + 1) % 4]);
  t.coverage_count = 4;
  t.line_rule = LineRule::rectangle;
  set_sample_box(t, std::min({cx[0], cx[1], cx[2], cx[3]}), std::max({cx[0], cx[1], cx[2], cx[3]}),
                 std::min({cy[0], cy[1], cy[2], cy[3]}), std::max({cy[0], cy[1], cy[2], cy[3]}));
}

std::shared_ptr<RasterPrimitive> PrimitiveSetup::setup_line(const ClippedPrimitive& in) {
  const RenderState& st = m_frame.draws.at(in.draw_id).state;
  const Subpixel xa = snap_to_subpixel(in.v[0].x), ya = snap_to_subpixel(in.v[0].y);
  const Subpixel xb = snap_to_subpixel(in.v[1].x), yb = snap_to_subpixel(in.v[1].y);
  const EdgeValue dx = EdgeValue{xb} - xa, dy = EdgeValue{yb} - ya;
  const EdgeValue l2 = dx * dx + dy * dy;  // < 2^51
  const bool rectangle = m_samples > 1;    // multisampled: every line (section 14)
  const bool bresenham = !rectangle && st.line_rasterization == LineRasterization::bresenham;
  if (l2 == 0 && !bresenham) {
    ++m_lines_degenerate;  // a diamond-exit or rectangle line of zero length draws nothing
    return nullptr;
  }
  ++m_lines_rasterized;

  auto t = new_primitive();
  t->primitive_kind = PrimitiveKind::line;
  t->vertex_count = 2;
  t->draw_id = in.draw_id;
  t->primitive_id = in.primitive_id;
  t->flat_varyings = in.flat_varyings;
  // Interpolation as the triangle (a, b, a) (spec section 9).
  const std::array<int, 3> slot{0, 1, 0};
  for (int i = 0; i < 3; ++i) {
    const ClippedVertex& v = in.v[slot[i]];
    t->x[i] = i == 1 ? xb : xa;
    t->y[i] = i == 1 ? yb : ya;
    t->z[i] = v.z;
    t->inv_w[i] = v.inv_w;
    t->varyings_over_w[i] = v.varyings_over_w;
  }
  if (l2 == 0) {  // a Bresenham line of zero length: vertex a's values
    t->edge[0] = EdgeEquation{0, 0, 1, 0};
    t->area2 = 1;
  } else {
    // E1 = T = (px - Xa) dx + (py - Ya) dy, E0 = L2 - T, E2 = 0.
    t->edge[1] = EdgeEquation{dx, dy, -(EdgeValue{xa} * dx) - EdgeValue{ya} * dy, 0};
    t->edge[0] = EdgeEquation{-dx, -dy, l2 + EdgeValue{xa} * dx + EdgeValue{ya} * dy, 0};
    t->area2 = l2;
  }
  if (rectangle) {
    setup_line_rectangle(*t, std::max(1.0f, st.line_width));  // at least 1 pixel wide
    return t;
  }
  const int64_t w =
      std::clamp<int64_t>(round_half_away(st.line_width), 1, static_cast<int64_t>(kMaxLineWidth));
  t->width = static_cast<uint16_t>(w);
  t->draw_first = in.draw_first;
  t->draw_last = in.draw_last;
  const bool x_major = std::llabs(dx) >= std::llabs(dy);

  int64_t bx0, bx1, by0, by1;  // pixel box before clamping
  if (bresenham) {
    // The walker's input: the end points' pixels; the box holds every pixel
    // it can produce (the major range, the minor range widened by the
    // replication y - floor((w - 1) / 2) ... + w - 1).
    ++m_lines_bresenham;
    t->line_rule = LineRule::bresenham;
    t->coverage_count = 0;
    t->ia_x = floor_div_subpixel(xa);
    t->ia_y = floor_div_subpixel(ya);
    t->ib_x = floor_div_subpixel(xb);
    t->ib_y = floor_div_subpixel(yb);
    const int64_t pdx = int64_t{t->ib_x} - t->ia_x, pdy = int64_t{t->ib_y} - t->ia_y;
    const bool px_major = std::llabs(pdx) >= std::llabs(pdy);
    const int64_t lo = (w - 1) / 2, hi = w - 1 - lo;
    bx0 = std::min(t->ia_x, t->ib_x) - (px_major ? 0 : lo);
    bx1 = std::max(t->ia_x, t->ib_x) + (px_major ? 0 : hi);
    by0 = std::min(t->ia_y, t->ib_y) - (px_major ? lo : 0);
    by1 = std::max(t->ia_y, t->ib_y) + (px_major ? hi : 0);
  } else {
    t->line_rule = LineRule::diamond_exit;
    MajorLine ln;
    ln.x_major = x_major;
    ln.ma = x_major ? xa : ya;
    ln.na = x_major ? ya : xa;
    ln.mb = x_major ? xb : yb;
    ln.nb = x_major ? yb : xb;
    ln.dm = ln.mb - ln.ma;
    ln.dn = ln.nb - ln.na;
    ln.s = ln.dm > 0 ? 1 : -1;
    ln.adm = std::llabs(ln.dm);
    ln.low_tie = x_major ? dx * dy <= 0 : true;
    ln.high_tie = x_major ? dx * dy > 0 : false;
    ln.w = w;
    // The band of w centres per column: -128 w |dm| < s D < 128 w |dm|,
    // s D = (cn - na) |dm| - (cm - ma) s dn, as two edges over (px, py).
    const EdgeValue coef_m = -ln.s * ln.dn, coef_n = ln.adm;
    const EdgeValue c0 = -ln.na * ln.adm + ln.ma * ln.s * ln.dn;
    const EdgeValue half = 128 * w * ln.adm;  // < 2^40
    const EdgeValue a = x_major ? coef_m : coef_n, b = x_major ? coef_n : coef_m;
    t->coverage[0] = EdgeEquation{a, b, c0 + half, ln.low_tie ? 0 : 1};
    t->coverage[1] = EdgeEquation{-a, -b, half - c0, ln.high_tie ? 0 : 1};
    t->coverage_count = 2;
    // The end columns (the end test, on the offset segment). Travelling in
    // +major: the first column is the first centre at or after ma, or the
    // one before it if A' lies in its band pixel's diamond; the last is the
    // last centre before mb, unless B' lies in its band pixel's diamond.
    // -major mirrors it.
    int64_t first, last;
    if (ln.s > 0) {
      first = ceil_div_subpixel(ln.ma - 128);
      if (ln.end_in_diamond(ln.ma, ln.na, first - 1, ln.band_pixel(first - 1, ln.na))) --first;
      last = floor_div_subpixel(ln.mb - 129);
      if (ln.end_in_diamond(ln.mb, ln.nb, last, ln.band_pixel(last, ln.nb))) --last;
    } else {
      first = floor_div_subpixel(ln.ma - 129);
      if (ln.end_in_diamond(ln.ma, ln.na, first + 1, ln.band_pixel(first + 1, ln.na))) ++first;
      last = ceil_div_subpixel(ln.mb - 128);
      if (ln.end_in_diamond(ln.mb, ln.nb, last, ln.band_pixel(last, ln.nb))) ++last;
    }
    const int64_t m_lo = std::min(first, last), m_hi = std::max(first, last);
    int64_t n_lo = 0, n_hi = -1;
    if ((ln.s > 0 && first <= last) || (ln.s < 0 && first >= last)) {
      // The minor range: the band pixels of the end columns (the band is
      // monotone along the line), the column of w upwards from each.
      const int64_t n_first = ln.band_pixel(first, ln.na), n_last = ln.band_pixel(last, ln.nb);
      n_lo = std::min(n_first, n_last);
      n_hi = std::max(n_first, n_last) + w - 1;
    }
    const bool empty = n_lo > n_hi;
    bx0 = x_major ? m_lo : n_lo;
    bx1 = x_major ? (empty ? m_lo - 1 : m_hi) : n_hi;
    by0 = x_major ? n_lo : m_lo;
    by1 = x_major ? n_hi : (empty ? m_lo - 1 : m_hi);
  }
  const PixelBounds r = bounds_of(in.draw_id);
  t->x0 = static_cast<int32_t>(std::max<int64_t>(r.x0, bx0));
  t->x1 = static_cast<int32_t>(std::min<int64_t>(r.x1, bx1));
  t->y0 = static_cast<int32_t>(std::max<int64_t>(r.y0, by0));
  t->y1 = static_cast<int32_t>(std::min<int64_t>(r.y1, by1));
  return t;
}

std::shared_ptr<RasterPrimitive> PrimitiveSetup::setup_point(const ClippedPrimitive& in) {
  const RenderState& st = m_frame.draws.at(in.draw_id).state;
  ++m_points_rasterized;
  const ClippedVertex& v = in.v[0];
  auto t = new_primitive();
  t->primitive_kind = PrimitiveKind::point;
  t->vertex_count = 1;
  t->draw_id = in.draw_id;
  t->primitive_id = in.primitive_id;
  t->flat_varyings = in.flat_varyings;
  for (int i = 0; i < 3; ++i) {
    t->x[i] = snap_to_subpixel(v.x);
    t->y[i] = snap_to_subpixel(v.y);
    t->z[i] = v.z;
    t->inv_w[i] = v.inv_w;
    t->varyings_over_w[i] = v.varyings_over_w;
  }
  // E0 = 1, E1 = E2 = 0, area2 = 1: z = z0 exactly (spec section 9).
  t->edge[0] = EdgeEquation{0, 0, 1, 0};
  t->area2 = 1;
  // The square (spec 8c): X0 <= 256 x < X0 + F, likewise y. The pixel box
  // is the square itself, so no coverage edge is needed.
  const int64_t f = std::max<int64_t>(256, round_half_away(st.point_size * 256.0f));
  const int64_t x0 = round_half_away((v.x - 0.5f) * 256.0f) - f / 2;
  const int64_t y0 = round_half_away((v.y - 0.5f) * 256.0f) - f / 2;
  if (m_samples > 1) {
    // Multisampled (section 14): sample point P (pixel centre 256 i + 128
    // plus its offset) is covered iff X0 <= P - 128 < X0 + F, likewise y: four
    // edges, the upper sides not owning their boundary.
    t->coverage[0] = EdgeEquation{1, 0, -(x0 + kSubpixelHalf), 0};
    t->coverage[1] = EdgeEquation{-1, 0, x0 + kSubpixelHalf + f, 1};
    t->coverage[2] = EdgeEquation{0, 1, -(y0 + kSubpixelHalf), 0};
    t->coverage[3] = EdgeEquation{0, -1, y0 + kSubpixelHalf + f, 1};
    t->coverage_count = 4;
    set_sample_box(*t, x0 + kSubpixelHalf, x0 + kSubpixelHalf + f - 1, y0 + kSubpixelHalf,
                   y0 + kSubpixelHalf + f - 1);
    return t;
  }
  t->coverage_count = 0;
  const PixelBounds r = bounds_of(in.draw_id);
  t->x0 = static_cast<int32_t>(std::max<int64_t>(r.x0, ceil_div_subpixel(x0)));
  t->x1 = static_cast<int32_t>(std::min<int64_t>(r.x1, floor_div_subpixel(x0 + f - 1)));
  t->y0 = static_cast<int32_t>(std::max<int64_t>(r.y0, ceil_div_subpixel(y0)));
  t->y1 = static_cast<int32_t>(std::min<int64_t>(r.y1, floor_div_subpixel(y0 + f - 1)));
  return t;
}

void PrimitiveSetup::reset_state() {
  m_samples = 1;
  m_reach_x0 = m_reach_x1 = m_reach_y0 = m_reach_y1 = 0;
}

void PrimitiveSetup::run() {
  // The frame's registers are final once the simulation runs.
  m_samples = m_frame.framebuffer.samples;
  for (unsigned i = 0; i < m_samples; ++i) {
    const SampleOffset o = sample_offset(m_samples, i);
    m_reach_x0 = std::min<int64_t>(m_reach_x0, o.dx);
    m_reach_x1 = std::max<int64_t>(m_reach_x1, o.dx);
    m_reach_y0 = std::min<int64_t>(m_reach_y0, o.dy);
    m_reach_y1 = std::max<int64_t>(m_reach_y1, o.dy);
  }
  for (;;) {
    const ClippedPrimitive tri = receive(in);
    work(m_cost.ii);

    SetupPacket p;
    p.kind = tri.kind;
    if (tri.kind == PacketKind::work) {
      std::shared_ptr<RasterPrimitive> t = setup(tri);
      if (!t) continue;
      if (t->x0 > t->x1 || t->y0 > t->y1) {
        ++(t->primitive_kind == PrimitiveKind::triangle ? m_offscreen
           : t->primitive_kind == PrimitiveKind::line   ? m_lines_offscreen
                                                        : m_points_offscreen);
        continue;
      }
      p.primitive = std::move(t);
    }
    emit(out, std::move(p));
  }
}

}  // namespace gpusim
