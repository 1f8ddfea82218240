#include "stages/triangle_setup.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "hw/fixed_point.h"
#include "hw/pixel_formats.h"

namespace gpusim {
namespace {

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

}  // namespace

TriangleSetup::TriangleSetup(sc_core::sc_module_name name, const GpuConfig& config,
                             const FrameState& frame)
    : PipelineStage(name, "triangle_setup", -1, config, frame, "triangles and control tokens read",
                    "setup packets written"),
      in("in"),
      out("out") {
  SC_HAS_PROCESS(TriangleSetup);
  SC_THREAD(run);
}

std::shared_ptr<RasterPrimitive> TriangleSetup::setup(const ClippedPrimitive& in_tri) {
  // The clipper assembles triangles only; another kind here is a model bug.
  if (in_tri.primitive_kind != PrimitiveKind::triangle ||
      in_tri.vertex_count != vertex_count_of(PrimitiveKind::triangle)) {
    std::ostringstream msg;
    msg << name() << ": triangle setup cannot set up a " << in_tri.primitive_kind << " of "
        << unsigned{in_tri.vertex_count} << " vertices (primitive " << in_tri.primitive_id << ")";
    SC_REPORT_ERROR("gpusim/triangle_setup", msg.str().c_str());
    return nullptr;
  }
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

  auto t = std::make_shared<RasterPrimitive>();
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

  if (st.offset_factor != 0.0f || st.offset_units != 0.0f) {
    t->has_depth_offset = true;
    t->depth_offset = polygon_offset(*t, st, m_frame.framebuffer.depth_format);
  }

  // Pixels whose centres (256 i + 128) lie within the vertices' box, clamped
  // to the framebuffer (spec section 8).
  const int64_t min_x = std::min({t->x[0], t->x[1], t->x[2]});
  const int64_t max_x = std::max({t->x[0], t->x[1], t->x[2]});
  const int64_t min_y = std::min({t->y[0], t->y[1], t->y[2]});
  const int64_t max_y = std::max({t->y[0], t->y[1], t->y[2]});
  const FramebufferDesc& fb = m_frame.framebuffer;
  t->x0 = std::max(0, -floor_div_subpixel(-(min_x - kSubpixelHalf)));
  t->x1 = std::min(fb.width - 1, floor_div_subpixel(max_x - kSubpixelHalf));
  t->y0 = std::max(0, -floor_div_subpixel(-(min_y - kSubpixelHalf)));
  t->y1 = std::min(fb.height - 1, floor_div_subpixel(max_y - kSubpixelHalf));
  return t;
}

void TriangleSetup::run() {
  for (;;) {
    const ClippedPrimitive tri = receive(in);
    work(m_cost.ii);

    SetupPacket p;
    p.kind = tri.kind;
    if (tri.kind == PacketKind::work) {
      std::shared_ptr<RasterPrimitive> t = setup(tri);
      if (!t) continue;
      if (t->x0 > t->x1 || t->y0 > t->y1) {
        ++m_offscreen;
        continue;
      }
      p.triangle = std::move(t);
    }
    emit(out, std::move(p));
  }
}

}  // namespace gpusim
