#include "testbench/golden/golden_model.h"

#include <algorithm>
#include <cmath>

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

glm::vec4 light_vertex(const Scene& scene, const Draw& draw, const glm::vec4& eye,
                       const glm::vec3& normal) {
  const Material& m = draw.material;
  const glm::vec3 n = normalized(mul(draw.normal_matrix, normal));
  const glm::vec3 p(eye.x, eye.y, eye.z);
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

bool is_finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// Per-triangle constants for the pixel loop.
struct SetupTriangle {
  std::array<WindowVertex, 3> v;  // counter-clockwise
  EdgeValue area2 = 0;
  std::array<EdgeValue, 3> bias{};  // 0 for owned edges, 1 otherwise
  float depth_offset = 0.0f;
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
  explicit Renderer(const Scene& scene)
      : m_scene(scene),
        m_fb(scene.framebuffer.width, scene.framebuffer.height, scene.framebuffer.color_format,
             scene.framebuffer.depth_format),
        m_guard_band(guard_band_for(m_fb.width, m_fb.height)) {
    const glm::vec4& c = scene.framebuffer.clear_color;
    const float rgba[4] = {c.x, c.y, c.z, c.w};
    m_fb.clear(rgba, scene.framebuffer.clear_depth);
    m_last_writer.assign(m_fb.depth.size(), -1);
  }

  Result run() {
    for (const Draw& draw : m_scene.draws) render_draw(draw);
    return Result{std::move(m_fb), std::move(m_last_writer), m_stats};
  }

 private:
  void render_draw(const Draw& draw) {
    std::vector<ShadedVertex> shaded(draw.positions.size());
    for (uint32_t i = 0; i < shaded.size(); ++i) shaded[i] = shade_vertex(m_scene, draw, i);

    for (const auto& slots : assemble_triangles(draw.primitive, draw.vertex_count())) {
      const int64_t id = m_next_triangle_id++;
      ++m_stats.triangles_in;
      std::array<ShadedVertex, 3> tri;
      bool valid = true;
      for (int k = 0; k < 3; ++k) {
        const uint32_t vi = draw.indices.empty() ? slots[k] : draw.indices[slots[k]];
        if (vi >= shaded.size()) {
          valid = false;
          break;
        }
        tri[k] = shaded[vi];
        valid = valid && is_finite(tri[k].clip);
      }
      if (!valid) {
        ++m_stats.triangles_invalid;
        continue;
      }
      render_triangle(draw.state, tri, id);
    }
  }

  void render_triangle(const RenderState& st, const std::array<ShadedVertex, 3>& tri, int64_t id) {
    const std::vector<ShadedVertex> poly = clip_triangle(tri, m_guard_band);
    if (poly.size() < 3) {
      ++m_stats.triangles_clipped_away;
      return;
    }
    const bool clipped = !(poly.size() == 3 && poly[0].clip == tri[0].clip &&
                           poly[1].clip == tri[1].clip && poly[2].clip == tri[2].clip);
    if (clipped) ++m_stats.triangles_clipped;
    // Flat shading takes the colour of the original triangle's last vertex.
    const glm::vec4 flat_color = tri[2].color;
    std::vector<WindowVertex> win(poly.size());
    for (size_t i = 0; i < poly.size(); ++i) win[i] = to_window(poly[i], m_fb.width, m_fb.height);
    for (size_t i = 1; i + 1 < poly.size(); ++i) {
      ++m_stats.triangles_after_clip;
      setup_and_rasterize(st, {win[0], win[i], win[i + 1]}, flat_color, id);
    }
  }

  void setup_and_rasterize(const RenderState& st, std::array<WindowVertex, 3> v,
                           const glm::vec4& flat_color, int64_t id) {
    const EdgeValue area2 = signed_area2(v[0], v[1], v[2]);
    if (area2 == 0) {
      ++m_stats.triangles_degenerate;
      return;
    }
    const bool ccw = area2 > 0;
    const bool front = (st.front_face == FrontFace::ccw) == ccw;
    if ((st.cull == CullMode::back && !front) || (st.cull == CullMode::front && front)) {
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
    if (st.offset_factor != 0.0f || st.offset_units != 0.0f) {
      t.depth_offset = polygon_offset(t, st, m_fb.depth_format);
    }
    const Subpixel min_x = std::min({v[0].x, v[1].x, v[2].x});
    const Subpixel max_x = std::max({v[0].x, v[1].x, v[2].x});
    const Subpixel min_y = std::min({v[0].y, v[1].y, v[2].y});
    const Subpixel max_y = std::max({v[0].y, v[1].y, v[2].y});
    // Pixels whose centres (i * 256 + 128) lie within the vertices' box.
    t.x0 = std::max(0, -floor_div_subpixel(-(int64_t{min_x} - kSubpixelHalf)));
    t.x1 = std::min(m_fb.width - 1, floor_div_subpixel(int64_t{max_x} - kSubpixelHalf));
    t.y0 = std::max(0, -floor_div_subpixel(-(int64_t{min_y} - kSubpixelHalf)));
    t.y1 = std::min(m_fb.height - 1, floor_div_subpixel(int64_t{max_y} - kSubpixelHalf));

    for (int y = t.y0; y <= t.y1; ++y) {
      for (int x = t.x0; x <= t.x1; ++x) {
        const Subpixel px = pixel_center(x), py = pixel_center(y);
        const EdgeValue e0 = edge_function(v[1], v[2], px, py);
        const EdgeValue e1 = edge_function(v[2], v[0], px, py);
        const EdgeValue e2 = edge_function(v[0], v[1], px, py);
        if (e0 - t.bias[0] < 0 || e1 - t.bias[1] < 0 || e2 - t.bias[2] < 0) continue;
        shade_fragment(st, t, flat_color, x, y, {e0, e1, e2}, id);
      }
    }
  }

  void shade_fragment(const RenderState& st, const SetupTriangle& t, const glm::vec4& flat_color,
                      int x, int y, const std::array<EdgeValue, 3>& e, int64_t id) {
    ++m_stats.fragments_generated;
    const float f0 = static_cast<float>(e[0]);
    const float f1 = static_cast<float>(e[1]);
    const float f2 = static_cast<float>(e[2]);
    const WindowVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];

    // Depth: linear in window space, relative to z0 so that a triangle of
    // constant depth gets exactly z0 everywhere; then polygon offset.
    float z = v0.z + (f1 * (v1.z - v0.z) + f2 * (v2.z - v0.z)) / static_cast<float>(t.area2);
    if (st.offset_factor != 0.0f || st.offset_units != 0.0f) z = z + t.depth_offset;

    const size_t p = m_fb.pixel_index(x, y);
    if (st.depth_test) {
      const DepthValue fragment_depth = encode_depth(m_fb.depth_format, z);
      if (!depth_compare(st.depth_func, fragment_depth, m_fb.depth[p])) return;
      if (st.depth_write) m_fb.depth[p] = fragment_depth;
    }
    ++m_stats.fragments_passed_depth;

    glm::vec4 src;
    if (st.shading == Shading::flat) {
      src = flat_color;
    } else {
      // Perspective-correct: sum(e_i * c_i / w_i) / sum(e_i / w_i).
      const float den = f0 * v0.inv_w + f1 * v1.inv_w + f2 * v2.inv_w;
      for (int i = 0; i < 4; ++i) {
        const float num =
            f0 * v0.color_over_w[i] + f1 * v1.color_over_w[i] + f2 * v2.color_over_w[i];
        src[i] = gpusim::clamp01(num / den);
      }
    }

    if (!(st.color_mask[0] || st.color_mask[1] || st.color_mask[2] || st.color_mask[3])) return;
    ++m_stats.fragments_written;
    m_last_writer[p] = id;
    ColorChannel* stored = &m_fb.color[p * 4];
    const ColorFormat fmt = m_fb.color_format;
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

  const Scene& m_scene;
  Framebuffer m_fb;
  GuardBand m_guard_band;
  std::vector<int64_t> m_last_writer;
  Stats m_stats;
  int64_t m_next_triangle_id = 0;
};

}  // namespace

ShadedVertex shade_vertex(const Scene& scene, const Draw& draw, uint32_t i) {
  ShadedVertex out;
  const glm::vec4& p = draw.positions[i];
  out.clip = mul(draw.mvp, p);
  if (draw.lighting && i < draw.normals.size()) {
    out.color = light_vertex(scene, draw, mul(draw.model_view, p), draw.normals[i]);
  } else {
    out.color = clamp01(i < draw.colors.size() ? draw.colors[i] : draw.material.diffuse);
  }
  return out;
}

std::vector<std::array<uint32_t, 3>> assemble_triangles(PrimitiveType type, size_t n) {
  std::vector<std::array<uint32_t, 3>> out;
  if (n < 3) return out;
  switch (type) {
    case PrimitiveType::triangles:
      out.reserve(n / 3);
      for (uint32_t i = 0; i + 2 < n; i += 3) out.push_back({i, i + 1, i + 2});
      break;
    case PrimitiveType::triangle_strip:
      out.reserve(n - 2);
      // Odd triangles swap their first two vertices so all keep one winding.
      for (uint32_t i = 0; i + 2 < n; ++i) {
        out.push_back(i % 2 == 0 ? std::array<uint32_t, 3>{i, i + 1, i + 2}
                                 : std::array<uint32_t, 3>{i + 1, i, i + 2});
      }
      break;
    case PrimitiveType::triangle_fan:
      out.reserve(n - 2);
      for (uint32_t i = 0; i + 2 < n; ++i) out.push_back({0, i + 1, i + 2});
      break;
  }
  return out;
}

GuardBand guard_band_for(int width, int height) {
  // Window x = (x/w + 1) * width/2 stays within [-L, L] when
  // -(2L/width + 1) <= x/w <= 2L/width - 1.
  const float sx = 2.0f * kGuardBandPixels / static_cast<float>(width);
  const float sy = 2.0f * kGuardBandPixels / static_cast<float>(height);
  return GuardBand{sx + 1.0f, sx - 1.0f, sy + 1.0f, sy - 1.0f};
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

std::vector<ShadedVertex> clip_triangle(const std::array<ShadedVertex, 3>& tri,
                                        const GuardBand& gb) {
  std::vector<ShadedVertex> poly(tri.begin(), tri.end());
  std::vector<ShadedVertex> next;
  for (int plane = 0; plane < kClipPlaneCount && !poly.empty(); ++plane) {
    std::vector<float> d(poly.size());
    bool all_inside = true;
    for (size_t i = 0; i < poly.size(); ++i) {
      d[i] = clip_distance(plane, poly[i].clip, gb);
      all_inside = all_inside && d[i] >= 0.0f;
    }
    if (all_inside) continue;
    next.clear();
    for (size_t i = 0; i < poly.size(); ++i) {
      const size_t j = (i + 1) % poly.size();
      const bool in_i = d[i] >= 0.0f, in_j = d[j] >= 0.0f;
      if (in_i) next.push_back(poly[i]);
      if (in_i == in_j) continue;
      // Interpolate from the endpoint nearer the plane (the inside one on a
      // tie), which keeps t small and the cut precise; the choice depends only
      // on the edge, so an edge shared by two triangles is cut identically.
      const bool from_i =
          std::fabs(d[i]) < std::fabs(d[j]) || (std::fabs(d[i]) == std::fabs(d[j]) && in_i);
      const ShadedVertex& a = from_i ? poly[i] : poly[j];
      const ShadedVertex& b = from_i ? poly[j] : poly[i];
      const float da = from_i ? d[i] : d[j];
      const float db = from_i ? d[j] : d[i];
      const float t = da / (da - db);
      ShadedVertex v;
      for (int k = 0; k < 4; ++k) {
        v.clip[k] = a.clip[k] + t * (b.clip[k] - a.clip[k]);
        v.color[k] = a.color[k] + t * (b.color[k] - a.color[k]);
      }
      // Rounding can leave a cut on the w plane at or below 0; 1/w must stay finite.
      if (plane == 0) v.clip.w = std::max(v.clip.w, kMinClipW);
      next.push_back(v);
    }
    poly.swap(next);
  }
  if (poly.size() < 3) poly.clear();
  return poly;
}

WindowVertex to_window(const ShadedVertex& v, int width, int height) {
  WindowVertex w;
  w.inv_w = 1.0f / v.clip.w;
  const float half_w = 0.5f * static_cast<float>(width);
  const float half_h = 0.5f * static_cast<float>(height);
  w.x = snap_to_subpixel((v.clip.x * w.inv_w + 1.0f) * half_w);
  w.y = snap_to_subpixel((v.clip.y * w.inv_w + 1.0f) * half_h);
  w.z = (v.clip.z * w.inv_w + 1.0f) * 0.5f;
  for (int k = 0; k < 4; ++k) w.color_over_w[k] = v.color[k] * w.inv_w;
  return w;
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

nlohmann::json Stats::to_json() const {
  return {{"triangles_in", triangles_in},
          {"triangles_invalid", triangles_invalid},
          {"triangles_clipped_away", triangles_clipped_away},
          {"triangles_clipped", triangles_clipped},
          {"triangles_after_clip", triangles_after_clip},
          {"triangles_degenerate", triangles_degenerate},
          {"triangles_culled", triangles_culled},
          {"triangles_rasterized", triangles_rasterized},
          {"fragments_generated", fragments_generated},
          {"fragments_passed_depth", fragments_passed_depth},
          {"fragments_written", fragments_written}};
}

Result render(const Scene& scene) {
  return Renderer(scene).run();
}

}  // namespace gpusim::golden
