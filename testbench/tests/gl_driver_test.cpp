// The fixed-function OpenGL driver (testbench/gl/gl_driver.h) on synthetic
// call sequences: primitive decomposition with GL's provoking vertices, display
// lists, the matrix stack against GLM, the lighting translation against GL's
// lighting equation evaluated here, batching, viewport, depth range, scissor
// and clears between draws against GL's rules, unsupported features reported
// with their counts, and the driver's frames bit-exact between the cycle
// model and the golden model.
#include "testbench/gl/gl_driver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "hw/pixel_formats.h"
#include "testbench/gl/gl_enums.h"
#include "testbench/gl/gl_primitive.h"
#include "testbench/gl/matrix_stack.h"
#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim::gl {
namespace {

TraceValue fv(double x) {
  TraceValue v;
  v.kind = TraceValue::Kind::float32;
  v.real = x;
  return v;
}
TraceValue iv(int64_t x) {
  TraceValue v;
  v.kind = TraceValue::Kind::sint;
  v.sint = x;
  return v;
}
TraceValue ev(uint32_t x) {
  TraceValue v;
  v.kind = TraceValue::Kind::enumeration;
  v.sint = x;
  return v;
}
TraceValue av(const std::vector<double>& xs) {
  TraceValue v;
  v.kind = TraceValue::Kind::array;
  for (double x : xs) v.elements.push_back(fv(x));
  return v;
}

// Feeds calls to a driver, numbering them as a trace would.
class Program {
 public:
  // Returns whether the call ended a frame.
  bool operator()(const std::string& function, std::vector<TraceValue> args = {}) {
    TraceCall c;
    c.number = m_number++;
    c.function = function;
    c.args = std::move(args);
    return driver.call(c);
  }
  // The window: apitrace's fake glViewport after make-current.
  void window(int w, int h) {
    (*this)("glXMakeCurrent", {iv(1), iv(2), iv(3)});
    (*this)("glViewport", {iv(0), iv(0), iv(w), iv(h)});
  }
  void clear() { (*this)("glClear", {ev(en::COLOR_BUFFER_BIT | en::DEPTH_BUFFER_BIT)}); }
  void vertex(float x, float y, float z = 0.0f) { (*this)("glVertex3f", {fv(x), fv(y), fv(z)}); }
  void color(float r, float g, float b) { (*this)("glColor3f", {fv(r), fv(g), fv(b)}); }
  DriverFrame swap() {
    EXPECT_TRUE((*this)("glXSwapBuffers", {iv(1), iv(2)}));
    return driver.take_frame();
  }

  GlDriver driver;

 private:
  uint32_t m_number = 0;
};

// Twice the signed area of triangle (a, b, c) in the xy plane.
float area2(const glm::vec4& a, const glm::vec4& b, const glm::vec4& c) {
  return (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
}

// The decomposition of each GL primitive, checked on counter-clockwise convex
// outlines: every triangle keeps the winding (positive area), the triangles
// tile the polygon (their areas sum to its area) and each ends with GL's
// provoking vertex (OpenGL 1.5 table 2.6: the last vertex of a quad, the first
// of a polygon).
TEST(GlPrimitive, QuadsQuadStripsAndPolygonsKeepWindingAreaAndProvokingVertex) {
  // Two unit squares side by side, as GL_QUADS (each counter-clockwise).
  const std::vector<glm::vec4> quads = {{0, 0, 0, 1}, {1, 0, 0, 1}, {1, 1, 0, 1}, {0, 1, 0, 1},
                                        {2, 0, 0, 1}, {3, 0, 0, 1}, {3, 1, 0, 1}, {2, 1, 0, 1},
                                        {9, 9, 0, 1}};  // an incomplete quad: dropped
  auto a = assemble_gl_primitive(en::QUADS, static_cast<uint32_t>(quads.size()));
  ASSERT_TRUE(a);
  EXPECT_EQ(a->type, PrimitiveType::triangles);
  ASSERT_EQ(a->indices.size(), 12u);
  for (size_t t = 0; t < 4; ++t) {
    const uint32_t* i = &a->indices[3 * t];
    EXPECT_GT(area2(quads[i[0]], quads[i[1]], quads[i[2]]), 0.0f) << t;
    EXPECT_EQ(i[2], (t / 2) * 4 + 3) << t;  // the quad's last vertex
  }
  float sum = 0.0f;
  for (size_t t = 0; t < 4; ++t) {
    const uint32_t* i = &a->indices[3 * t];
    sum += area2(quads[i[0]], quads[i[1]], quads[i[2]]);
  }
  EXPECT_FLOAT_EQ(sum, 4.0f);  // 2 unit squares, area2 = 2 each

  // A quad strip of three quads along x: pairs (bottom, top).
  std::vector<glm::vec4> strip;
  for (int i = 0; i < 4; ++i)
    strip.push_back({float(i), 0, 0, 1}), strip.push_back({float(i), 1, 0, 1});
  a = assemble_gl_primitive(en::QUAD_STRIP, static_cast<uint32_t>(strip.size()));
  ASSERT_TRUE(a);
  ASSERT_EQ(a->indices.size(), 18u);
  sum = 0.0f;
  for (size_t t = 0; t < 6; ++t) {
    const uint32_t* i = &a->indices[3 * t];
    // GL's quad strip orders quad q as (2q, 2q+1, 2q+3, 2q+2); the strip
    // above is counter-clockwise that way round, with 2q+3 provoking.
    EXPECT_LT(area2(strip[i[0]], strip[i[1]], strip[i[2]]), 0.0f)
        << "quad strip (bottom, top) pairs run clockwise in (2q, 2q+1, 2q+3, 2q+2) order";
    EXPECT_EQ(i[2], 2 * (t / 2) + 3) << t;
    sum += area2(strip[i[0]], strip[i[1]], strip[i[2]]);
  }
  EXPECT_FLOAT_EQ(sum, -6.0f);

  // A regular pentagon as GL_POLYGON.
  std::vector<glm::vec4> pentagon;
  for (int i = 0; i < 5; ++i) {
    const float t = 2.0f * static_cast<float>(M_PI) * static_cast<float>(i) / 5.0f;
    pentagon.push_back({std::cos(t), std::sin(t), 0, 1});
  }
  a = assemble_gl_primitive(en::POLYGON, 5);
  ASSERT_TRUE(a);
  ASSERT_EQ(a->indices.size(), 9u);
  sum = 0.0f;
  for (size_t t = 0; t < 3; ++t) {
    const uint32_t* i = &a->indices[3 * t];
    EXPECT_GT(area2(pentagon[i[0]], pentagon[i[1]], pentagon[i[2]]), 0.0f);
    EXPECT_EQ(i[2], 0u);
    sum += area2(pentagon[i[0]], pentagon[i[1]], pentagon[i[2]]);
  }
  // Area of a regular pentagon of circumradius 1: (5/2) sin(72 deg).
  EXPECT_NEAR(sum / 2.0f, 2.5f * std::sin(2.0f * static_cast<float>(M_PI) / 5.0f), 1e-5f);

  // Strips and fans end each triangle with its GL provoking vertex (i + 2).
  for (uint32_t mode : {en::TRIANGLE_STRIP, en::TRIANGLE_FAN}) {
    a = assemble_gl_primitive(mode, 6);
    ASSERT_TRUE(a);
    ASSERT_EQ(a->indices.size(), 12u);
    for (uint32_t t = 0; t < 4; ++t) EXPECT_EQ(a->indices[3 * t + 2], t + 2);
  }
  EXPECT_FALSE(assemble_gl_primitive(0x1234, 4));
  EXPECT_TRUE(assemble_gl_primitive(en::QUAD_STRIP, 3)->indices.empty());
}

// The rendered colour at pixel (x, y) of a golden-model frame.
glm::vec4 pixel(const golden::Result& r, int x, int y) {
  const ColorChannel* c = r.framebuffer.color_at(x, y);
  return {decode_color(r.framebuffer.color_format, c[0]),
          decode_color(r.framebuffer.color_format, c[1]),
          decode_color(r.framebuffer.color_format, c[2]),
          decode_color(r.framebuffer.color_format, c[3])};
}

void expect_color(const glm::vec4& got, const glm::vec3& want, float tolerance = 0.5f / 255.0f) {
  EXPECT_NEAR(got.r, want.r, tolerance);
  EXPECT_NEAR(got.g, want.g, tolerance);
  EXPECT_NEAR(got.b, want.b, tolerance);
}

// Flat shading takes GL's provoking vertex: a quad's fourth, a polygon's first.
TEST(GlDriver, FlatShadedQuadsAndPolygonsTakeGlsProvokingVertexColour) {
  Program gl;
  gl.window(32, 16);
  gl("glShadeModel", {ev(en::FLAT)});
  gl.clear();
  // Left half: a quad (clip space), vertex colours red, green, blue, white.
  gl("glBegin", {ev(en::QUADS)});
  gl.color(1, 0, 0), gl.vertex(-1, -1);
  gl.color(0, 1, 0), gl.vertex(0, -1);
  gl.color(0, 0, 1), gl.vertex(0, 1);
  gl.color(1, 1, 1), gl.vertex(-1, 1);
  gl("glEnd");
  // Right half: a polygon, first vertex yellow.
  gl("glBegin", {ev(en::POLYGON)});
  gl.color(1, 1, 0), gl.vertex(0, -1);
  gl.color(0, 1, 1), gl.vertex(1, -1);
  gl.color(1, 0, 1), gl.vertex(1, 1);
  gl.color(0, 0, 0), gl.vertex(0, 1);
  gl("glEnd");
  const DriverFrame f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  ASSERT_EQ(f.scene.draws.size(), 1u);  // one state, one draw
  EXPECT_EQ(f.primitives, 4u);
  const golden::Result r = golden::render(f.scene);
  for (int y : {2, 8, 13}) {
    for (int x : {2, 7, 13}) expect_color(pixel(r, x, y), {1, 1, 1});
    for (int x : {18, 24, 29}) expect_color(pixel(r, x, y), {1, 1, 0});
  }
}

// Display lists: COMPILE records without drawing, glCallList replays under the
// current matrices, COMPILE_AND_EXECUTE draws while recording, nested lists
// and glDeleteLists.
TEST(GlDriver, DisplayListsReplayTheirCallsUnderTheCurrentState) {
  Program gl;
  gl.window(16, 16);
  gl("glNewList", {iv(1), ev(en::COMPILE)});
  gl("glBegin", {ev(en::TRIANGLES)});
  gl.vertex(0, 0), gl.vertex(1, 0), gl.vertex(0, 1);
  gl("glEnd");
  gl("glEndList");
  gl("glNewList", {iv(2), ev(en::COMPILE_AND_EXECUTE)});
  gl("glCallList", {iv(1)});
  gl("glEndList");
  DriverFrame f = gl.swap();
  // Only the COMPILE_AND_EXECUTE list drew (list 1 through it).
  ASSERT_EQ(f.scene.draws.size(), 1u);
  EXPECT_EQ(f.scene.draws[0].positions.size(), 3u);

  gl.clear();
  gl("glTranslatef", {fv(5), fv(0), fv(0)});
  gl("glCallList", {iv(2)});
  gl("glLoadIdentity");
  gl("glScalef", {fv(2), fv(2), fv(2)});
  gl("glCallList", {iv(1)});
  gl("glCallList", {iv(7)});  // undefined: nothing
  gl("glDeleteLists", {iv(1), iv(1)});
  gl("glCallList", {iv(2)});  // list 2 still calls list 1, now gone: nothing
  f = gl.swap();
  ASSERT_EQ(f.scene.draws.size(), 2u);
  EXPECT_EQ(f.scene.draws[0].model_view, glm::translate(glm::mat4(1.0f), glm::vec3(5, 0, 0)));
  EXPECT_EQ(f.scene.draws[1].model_view, glm::scale(glm::mat4(1.0f), glm::vec3(2, 2, 2)));
  EXPECT_EQ(f.scene.draws[1].positions[1], glm::vec4(1, 0, 0, 1));
  EXPECT_EQ(f.vertices, 6u);
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
}

void expect_mat_near(const glm::mat4& got, const glm::mat4& want) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(got[c][r], want[c][r], 1e-5f) << c << "," << r;
  }
}

TEST(MatrixStack, OperationsMatchGlm) {
  MatrixStack s(4);
  s.translate(1, 2, 3);
  s.rotate(30, 1, 2, 2);
  s.scale(2, 3, 4);
  glm::mat4 want = glm::translate(glm::mat4(1.0f), glm::vec3(1, 2, 3));
  want = glm::rotate(want, glm::radians(30.0f), glm::normalize(glm::vec3(1, 2, 2)));
  want = glm::scale(want, glm::vec3(2, 3, 4));
  expect_mat_near(s.top(), want);

  ASSERT_TRUE(s.push());
  s.load_identity();
  s.frustum(-1, 1, -0.5f, 0.5f, 2, 50);
  expect_mat_near(s.top(), glm::frustum(-1.0f, 1.0f, -0.5f, 0.5f, 2.0f, 50.0f));
  s.load_identity();
  s.ortho(-2, 4, -1, 3, -5, 7);
  expect_mat_near(s.top(), glm::ortho(-2.0f, 4.0f, -1.0f, 3.0f, -5.0f, 7.0f));
  ASSERT_TRUE(s.pop());
  expect_mat_near(s.top(), want);
  EXPECT_FALSE(s.pop());  // underflow: unchanged
  expect_mat_near(s.top(), want);
  EXPECT_TRUE(s.push() && s.push() && s.push());
  EXPECT_FALSE(s.push());  // depth 4
  EXPECT_EQ(s.depth(), 4u);
  // A rotation about a coordinate axis is exact (no rounding in the zeros).
  MatrixStack z(2);
  z.rotate(90, 0, 0, 1);
  EXPECT_EQ(z.top()[0][2], 0.0f);
  EXPECT_EQ(z.top()[2][2], 1.0f);
  z.rotate(0, 0, 0, 0);  // a zero axis: no change
  EXPECT_NEAR(z.top()[0][1], 1.0f, 1e-7f);
}

// GL's fixed-function lighting evaluated here (OpenGL 1.5 section 2.14.1) for
// one directional light and a normal, the expected colour of a lit draw.
glm::vec3 gl_lighting(const glm::vec4& model_ambient, const glm::vec4& light_ambient,
                      const glm::vec4& light_diffuse, const glm::vec4& light_specular,
                      const glm::vec3& to_light, const glm::vec4& ambient, const glm::vec4& diffuse,
                      const glm::vec4& specular, const glm::vec4& emission, float shininess,
                      const glm::vec3& n) {
  const glm::vec3 l = glm::normalize(to_light);
  const float ndotl = std::max(glm::dot(n, l), 0.0f);
  const glm::vec3 h = glm::normalize(l + glm::vec3(0, 0, 1));
  const float spec = ndotl > 0.0f ? std::pow(std::max(glm::dot(n, h), 0.0f), shininess) : 0.0f;
  const glm::vec3 c = glm::vec3(emission) + glm::vec3(model_ambient) * glm::vec3(ambient) +
                      glm::vec3(light_ambient) * glm::vec3(ambient) +
                      glm::vec3(light_diffuse) * glm::vec3(diffuse) * ndotl +
                      glm::vec3(light_specular) * glm::vec3(specular) * spec;
  return glm::clamp(c, 0.0f, 1.0f);
}

TEST(GlDriver, LightingStateTranslatesToTheGpusLightsAndMaterials) {
  Program gl;
  gl.window(16, 16);
  // The light is placed under a modelview that rotates it: GL stores it in
  // eye space at glLight time.
  gl("glMatrixMode", {ev(en::MODELVIEW)});
  gl("glRotatef", {fv(90), fv(0), fv(1), fv(0)});  // +x of object space -> -z of eye space
  gl("glLightfv", {ev(en::LIGHT0), ev(en::POSITION), av({-1, 0, 1, 0})});
  gl("glLoadIdentity");
  gl("glLightfv", {ev(en::LIGHT0), ev(en::AMBIENT), av({0.1, 0.2, 0.3, 1})});
  gl("glLightfv", {ev(en::LIGHT0), ev(en::SPECULAR), av({0.5, 0.5, 0.5, 1})});
  gl("glLightModelfv", {ev(en::LIGHT_MODEL_AMBIENT), av({0.3, 0.1, 0.1, 1})});
  gl("glMaterialfv", {ev(en::FRONT), ev(en::SPECULAR), av({1, 1, 1, 1})});
  gl("glMaterialf", {ev(en::FRONT), ev(en::SHININESS), fv(8)});
  gl("glMaterialfv", {ev(en::FRONT_AND_BACK), ev(en::EMISSION), av({0.05, 0, 0, 1})});
  gl("glEnable", {ev(en::LIGHTING)});
  gl("glEnable", {ev(en::LIGHT0)});
  gl("glEnable", {ev(en::COLOR_MATERIAL)});  // default: GL_AMBIENT_AND_DIFFUSE
  gl.clear();
  // Two quads covering the window halves with different colours: two
  // materials, so two draws; the normal tilted towards the light.
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));
  gl("glNormal3f", {fv(n.x), fv(n.y), fv(n.z)});
  gl("glBegin", {ev(en::QUADS)});
  gl.color(0.8f, 0.4f, 0.2f);
  gl.vertex(-1, -1), gl.vertex(0, -1), gl.vertex(0, 1), gl.vertex(-1, 1);
  gl.color(0.1f, 0.6f, 0.9f);
  gl.vertex(0, -1), gl.vertex(1, -1), gl.vertex(1, 1), gl.vertex(0, 1);
  gl("glEnd");
  const DriverFrame f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  ASSERT_EQ(f.scene.lights.size(), 1u);
  const Light& l = f.scene.lights[0];
  EXPECT_EQ(l.type, LightType::directional);
  // Rotating (-1, 0, 1) by 90 degrees about y gives (1, 0, 1), normalised.
  EXPECT_NEAR(l.vector.x, std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(l.vector.y, 0.0f, 1e-6f);
  EXPECT_NEAR(l.vector.z, std::sqrt(0.5f), 1e-6f);
  EXPECT_EQ(f.scene.global_ambient, glm::vec4(0.3f, 0.1f, 0.1f, 1.0f));
  ASSERT_EQ(f.scene.draws.size(), 2u);
  EXPECT_TRUE(f.scene.draws[0].lighting);
  EXPECT_EQ(f.scene.draws[0].material.diffuse, glm::vec4(0.8f, 0.4f, 0.2f, 1.0f));
  EXPECT_EQ(f.scene.draws[1].material.ambient, glm::vec4(0.1f, 0.6f, 0.9f, 1.0f));

  const golden::Result r = golden::render(f.scene);
  const glm::vec4 la(0.1f, 0.2f, 0.3f, 1), ld(1), ls(0.5f, 0.5f, 0.5f, 1);
  const glm::vec4 spec(1), emission(0.05f, 0, 0, 1);
  const glm::vec4 left(0.8f, 0.4f, 0.2f, 1), right(0.1f, 0.6f, 0.9f, 1);
  const glm::vec3 to_light(1, 0, 1);
  expect_color(pixel(r, 4, 8),
               gl_lighting(f.scene.global_ambient, la, ld, ls, to_light, left, left, spec, emission,
                           8.0f, n),
               1.0f / 255.0f);
  expect_color(pixel(r, 12, 8),
               gl_lighting(f.scene.global_ambient, la, ld, ls, to_light, right, right, spec,
                           emission, 8.0f, n),
               1.0f / 255.0f);
}

// Two-sided lighting: back faces take the back material and the negated
// normal (OpenGL 1.5 section 2.14.1); the driver draws such calls twice, front
// faces then back faces, each pass culling the other.
TEST(GlDriver, TwoSidedLightingLightsBackFacesWithTheBackMaterial) {
  Program gl;
  gl.window(16, 8);
  gl("glLightModeli", {ev(en::LIGHT_MODEL_TWO_SIDE), iv(1)});
  gl("glMaterialfv", {ev(en::FRONT), ev(en::DIFFUSE), av({0.9, 0.1, 0.1, 1})});
  gl("glMaterialfv", {ev(en::BACK), ev(en::DIFFUSE), av({0.1, 0.7, 0.2, 1})});
  gl("glEnable", {ev(en::LIGHTING)});
  gl("glEnable", {ev(en::LIGHT0)});  // directional, towards +z (eye space)
  gl("glEnable", {ev(en::DEPTH_TEST)});
  gl.clear();
  // Both quads have the normal (0, 0, -1): lit from behind. The left quad is
  // counter-clockwise (front facing): dark. The right one is clockwise (back
  // facing): lit with the negated normal, full diffuse.
  gl("glNormal3f", {fv(0), fv(0), fv(-1)});
  gl("glBegin", {ev(en::QUADS)});
  gl.vertex(-1, -1), gl.vertex(0, -1), gl.vertex(0, 1), gl.vertex(-1, 1);
  gl.vertex(0, -1), gl.vertex(0, 1), gl.vertex(1, 1), gl.vertex(1, -1);
  gl("glEnd");
  gl("glBegin", {ev(en::QUADS)});  // the same again joins the two draws
  gl.vertex(-1, -1), gl.vertex(0, -1), gl.vertex(0, 1), gl.vertex(-1, 1);
  gl("glEnd");
  const DriverFrame f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  ASSERT_EQ(f.scene.draws.size(), 2u);
  EXPECT_EQ(f.scene.draws[0].state.cull, CullMode::back);
  EXPECT_EQ(f.scene.draws[1].state.cull, CullMode::front);
  EXPECT_EQ(f.primitives, 6u);
  const golden::Result r = golden::render(f.scene);
  const glm::vec4 ambient(0.2f, 0.2f, 0.2f, 1), none(0, 0, 0, 1), white(1);
  const glm::vec4 front_diffuse(0.9f, 0.1f, 0.1f, 1), back_diffuse(0.1f, 0.7f, 0.2f, 1);
  expect_color(pixel(r, 4, 4),
               gl_lighting(ambient, none, white, white, {0, 0, 1}, ambient, front_diffuse, none,
                           none, 0.0f, {0, 0, -1}),
               1.0f / 255.0f);
  expect_color(pixel(r, 12, 4),
               gl_lighting(ambient, none, white, white, {0, 0, 1}, ambient, back_diffuse, none,
                           none, 0.0f, {0, 0, 1}),
               1.0f / 255.0f);
}

// With GL_COLOR_MATERIAL on, the tracked properties follow the current colour
// even after a glMaterial of them; the others follow glMaterial.
TEST(GlDriver, ColorMaterialTracksTheCurrentColourOverGlMaterial) {
  Program gl;
  gl.window(8, 8);
  gl("glColorMaterial", {ev(en::FRONT), ev(en::DIFFUSE)});
  gl("glEnable", {ev(en::COLOR_MATERIAL)});
  gl("glEnable", {ev(en::LIGHTING)});
  gl("glEnable", {ev(en::NORMALIZE)});
  gl.clear();
  gl.color(0.5f, 0.25f, 1.0f);
  gl("glMaterialfv", {ev(en::FRONT), ev(en::DIFFUSE), av({0, 1, 0, 1})});        // tracked
  gl("glMaterialfv", {ev(en::FRONT), ev(en::AMBIENT), av({0.1, 0.2, 0.3, 1})});  // not
  gl("glBegin", {ev(en::TRIANGLES)});
  gl.vertex(0, 0), gl.vertex(1, 0), gl.vertex(0, 1);
  gl("glEnd");
  const DriverFrame f = gl.swap();
  ASSERT_EQ(f.scene.draws.size(), 1u);
  EXPECT_EQ(f.scene.draws[0].material.diffuse, glm::vec4(0.5f, 0.25f, 1.0f, 1.0f));
  EXPECT_EQ(f.scene.draws[0].material.ambient, glm::vec4(0.1f, 0.2f, 0.3f, 1.0f));
}

// GL_NORMALIZE off: GL lights with the eye-space normal as the modelview left
// it (here twice as long, a scale of 0.5 along z); the driver folds the length
// into the material. Lengths differing within a smooth primitive are reported.
TEST(GlDriver, UnnormalizedNormalsScaleTheDiffuseTerm) {
  Program gl;
  gl.window(8, 8);
  gl("glLightfv", {ev(en::LIGHT0), ev(en::DIFFUSE), av({0.3, 0.3, 0.3, 1})});
  gl("glMaterialfv", {ev(en::FRONT), ev(en::DIFFUSE), av({0.4, 0.2, 0.1, 1})});
  gl("glEnable", {ev(en::LIGHTING)});
  gl("glEnable", {ev(en::LIGHT0)});  // directional, towards +z
  gl.clear();
  gl("glScalef", {fv(1), fv(1), fv(0.5)});
  gl("glNormal3f", {fv(0), fv(0), fv(1)});
  gl("glBegin", {ev(en::QUADS)});
  gl.vertex(-1, -1), gl.vertex(1, -1), gl.vertex(1, 1), gl.vertex(-1, 1);
  gl("glEnd");
  DriverFrame f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  const golden::Result r = golden::render(f.scene);
  const glm::vec4 ambient(0.2f, 0.2f, 0.2f, 1), none(0, 0, 0, 1), light(0.3f, 0.3f, 0.3f, 1);
  expect_color(pixel(r, 4, 4),
               gl_lighting(ambient, none, light, glm::vec4(1), {0, 0, 1}, ambient,
                           {0.4f, 0.2f, 0.1f, 1}, none, none, 0.0f, {0, 0, 2}),
               1.0f / 255.0f);

  gl.clear();
  gl("glBegin", {ev(en::TRIANGLES)});
  gl("glNormal3f", {fv(0), fv(0), fv(1)}), gl.vertex(-1, -1);
  gl("glNormal3f", {fv(1), fv(0), fv(0)}), gl.vertex(1, -1);  // length 1 in eye space
  gl.vertex(1, 1);
  gl("glEnd");
  f = gl.swap();
  EXPECT_EQ(f.features.unsupported().at(
                "normals of different eye-space lengths within a primitive with GL_NORMALIZE off"),
            1u);
}

TEST(GlDriver, PointLightsCarryEyeSpacePositionAndAttenuation) {
  Program gl;
  gl.window(8, 8);
  gl("glTranslatef", {fv(0), fv(0), fv(-10)});
  gl("glLightfv", {ev(en::LIGHT0 + 1), ev(en::POSITION), av({2, 4, 6, 2})});
  gl("glLightf", {ev(en::LIGHT0 + 1), ev(en::LINEAR_ATTENUATION), fv(0.5)});
  gl("glEnable", {ev(en::LIGHTING)});
  gl("glEnable", {ev(en::LIGHT0 + 1)});
  gl.clear();
  gl("glBegin", {ev(en::TRIANGLES)});
  gl.vertex(0, 0), gl.vertex(1, 0), gl.vertex(0, 1);
  gl("glEnd");
  const DriverFrame f = gl.swap();
  ASSERT_EQ(f.scene.lights.size(), 1u);
  const Light& l = f.scene.lights[0];
  EXPECT_EQ(l.type, LightType::point);
  // (2, 4, 6, 2) translated by (0, 0, -10) w-scaled: (2, 4, 6 - 20, 2) / 2.
  EXPECT_EQ(l.vector, glm::vec3(1, 2, -7));
  EXPECT_EQ(l.linear_attenuation, 0.5f);
  EXPECT_EQ(l.diffuse, glm::vec4(0, 0, 0, 1));  // GL_LIGHT1's default
}

TEST(GlDriver, BatchesGeometryWithTheSameStateIntoOneDraw) {
  Program gl;
  gl.window(8, 8);
  gl.clear();
  for (int k = 0; k < 3; ++k) {
    gl("glBegin", {ev(en::TRIANGLE_STRIP)});
    gl.color(0.1f * static_cast<float>(k), 0, 0);  // unlit: colours are per vertex
    gl.vertex(0, 0), gl.vertex(1, 0), gl.vertex(0, 1), gl.vertex(1, 1);
    gl("glEnd");
  }
  gl("glRotatef", {fv(10), fv(0), fv(0), fv(1)});
  gl("glBegin", {ev(en::LINES)});
  gl.vertex(0, 0), gl.vertex(1, 1);
  gl("glEnd");
  gl("glBegin", {ev(en::LINE_STRIP)});
  gl.vertex(0, 0), gl.vertex(1, 1), gl.vertex(1, 0);
  gl("glEnd");
  const DriverFrame f = gl.swap();
  ASSERT_EQ(f.scene.draws.size(), 3u);
  EXPECT_EQ(f.scene.draws[0].primitive, PrimitiveType::triangles);
  EXPECT_EQ(f.scene.draws[0].indices.size(), 18u);  // 3 strips of 2 triangles
  EXPECT_EQ(f.scene.draws[0].positions.size(), 12u);
  EXPECT_EQ(f.scene.draws[1].primitive, PrimitiveType::lines);
  EXPECT_EQ(f.scene.draws[2].primitive, PrimitiveType::line_strip);
  EXPECT_TRUE(f.scene.draws[2].indices.empty());
  EXPECT_EQ(f.scene.draws[2].positions.size(), 3u);
  EXPECT_EQ(f.vertices, 17u);
  EXPECT_EQ(f.primitives, 6u + 1u + 2u);
}

TEST(GlDriver, ReportsUnsupportedFeaturesWithTheirCounts) {
  Program gl;
  gl.window(8, 8);
  gl.clear();
  gl("glFogf", {ev(0x0B65), fv(1)});
  TraceCall fog;
  fog.function = "glEnable";
  fog.args = {ev(0x0B60)};
  fog.args[0].name = "GL_FOG";
  gl.driver.call(fog);
  gl("glLightModeli", {ev(en::LIGHT_MODEL_LOCAL_VIEWER), iv(1)});
  gl("glEnable", {ev(en::LIGHTING)});
  gl("glEnable", {ev(en::NORMALIZE)});
  for (int k = 0; k < 2; ++k) {
    gl("glBegin", {ev(en::TRIANGLES)});
    gl("glTexCoord2f", {fv(0), fv(0)});
    gl.vertex(0, 0), gl.vertex(1, 0), gl.vertex(0, 1);
    gl("glEnd");
  }
  // A matrix read back by the program: the driver's equals it, then does not.
  gl("glTranslatef", {fv(1), fv(2), fv(3)});
  const std::vector<double> translated = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 2, 3, 1};
  gl("glGetFloatv", {ev(en::MODELVIEW_MATRIX), av(translated)});
  std::vector<double> other = translated;
  other[13] = 2.01;
  gl("glGetFloatv", {ev(en::MODELVIEW_MATRIX), av(other)});
  gl("glFrobnicateSGIX", {iv(1)});
  gl("glFrobnicateSGIX", {iv(2)});
  // A clear inside a scissor box: GL clears the box only, the GPU's clears
  // the whole buffer.
  gl("glEnable", {ev(en::SCISSOR_TEST)});
  gl("glScissor", {iv(0), iv(0), iv(4), iv(4)});
  gl.clear();
  gl("glDisable", {ev(en::SCISSOR_TEST)});
  DriverFrame f = gl.swap();
  const auto& u = f.features.unsupported();
  EXPECT_EQ(u.at("GL_FOG enabled while drawing"), 2u);
  EXPECT_EQ(u.at("GL_LIGHT_MODEL_LOCAL_VIEWER"), 2u);
  EXPECT_EQ(u.at("glFrobnicateSGIX"), 2u);
  EXPECT_EQ(u.at("glClear inside a scissor box smaller than the window"), 1u);
  EXPECT_EQ(u.at("driver matrix differs from the program's glGet of GL_MODELVIEW_MATRIX"), 1u);
  EXPECT_EQ(u.size(), 5u) << f.to_json().dump();
  EXPECT_EQ(f.features.ignored().at("glTexCoord* (texturing off)"), 2u);
  EXPECT_TRUE(f.to_json()["unsupported_used"].get<bool>());

  // The next frame without fog is clean again.
  gl("glDisable", {ev(0x0B60)});
  gl("glDisable", {ev(en::LIGHTING)});
  gl.clear();
  gl("glBegin", {ev(en::POINTS)});
  gl.vertex(0, 0);
  gl("glEnd");
  f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  EXPECT_EQ(f.index, 1u);
}

// The stored depth of pixel (x, y) of a golden-model frame.
DepthValue depth(const golden::Result& r, int x, int y) {
  return r.framebuffer.depth[r.framebuffer.sample_index(x, y, 0)];
}

// A quad over all of clip space at NDC depth z, in the current colour.
void full_quad(Program& gl, float z) {
  gl("glBegin", {ev(en::QUADS)});
  gl.vertex(-1, -1, z), gl.vertex(1, -1, z), gl.vertex(1, 1, z), gl.vertex(-1, 1, z);
  gl("glEnd");
}

// glViewport after the window's, glDepthRange and glScissor become the
// draws' viewport, depth range and scissor; the frame renders as GL's rules
// say: NDC [-1, 1] maps onto the viewport, z_w = n + (z + 1) / 2 * (f - n),
// and only pixels inside the scissor box are written.
TEST(GlDriver, ViewportDepthRangeAndScissorFollowGlsRules) {
  Program gl;
  gl.window(32, 16);
  gl("glClearColor", {fv(0), fv(0), fv(0), fv(1)});
  gl.clear();
  gl("glEnable", {ev(en::DEPTH_TEST)});
  gl("glDepthFunc", {ev(en::ALWAYS)});
  // The right half, depth range [0.2, 0.6]: NDC z 0.5 lands at 0.5.
  gl("glViewport", {iv(16), iv(0), iv(16), iv(16)});
  gl("glDepthRange", {fv(0.2), fv(0.6)});
  gl.color(1, 0, 0);
  full_quad(gl, 0.5f);
  // The whole window again, GL clamping the depth range to [0, 1]; the
  // scissor box (4, 2) 8 x 6 limits a green quad at NDC z -1 (window z 0).
  gl("glViewport", {iv(0), iv(0), iv(32), iv(16)});
  gl("glDepthRange", {fv(-1), fv(2)});
  gl("glEnable", {ev(en::SCISSOR_TEST)});
  gl("glScissor", {iv(4), iv(2), iv(8), iv(6)});
  gl.color(0, 1, 0);
  full_quad(gl, -1.0f);
  // A box reaching past the window is cut to it; an empty one draws nothing.
  gl("glScissor", {iv(-5), iv(-5), iv(7), iv(100)});
  gl.color(0, 0, 1);
  full_quad(gl, -1.0f);
  gl("glScissor", {iv(40), iv(0), iv(8), iv(8)});
  gl.color(1, 1, 1);
  full_quad(gl, -1.0f);
  // A box covering the window is no scissor at all.
  gl("glScissor", {iv(0), iv(0), iv(32), iv(16)});
  gl("glViewport", {iv(0), iv(0), iv(0), iv(16)});  // empty viewport: nothing drawn
  full_quad(gl, -1.0f);
  const DriverFrame f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  ASSERT_EQ(f.scene.draws.size(), 3u);
  const RenderState& a = f.scene.draws[0].state;
  ASSERT_TRUE(a.viewport);
  EXPECT_EQ(*a.viewport, (PixelRect{16, 0, 16, 16}));
  EXPECT_EQ(a.depth_near, 0.2f);
  EXPECT_EQ(a.depth_far, 0.6f);
  EXPECT_FALSE(a.scissor);
  const RenderState& b = f.scene.draws[1].state;
  EXPECT_FALSE(b.viewport);  // the whole window
  EXPECT_EQ(b.depth_near, 0.0f);
  EXPECT_EQ(b.depth_far, 1.0f);
  ASSERT_TRUE(b.scissor);
  EXPECT_EQ(*b.scissor, (PixelRect{4, 2, 8, 6}));
  ASSERT_TRUE(f.scene.draws[2].state.scissor);
  EXPECT_EQ(*f.scene.draws[2].state.scissor, (PixelRect{0, 0, 2, 16}));

  const golden::Result r = golden::render(f.scene);
  const DepthFormat df = r.framebuffer.depth_format;
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 32; ++x) {
      const bool blue = x < 2, green = x >= 4 && x < 12 && y >= 2 && y < 8, red = x >= 16;
      const glm::vec3 want = blue    ? glm::vec3(0, 0, 1)
                             : green ? glm::vec3(0, 1, 0)
                             : red   ? glm::vec3(1, 0, 0)
                                     : glm::vec3(0, 0, 0);
      expect_color(pixel(r, x, y), want);
      const float z = blue || green ? 0.0f : red ? 0.5f : 1.0f;
      EXPECT_EQ(depth(r, x, y), encode_depth(df, z)) << x << ", " << y;
    }
  }
}

// glClear after a draw is a clear in the draw list at its place: draws
// before it are overwritten, its depth (or kept depth) decides later draws,
// and later geometry does not join a draw from before it.
TEST(GlDriver, ClearsAfterDrawsExecuteAtTheirPlace) {
  Program gl;
  gl.window(16, 8);
  gl("glClearColor", {fv(1), fv(0), fv(0), fv(1)});
  gl.clear();
  gl("glEnable", {ev(en::DEPTH_TEST)});
  gl.color(0, 0, 1);
  full_quad(gl, 0.0f);  // blue, window z 0.5 everywhere
  gl("glClearColor", {fv(0), fv(1), fv(0), fv(1)});
  gl("glClear", {ev(en::COLOR_BUFFER_BIT)});  // green; the depth 0.5 stays
  gl.color(0, 0, 1);    // the same state as the blue quad: a new draw all the same
  full_quad(gl, 0.5f);  // z 0.75 fails GL_LESS against 0.5: stays green
  gl("glClearDepth", {fv(1)});
  // With the colour mask shut, GL's glClear clears the depth buffer only.
  gl("glColorMask", {iv(0), iv(0), iv(0), iv(0)});
  gl("glClear", {ev(en::COLOR_BUFFER_BIT | en::DEPTH_BUFFER_BIT)});
  gl("glColorMask", {iv(1), iv(1), iv(1), iv(1)});
  // With the depth mask shut, a depth clear clears nothing.
  gl("glDepthMask", {iv(0)});
  gl("glClearDepth", {fv(0)});
  gl("glClear", {ev(en::DEPTH_BUFFER_BIT)});
  gl("glDepthMask", {iv(1)});
  // Right half: passes against the cleared depth 1.
  gl.color(1, 1, 1);
  gl("glBegin", {ev(en::QUADS)});
  gl.vertex(0, -1, 0.5f), gl.vertex(1, -1, 0.5f), gl.vertex(1, 1, 0.5f), gl.vertex(0, 1, 0.5f);
  gl("glEnd");
  const DriverFrame f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  ASSERT_EQ(f.scene.draws.size(), 3u);
  ASSERT_EQ(f.scene.clears.size(), 2u);
  ClearState green;
  green.color = true;
  green.color_value = {0, 1, 0, 1};
  green.before_draw = 1;
  EXPECT_EQ(f.scene.clears[0], green);
  ClearState depth_only;
  depth_only.depth = true;
  depth_only.depth_value = 1.0f;
  depth_only.before_draw = 2;
  EXPECT_EQ(f.scene.clears[1], depth_only);

  const golden::Result r = golden::render(f.scene);
  const DepthFormat df = r.framebuffer.depth_format;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 16; ++x) {
      expect_color(pixel(r, x, y), x < 8 ? glm::vec3(0, 1, 0) : glm::vec3(1, 1, 1));
      EXPECT_EQ(depth(r, x, y), encode_depth(df, x < 8 ? 1.0f : 0.75f)) << x << ", " << y;
    }
  }
  const nlohmann::json c = r.stats.to_json();
  EXPECT_EQ(c.value("color_clears", 0), 2);  // the frame clear and the green one
  EXPECT_EQ(c.value("depth_clears", 0), 2);
}

// What the GPU's whole-buffer clears and viewport bound cannot express is
// reported, never drawn silently wrong.
TEST(GlDriver, ReportsClearsAndViewportsTheGpuCannotExpress) {
  Program gl;
  gl.window(16, 8);
  gl.clear();
  gl("glColorMask", {iv(1), iv(0), iv(1), iv(1)});
  gl.clear();  // a partial colour mask
  gl("glColorMask", {iv(1), iv(1), iv(1), iv(1)});
  gl("glEnable", {ev(en::SCISSOR_TEST)});
  gl("glScissor", {iv(100), iv(0), iv(4), iv(4)});
  gl.clear();  // the box misses the window: GL clears nothing, exactly
  gl("glDisable", {ev(en::SCISSOR_TEST)});
  gl("glViewport", {iv(0), iv(0), iv(8), iv(8)});
  gl("glLineWidth", {fv(3)});
  gl("glBegin", {ev(en::LINES)});
  gl.vertex(-1, 0), gl.vertex(1, 0);  // thin lines would be exact; wide ones reach past
  gl("glEnd");
  gl("glLineWidth", {fv(1)});
  gl("glBegin", {ev(en::LINES)});
  gl.vertex(-1, 0.5f), gl.vertex(1, 0.5f);
  gl("glEnd");
  gl("glShadeModel", {ev(en::FLAT)});
  gl("glProvokingVertex", {ev(en::FIRST_VERTEX_CONVENTION)});
  gl("glBegin", {ev(en::TRIANGLES)});
  gl.vertex(-1, -1), gl.vertex(1, -1), gl.vertex(0, 1);
  gl("glEnd");
  gl("glShadeModel", {ev(en::SMOOTH)});  // the provoking vertex no longer matters
  gl("glBegin", {ev(en::TRIANGLES)});
  gl.vertex(-1, -1), gl.vertex(1, -1), gl.vertex(0, 1);
  gl("glEnd");
  gl("glViewport", {iv(-4), iv(-4), iv(20000), iv(8)});
  gl("glBegin", {ev(en::TRIANGLES)});
  gl.vertex(-1, -1), gl.vertex(1, -1), gl.vertex(0, 1);
  gl("glEnd");
  const DriverFrame f = gl.swap();
  const auto& u = f.features.unsupported();
  EXPECT_EQ(u.at("glClear with a glColorMask other than all or none"), 1u);
  EXPECT_EQ(u.at("wide lines or points larger than 1 with a glViewport smaller than the window"),
            1u);
  EXPECT_EQ(u.at("glProvokingVertex(GL_FIRST_VERTEX_CONVENTION) with flat shading"), 1u);
  EXPECT_EQ(u.at("glViewport reaching beyond 16384 pixels from the window's origin"), 1u);
  EXPECT_EQ(u.size(), 4u) << f.to_json().dump();
}

// A malformed call is bad input: one line naming the call, InputError.
TEST(GlDriver, MalformedCallsAreInputErrorsNamingTheCall) {
  Program gl;
  gl.window(8, 8);
  gl("glBegin", {ev(en::TRIANGLES)});
  try {
    gl("glVertex3f", {fv(1), fv(2)});  // the call number is 3
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "call 3 glVertex3f: argument 3 is missing");
  }
  TraceValue text;
  text.kind = TraceValue::Kind::string;
  text.bytes = "x";
  EXPECT_THROW(gl("glLineWidth", {text}), InputError);
  EXPECT_THROW(gl("glLightfv", {ev(en::LIGHT0), ev(en::DIFFUSE), av({1, 1})}), InputError);
}

TEST(GlDriver, ClientArraysDrawAsTheirElements) {
  Program gl;
  gl.window(8, 8);
  gl.clear();
  // Three float positions and unsigned-byte colours, as apitrace records
  // client memory: blobs.
  const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint8_t col[] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 51, 255};
  TraceValue pblob, cblob;
  pblob.kind = cblob.kind = TraceValue::Kind::blob;
  pblob.bytes.assign(reinterpret_cast<const char*>(pos), sizeof pos);
  cblob.bytes.assign(reinterpret_cast<const char*>(col), sizeof col);
  gl("glEnableClientState", {ev(en::VERTEX_ARRAY)});
  gl("glEnableClientState", {ev(en::COLOR_ARRAY)});
  gl("glVertexPointer", {iv(3), ev(en::FLOAT), iv(0), pblob});
  gl("glColorPointer", {iv(4), ev(en::UNSIGNED_BYTE), iv(0), cblob});
  TraceValue ind;
  ind.kind = TraceValue::Kind::blob;
  const uint16_t idx[] = {2, 1, 0};
  ind.bytes.assign(reinterpret_cast<const char*>(idx), sizeof idx);
  gl("glDrawElements", {ev(en::TRIANGLES), iv(3), ev(en::UNSIGNED_SHORT), ind});
  const DriverFrame f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  ASSERT_EQ(f.scene.draws.size(), 1u);
  const Draw& d = f.scene.draws[0];
  ASSERT_EQ(d.positions.size(), 3u);
  EXPECT_EQ(d.positions[0], glm::vec4(0, 1, 0, 1));  // element 2 first
  EXPECT_EQ(d.colors[0], glm::vec4(0, 0, 0.2f, 1));  // 51 / 255
  EXPECT_EQ(d.colors[2], glm::vec4(1, 0, 0, 1));
}

// A driver frame like glxgears' (lit, flat and smooth quad strips and quads,
// culling, depth test) plus lit lines and points, 48 x 40.
Scene gears_like_frame() {
  Program gl;
  gl.window(48, 40);
  gl("glLightfv", {ev(en::LIGHT0), ev(en::POSITION), av({5, 5, 10, 0})});
  gl("glEnable", {ev(en::CULL_FACE)});
  gl("glEnable", {ev(en::LIGHTING)});
  gl("glEnable", {ev(en::LIGHT0)});
  gl("glEnable", {ev(en::DEPTH_TEST)});
  gl("glEnable", {ev(en::NORMALIZE)});
  gl("glMatrixMode", {ev(en::PROJECTION)});
  gl("glFrustum", {fv(-1), fv(1), fv(-0.8), fv(0.8), fv(5), fv(60)});
  gl("glMatrixMode", {ev(en::MODELVIEW)});
  gl("glTranslatef", {fv(0), fv(0), fv(-20)});
  gl("glRotatef", {fv(25), fv(1), fv(0.5), fv(0)});
  gl("glClearColor", {fv(0.1), fv(0.1), fv(0.2), fv(1)});
  gl.clear();
  gl("glMaterialfv", {ev(en::FRONT), ev(en::AMBIENT_AND_DIFFUSE), av({0.8, 0.1, 0, 1})});
  gl("glShadeModel", {ev(en::FLAT)});
  gl("glNormal3f", {fv(0), fv(0), fv(1)});
  gl("glBegin", {ev(en::QUAD_STRIP)});
  for (int i = 0; i <= 12; ++i) {
    const float t = 2.0f * static_cast<float>(M_PI) * static_cast<float>(i) / 12.0f;
    gl.vertex(std::cos(t), std::sin(t), 0.5f);
    gl.vertex(3.5f * std::cos(t), 3.5f * std::sin(t), 0.5f);
  }
  gl("glEnd");
  gl("glShadeModel", {ev(en::SMOOTH)});
  gl("glBegin", {ev(en::QUAD_STRIP)});
  for (int i = 0; i <= 12; ++i) {
    const float t = 2.0f * static_cast<float>(M_PI) * static_cast<float>(i) / 12.0f;
    gl("glNormal3f", {fv(-std::cos(t)), fv(-std::sin(t)), fv(0)});
    gl.vertex(std::cos(t), std::sin(t), -0.5f);
    gl.vertex(std::cos(t), std::sin(t), 0.5f);
  }
  gl("glEnd");
  gl("glLineWidth", {fv(3)});
  gl("glBegin", {ev(en::LINE_LOOP)});
  gl.vertex(-4, -3, 1), gl.vertex(4, -3, 1), gl.vertex(4, 3, 1);
  gl("glEnd");
  gl("glPointSize", {fv(4)});
  gl("glBegin", {ev(en::POINTS)});
  gl.vertex(-4, 3, 1), gl.vertex(0, 0, 2);
  gl("glEnd");
  DriverFrame f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  EXPECT_EQ(f.scene.draws.size(), 4u);
  return std::move(f.scene);
}

// A frame using the window state: two viewports (a split screen), a depth
// range, a scissor box and clears between draws, lit and unlit, 40 x 32.
Scene window_state_frame() {
  Program gl;
  gl.window(40, 32);
  gl("glLightfv", {ev(en::LIGHT0), ev(en::POSITION), av({1, 2, 3, 0})});
  gl("glEnable", {ev(en::LIGHT0)});
  gl("glEnable", {ev(en::DEPTH_TEST)});
  gl("glMatrixMode", {ev(en::PROJECTION)});
  gl("glFrustum", {fv(-1), fv(1), fv(-1), fv(1), fv(2), fv(20)});
  gl("glMatrixMode", {ev(en::MODELVIEW)});
  gl("glTranslatef", {fv(0), fv(0), fv(-6)});
  gl("glRotatef", {fv(30), fv(1), fv(1), fv(0)});
  gl("glClearColor", {fv(0.2), fv(0.2), fv(0.3), fv(1)});
  gl.clear();
  for (int half = 0; half < 2; ++half) {
    gl("glViewport", {iv(half * 20), iv(0), iv(20), iv(32)});
    gl("glDepthRange", {fv(half ? 0.3 : 0.0), fv(half ? 0.9 : 1.0)});
    if (half) gl("glEnable", {ev(en::LIGHTING)});
    gl("glBegin", {ev(en::QUAD_STRIP)});
    for (int i = 0; i <= 10; ++i) {
      const float t = 2.0f * static_cast<float>(M_PI) * static_cast<float>(i) / 10.0f;
      gl("glNormal3f", {fv(std::cos(t)), fv(std::sin(t)), fv(0)});
      gl.color(0.5f + 0.5f * std::cos(t), 0.5f, 0.5f + 0.5f * std::sin(t));
      gl.vertex(std::cos(t), std::sin(t), -1.2f), gl.vertex(std::cos(t), std::sin(t), 1.2f);
    }
    gl("glEnd");
    // Between the halves: the depth buffer only, then the colour of a band.
    if (!half) gl("glClear", {ev(en::DEPTH_BUFFER_BIT)});
  }
  gl("glDisable", {ev(en::LIGHTING)});
  gl("glViewport", {iv(0), iv(0), iv(40), iv(32)});
  gl("glDepthRange", {fv(0), fv(1)});
  gl("glEnable", {ev(en::SCISSOR_TEST)});
  gl("glScissor", {iv(6), iv(4), iv(28), iv(10)});
  gl.color(1, 1, 0);
  gl("glBegin", {ev(en::TRIANGLES)});
  gl.vertex(-2, -2, 0), gl.vertex(2, -2, 0), gl.vertex(0, 2, 0);
  gl("glEnd");
  gl("glDisable", {ev(en::SCISSOR_TEST)});
  gl("glClearColor", {fv(0), fv(0), fv(0), fv(1)});
  gl("glClear", {ev(en::COLOR_BUFFER_BIT)});  // the depths stay and test what follows
  gl("glPointSize", {fv(3)});
  gl("glBegin", {ev(en::POINTS)});
  for (int i = 0; i < 8; ++i) gl.vertex(-1.5f + 0.4f * static_cast<float>(i), 0.1f, 0.5f);
  gl("glEnd");
  DriverFrame f = gl.swap();
  EXPECT_FALSE(f.features.any_unsupported()) << f.to_json().dump();
  EXPECT_EQ(f.scene.clears.size(), 2u);
  return std::move(f.scene);
}

class DriverBitExact : public ::testing::TestWithParam<int> {};

// The driver's frames go through both models like any scene: bit-exact under
// the configuration rows of sim_bitexact_test (units, FIFO depth, tile, stamp).
TEST_P(DriverBitExact, CycleModelEqualsGolden) {
  const int row = GetParam() % 18;
  const bool window_state = GetParam() >= 18;
  const Scene scene = window_state ? window_state_frame() : gears_like_frame();
  const unsigned units[] = {1, 2, 3, 4, 8, 16}, depths[] = {1, 2, 16}, tiles[] = {8, 16, 64},
                 stamps[] = {2, 4, 8};
  const int i = row / 3, j = row % 3;
  GpuConfig config;
  config.units = units[i];
  config.fifo_depth = depths[j];
  config.tile_size = tiles[(i + j) % 3];
  config.stamp = {stamps[(i + 2 * j) % 3], stamps[(i + 2 * j) % 3]};
  GpuRunOptions options;
  options.record_last_writer = true;
  const GpuRunResult got = run_gpu(scene, config, options);
  const golden::Result want = golden::render(scene);
  ASSERT_EQ(got.framebuffer.color, want.framebuffer.color);
  ASSERT_EQ(got.framebuffer.depth, want.framebuffer.depth);
  EXPECT_EQ(got.counts, want.stats);
  EXPECT_EQ(got.last_writer, want.last_writer);
  // Something of every kind was drawn.
  const nlohmann::json c = want.stats.to_json();
  EXPECT_GT(c.value("triangles_rasterized", 0), 0);
  EXPECT_GT(c.value("points_in", 0), 0);
  if (window_state) {
    EXPECT_EQ(c.value("color_clears", 0), 2);
    EXPECT_EQ(c.value("depth_clears", 0), 2);
  } else {
    EXPECT_GT(c.value("lines_in", 0), 0);
  }
}

// Rows 0-17: the gears-like frame; 18-35: the window-state frame.
INSTANTIATE_TEST_SUITE_P(Rows, DriverBitExact, ::testing::Range(0, 36));

}  // namespace
}  // namespace gpusim::gl
