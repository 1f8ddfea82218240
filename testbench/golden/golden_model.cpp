#include "testbench/golden/golden_model.h"

#include <algorithm>
#include <cmath>

#include "hw/sample_pattern.h"
#include "testbench/golden/texture_sampling.h"

namespace gpusim::golden {
namespace {

// Matrix times vector, each row summed left to right (spec: "Arithmetic").
glm::vec4 mul(const glm::mat4& m, const glm::vec4& v) {
  glm::vec4 r;
  for (int i = 0; i < 4; ++i) {
    r[i] = m[0][i] * v.x + m[1][i] * v.y + m[2][i] * v.z + m[3][i] * v.w;
  }
  return r;
}
glm::vec3 mul(const glm::mat3& m, const glm::vec3& v) {
  glm::vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = m[0][i] * v.x + m[1][i] * v.y + m[2][i] * v.z;
  return r;
}
float dot3(const glm::vec3& a, const glm::vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
glm::vec3 normalized(const glm::vec3& v) {
  const float len2 = dot3(v, v);
  if (!(len2 > 0.0f)) return v;
  const float inv = 1.0f / std::sqrt(len2);
  return glm::vec3(v.x * inv, v.y * inv, v.z * inv);
}
glm::vec4 clamp01(const glm::vec4& c) {
  return glm::vec4(gpusim::clamp01(c.x), gpusim::clamp01(c.y), gpusim::clamp01(c.z),
                   gpusim::clamp01(c.w));
}

}  // namespace

glm::vec4 light(const Scene& scene, const Material& m, const glm::vec3& p, const glm::vec3& n) {
  glm::vec3 c;
  for (int i = 0; i < 3; ++i) c[i] = m.emission[i] + scene.global_ambient[i] * m.ambient[i];
  for (const Light& l : scene.lights) {
    glm::vec3 to_light;
    float attenuation = 1.0f;
    if (l.type == LightType::directional) {
      to_light = l.vector;
    } else {
      const glm::vec3 d = l.vector - p;
      const float dist2 = dot3(d, d);
      const float dist = std::sqrt(dist2);
      to_light = dist > 0.0f ? d * (1.0f / dist) : d;
      attenuation = 1.0f / (l.constant_attenuation + l.linear_attenuation * dist +
                            l.quadratic_attenuation * dist2);
    }
    const float n_dot_l = std::max(dot3(n, to_light), 0.0f);
    float specular = 0.0f;
    if (n_dot_l > 0.0f) {
      // Infinite viewer: the half vector of the light direction and +z.
      const glm::vec3 h = normalized(glm::vec3(to_light.x, to_light.y, to_light.z + 1.0f));
      specular = std::pow(std::max(dot3(n, h), 0.0f), m.shininess);
    }
    for (int i = 0; i < 3; ++i) {
      const float term = l.ambient[i] * m.ambient[i] + l.diffuse[i] * m.diffuse[i] * n_dot_l +
                         l.specular[i] * m.specular[i] * specular;
      c[i] = c[i] + attenuation * term;
    }
  }
  return clamp01(glm::vec4(c, m.diffuse.w));
}

glm::vec4 light_pixel(const Scene& scene, const Material& material, const glm::vec3& normal,
                      const glm::vec3& eye) {
  return light(scene, material, eye, normalized(normal));
}

bool lit_per_pixel(const Draw& draw) {
  return draw.state.shading == Shading::phong && draw.lighting && !draw.normals.empty();
}

namespace {

// Blend factor for channel i (3 = alpha) given source s and destination d.
float blend_factor(BlendFactor f, const glm::vec4& s, const glm::vec4& d, int i) {
  switch (f) {
    case BlendFactor::zero:
      return 0.0f;
    case BlendFactor::one:
      return 1.0f;
    case BlendFactor::src_color:
      return s[i];
    case BlendFactor::one_minus_src_color:
      return 1.0f - s[i];
    case BlendFactor::dst_color:
      return d[i];
    case BlendFactor::one_minus_dst_color:
      return 1.0f - d[i];
    case BlendFactor::src_alpha:
      return s.w;
    case BlendFactor::one_minus_src_alpha:
      return 1.0f - s.w;
    case BlendFactor::dst_alpha:
      return d.w;
    case BlendFactor::one_minus_dst_alpha:
      return 1.0f - d.w;
    case BlendFactor::src_alpha_saturate:
      return i < 3 ? std::min(s.w, 1.0f - d.w) : 1.0f;
  }
  return 0.0f;
}

float blend_channel(const RenderState& st, const glm::vec4& s, const glm::vec4& d, int i) {
  const float a = s[i] * blend_factor(st.blend_src, s, d, i);
  const float b = d[i] * blend_factor(st.blend_dst, s, d, i);
  switch (st.blend_equation) {
    case BlendEquation::add:
      return a + b;
    case BlendEquation::subtract:
      return a - b;
    case BlendEquation::reverse_subtract:
      return b - a;
  }
  return a;
}

// Exact integer floor and ceiling of a / b for b > 0.
int64_t floor_div(int64_t a, int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
int64_t ceil_div(int64_t a, int64_t b) {
  return -floor_div(-a, b);
}

// c0 + c1 eps + c2 eps^2 for an infinitesimal eps > 0: values of the
// perturbed diamond-exit test (spec section 8b), compared exactly by their
// coefficients in order (lexicographically).
struct Perturbed {
  int64_t c0 = 0, c1 = 0, c2 = 0;
  bool operator<(const Perturbed& o) const {
    if (c0 != o.c0) return c0 < o.c0;
    if (c1 != o.c1) return c1 < o.c1;
    return c2 < o.c2;
  }
};

bool is_finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// Where the edge from p (distance dp) to q (distance dq) crosses `plane`,
// exactly one of them inside (spec section 4). Interpolates from the endpoint
// nearer the plane (the inside one on a tie), which keeps t small and the cut
// precise; the choice depends only on the edge, not on its direction, so an
// edge shared by two triangles, or a line, is cut identically.
ShadedVertex clip_intersection(const ShadedVertex& p, float dp, const ShadedVertex& q, float dq,
                               int plane) {
  const bool in_p = dp >= 0.0f;
  const bool from_p = std::fabs(dp) < std::fabs(dq) || (std::fabs(dp) == std::fabs(dq) && in_p);
  const ShadedVertex& a = from_p ? p : q;
  const ShadedVertex& b = from_p ? q : p;
  const float da = from_p ? dp : dq;
  const float db = from_p ? dq : dp;
  const float t = da / (da - db);
  ShadedVertex v;
  for (int k = 0; k < 4; ++k) {
    v.clip[k] = a.clip[k] + t * (b.clip[k] - a.clip[k]);
    v.color[k] = a.color[k] + t * (b.color[k] - a.color[k]);
  }
  for (int k = 0; k < 3; ++k) {
    v.normal[k] = a.normal[k] + t * (b.normal[k] - a.normal[k]);
    v.eye[k] = a.eye[k] + t * (b.eye[k] - a.eye[k]);
  }
  for (int k = 0; k < 2; ++k) v.texcoord[k] = a.texcoord[k] + t * (b.texcoord[k] - a.texcoord[k]);
  // Rounding can leave a cut on the w plane at or below 0; 1/w must stay finite.
  if (plane == 0) v.clip.w = std::max(v.clip.w, kMinClipW);
  return v;
}

// Screen interpolation at the clipper (spec section 4): a vertex made by a
// cut takes the primitive's varyings (colour, a Phong draw's normal and eye
// position, a textured draw's texture coordinate) extended affinely over the window plane, at its
// own projection. A vertex equal to an original keeps that vertex's varyings; where the formula is
// not finite the cut's perspective-correct ones stay.
template <int N>
glm::vec<N, float> extend_affine(const glm::vec<N, float>& a, const glm::vec<N, float>& b,
                                 const glm::vec<N, float>* c, float b1, float b2) {
  glm::vec<N, float> r;
  for (int k = 0; k < N; ++k) {
    r[k] = c ? a[k] + b1 * (b[k] - a[k]) + b2 * ((*c)[k] - a[k]) : a[k] + b1 * (b[k] - a[k]);
  }
  return r;
}

void screen_colors(std::vector<ShadedVertex>& poly, const ShadedVertex* orig, int n) {
  float px[3] = {}, py[3] = {};
  for (int i = 0; i < n; ++i) {
    px[i] = orig[i].clip.x / orig[i].clip.w;
    py[i] = orig[i].clip.y / orig[i].clip.w;
  }
  for (ShadedVertex& v : poly) {
    const ShadedVertex* same = nullptr;
    for (int i = 0; i < n && same == nullptr; ++i) {
      if (v.clip == orig[i].clip) same = &orig[i];
    }
    if (same != nullptr) {
      v.color = same->color;
      v.normal = same->normal;
      v.eye = same->eye;
      v.texcoord = same->texcoord;
      continue;
    }
    const float qx = v.clip.x / v.clip.w, qy = v.clip.y / v.clip.w;
    float b1 = 0.0f, b2 = 0.0f;
    if (n == 2) {
      const float dx = px[1] - px[0], dy = py[1] - py[0];
      b1 = std::fabs(dx) >= std::fabs(dy) ? (qx - px[0]) / dx : (qy - py[0]) / dy;
      if (!std::isfinite(b1)) continue;
    } else {
      const float d1x = px[1] - px[0], d1y = py[1] - py[0];
      const float d2x = px[2] - px[0], d2y = py[2] - py[0];
      const float ex = qx - px[0], ey = qy - py[0];
      const float den = d1x * d2y - d1y * d2x;
      b1 = (ex * d2y - ey * d2x) / den;
      b2 = (d1x * ey - d1y * ex) / den;
      if (!(std::isfinite(b1) && std::isfinite(b2))) continue;
    }
    const bool tri = n == 3;
    v.color = extend_affine(orig[0].color, orig[1].color, tri ? &orig[2].color : nullptr, b1, b2);
    v.normal =
        extend_affine(orig[0].normal, orig[1].normal, tri ? &orig[2].normal : nullptr, b1, b2);
    v.eye = extend_affine(orig[0].eye, orig[1].eye, tri ? &orig[2].eye : nullptr, b1, b2);
    v.texcoord = extend_affine(orig[0].texcoord, orig[1].texcoord,
                               tri ? &orig[2].texcoord : nullptr, b1, b2);
  }
}

// Per-triangle constants for the pixel loop; a line is shaded as the
// triangle (a, b, a) with area2 = its squared length (spec section 9).
struct SetupTriangle {
  std::array<WindowVertex, 3> v;  // counter-clockwise
  EdgeValue area2 = 0;
  std::array<EdgeValue, 3> bias{};  // 0 for owned edges, 1 otherwise
  float depth_offset = 0.0f;
  bool apply_offset = false;             // polygon offset is not [0, 0] (filled triangles)
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;  // pixel bounding box, inclusive
};

float polygon_offset(const SetupTriangle& t, const RenderState& st, DepthFormat fmt) {
  const WindowVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
  const float inv_one = 1.0f / static_cast<float>(kSubpixelOne);
  const float dx1 = static_cast<float>(v1.x - v0.x) * inv_one;
  const float dy1 = static_cast<float>(v1.y - v0.y) * inv_one;
  const float dx2 = static_cast<float>(v2.x - v0.x) * inv_one;
  const float dy2 = static_cast<float>(v2.y - v0.y) * inv_one;
  const float dz1 = v1.z - v0.z;
  const float dz2 = v2.z - v0.z;
  const float area = static_cast<float>(t.area2) * (inv_one * inv_one);
  const float dzdx = (dz1 * dy2 - dz2 * dy1) / area;
  const float dzdy = (dz2 * dx1 - dz1 * dx2) / area;
  const float max_slope = std::max(std::fabs(dzdx), std::fabs(dzdy));
  const float max_z = std::max({std::fabs(v0.z), std::fabs(v1.z), std::fabs(v2.z)});
  return st.offset_factor * max_slope + st.offset_units * min_resolvable_depth(fmt, max_z);
}

class Renderer {
 public:
  Renderer(const Scene& scene, const RenderOptions& options)
      : m_scene(scene),
        m_k(scene.framebuffer.supersample),
        m_samples(scene.framebuffer.samples),
        m_fb(scene.framebuffer.width * static_cast<int>(m_k),
             scene.framebuffer.height * static_cast<int>(m_k), scene.framebuffer.color_format,
             scene.framebuffer.depth_format, m_samples) {
    const glm::vec4& c = scene.framebuffer.clear_color;
    const float rgba[4] = {c.x, c.y, c.z, c.w};
    m_fb.clear(rgba, scene.framebuffer.clear_depth);
    ++m_stats.color_clears;
    ++m_stats.depth_clears;
    if (options.record_last_writer) {
      m_last_writer.assign(static_cast<size_t>(m_fb.width) * m_fb.height, -1);
    }
    for (unsigned i = 0; i < m_samples; ++i) {
      const SampleOffset o = sample_offset(m_samples, i);
      m_sample_dx[i] = o.dx;
      m_sample_dy[i] = o.dy;
    }
    const auto [min_dx, max_dx] =
        std::minmax_element(m_sample_dx.begin(), m_sample_dx.begin() + m_samples);
    const auto [min_dy, max_dy] =
        std::minmax_element(m_sample_dy.begin(), m_sample_dy.begin() + m_samples);
    m_reach_x = {*min_dx, *max_dx};
    m_reach_y = {*min_dy, *max_dy};
  }

  Result run() {
    // Section 15: the draw list's clears at their places among the draws.
    size_t next_clear = 0;
    for (size_t i = 0; i <= m_scene.draws.size(); ++i) {
      for (; next_clear < m_scene.clears.size() && m_scene.clears[next_clear].before_draw == i;
           ++next_clear) {
        clear(m_scene.clears[next_clear]);
      }
      if (i < m_scene.draws.size()) render_draw(m_scene.draws[i]);
    }
    return Result{resolve(m_fb, m_k), std::move(m_last_writer), m_stats};
  }

 private:
  // Every sample of the render target (supersampled: the whole of it), in
  // the buffer formats, as the frame clear converts the values. A colour
  // clear also forgets the pixels' last writers: no primitive wrote them
  // since.
  void clear(const ClearState& c) {
    if (c.color) {
      const float rgba[4] = {c.color_value.x, c.color_value.y, c.color_value.z, c.color_value.w};
      m_fb.clear_color(rgba);
      std::fill(m_last_writer.begin(), m_last_writer.end(), -1);
      ++m_stats.color_clears;
    }
    if (c.depth) {
      m_fb.clear_depth(c.depth_value);
      ++m_stats.depth_clears;
    }
  }

  void render_draw(const Draw& draw) {
    m_draw = &draw;
    m_phong = lit_per_pixel(draw);
    m_texture = draw.texture >= 0 ? &m_scene.textures[static_cast<size_t>(draw.texture)] : nullptr;
    // Supersampling: widths and sizes keep their size in output pixels.
    RenderState state = draw.state;
    state.line_width = state.line_width * static_cast<float>(m_k);
    state.point_size = state.point_size * static_cast<float>(m_k);
    // Viewport and scissor are in output pixels: k times them in the target.
    const int k = static_cast<int>(m_k);
    if (state.viewport) state.viewport = scaled(*state.viewport, k);
    if (state.scissor) state.scissor = scaled(*state.scissor, k);
    m_viewport = {viewport_of(state, m_fb.width, m_fb.height), state.depth_near, state.depth_far};
    m_guard_band = guard_band_for(m_viewport.rect);
    m_bounds = draw_bounds(state, m_fb.width, m_fb.height);
    // The shaded-vertex cache: a power of two of entries, no more than the
    // draw has positions (up to kShadedVertexCache), entry vi % size; tag -1:
    // empty. Meshes index neighbouring vertices close together, so a vertex
    // is mostly shaded once; a miss only costs its shading again.
    const size_t n = draw.positions.size();
    size_t entries = 1;
    while (entries < std::min<size_t>(n, kShadedVertexCache)) entries *= 2;
    m_shaded.resize(entries);
    m_shaded_tag.assign(entries, -1);
    const size_t mask = entries - 1;
    // The vertex in a slot, copied into `out` (a primitive's next vertex
    // may evict it); false when the primitive is invalid (an index out of
    // range or a non-finite clip coordinate).
    const auto vertex = [&](uint32_t slot, ShadedVertex& out) {
      const uint32_t vi = draw.indices.empty() ? slot : draw.indices[slot];
      if (vi >= n) return false;
      const size_t e = vi & mask;
      if (m_shaded_tag[e] != vi) {
        m_shaded[e] = shade_vertex(m_scene, draw, vi);
        m_shaded_tag[e] = vi;
      }
      out = m_shaded[e];
      return is_finite(out.clip);
    };

    switch (primitive_kind_of(draw.primitive)) {
      case PrimitiveKind::triangle: {
        const uint64_t triangles = primitive_count(draw.primitive, draw.vertex_count());
        for (uint32_t i = 0; i < triangles; ++i) {
          const std::array<uint32_t, 3> slots = triangle_slots(draw.primitive, i);
          const int provoking = provoking_position(draw.primitive, i, state.provoking_vertex);
          const int64_t id = m_next_primitive_id++;
          ++m_stats.triangles_in;
          std::array<ShadedVertex, 3> tri;
          bool valid = true;
          for (int k = 0; k < 3 && valid; ++k) valid = vertex(slots[k], tri[k]);
          if (!valid) {
            ++m_stats.triangles_invalid;
          } else if (state.polygon_mode == PolygonMode::fill) {
            render_triangle(state, tri, tri[provoking].color, id);
          } else {
            render_unfilled_triangle(state, tri, tri[provoking].color, id);
          }
        }
        break;
      }
      case PrimitiveKind::line:
        for (const LineSlots& slots : assemble_lines(draw.primitive, draw.vertex_count())) {
          const int64_t id = m_next_primitive_id++;
          ++m_stats.lines_in;
          std::array<ShadedVertex, 2> line;
          if (!vertex(slots.v[0], line[0]) || !vertex(slots.v[1], line[1])) {
            ++m_stats.lines_invalid;
            continue;
          }
          render_line(state, line, slots.draw_first, slots.draw_last, id);
        }
        break;
      case PrimitiveKind::point:
        for (const uint32_t slot : assemble_points(draw.primitive, draw.vertex_count())) {
          const int64_t id = m_next_primitive_id++;
          ++m_stats.points_in;
          ShadedVertex v;
          if (!vertex(slot, v)) {
            ++m_stats.points_invalid;
          } else if (!point_in_view_volume(v.clip)) {
            ++m_stats.points_clipped_away;
          } else {
            // A point's colour is its vertex's, whatever the shading.
            rasterize_point(state, v, v.color, id);
          }
        }
        break;
    }
  }

  // `flat_color`: the provoking vertex's colour, before clipping.
  void render_triangle(const RenderState& st, const std::array<ShadedVertex, 3>& tri,
                       const glm::vec4& flat_color, int64_t id) {
    const std::vector<ShadedVertex> poly = clip_triangle(tri, m_guard_band, st.interpolation);
    if (poly.size() < 3) {
      ++m_stats.triangles_clipped_away;
      return;
    }
    if (was_clipped(poly, tri)) ++m_stats.triangles_clipped;
    std::vector<WindowVertex> win(poly.size());
    for (size_t i = 0; i < poly.size(); ++i)
      win[i] = to_window(poly[i], m_viewport, st.interpolation);
    for (size_t i = 1; i + 1 < poly.size(); ++i) {
      ++m_stats.triangles_after_clip;
      setup_and_rasterize(st, {win[0], win[i], win[i + 1]}, flat_color, id);
    }
  }

  static bool was_clipped(const std::vector<ShadedVertex>& poly,
                          const std::array<ShadedVertex, 3>& tri) {
    return !(poly.size() == 3 && poly[0].clip == tri[0].clip && poly[1].clip == tri[1].clip &&
             poly[2].clip == tri[2].clip);
  }

  // Whether a triangle of this signed area survives face culling.
  static bool survives_culling(const RenderState& st, EdgeValue area2) {
    const bool front = (st.front_face == FrontFace::ccw) == (area2 > 0);
    return !((st.cull == CullMode::back && !front) || (st.cull == CullMode::front && front));
  }

  // Polygon mode line or point (spec section 4d): clipped with edge flags,
  // facing decided once on the whole polygon, then its flagged edges or
  // vertices drawn with the triangle's id and provoking colour.
  void render_unfilled_triangle(const RenderState& st, const std::array<ShadedVertex, 3>& tri,
                                const glm::vec4& provoking, int64_t id) {
    const FlaggedPolygon poly = clip_triangle_with_edge_flags(tri, m_guard_band, st.interpolation);
    const size_t n = poly.v.size();
    if (n < 3) {
      ++m_stats.triangles_clipped_away;
      return;
    }
    if (was_clipped(poly.v, tri)) ++m_stats.triangles_clipped;
    std::vector<WindowVertex> win(n);
    for (size_t i = 0; i < n; ++i) win[i] = to_window(poly.v[i], m_viewport, st.interpolation);
    const EdgeValue area2 = polygon_area2(win);
    if (area2 == 0) {
      ++m_stats.triangles_degenerate;
      return;
    }
    if (!survives_culling(st, area2)) {
      ++m_stats.triangles_culled;
      return;
    }
    ++m_stats.triangles_unfilled;
    for (size_t i = 0; i < n; ++i) {
      if (!poly.edge_flag[i]) continue;
      if (st.polygon_mode == PolygonMode::line) {
        // Each vertex once: the edge's first pixel is drawn, its last is the
        // next edge's first (Bresenham's end flags).
        rasterize_line(st, win[i], win[(i + 1) % n], provoking, true, false, id);
      } else {
        rasterize_point(st, poly.v[i], st.shading == Shading::flat ? provoking : poly.v[i].color,
                        id);
      }
    }
  }

  void render_line(const RenderState& st, const std::array<ShadedVertex, 2>& line, bool draw_first,
                   bool draw_last, int64_t id) {
    const ClippedLine c = clip_line(line, m_guard_band, st.interpolation);
    if (c.result == LineClip::rejected) {
      ++m_stats.lines_clipped_away;
      return;
    }
    if (c.result == LineClip::clipped) ++m_stats.lines_clipped;
    // Flat shading: the provoking vertex's colour before clipping (the
    // second vertex, the first under the first-vertex convention).
    const glm::vec4& flat_color = line[st.provoking_vertex == ProvokingVertex::first ? 0 : 1].color;
    rasterize_line(st, to_window(c.v[0], m_viewport, st.interpolation),
                   to_window(c.v[1], m_viewport, st.interpolation), flat_color, draw_first,
                   draw_last, id);
  }

  // A clipped line in window space (spec sections 8b and 9; multisampled:
  // section 14's rectangle).
  void rasterize_line(const RenderState& st, const WindowVertex& a, const WindowVertex& b,
                      const glm::vec4& flat_color, bool draw_first, bool draw_last, int64_t id) {
    const EdgeValue dx = EdgeValue{b.x} - a.x, dy = EdgeValue{b.y} - a.y;
    const EdgeValue l2 = dx * dx + dy * dy;
    if (m_samples > 1) {
      if (l2 == 0) {
        ++m_stats.lines_degenerate;
        return;
      }
      rasterize_line_rectangle(st, a, b, flat_color, id);
      return;
    }
    const int w = line_width_pixels(st.line_width);
    std::vector<Pixel> pixels;
    if (st.line_rasterization == LineRasterization::diamond_exit) {
      if (l2 == 0) {
        ++m_stats.lines_degenerate;
        return;
      }
      pixels = diamond_exit_pixels(a.x, a.y, b.x, b.y, w, m_fb.width, m_fb.height);
    } else {
      pixels =
          bresenham_pixels(a.x, a.y, b.x, b.y, draw_first, draw_last, w, m_fb.width, m_fb.height);
    }
    // Only the draw rectangle's pixels (section 8d).
    pixels.erase(std::remove_if(pixels.begin(), pixels.end(),
                                [&](const Pixel& p) { return !m_bounds.contains(p.x, p.y); }),
                 pixels.end());
    ++m_stats.lines_rasterized;
    const SetupTriangle t = line_setup(a, b, l2);
    const auto weights = [&](int x, int y) {
      return line_functions(a, dx, dy, l2, pixel_center(x), pixel_center(y));
    };
    for (const Pixel& p : pixels) {
      const std::array<EdgeValue, 3> e = weights(p.x, p.y);
      const float z = depth_at(t, e);
      write_fragment(st, p.x, p.y, 1, &z, color_at(st, t, flat_color, p.x, p.y, weights), id);
    }
  }

  // Attributes of a line as for the triangle (a, b, a) with the line
  // parameter in place of the edge functions, so the float operations are
  // the triangle's (spec section 9).
  static SetupTriangle line_setup(const WindowVertex& a, const WindowVertex& b, EdgeValue l2) {
    SetupTriangle t;
    t.v = {a, b, a};
    t.area2 = l2 == 0 ? 1 : l2;
    t.apply_offset = false;  // polygon offset is for filled triangles only
    return t;
  }
  static std::array<EdgeValue, 3> line_functions(const WindowVertex& a, EdgeValue dx, EdgeValue dy,
                                                 EdgeValue l2, EdgeValue px, EdgeValue py) {
    if (l2 == 0) return {1, 0, 0};
    const EdgeValue T = (px - a.x) * dx + (py - a.y) * dy;
    return {l2 - T, T, 0};
  }

  // A multisampled line (spec section 14): the rectangle's four edges
  // tested at every sample, depth per sample from the line parameter at the
  // sample, colour at the pixel centre.
  void rasterize_line_rectangle(const RenderState& st, const WindowVertex& a, const WindowVertex& b,
                                const glm::vec4& flat_color, int64_t id) {
    ++m_stats.lines_rasterized;
    const EdgeValue dx = EdgeValue{b.x} - a.x, dy = EdgeValue{b.y} - a.y;
    const EdgeValue l2 = dx * dx + dy * dy;
    // At least one pixel wide, as OpenGL clamps widths to its range.
    const LineRectangle r = line_rectangle(a.x, a.y, b.x, b.y, std::max(1.0f, st.line_width));
    struct Edge {
      int64_t x, y, dx, dy, bias;
    };
    std::array<Edge, 4> edges;
    for (int k = 0; k < 4; ++k) {
      const int64_t ex = r.x[(k + 1) % 4] - r.x[k], ey = r.y[(k + 1) % 4] - r.y[k];
      const bool owns = ey < 0 || (ey == 0 && ex > 0);  // section 8's rule
      edges[k] = {r.x[k], r.y[k], ex, ey, owns ? 0 : 1};
    }
    const SetupTriangle t = line_setup(a, b, l2);
    const auto [x0, x1] = std::minmax({r.x[0], r.x[1], r.x[2], r.x[3]});
    const auto [y0, y1] = std::minmax({r.y[0], r.y[1], r.y[2], r.y[3]});
    scan_samples(st, id, x0, x1, y0, y1, [&](int x, int y, uint32_t& mask, float* z) {
      for (unsigned s = 0; s < m_samples; ++s) {
        const int64_t sx = pixel_center(x) + m_sample_dx[s], sy = pixel_center(y) + m_sample_dy[s];
        bool in = true;
        for (const Edge& e : edges) in = in && e.dx * (sy - e.y) - e.dy * (sx - e.x) - e.bias >= 0;
        if (!in) continue;
        mask |= 1u << s;
        z[s] = depth_at(t, line_functions(a, dx, dy, l2, sx, sy));
      }
      if (mask == 0) return glm::vec4(0.0f);
      return color_at(st, t, flat_color, x, y, [&](int px, int py) {
        return line_functions(a, dx, dy, l2, pixel_center(px), pixel_center(py));
      });
    });
  }

  // Calls shade(x, y, mask, z) for every pixel of the render target that has
  // a sample point within the subpixel box [x0, x1] x [y0, y1] (section 14's
  // widened box), and writes the fragment when shade() covered a sample;
  // shade returns the fragment's colour. Returns whether that pixel box was
  // non-empty.
  template <typename Shade>
  bool scan_samples(const RenderState& st, int64_t id, int64_t x0, int64_t x1, int64_t y0,
                    int64_t y1, Shade&& shade) {
    // Clamped to the draw rectangle (section 8d), not just the target.
    const int px0 = static_cast<int>(std::max<int64_t>(
        m_bounds.x0, ceil_div(x0 - kSubpixelHalf - m_reach_x.second, kSubpixelOne)));
    const int px1 = static_cast<int>(std::min<int64_t>(
        m_bounds.x1, floor_div(x1 - kSubpixelHalf - m_reach_x.first, kSubpixelOne)));
    const int py0 = static_cast<int>(std::max<int64_t>(
        m_bounds.y0, ceil_div(y0 - kSubpixelHalf - m_reach_y.second, kSubpixelOne)));
    const int py1 = static_cast<int>(std::min<int64_t>(
        m_bounds.y1, floor_div(y1 - kSubpixelHalf - m_reach_y.first, kSubpixelOne)));
    std::array<float, kMaxSamples> z;
    for (int y = py0; y <= py1; ++y) {
      for (int x = px0; x <= px1; ++x) {
        uint32_t mask = 0;
        const glm::vec4 color = shade(x, y, mask, z.data());
        if (mask != 0) write_fragment(st, x, y, mask, z.data(), color, id);
      }
    }
    return px0 <= px1 && py0 <= py1;
  }

  // A point that passed the view-volume test, or a polygon-mode vertex
  // (spec sections 8c and 14): depth z_w and a constant colour at every
  // sample inside its square.
  void rasterize_point(const RenderState& st, const ShadedVertex& v, const glm::vec4& color,
                       int64_t id) {
    ++m_stats.points_rasterized;
    const float z = to_window(v, m_viewport).z;
    const glm::vec2 xy = window_xy(v, m_viewport.rect);
    const PointSquare sq = point_square(xy.x, xy.y, st.point_size);
    // Textured: every fragment samples at the vertex's texture coordinate.
    const glm::vec4 fragment_color =
        m_texture ? textured(v.texcoord, TexcoordDerivatives(0.0f), color) : color;
    // Section 8c's space has pixel centres at 256 x: sample s of pixel x is at
    // 256 x + dx_s, covered iff x0 <= it < x0 + side (likewise y).
    scan_samples(st, id, sq.x0 + kSubpixelHalf, sq.x0 + sq.side - 1 + kSubpixelHalf,
                 sq.y0 + kSubpixelHalf, sq.y0 + sq.side - 1 + kSubpixelHalf,
                 [&](int x, int y, uint32_t& mask, float* zs) {
                   for (unsigned s = 0; s < m_samples; ++s) {
                     const int64_t sx = int64_t{x} * kSubpixelOne + m_sample_dx[s];
                     const int64_t sy = int64_t{y} * kSubpixelOne + m_sample_dy[s];
                     if (sx < sq.x0 || sx >= sq.x0 + sq.side || sy < sq.y0 || sy >= sq.y0 + sq.side)
                       continue;
                     mask |= 1u << s;
                     zs[s] = z;
                   }
                   return fragment_color;
                 });
  }

  void setup_and_rasterize(const RenderState& st, std::array<WindowVertex, 3> v,
                           const glm::vec4& flat_color, int64_t id) {
    const EdgeValue area2 = signed_area2(v[0], v[1], v[2]);
    if (area2 == 0) {
      ++m_stats.triangles_degenerate;
      return;
    }
    const bool ccw = area2 > 0;
    if (!survives_culling(st, area2)) {
      ++m_stats.triangles_culled;
      return;
    }
    ++m_stats.triangles_rasterized;
    SetupTriangle t;
    if (!ccw) std::swap(v[1], v[2]);
    t.v = v;
    t.area2 = ccw ? area2 : -area2;
    for (int e = 0; e < 3; ++e) {
      // Edge e is opposite vertex e: v[e+1] -> v[e+2].
      t.bias[e] = edge_owns_boundary(v[(e + 1) % 3], v[(e + 2) % 3]) ? 0 : 1;
    }
    t.apply_offset = st.offset_factor != 0.0f || st.offset_units != 0.0f;
    if (t.apply_offset) t.depth_offset = polygon_offset(t, st, m_fb.depth_format);
    const auto [min_x, max_x] = std::minmax({v[0].x, v[1].x, v[2].x});
    const auto [min_y, max_y] = std::minmax({v[0].y, v[1].y, v[2].y});
    const auto edges_at = [&](Subpixel px, Subpixel py) {
      return std::array<EdgeValue, 3>{edge_function(v[1], v[2], px, py),
                                      edge_function(v[2], v[0], px, py),
                                      edge_function(v[0], v[1], px, py)};
    };
    // Off screen: no pixel has a sample point within the box.
    const bool on_screen = scan_samples(
        st, id, min_x, max_x, min_y, max_y, [&](int x, int y, uint32_t& mask, float* z) {
          const Subpixel px = pixel_center(x), py = pixel_center(y);
          for (unsigned s = 0; s < m_samples; ++s) {
            const std::array<EdgeValue, 3> e = edges_at(px + m_sample_dx[s], py + m_sample_dy[s]);
            if (e[0] - t.bias[0] < 0 || e[1] - t.bias[1] < 0 || e[2] - t.bias[2] < 0) continue;
            mask |= 1u << s;
            z[s] = depth_at(t, e);
          }
          // Colour once per fragment, at the centre (section 14).
          return mask == 0 ? glm::vec4(0.0f)
                           : color_at(st, t, flat_color, x, y, [&](int qx, int qy) {
                               return edges_at(pixel_center(qx), pixel_center(qy));
                             });
        });
    if (!on_screen) ++m_stats.triangles_offscreen;
  }

  // Depth from the three weights e (edge functions, or a line's parameter):
  // linear in window space, relative to z0 so that a triangle of constant
  // depth gets exactly z0 everywhere; then polygon offset (spec section 9).
  static float depth_at(const SetupTriangle& t, const std::array<EdgeValue, 3>& e) {
    const float f1 = static_cast<float>(e[1]);
    const float f2 = static_cast<float>(e[2]);
    const WindowVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
    float z = v0.z + (f1 * (v1.z - v0.z) + f2 * (v2.z - v0.z)) / static_cast<float>(t.area2);
    if (t.apply_offset) z = z + t.depth_offset;
    return z;
  }

  // Colour from the three weights e: flat, or perspective-correct
  // sum(e_i * c_i / w_i) / sum(e_i / w_i) (spec section 9); a lit Phong
  // draw's lit from the normal and eye position interpolated so (9b).
  // The colour of pixel (x, y), whose weights (edge values, or a line's
  // parameter) weights(x, y) gives: flat, Gouraud or Phong (section 9), then
  // textured (9c) with the texture coordinate interpolated as any varying,
  // whatever the shading, and its derivatives over the pixel's 2x2 quad:
  // from the quad's lower-left pixel to its right and upper neighbours,
  // evaluated there whether or not they are covered.
  template <typename Weights>
  glm::vec4 color_at(const RenderState& st, const SetupTriangle& t, const glm::vec4& flat_color,
                     int x, int y, Weights&& weights) const {
    const std::array<EdgeValue, 3> e = weights(x, y);
    const glm::vec4 c = untextured_color_at(st, t, flat_color, e);
    if (m_texture == nullptr) return c;
    TexcoordDerivatives d(0.0f);
    if (m_texture->sampler.needs_lod()) {
      const int x0 = x & ~1, y0 = y & ~1;
      const glm::vec2 p00 = texcoord_at(t, weights(x0, y0));
      const glm::vec2 p10 = texcoord_at(t, weights(x0 + 1, y0));
      const glm::vec2 p01 = texcoord_at(t, weights(x0, y0 + 1));
      d = TexcoordDerivatives(p10.x - p00.x, p10.y - p00.y, p01.x - p00.x, p01.y - p00.y);
    }
    return textured(texcoord_at(t, e), d, c);
  }

  // Section 9's perspective-correct formula for the texture coordinate.
  static glm::vec2 texcoord_at(const SetupTriangle& t, const std::array<EdgeValue, 3>& e) {
    const float f0 = static_cast<float>(e[0]);
    const float f1 = static_cast<float>(e[1]);
    const float f2 = static_cast<float>(e[2]);
    const WindowVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
    const float den = f0 * v0.inv_w + f1 * v1.inv_w + f2 * v2.inv_w;
    glm::vec2 tc;
    for (int i = 0; i < 2; ++i) {
      tc[i] =
          (f0 * v0.texcoord_over_w[i] + f1 * v1.texcoord_over_w[i] + f2 * v2.texcoord_over_w[i]) /
          den;
    }
    return tc;
  }

  // Section 9c: the texture sampled at `tc` and combined with the colour.
  glm::vec4 textured(const glm::vec2& tc, const TexcoordDerivatives& d,
                     const glm::vec4& color) const {
    return apply_texture_env(m_draw->texture_env, m_texture->format, sample(*m_texture, tc, d),
                             color);
  }

  glm::vec4 untextured_color_at(const RenderState& st, const SetupTriangle& t,
                                const glm::vec4& flat_color,
                                const std::array<EdgeValue, 3>& e) const {
    if (st.shading == Shading::flat) return flat_color;
    const float f0 = static_cast<float>(e[0]);
    const float f1 = static_cast<float>(e[1]);
    const float f2 = static_cast<float>(e[2]);
    const WindowVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
    const float den = f0 * v0.inv_w + f1 * v1.inv_w + f2 * v2.inv_w;
    if (m_phong) {
      glm::vec3 n, p;
      for (int i = 0; i < 3; ++i) {
        n[i] =
            (f0 * v0.normal_over_w[i] + f1 * v1.normal_over_w[i] + f2 * v2.normal_over_w[i]) / den;
        p[i] = (f0 * v0.eye_over_w[i] + f1 * v1.eye_over_w[i] + f2 * v2.eye_over_w[i]) / den;
      }
      return light_pixel(m_scene, m_draw->material, n, p);
    }
    glm::vec4 src;
    for (int i = 0; i < 4; ++i) {
      const float num = f0 * v0.color_over_w[i] + f1 * v1.color_over_w[i] + f2 * v2.color_over_w[i];
      src[i] = gpusim::clamp01(num / den);
    }
    return src;
  }

  // Depth test, colour mask, blending and storage of one fragment: the
  // samples of `mask`, sample s at depth z[s], all with colour `src` (spec
  // sections 11, 12 and 14), the same for every kind of primitive.
  void write_fragment(const RenderState& st, int x, int y, uint32_t mask, const float* z,
                      const glm::vec4& src, int64_t id) {
    ++m_stats.fragments_generated;
    m_stats.samples_generated += static_cast<uint64_t>(__builtin_popcount(mask));
    uint32_t passed = mask;
    if (st.depth_test) {
      for (unsigned s = 0; s < m_samples; ++s) {
        if (!(mask >> s & 1)) continue;
        DepthValue& stored = m_fb.depth[m_fb.sample_index(x, y, s)];
        const DepthValue fragment_depth = encode_depth(m_fb.depth_format, z[s]);
        if (!depth_compare(st.depth_func, fragment_depth, stored)) {
          passed &= ~(1u << s);
        } else if (st.depth_write) {
          stored = fragment_depth;
        }
      }
    }
    if (passed == 0) return;
    const uint64_t n = static_cast<uint64_t>(__builtin_popcount(passed));
    ++m_stats.fragments_passed_depth;
    m_stats.samples_passed_depth += n;

    if (!(st.color_mask[0] || st.color_mask[1] || st.color_mask[2] || st.color_mask[3])) return;
    ++m_stats.fragments_written;
    m_stats.samples_written += n;
    if (!m_last_writer.empty()) m_last_writer[m_fb.pixel_index(x, y)] = id;
    const ColorFormat fmt = m_fb.color_format;
    for (unsigned s = 0; s < m_samples; ++s) {
      if (!(passed >> s & 1)) continue;
      ColorChannel* stored = &m_fb.color[m_fb.sample_index(x, y, s) * 4];
      glm::vec4 dst(0.0f);
      if (st.blend) {
        for (int i = 0; i < 4; ++i) dst[i] = decode_color(fmt, stored[i]);
      }
      for (int i = 0; i < 4; ++i) {
        if (!st.color_mask[i]) continue;
        const float out = st.blend ? blend_channel(st, src, dst, i) : src[i];
        // Fixed-point buffers clamp the blended value; float buffers keep it.
        stored[i] = encode_color(fmt, fmt == ColorFormat::rgba8 ? gpusim::clamp01(out) : out);
      }
    }
  }

  const Scene& m_scene;
  const Draw* m_draw = nullptr;        // the draw being rendered
  bool m_phong = false;                // it is lit per pixel
  const Texture* m_texture = nullptr;  // the texture it samples, if any
  const unsigned m_k;                  // supersample factor
  const unsigned m_samples;            // per pixel
  Framebuffer m_fb;                    // the render target, m_samples per pixel
  // The current draw's viewport transform, guard band and draw rectangle.
  ViewportTransform m_viewport;
  GuardBand m_guard_band{};
  PixelBounds m_bounds;
  std::vector<int64_t> m_last_writer;  // empty unless recorded
  // The current draw's shaded-vertex cache (render_draw) and its tags: the
  // vertex index an entry holds, or -1.
  std::vector<ShadedVertex> m_shaded;
  std::vector<int64_t> m_shaded_tag;
  Stats m_stats;
  int64_t m_next_primitive_id = 0;  // every kind, in API order
  // Sample offsets from the pixel centre (subpixels), and their extremes.
  std::array<Subpixel, kMaxSamples> m_sample_dx{}, m_sample_dy{};
  std::pair<Subpixel, Subpixel> m_reach_x, m_reach_y;
};

}  // namespace

ShadedVertex shade_vertex(const Scene& scene, const Draw& draw, uint32_t i) {
  ShadedVertex out;
  const glm::vec4& p = draw.positions[i];
  out.clip = mul(draw.mvp, p);
  if (draw.lighting && i < draw.normals.size()) {
    const glm::vec4 e = mul(draw.model_view, p);
    const glm::vec3 eye(e.x, e.y, e.z);
    const glm::vec3 n = normalized(mul(draw.normal_matrix, draw.normals[i]));
    out.color = light(scene, draw.material, eye, n);
    if (lit_per_pixel(draw)) {
      out.normal = n;
      out.eye = eye;
    }
  } else {
    out.color = clamp01(i < draw.colors.size() ? draw.colors[i] : draw.material.diffuse);
  }
  if (draw.texture >= 0) out.texcoord = draw.texcoords[i];
  return out;
}

std::array<uint32_t, 3> triangle_slots(PrimitiveType type, uint32_t i) {
  switch (type) {
    case PrimitiveType::triangle_strip:
      // Odd triangles swap their first two vertices so all keep one winding.
      return i % 2 == 0 ? std::array<uint32_t, 3>{i, i + 1, i + 2}
                        : std::array<uint32_t, 3>{i + 1, i, i + 2};
    case PrimitiveType::triangle_fan:
      return {0, i + 1, i + 2};
    default:  // triangles
      return {3 * i, 3 * i + 1, 3 * i + 2};
  }
}

std::vector<std::array<uint32_t, 3>> assemble_triangles(PrimitiveType type, size_t n) {
  std::vector<std::array<uint32_t, 3>> out;
  if (primitive_kind_of(type) != PrimitiveKind::triangle) return out;  // points and lines
  const uint64_t count = primitive_count(type, n);
  out.reserve(count);
  for (uint32_t i = 0; i < count; ++i) out.push_back(triangle_slots(type, i));
  return out;
}

int provoking_position(PrimitiveType type, uint32_t i, ProvokingVertex convention) {
  if (convention == ProvokingVertex::last) return 2;
  switch (type) {
    case PrimitiveType::triangle_strip:
      return i % 2 == 0 ? 0 : 1;  // slot i: an odd triangle is (i+1, i, i+2)
    case PrimitiveType::triangle_fan:
      return 1;  // slot i+1 of (0, i+1, i+2)
    default:
      return 0;
  }
}

std::vector<LineSlots> assemble_lines(PrimitiveType type, size_t n) {
  std::vector<LineSlots> out;
  if (n < 2) return out;
  switch (type) {
    case PrimitiveType::lines:
      for (uint32_t i = 0; i + 1 < n; i += 2) out.push_back({{i, i + 1}, true, true});
      break;
    case PrimitiveType::line_strip:
    case PrimitiveType::line_loop:
      // A shared vertex is the last pixel of one line and, with its first flag
      // cleared, not the first of the next (the Bresenham rule draws it once).
      for (uint32_t i = 0; i + 1 < n; ++i) out.push_back({{i, i + 1}, i == 0, true});
      // The closing line ends on vertex 0, its provoking vertex; both of its
      // ends are drawn by the lines next to it.
      if (type == PrimitiveType::line_loop) {
        out.push_back({{static_cast<uint32_t>(n - 1), 0}, false, false});
      }
      break;
    default:
      break;
  }
  return out;
}

std::vector<uint32_t> assemble_points(PrimitiveType type, size_t n) {
  std::vector<uint32_t> out;
  if (type != PrimitiveType::points) return out;
  out.reserve(n);
  for (uint32_t i = 0; i < n; ++i) out.push_back(i);
  return out;
}

GuardBand guard_band_for(const PixelRect& viewport) {
  // Window x = (x/w + 1) * Vw/2 + Vx stays within [-L, L] when
  // -(2(L + Vx)/Vw + 1) <= x/w <= 2(L - Vx)/Vw - 1 (likewise y).
  const float vx = static_cast<float>(viewport.x), vy = static_cast<float>(viewport.y);
  const float vw = static_cast<float>(viewport.width), vh = static_cast<float>(viewport.height);
  const float sl = 2.0f * (kGuardBandPixels + vx) / vw;
  const float sr = 2.0f * (kGuardBandPixels - vx) / vw;
  const float sb = 2.0f * (kGuardBandPixels + vy) / vh;
  const float st = 2.0f * (kGuardBandPixels - vy) / vh;
  return GuardBand{sl + 1.0f, sr - 1.0f, sb + 1.0f, st - 1.0f};
}

GuardBand guard_band_for(int width, int height) {
  return guard_band_for(PixelRect{0, 0, width, height});
}

float clip_distance(int plane, const glm::vec4& c, const GuardBand& gb) {
  switch (plane) {
    case 0:
      return c.w - kMinClipW;
    case 1:
      return c.z + c.w;
    case 2:
      return c.w - c.z;
    case 3:
      return c.x + gb.left * c.w;
    case 4:
      return gb.right * c.w - c.x;
    case 5:
      return c.y + gb.bottom * c.w;
    case 6:
      return gb.top * c.w - c.y;
  }
  return 0.0f;
}

FlaggedPolygon clip_triangle_with_edge_flags(const std::array<ShadedVertex, 3>& tri,
                                             const GuardBand& gb, Interpolation interpolation) {
  FlaggedPolygon poly{{tri.begin(), tri.end()}, {true, true, true}};
  FlaggedPolygon next;
  bool cut = false;
  for (int plane = 0; plane < kClipPlaneCount && !poly.v.empty(); ++plane) {
    const size_t n = poly.v.size();
    std::vector<float> d(n);
    bool all_inside = true;
    for (size_t i = 0; i < n; ++i) {
      d[i] = clip_distance(plane, poly.v[i].clip, gb);
      all_inside = all_inside && d[i] >= 0.0f;
    }
    if (all_inside) continue;
    cut = true;
    next.v.clear();
    next.edge_flag.clear();
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (i + 1) % n;
      const bool in_i = d[i] >= 0.0f, in_j = d[j] >= 0.0f;
      if (in_i) {
        next.v.push_back(poly.v[i]);
        next.edge_flag.push_back(poly.edge_flag[i]);
      }
      if (in_i == in_j) continue;
      next.v.push_back(clip_intersection(poly.v[i], d[i], poly.v[j], d[j], plane));
      // Leaving: the polygon edge from the cut runs along the plane, on no
      // edge of the triangle. Entering: it continues the edge v_i -> v_j.
      next.edge_flag.push_back(in_i ? false : poly.edge_flag[i]);
    }
    std::swap(poly, next);
  }
  if (poly.v.size() < 3) {
    poly.v.clear();
    poly.edge_flag.clear();
  }
  if (cut && interpolation == Interpolation::screen) screen_colors(poly.v, tri.data(), 3);
  return poly;
}

std::vector<ShadedVertex> clip_triangle(const std::array<ShadedVertex, 3>& tri, const GuardBand& gb,
                                        Interpolation interpolation) {
  return clip_triangle_with_edge_flags(tri, gb, interpolation).v;
}

ClippedLine clip_line(const std::array<ShadedVertex, 2>& line, const GuardBand& gb,
                      Interpolation interpolation) {
  ClippedLine out;
  out.v = line;
  // Outcodes: trivial accept when every distance is inside, trivial reject
  // when both endpoints are outside one plane. "Inside" is d >= 0, as for
  // triangles, so a NaN distance is outside.
  bool all_inside = true;
  for (int plane = 0; plane < kClipPlaneCount; ++plane) {
    const bool in_a = clip_distance(plane, line[0].clip, gb) >= 0.0f;
    const bool in_b = clip_distance(plane, line[1].clip, gb) >= 0.0f;
    if (!in_a && !in_b) return out;  // rejected
    all_inside = all_inside && in_a && in_b;
  }
  if (all_inside) {
    out.result = LineClip::accepted;
    return out;
  }
  for (int plane = 0; plane < kClipPlaneCount; ++plane) {
    const float da = clip_distance(plane, out.v[0].clip, gb);
    const float db = clip_distance(plane, out.v[1].clip, gb);
    const bool in_a = da >= 0.0f, in_b = db >= 0.0f;
    if (in_a && in_b) continue;
    if (!in_a && !in_b) return out;  // rejected (result stays rejected)
    // The same cut as a triangle edge's, so the float operations are identical.
    const ShadedVertex cut = clip_intersection(out.v[0], da, out.v[1], db, plane);
    out.v[in_a ? 1 : 0] = cut;
  }
  out.result = LineClip::clipped;
  if (interpolation == Interpolation::screen) {
    std::vector<ShadedVertex> ends(out.v.begin(), out.v.end());
    screen_colors(ends, line.data(), 2);
    out.v = {ends[0], ends[1]};
  }
  return out;
}

bool point_in_view_volume(const glm::vec4& c) {
  return c.w - kMinClipW >= 0.0f && c.x + c.w >= 0.0f && c.w - c.x >= 0.0f && c.y + c.w >= 0.0f &&
         c.w - c.y >= 0.0f && c.z + c.w >= 0.0f && c.w - c.z >= 0.0f;
}

glm::vec2 window_xy(const ShadedVertex& v, const PixelRect& viewport) {
  const float inv_w = 1.0f / v.clip.w;
  const float half_w = 0.5f * static_cast<float>(viewport.width);
  const float half_h = 0.5f * static_cast<float>(viewport.height);
  return {(v.clip.x * inv_w + 1.0f) * half_w + static_cast<float>(viewport.x),
          (v.clip.y * inv_w + 1.0f) * half_h + static_cast<float>(viewport.y)};
}

glm::vec2 window_xy(const ShadedVertex& v, int width, int height) {
  return window_xy(v, PixelRect{0, 0, width, height});
}

WindowVertex to_window(const ShadedVertex& v, const ViewportTransform& vp,
                       Interpolation interpolation) {
  WindowVertex w;
  const float q = 1.0f / v.clip.w;
  const glm::vec2 xy = window_xy(v, vp.rect);
  w.x = snap_to_subpixel(xy.x);
  w.y = snap_to_subpixel(xy.y);
  w.z = (v.clip.z * q + 1.0f) * 0.5f * (vp.far - vp.near) + vp.near;
  // Screen interpolation weighs every vertex alike: section 9's formula with
  // q = 1 is affine in window space.
  w.inv_w = interpolation == Interpolation::screen ? 1.0f : q;
  for (int k = 0; k < 4; ++k) w.color_over_w[k] = v.color[k] * w.inv_w;
  for (int k = 0; k < 3; ++k) {
    w.normal_over_w[k] = v.normal[k] * w.inv_w;
    w.eye_over_w[k] = v.eye[k] * w.inv_w;
  }
  for (int k = 0; k < 2; ++k) w.texcoord_over_w[k] = v.texcoord[k] * w.inv_w;
  return w;
}

WindowVertex to_window(const ShadedVertex& v, int width, int height, Interpolation interpolation) {
  return to_window(v, ViewportTransform{PixelRect{0, 0, width, height}, 0.0f, 1.0f}, interpolation);
}

EdgeValue signed_area2(const WindowVertex& a, const WindowVertex& b, const WindowVertex& c) {
  return edge_function(a, b, c.x, c.y);
}

EdgeValue edge_function(const WindowVertex& a, const WindowVertex& b, Subpixel px, Subpixel py) {
  const EdgeValue dx = EdgeValue{b.x} - a.x;
  const EdgeValue dy = EdgeValue{b.y} - a.y;
  return dx * (EdgeValue{py} - a.y) - dy * (EdgeValue{px} - a.x);
}

bool edge_owns_boundary(const WindowVertex& a, const WindowVertex& b) {
  // In a counter-clockwise triangle with y up, left edges run downwards and
  // the bottom edge runs in +x.
  const Subpixel dx = b.x - a.x, dy = b.y - a.y;
  return dy < 0 || (dy == 0 && dx > 0);
}

EdgeValue polygon_area2(const std::vector<WindowVertex>& poly) {
  EdgeValue sum = 0;
  for (size_t i = 1; i + 1 < poly.size(); ++i) sum += signed_area2(poly[0], poly[i], poly[i + 1]);
  return sum;
}

bool line_is_x_major(int64_t dx, int64_t dy) {
  return std::llabs(dx) >= std::llabs(dy);
}

int line_width_pixels(float line_width) {
  // Widths are at most 255 (the scene loader's range).
  return std::max(1, static_cast<int>(round_half_away(line_width)));
}

bool diamond_exit_covers(int64_t ax, int64_t ay, int64_t bx, int64_t by, int x, int y) {
  const int64_t cx = pixel_center(x), cy = pixel_center(y);
  const int64_t dx = bx - ax, dy = by - ay;
  const int64_t h = kSubpixelHalf;  // the diamond's radius
  // Separating axes of a segment and a diamond: the diamond's two edge
  // normals (1, 1), (1, -1), and the segment's normal (-dy, dx). Every value
  // is an exact integer plus the projection of the shift -(eps, eps^2), so
  // each is a Perturbed value. The open diamond projects to an open interval
  // (lo, hi); the closed segment to [min, max]: they meet iff on every axis
  // max > lo and min < hi.
  struct Axis {
    int64_t nx, ny;
  };
  const Axis axes[3] = {{1, 1}, {1, -1}, {-dy, dx}};
  bool meets = true;
  bool b_inside = true;
  for (int k = 0; k < 3; ++k) {
    const Axis& n = axes[k];
    // The shift -(eps, eps^2) projects to -nx eps - ny eps^2 for both ends.
    const Perturbed pa{n.nx * ax + n.ny * ay, -n.nx, -n.ny};
    const Perturbed pb{n.nx * bx + n.ny * by, -n.nx, -n.ny};
    // Support of the diamond |u| + |v| < h along n: h * max(|nx|, |ny|).
    const int64_t centre = n.nx * cx + n.ny * cy;
    const int64_t reach = h * std::max(std::llabs(n.nx), std::llabs(n.ny));
    const Perturbed lo{centre - reach, 0, 0}, hi{centre + reach, 0, 0};
    const Perturbed seg_min = std::min(pa, pb), seg_max = std::max(pa, pb);
    meets = meets && lo < seg_max && seg_min < hi;
    // The diamond is the intersection of its slabs on the first two axes.
    if (k < 2) b_inside = b_inside && lo < pb && pb < hi;
  }
  return meets && !b_inside;
}

std::vector<Pixel> diamond_exit_pixels(int64_t ax, int64_t ay, int64_t bx, int64_t by, int w,
                                       int width, int height) {
  std::vector<Pixel> out;
  const int64_t dx = bx - ax, dy = by - ay;
  if (dx == 0 && dy == 0) return out;
  const bool x_major = line_is_x_major(dx, dy);
  // Wide lines: the width-1 rule on the segment moved down (x-major) or left
  // (y-major) by half of w - 1 pixels, each fragment then repeated w times
  // up (or right).
  const int64_t offset = int64_t{kSubpixelHalf} * (w - 1);
  if (x_major) {
    ay -= offset;
    by -= offset;
  } else {
    ax -= offset;
    bx -= offset;
  }
  // Walk the major axis: u is the major coordinate, v the minor one.
  const int64_t ua = x_major ? ax : ay, ub = x_major ? bx : by;
  const int64_t va = x_major ? ay : ax;
  const int64_t du = ub - ua, dv = x_major ? dy : dx;
  const int major_size = x_major ? width : height;
  const int minor_size = x_major ? height : width;
  const int64_t umin = std::min(ua, ub), umax = std::max(ua, ub);
  // A diamond reaches half a pixel from its centre: every pixel whose diamond
  // can meet the segment lies within these lines (a superset is harmless).
  const int64_t first = std::max<int64_t>(0, floor_div(umin, kSubpixelOne) - 1);
  const int64_t last = std::min<int64_t>(major_size - 1, floor_div(umax, kSubpixelOne) + 1);
  for (int64_t i = first; i <= last; ++i) {
    // The segment's minor coordinate at this line's centre (or at the nearer
    // end, beyond the segment): |slope| <= 1, so within the diamond's reach
    // the segment stays within a pixel of it; two either side is a superset.
    const int64_t u = std::clamp<int64_t>(pixel_center(static_cast<int>(i)), umin, umax);
    const int64_t num = (u - ua) * dv;
    const int64_t v = va + (du > 0 ? floor_div(num, du) : floor_div(-num, -du));
    const int64_t base = floor_div(v, kSubpixelOne);
    for (int64_t j = base - 2; j <= base + 2; ++j) {
      if (j + w <= 0 || j >= minor_size) continue;  // its run is off-screen
      const int px = static_cast<int>(x_major ? i : j), py = static_cast<int>(x_major ? j : i);
      if (!diamond_exit_covers(ax, ay, bx, by, px, py)) continue;
      for (int k = 0; k < w; ++k) {
        if (j + k < 0 || j + k >= minor_size) continue;
        out.push_back(x_major ? Pixel{px, py + k} : Pixel{px + k, py});
      }
    }
  }
  return out;
}

std::vector<Pixel> bresenham_pixels(int64_t ax, int64_t ay, int64_t bx, int64_t by, bool draw_first,
                                    bool draw_last, int w, int width, int height) {
  std::vector<Pixel> out;
  // The pixels containing the end points.
  const int64_t iax = floor_div(ax, kSubpixelOne), iay = floor_div(ay, kSubpixelOne);
  const int64_t ibx = floor_div(bx, kSubpixelOne), iby = floor_div(by, kSubpixelOne);
  const int64_t DX = ibx - iax, DY = iby - iay;
  const bool x_major = line_is_x_major(DX, DY);
  const int64_t du = std::llabs(x_major ? DX : DY), dv = std::llabs(x_major ? DY : DX);
  const int64_t su = (x_major ? DX : DY) < 0 ? -1 : 1;
  const int64_t sv = (x_major ? DY : DX) < 0 ? -1 : 1;
  const int64_t u0 = x_major ? iax : iay, v0 = x_major ? iay : iax;
  const int64_t m = du;
  // Wide lines: the minor run starts floor((w - 1) / 2) below the pixel.
  const int64_t below = (w - 1) / 2;
  // Only the steps whose major coordinate is inside the framebuffer can
  // produce fragments: skip the rest of a line that runs far off-screen.
  const int64_t major_size = x_major ? width : height;
  const int64_t i_first = std::max<int64_t>(0, su > 0 ? -u0 : u0 - (major_size - 1));
  const int64_t i_last = std::min<int64_t>(m, su > 0 ? major_size - 1 - u0 : u0);
  for (int64_t i = i_first; i <= i_last; ++i) {
    if (i == 0 && !draw_first) continue;
    if (i == m && !draw_last) continue;
    // Closed form: the minor step nearest the line, a tie not stepping.
    const int64_t step = du == 0 ? 0 : ceil_div(2 * i * dv - du, 2 * du);
    const int64_t u = u0 + su * i, v = v0 + sv * step;
    for (int64_t k = 0; k < w; ++k) {
      const int64_t vk = v - below + k;
      const int64_t px = x_major ? u : vk, py = x_major ? vk : u;
      if (px < 0 || py < 0 || px >= width || py >= height) continue;
      out.push_back({static_cast<int>(px), static_cast<int>(py)});
    }
  }
  return out;
}

PointSquare point_square(float x_w, float y_w, float point_size) {
  // Multiplying by 256 is exact; the rounding is half away from zero and
  // saturates on extreme inputs (section 8c).
  PointSquare sq;
  sq.side = std::max<int64_t>(kSubpixelOne, round_half_away(point_size * 256.0f));
  sq.x0 = int64_t{round_half_away((x_w - 0.5f) * 256.0f)} - sq.side / 2;
  sq.y0 = int64_t{round_half_away((y_w - 0.5f) * 256.0f)} - sq.side / 2;
  return sq;
}

std::vector<Pixel> point_pixels(const PointSquare& sq, int width, int height) {
  // Pixel x is covered iff x0 <= 256 x < x0 + side (half-open).
  const int64_t x_first = std::max<int64_t>(0, ceil_div(sq.x0, kSubpixelOne));
  const int64_t x_last = std::min<int64_t>(width - 1, ceil_div(sq.x0 + sq.side, kSubpixelOne) - 1);
  const int64_t y_first = std::max<int64_t>(0, ceil_div(sq.y0, kSubpixelOne));
  const int64_t y_last = std::min<int64_t>(height - 1, ceil_div(sq.y0 + sq.side, kSubpixelOne) - 1);
  std::vector<Pixel> out;
  for (int64_t y = y_first; y <= y_last; ++y) {
    for (int64_t x = x_first; x <= x_last; ++x) {
      out.push_back({static_cast<int>(x), static_cast<int>(y)});
    }
  }
  return out;
}

LineRectangle line_rectangle(int64_t ax, int64_t ay, int64_t bx, int64_t by, float w) {
  const int64_t dx = bx - ax, dy = by - ay;
  // Half the width along the left normal (-dy, dx), in float, then snapped.
  const float s = (w * 128.0f) / std::sqrt(static_cast<float>(dx * dx + dy * dy));
  const int64_t ox = round_half_away(static_cast<float>(-dy) * s);
  const int64_t oy = round_half_away(static_cast<float>(dx) * s);
  LineRectangle r;
  r.x = {ax - ox, bx - ox, bx + ox, ax + ox};
  r.y = {ay - oy, by - oy, by + oy, ay + oy};
  return r;
}

Framebuffer resolve(const Framebuffer& target, unsigned k) {
  const int width = target.width / static_cast<int>(k),
            height = target.height / static_cast<int>(k);
  Framebuffer out(width, height, target.color_format, target.depth_format);
  const unsigned n = k * k * target.samples;
  if (n == 1) {
    out.color = target.color;  // one sample: the stored bits, unchanged
    out.depth = target.depth;
    return out;
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      ColorChannel* c = out.color_at(x, y);
      for (int ch = 0; ch < 4; ++ch) {
        // Rows j, then columns i, then samples, all ascending; the float sum
        // starts from the first sample.
        uint32_t sum = 0;
        float sum_f = 0.0f;
        bool first = true;
        for (unsigned j = 0; j < k; ++j) {
          for (unsigned i = 0; i < k; ++i) {
            for (unsigned s = 0; s < target.samples; ++s) {
              const size_t at =
                  target.sample_index(static_cast<int>(k * x + i), static_cast<int>(k * y + j), s);
              const ColorChannel v = target.color[at * 4 + static_cast<size_t>(ch)];
              if (target.color_format == ColorFormat::rgba8) {
                sum += v;
              } else {
                const float f = decode_color(ColorFormat::rgba16f, v);
                sum_f = first ? f : sum_f + f;
                first = false;
              }
            }
          }
        }
        c[ch] = target.color_format == ColorFormat::rgba8
                    ? static_cast<ColorChannel>((2 * sum + n) / (2 * n))
                    : encode_color(ColorFormat::rgba16f, sum_f / static_cast<float>(n));
      }
      out.depth[out.pixel_index(x, y)] =
          target.depth[target.sample_index(static_cast<int>(k * x), static_cast<int>(k * y), 0)];
    }
  }
  return out;
}

Result render(const Scene& scene, const RenderOptions& options) {
  return Renderer(scene, options).run();
}

}  // namespace gpusim::golden
