// Golden model: vertex transform, lighting, unlit colours, flat and Gouraud
// shading, perspective-correct interpolation (docs/pipeline-spec.md sections
// 2, 5 and 9). Expected values are analytic, worked out in the comments.
//
// Tolerances: lighting values are compared within 1e-6 (or a stated multiple)
// of the exact real-number answer: each result is a handful of float
// operations, each off by at most half an ulp (6e-8 relative), on values
// below 1, so the float result cannot stray further.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "hw/pixel_formats.h"
#include "testbench/golden/golden_model.h"

namespace gpusim {
namespace {

constexpr float kTol = 1e-6f;

Scene dark_scene() {
  Scene s;
  s.global_ambient = {0.0f, 0.0f, 0.0f, 1.0f};
  return s;
}

Material plain_material(glm::vec4 diffuse) {
  Material m;
  m.ambient = {0, 0, 0, 1};
  m.diffuse = diffuse;
  m.specular = {0, 0, 0, 1};
  m.emission = {0, 0, 0, 1};
  m.shininess = 0.0f;
  return m;
}

Light directional(glm::vec3 towards_light) {
  Light l;
  l.type = LightType::directional;
  l.vector = towards_light;
  l.ambient = {0, 0, 0, 1};
  l.diffuse = {1, 1, 1, 1};
  l.specular = {0, 0, 0, 1};
  return l;
}

Draw lit_point(glm::vec3 normal, const Material& m) {
  Draw d;
  d.lighting = true;
  d.positions = {{0.0f, 0.0f, 0.0f, 1.0f}};
  d.normals = {normal};
  d.material = m;
  return d;
}

void expect_rgb_near(const glm::vec4& got, glm::vec3 want, float tol, const char* what) {
  EXPECT_NEAR(got.r, want.r, tol) << what;
  EXPECT_NEAR(got.g, want.g, tol) << what;
  EXPECT_NEAR(got.b, want.b, tol) << what;
}

// ---------------------------------------------------------------------------
// Section 2: transform.

TEST(GoldenVertex, ClipIsMvpTimesPositionColumnMajor) {
  Scene s;
  Draw d;
  // M[c][r] = 4c + r + 1: columns (1,2,3,4), (5,6,7,8), (9,10,11,12), (13,14,15,16).
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) d.mvp[c][r] = static_cast<float>(4 * c + r + 1);
  }
  // model_view and projection are not used for the position.
  d.model_view = glm::mat4(2.0f);
  d.projection = glm::mat4(3.0f);
  d.positions = {{2.0f, -1.0f, 0.5f, 1.0f}, {1.0f, 0.0f, 0.0f, 0.0f}};
  // out[r] = 2 M[0][r] - M[1][r] + 0.5 M[2][r] + M[3][r]:
  // r0: 2 - 5 + 4.5 + 13; r1: 4 - 6 + 5 + 14; r2: 6 - 7 + 5.5 + 15; r3: 8 - 8 + 6 + 16.
  EXPECT_EQ(golden::shade_vertex(s, d, 0).clip, glm::vec4(14.5f, 17.0f, 19.5f, 22.0f));
  // (1, 0, 0, 0) picks column 0.
  EXPECT_EQ(golden::shade_vertex(s, d, 1).clip, glm::vec4(1.0f, 2.0f, 3.0f, 4.0f));
}

TEST(GoldenVertex, UnlitColourIsClampedVertexColourOrMaterialDiffuse) {
  Scene s;
  s.lights.push_back(directional({0, 0, 1}));  // present but unused: lighting off
  Draw d;
  d.positions = {{0, 0, 0, 1}, {0, 0, 0, 1}};
  d.normals = {{0, 0, 1}, {0, 0, 1}};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  d.colors = {{1.5f, -0.5f, nan, 0.25f}, {0.125f, 0.5f, 1.0f, 0.0f}};
  EXPECT_EQ(golden::shade_vertex(s, d, 0).color, glm::vec4(1.0f, 0.0f, 0.0f, 0.25f));
  EXPECT_EQ(golden::shade_vertex(s, d, 1).color, glm::vec4(0.125f, 0.5f, 1.0f, 0.0f));
  d.colors.clear();
  d.material.diffuse = {0.3f, 1.2f, -0.1f, 0.7f};
  EXPECT_EQ(golden::shade_vertex(s, d, 0).color, glm::vec4(0.3f, 1.0f, 0.0f, 0.7f));
}

// ---------------------------------------------------------------------------
// Section 2: lighting.

TEST(GoldenLighting, DirectionalDiffuseIsCosineTimesDiffuse) {
  Scene s = dark_scene();
  s.lights.push_back(directional({0, 0, 1}));
  // Normal (0, 3, 4) normalizes to (0, 0.6, 0.8): n.L = 0.8.
  const Draw d = lit_point({0, 3, 4}, plain_material({0.5f, 0.25f, 0.75f, 0.6f}));
  const glm::vec4 c = golden::shade_vertex(s, d, 0).color;
  expect_rgb_near(c, {0.4f, 0.2f, 0.6f}, kTol, "0.8 * diffuse");
  EXPECT_EQ(c.a, 0.6f);  // alpha is the material's diffuse alpha
  // Facing the light: exactly the material colour (all factors 1).
  const Draw facing = lit_point({0, 0, 2}, plain_material({0.5f, 0.25f, 0.75f, 0.6f}));
  EXPECT_EQ(golden::shade_vertex(s, facing, 0).color, glm::vec4(0.5f, 0.25f, 0.75f, 0.6f));
}

TEST(GoldenLighting, AmbientAndEmissionAndBackFacingNormal) {
  Scene s = dark_scene();
  s.global_ambient = {0.2f, 0.3f, 0.4f, 1.0f};
  Light l = directional({0, 0, 1});
  l.ambient = {0.1f, 0.2f, 0.3f, 1.0f};
  l.specular = {1, 1, 1, 1};
  s.lights.push_back(l);
  Material m = plain_material({0.9f, 0.9f, 0.9f, 0.5f});
  m.ambient = {0.5f, 0.5f, 0.5f, 1.0f};
  m.emission = {0.05f, 0.0f, 0.1f, 1.0f};
  m.specular = {1, 1, 1, 1};
  m.shininess = 1.0f;
  // Normal facing away (n.L = -1 -> 0): no diffuse, no specular.
  // emission + global * ambient + light ambient * ambient:
  // r 0.05 + 0.1 + 0.05 = 0.2; g 0 + 0.15 + 0.1 = 0.25; b 0.1 + 0.2 + 0.15 = 0.45.
  const glm::vec4 c = golden::shade_vertex(s, lit_point({0, 0, -1}, m), 0).color;
  expect_rgb_near(c, {0.2f, 0.25f, 0.45f}, kTol, "ambient only");
  EXPECT_EQ(c.a, 0.5f);
}

TEST(GoldenLighting, PointLightAttenuation) {
  Scene s = dark_scene();
  Light l = directional({0, 0, 0});
  l.type = LightType::point;
  l.vector = {0.0f, 0.0f, 1.0f};  // eye-space position
  l.constant_attenuation = 1.0f;
  l.linear_attenuation = 0.5f;
  l.quadratic_attenuation = 0.25f;
  s.lights.push_back(l);
  // The vertex at eye (0, 0, -3) (model_view translates by -3 in z):
  // d = (0, 0, 4), dist 4, att = 1 / (1 + 0.5 * 4 + 0.25 * 16) = 1/7; n.L = 1.
  Draw d = lit_point({0, 0, 1}, plain_material({0.7f, 0.35f, 0.14f, 1.0f}));
  d.model_view[3] = {0.0f, 0.0f, -3.0f, 1.0f};
  expect_rgb_near(golden::shade_vertex(s, d, 0).color, {0.1f, 0.05f, 0.02f}, kTol, "1/7");

  // Off-axis: light at (3, 0, 1): d = (3, 0, 4), dist 5, L = (0.6, 0, 0.8),
  // n.L = 0.8; att = 1 / (1 + 2.5 + 6.25) = 1 / 9.75.
  s.lights[0].vector = {3.0f, 0.0f, 1.0f};
  expect_rgb_near(golden::shade_vertex(s, d, 0).color,
                  {0.7f * 0.8f / 9.75f, 0.35f * 0.8f / 9.75f, 0.14f * 0.8f / 9.75f}, kTol,
                  "off axis");

  // The light at the vertex (dist 0): L = d = 0, n.L = 0, only ambient terms
  // (none here), and nothing undefined.
  s.lights[0].vector = {0.0f, 0.0f, -3.0f};
  s.lights[0].ambient = {0.5f, 0.5f, 0.5f, 1.0f};
  Draw amb = d;
  amb.material.ambient = {0.4f, 0.2f, 1.0f, 1.0f};
  // att = 1 / (1 + 0 + 0) = 1: 0.5 * ambient.
  expect_rgb_near(golden::shade_vertex(s, amb, 0).color, {0.2f, 0.1f, 0.5f}, kTol, "dist 0");
}

TEST(GoldenLighting, SpecularWithShininess) {
  Scene s = dark_scene();
  Light l = directional({0.6f, 0.0f, 0.8f});
  l.diffuse = {0, 0, 0, 1};
  l.specular = {1, 1, 1, 1};
  s.lights.push_back(l);
  Material m = plain_material({0, 0, 0, 1});
  m.specular = {1.0f, 0.5f, 0.25f, 1.0f};
  m.shininess = 10.0f;
  // n = (0, 0, 1): n.L = 0.8 > 0. H = normalize(0.6, 0, 1.8) = (0.6, 0, 1.8) / sqrt(3.6),
  // n.H = 1.8 / sqrt(3.6), (n.H)^2 = 3.24 / 3.6 = 0.9, so (n.H)^10 = 0.9^5 = 0.59049.
  // pow amplifies the relative error of n.H (a few ulps) tenfold: 5e-6.
  const Draw d = lit_point({0, 0, 1}, m);
  expect_rgb_near(golden::shade_vertex(s, d, 0).color, {0.59049f, 0.295245f, 0.1476225f}, 5e-6f,
                  "0.9^5");
  // Shininess 0: pow(x, 0) = 1.
  Draw d0 = d;
  d0.material.shininess = 0.0f;
  expect_rgb_near(golden::shade_vertex(s, d0, 0).color, {1.0f, 0.5f, 0.25f}, kTol, "shininess 0");
  // Light grazing the surface (n.L = 0): no specular even though n.H > 0.
  s.lights[0].vector = {1.0f, 0.0f, 0.0f};
  expect_rgb_near(golden::shade_vertex(s, d0, 0).color, {0.0f, 0.0f, 0.0f}, 0.0f, "grazing");
}

TEST(GoldenLighting, ResultIsClampedToZeroOne) {
  Scene s = dark_scene();
  Light l = directional({0, 0, 1});
  l.diffuse = {3.0f, 3.0f, 0.0f, 1.0f};
  s.lights.push_back(l);
  Material m = plain_material({0.5f, 0.2f, 0.5f, 1.5f});
  m.emission = {0.0f, 0.0f, -0.5f, 1.0f};
  // r: 3 * 0.5 = 1.5 -> 1; g: 3 * 0.2 = 0.6; b: -0.5 + 0 -> 0; a: 1.5 -> 1.
  const glm::vec4 c = golden::shade_vertex(s, lit_point({0, 0, 1}, m), 0).color;
  EXPECT_EQ(c.r, 1.0f);
  EXPECT_NEAR(c.g, 0.6f, kTol);
  EXPECT_EQ(c.b, 0.0f);
  EXPECT_EQ(c.a, 1.0f);
}

TEST(GoldenLighting, LightsAreSummed) {
  Scene s = dark_scene();
  Light a = directional({0, 0, 1});
  a.diffuse = {0.25f, 0.5f, 0.0f, 1.0f};
  Light b = directional({0.6f, 0.0f, 0.8f});  // n.L = 0.8
  b.diffuse = {0.5f, 0.0f, 0.5f, 1.0f};
  s.lights = {a, b};
  // 0.25 + 0.4 = 0.65; 0.5 + 0; 0 + 0.4.
  expect_rgb_near(
      golden::shade_vertex(s, lit_point({0, 0, 1}, plain_material({1, 1, 1, 1})), 0).color,
      {0.65f, 0.5f, 0.4f}, kTol, "two lights");
}

TEST(GoldenLighting, NormalMatrixIsAppliedColumnMajorThenNormalized) {
  Scene s = dark_scene();
  s.lights.push_back(directional({0, 0, 1}));
  Draw d = lit_point({0, 1, 0}, plain_material({1, 1, 1, 1}));
  // A 90 degree rotation about x taking +y to +z: columns (1,0,0), (0,0,1),
  // (0,-1,0). The normal (0, 1, 0) becomes (0, 0, 1): fully lit. (The
  // transpose would give (0, 0, -1): dark.)
  d.normal_matrix = glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0, -1, 0));
  EXPECT_EQ(golden::shade_vertex(s, d, 0).color, glm::vec4(1, 1, 1, 1));
  // A scaled normal matrix (model_view scaled by 2) is renormalized.
  Draw e = lit_point({0, 0, 1}, plain_material({0.5f, 0.5f, 0.5f, 1}));
  e.normal_matrix = glm::mat3(0.5f);
  EXPECT_EQ(golden::shade_vertex(s, e, 0).color, glm::vec4(0.5f, 0.5f, 0.5f, 1));
}

// ---------------------------------------------------------------------------
// Section 9: flat and Gouraud shading in a rendered frame.

Scene frame(int w, int h, ColorFormat cf = ColorFormat::rgba8) {
  Scene s;
  s.framebuffer.width = w;
  s.framebuffer.height = h;
  s.framebuffer.color_format = cf;
  s.framebuffer.depth_format = DepthFormat::float32;
  s.framebuffer.clear_color = {0, 0, 0, 0};
  return s;
}

// Triangle window (0, 0), (64, 0), (0, 64) in 64 x 64 (w = 1), colours
// black, red, green. Covered: x + y <= 62 (centres with x + y = 63 are on the
// hypotenuse, which runs up: not owned).
// Gouraud with w = 1: red = (x + 0.5) / 64, green = (y + 0.5) / 64, so the
// stored byte is round(255 (2x + 1) / 128); 255 (2x + 1) is odd, so the
// fraction is a nonzero multiple of 1/128, never within 1/128 of a tie, far
// beyond float error.
TEST(GoldenShading, GouraudAndFlatOnAnAffineTriangle) {
  for (Shading sh : {Shading::gouraud, Shading::flat}) {
    Scene s = frame(64, 64);
    Draw d;
    d.positions = {{-1, -1, 0, 1}, {1, -1, 0, 1}, {-1, 1, 0, 1}};
    d.colors = {{0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}};
    d.state.shading = sh;
    s.draws.push_back(d);
    const golden::Result r = golden::render(s);
    int covered = 0;
    for (int y = 0; y < 64; ++y) {
      for (int x = 0; x < 64; ++x) {
        const bool in = x + y <= 62;
        EXPECT_EQ(r.last_writer[y * 64 + x] == 0, in) << x << ", " << y;
        if (!in) continue;
        ++covered;
        const ColorChannel* c = r.framebuffer.color_at(x, y);
        if (sh == Shading::flat) {
          // The provoking (last) vertex: green.
          ASSERT_EQ(c[0], 0);
          ASSERT_EQ(c[1], 255);
        } else {
          ASSERT_EQ(c[0], std::lround(255.0 * (2 * x + 1) / 128.0)) << x << ", " << y;
          ASSERT_EQ(c[1], std::lround(255.0 * (2 * y + 1) / 128.0)) << x << ", " << y;
        }
        ASSERT_EQ(c[2], 0);
        ASSERT_EQ(c[3], 255);
      }
    }
    EXPECT_EQ(covered, 63 * 64 / 2);
  }
}

// Perspective: an eye-space quad A (-1,-1,-1), B (1,-1,-2), C (1,1,-2),
// D (-1,1,-1) (plane z = -1.5 - x/2), red = (x + 1) / 2 (0 at A, D; 1 at B,
// C), linear in object space. Projection with n = 1, f = 3 (exact entries):
// clip = (x, y, -2z - 3, -z). Window (64 x 64): A (0,0), B (48,16), C (48,48),
// D (0,64), all on the grid, and z_w = 0 at A, D, 0.75 at B, C.
//
// Inverting the projection at a pixel with NDC x_n: x_n = x / (1.5 + x/2), so
// x = 3 x_n / (2 - x_n) and red = (x + 1) / 2 = (1 + x_n) / (2 - x_n).
// The screen-linear (affine) value would be (1 + x_n) / 1.5.
// Depth is linear in screen space: z_ndc = (-2 z_e - 3) / (-z_e) with
// z_e = -1.5 - x/2, z_w = (z_ndc + 1) / 2.
TEST(GoldenShading, PerspectiveCorrectColourAndLinearDepth) {
  glm::mat4 proj(0.0f);
  proj[0][0] = 1.0f;
  proj[1][1] = 1.0f;
  proj[2][2] = -2.0f;  // -(f + n) / (f - n)
  proj[2][3] = -1.0f;
  proj[3][2] = -3.0f;  // -2 f n / (f - n)
  const glm::vec4 A(-1, -1, -1, 1), B(1, -1, -2, 1), C(1, 1, -2, 1), D(-1, 1, -1, 1);
  const glm::vec4 black(0, 0, 0, 1), red(1, 0, 0, 1);
  for (ColorFormat cf : {ColorFormat::rgba16f, ColorFormat::rgba8}) {
    Scene s = frame(64, 64, cf);
    Draw d;
    d.positions = {A, B, C, A, C, D};
    d.colors = {black, red, red, black, red, black};
    d.projection = proj;
    d.mvp = proj;
    s.draws.push_back(d);
    const golden::Result r = golden::render(s);
    EXPECT_EQ(r.stats.triangles_clipped, 0u);  // A and D lie on the near plane: inside
    // Row 31 (y_n = -1/64) lies inside the quad for window x in [0, 48):
    // pixels 0..47.
    const int y = 31;
    for (int x = 0; x < 48; ++x) {
      ASSERT_GE(r.last_writer[y * 64 + x], 0) << x;
      const double xn = (x + 0.5) / 32.0 - 1.0;
      const double want = (1.0 + xn) / (2.0 - xn);
      const double affine = (1.0 + xn) / 1.5;
      const ColorChannel stored = r.framebuffer.color_at(x, y)[0];
      if (cf == ColorFormat::rgba16f) {
        // rgba16f: half rounding is at most 2^-12 for values below 1; the
        // float arithmetic adds ~1e-6. Vertex positions are exact.
        const double got = decode_half(stored);
        EXPECT_NEAR(got, want, 2.5e-4) << "pixel " << x;
        if (x >= 8 && x <= 40) {
          EXPECT_GT(std::fabs(got - affine), 0.05) << "affine at " << x;
        }
      } else {
        // rgba8: round to nearest of 255 * red; float error ~1e-6 * 255.
        EXPECT_NEAR(static_cast<double>(stored), 255.0 * want, 0.5 + 1e-3) << "pixel " << x;
      }
      // Depth (float32 buffer).
      const double xe = 3.0 * xn / (2.0 - xn);
      const double ze = -1.5 - xe / 2.0;
      const double zw = ((-2.0 * ze - 3.0) / -ze + 1.0) / 2.0;
      EXPECT_NEAR(float_from_bits(r.framebuffer.depth[y * 64 + x]), zw, 2e-6) << "depth " << x;
    }
    EXPECT_LT(r.last_writer[y * 64 + 48], 0);
  }
}

// ---------------------------------------------------------------------------
// Section 9b: Phong shading.

TEST(GoldenPhong, LitPhongVertexCarriesItsUnitNormalAndEyePosition) {
  Scene s = dark_scene();
  s.lights.push_back(directional({0, 0, 1}));
  Draw d = lit_point({0, 3, 4}, plain_material({1, 1, 1, 1}));
  d.positions = {{1.0f, 2.0f, 3.0f, 1.0f}};
  d.model_view = glm::mat4(2.0f);  // scales x, y, z by 2, w by 2
  d.state.shading = Shading::phong;
  ASSERT_TRUE(golden::lit_per_pixel(d));
  const golden::ShadedVertex v = golden::shade_vertex(s, d, 0);
  expect_rgb_near(glm::vec4(v.normal, 0), {0.0f, 0.6f, 0.8f}, kTol, "unit normal");
  EXPECT_EQ(v.eye, glm::vec3(2.0f, 4.0f, 6.0f));
  // The vertex keeps its Gouraud colour (for points): n.L = 0.8.
  expect_rgb_near(v.color, {0.8f, 0.8f, 0.8f}, kTol, "vertex colour");
  // Gouraud, or unlit: no normal or position.
  for (int k = 0; k < 2; ++k) {
    Draw other = d;
    if (k == 0) other.state.shading = Shading::gouraud;
    if (k == 1) other.lighting = false;
    EXPECT_FALSE(golden::lit_per_pixel(other)) << k;
    EXPECT_EQ(golden::shade_vertex(s, other, 0).normal, glm::vec3(0.0f)) << k;
    EXPECT_EQ(golden::shade_vertex(s, other, 0).eye, glm::vec3(0.0f)) << k;
  }
}

TEST(GoldenPhong, PixelLightingRenormalisesTheInterpolatedNormal) {
  Scene s = dark_scene();
  s.lights.push_back(directional({0, 0, 1}));
  const Material m = plain_material({0.5f, 0.25f, 0.75f, 0.6f});
  // (0, 3, 4) / 10, shortened as interpolation between unit normals does:
  // renormalised to (0, 0.6, 0.8), n.L = 0.8 (unrenormalised it would be 0.08).
  const glm::vec4 c = golden::light_pixel(s, m, {0.0f, 0.3f, 0.4f}, {0, 0, 0});
  expect_rgb_near(c, {0.4f, 0.2f, 0.6f}, kTol, "0.8 * diffuse");
  EXPECT_EQ(c.a, 0.6f);
  // A zero normal stays zero: diffuse 0, the colour is emission + ambient = 0.
  expect_rgb_near(golden::light_pixel(s, m, {0, 0, 0}, {0, 0, 0}), {0, 0, 0}, 0.0f, "zero normal");
}

// A 64x64 square in the eye-space plane z = -2, seen orthographically
// (window x = 32 (x_eye + 1)), normals +z, under a point light at height h
// above its centre, no attenuation, diffuse only: the exact lit value at eye
// position (x, y, -2) is n.L = h / sqrt(x^2 + y^2 + h^2).
Scene square_under_point_light(Shading shading, float h) {
  Scene s = dark_scene();
  s.framebuffer.width = 64;
  s.framebuffer.height = 64;
  Light l;
  l.type = LightType::point;
  l.vector = {0.0f, 0.0f, -2.0f + h};
  l.ambient = {0, 0, 0, 1};
  l.diffuse = {1, 1, 1, 1};
  l.specular = {0, 0, 0, 1};
  s.lights.push_back(l);
  Draw d;
  d.lighting = true;
  d.positions = {{-1, -1, -2, 1}, {1, -1, -2, 1}, {1, 1, -2, 1}, {-1, 1, -2, 1}};
  d.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  d.indices = {0, 1, 2, 0, 2, 3};
  d.material = plain_material({1, 1, 1, 1});
  d.model_view = glm::mat4(1.0f);
  d.mvp = glm::mat4(1.0f);
  d.mvp[2][2] = 0.0f;  // clip z = 0: the eye z of -2 is not a clip depth
  d.state.shading = shading;
  d.state.depth_test = false;
  s.draws.push_back(d);
  return s;
}

TEST(GoldenPhong, PointLightCloseToASquareIsLitPerPixel) {
  const float h = 0.25f;
  const golden::Result phong = golden::render(square_under_point_light(Shading::phong, h));
  const golden::Result gouraud = golden::render(square_under_point_light(Shading::gouraud, h));
  // The corners see n.L = h / sqrt(2 + h^2) = 0.1741: Gouraud spreads that
  // over the whole square. Phong follows the exact value pixel by pixel,
  // within half an rgba8 step (the store's rounding) and float error.
  const float corner = h / std::sqrt(2.0f + h * h);
  double max_error = 0.0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const double ex = (x + 0.5) / 32.0 - 1.0, ey = (y + 0.5) / 32.0 - 1.0;
      const double want = h / std::sqrt(ex * ex + ey * ey + double{h} * h);
      for (int k = 0; k < 3; ++k) {
        const double got = decode_color(ColorFormat::rgba8, phong.framebuffer.color_at(x, y)[k]);
        max_error = std::max(max_error, std::fabs(got - want));
        const double g = decode_color(ColorFormat::rgba8, gouraud.framebuffer.color_at(x, y)[k]);
        ASSERT_NEAR(g, corner, 0.5 / 255 + 1e-6) << x << "," << y;
      }
    }
  }
  EXPECT_LE(max_error, 0.5 / 255 + 1e-5);
  // At the centre pixels the light is nearly overhead: n.L > 0.98.
  EXPECT_GE(phong.framebuffer.color_at(32, 32)[0], 250);
  EXPECT_EQ(gouraud.framebuffer.color_at(32, 32)[0], 44);  // round(255 * 0.1741)
}

// Perspective: the same square tilted away from the viewer. The eye-space
// position interpolated perspective-correctly at a pixel centre is the
// point of the plane seen through that centre, so the lit value is the
// exact one at that point; interpolated linearly in the window it would not
// be.
TEST(GoldenPhong, EyePositionIsInterpolatedPerspectiveCorrectly) {
  Scene s = square_under_point_light(Shading::phong, 0.5f);
  s.framebuffer.clear_color = {0, 0, 0, 0};  // alpha 0 where the square is not
  Draw& d = s.draws[0];
  // Eye-space square: x in [-1, 1], z = -3 + y_obj (y_obj in [-1, 1]), eye
  // y = 0.5 y_obj: the plane z = -3 + 2 y, tilted.
  d.model_view = glm::mat4(1.0f);
  d.model_view[1] = glm::vec4(0.0f, 0.5f, 1.0f, 0.0f);  // column y: (0, 0.5, 1)
  d.model_view[3] = glm::vec4(0.0f, 0.0f, -3.0f, 1.0f);
  // The plane z - 2 y = -3; its normal towards the viewer (the origin).
  const glm::vec3 n = glm::normalize(glm::vec3(0.0f, -2.0f, 1.0f));
  for (auto& nv : d.normals) nv = n;
  d.positions = {{-1, -1, 0, 1}, {1, -1, 0, 1}, {1, 1, 0, 1}, {-1, 1, 0, 1}};
  // Projection: x_clip = x, y_clip = y, w_clip = -z (a 90-degree frustum),
  // z_clip = 0.
  glm::mat4 proj(0.0f);
  proj[0][0] = 1.0f;
  proj[1][1] = 1.0f;
  proj[2][3] = -1.0f;
  d.mvp = proj * d.model_view;
  d.normal_matrix = glm::mat3(1.0f);  // the normals are already eye space
  s.lights[0].vector = {0.0f, 0.2f, -2.0f};
  const golden::Result r = golden::render(s);
  int checked = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      if (decode_color(ColorFormat::rgba8, r.framebuffer.color_at(x, y)[3]) == 0.0f) continue;
      // The ray through the pixel centre: (sx t, sy t, -t) with s = NDC;
      // it meets the plane z = -3 + 2 y_eye, i.e. -t = -3 + 2 sy t.
      const double sx = (x + 0.5) / 32.0 - 1.0, sy = (y + 0.5) / 32.0 - 1.0;
      const double t = 3.0 / (1.0 + 2.0 * sy);
      const glm::dvec3 p(sx * t, sy * t, -t);
      const glm::dvec3 to_light = glm::dvec3(0.0, 0.2, -2.0) - p;
      const double want = std::max(0.0, glm::dot(glm::dvec3(n), glm::normalize(to_light)));
      const double got = decode_color(ColorFormat::rgba8, r.framebuffer.color_at(x, y)[0]);
      ASSERT_NEAR(got, want, 0.5 / 255 + 1e-4) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 250);  // the square covers 288 pixels
}

}  // namespace
}  // namespace gpusim
