#include "testbench/gl/gl_driver.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <optional>
#include <set>
#include <unordered_map>
#include <vector>

#include "hw/input_error.h"
#include "testbench/gl/gl_enums.h"
#include "testbench/gl/gl_primitive.h"
#include "testbench/gl/matrix_stack.h"

namespace gpusim::gl {
namespace {

constexpr int kMaxLights = 8;
constexpr int kMaxListNesting = 64;  // GL_MAX_LIST_NESTING

[[noreturn]] void bad_call(const TraceCall& c, const std::string& what) {
  throw InputError("call " + std::to_string(c.number) + " " + c.function + ": " + what);
}

const TraceValue& arg(const TraceCall& c, size_t i) {
  if (i >= c.args.size()) bad_call(c, "argument " + std::to_string(i + 1) + " is missing");
  return c.args[i];
}

// A scalar argument as a number, whatever type apitrace recorded it with.
double number(const TraceCall& c, const TraceValue& v) {
  switch (v.kind) {
    case TraceValue::Kind::boolean:
    case TraceValue::Kind::sint:
    case TraceValue::Kind::enumeration:
      return static_cast<double>(v.sint);
    case TraceValue::Kind::uint:
    case TraceValue::Kind::bitmask:
    case TraceValue::Kind::pointer:
      return static_cast<double>(v.uint);
    case TraceValue::Kind::float32:
    case TraceValue::Kind::float64:
      return v.real;
    case TraceValue::Kind::repr:
      if (!v.elements.empty()) return number(c, v.elements[0]);
      break;
    default:
      break;
  }
  bad_call(c, "an argument is not a number");
}

double num_arg(const TraceCall& c, size_t i) {
  return number(c, arg(c, i));
}
float float_arg(const TraceCall& c, size_t i) {
  return static_cast<float>(num_arg(c, i));
}
int64_t int_arg(const TraceCall& c, size_t i) {
  const TraceValue& v = arg(c, i);
  if (v.kind == TraceValue::Kind::uint || v.kind == TraceValue::Kind::bitmask ||
      v.kind == TraceValue::Kind::pointer) {
    return static_cast<int64_t>(v.uint);
  }
  if (v.kind == TraceValue::Kind::float32 || v.kind == TraceValue::Kind::float64) {
    return static_cast<int64_t>(v.real);
  }
  return static_cast<int64_t>(number(c, v));
}
uint32_t enum_arg(const TraceCall& c, size_t i) {
  return static_cast<uint32_t>(int_arg(c, i));
}

// The numbers of an array argument (glLightfv's params, glMultMatrixf's m); a
// scalar counts as an array of one.
std::vector<double> numbers(const TraceCall& c, size_t i) {
  const TraceValue& v = arg(c, i);
  std::vector<double> out;
  if (v.kind == TraceValue::Kind::array) {
    for (const TraceValue& e : v.elements) out.push_back(number(c, e));
  } else {
    out.push_back(number(c, v));
  }
  return out;
}

std::vector<double> numbers_at_least(const TraceCall& c, size_t i, size_t n) {
  std::vector<double> v = numbers(c, i);
  if (v.size() < n) {
    bad_call(c, "argument " + std::to_string(i + 1) + " holds " + std::to_string(v.size()) +
                    " values, expected " + std::to_string(n));
  }
  return v;
}

glm::vec4 vec4_of(const std::vector<double>& v) {
  return glm::vec4(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]),
                   static_cast<float>(v[3]));
}

// GL's conversion of a signed or unsigned integer colour or normal component
// to float (OpenGL 1.5, table 2.9): unsigned c / (2^b - 1), signed
// (2c + 1) / (2^b - 1).
float normalized(char type, double c) {
  switch (type) {
    case 'B':  // ub
      return static_cast<float>(c / 255.0);
    case 'S':  // us
      return static_cast<float>(c / 65535.0);
    case 'U':  // ui
      return static_cast<float>(c / 4294967295.0);
    case 'b':
      return static_cast<float>((2.0 * c + 1.0) / 255.0);
    case 's':
      return static_cast<float>((2.0 * c + 1.0) / 65535.0);
    case 'i':
      return static_cast<float>((2.0 * c + 1.0) / 4294967295.0);
    default:  // f, d
      return static_cast<float>(c);
  }
}

std::optional<CompareFunc> compare_func(uint32_t f) {
  if (f < en::NEVER || f > en::ALWAYS) return std::nullopt;
  static const CompareFunc funcs[] = {
      CompareFunc::never,   CompareFunc::less,     CompareFunc::equal,  CompareFunc::lequal,
      CompareFunc::greater, CompareFunc::notequal, CompareFunc::gequal, CompareFunc::always};
  return funcs[f - en::NEVER];
}

std::optional<BlendFactor> blend_factor(uint32_t f) {
  switch (f) {
    case en::ZERO:
      return BlendFactor::zero;
    case en::ONE:
      return BlendFactor::one;
    case en::SRC_COLOR:
      return BlendFactor::src_color;
    case en::ONE_MINUS_SRC_COLOR:
      return BlendFactor::one_minus_src_color;
    case en::DST_COLOR:
      return BlendFactor::dst_color;
    case en::ONE_MINUS_DST_COLOR:
      return BlendFactor::one_minus_dst_color;
    case en::SRC_ALPHA:
      return BlendFactor::src_alpha;
    case en::ONE_MINUS_SRC_ALPHA:
      return BlendFactor::one_minus_src_alpha;
    case en::DST_ALPHA:
      return BlendFactor::dst_alpha;
    case en::ONE_MINUS_DST_ALPHA:
      return BlendFactor::one_minus_dst_alpha;
    case en::SRC_ALPHA_SATURATE:
      return BlendFactor::src_alpha_saturate;
    default:
      return std::nullopt;  // GL_CONSTANT_COLOR and the like
  }
}

std::optional<BlendEquation> blend_equation(uint32_t e) {
  switch (e) {
    case en::FUNC_ADD:
      return BlendEquation::add;
    case en::FUNC_SUBTRACT:
      return BlendEquation::subtract;
    case en::FUNC_REVERSE_SUBTRACT:
      return BlendEquation::reverse_subtract;
    default:
      return std::nullopt;  // GL_MIN, GL_MAX
  }
}

std::string hex(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%04X", v);
  return buf;
}

bool same(const glm::vec4& a, const glm::vec4& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
bool same(const glm::mat4& a, const glm::mat4& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
bool same(const Material& a, const Material& b) {
  return same(a.ambient, b.ambient) && same(a.diffuse, b.diffuse) && same(a.specular, b.specular) &&
         same(a.emission, b.emission) && a.shininess == b.shininess;
}
bool same(const Light& a, const Light& b) {
  return a.type == b.type && a.vector == b.vector && same(a.ambient, b.ambient) &&
         same(a.diffuse, b.diffuse) && same(a.specular, b.specular) &&
         a.constant_attenuation == b.constant_attenuation &&
         a.linear_attenuation == b.linear_attenuation &&
         a.quadratic_attenuation == b.quadratic_attenuation;
}

struct GlLight {
  glm::vec4 ambient{0.0f, 0.0f, 0.0f, 1.0f};
  glm::vec4 diffuse{0.0f, 0.0f, 0.0f, 1.0f};
  glm::vec4 specular{0.0f, 0.0f, 0.0f, 1.0f};
  glm::vec4 position{0.0f, 0.0f, 1.0f, 0.0f};  // eye space
  glm::vec3 spot_direction{0.0f, 0.0f, -1.0f};
  float spot_exponent = 0.0f;
  float spot_cutoff = 180.0f;
  float kc = 1.0f, kl = 0.0f, kq = 0.0f;
};

// A vertex as glVertex captures it: the current attributes and, for
// lighting, the front material then in effect (glMaterial and
// GL_COLOR_MATERIAL may change it between vertices).
struct Vertex {
  glm::vec4 position;
  glm::vec3 normal;
  glm::vec4 color;
  Material material;
  Material back_material;  // for two-sided lighting
};

// A client array (glVertexPointer and the like): apitrace records the client
// memory a draw reads as a blob.
struct ClientArray {
  bool enabled = false;
  int size = 4;
  uint32_t type = en::FLOAT;
  int64_t stride = 0;
  std::string bytes;
  bool has_blob = false;
};

// What makes two pieces of geometry one draw.
struct DrawKey {
  PrimitiveType type = PrimitiveType::triangles;
  bool lighting = false;
  Material material;
  bool back_lit = false;  // back faces of two-sided lighting: back material, normals negated
  glm::mat4 model_view{1.0f}, projection{1.0f};
  RenderState state;
  bool operator==(const DrawKey& o) const {
    return type == o.type && lighting == o.lighting && (!lighting || same(material, o.material)) &&
           back_lit == o.back_lit && same(model_view, o.model_view) &&
           same(projection, o.projection) && state == o.state;
  }
};

// The attribute calls: glVertex3f, glColor4ubv, glNormal3b, glTexCoord2f, ...
struct AttribCall {
  char attrib;  // 'v' vertex, 'n' normal, 'c' colour, 't' texture coordinate
  int count;
  char type;  // b s i f d, and B S U for ub us ui
  bool vector;
};

std::unordered_map<std::string, AttribCall> make_attrib_calls() {
  std::unordered_map<std::string, AttribCall> out;
  const std::pair<const char*, char> types[] = {{"b", 'b'}, {"s", 's'},  {"i", 'i'},  {"f", 'f'},
                                                {"d", 'd'}, {"ub", 'B'}, {"us", 'S'}, {"ui", 'U'}};
  const auto add = [&](const char* base, char attrib, std::initializer_list<int> counts,
                       const std::string& allowed) {
    for (int n : counts) {
      for (const auto& [suffix, t] : types) {
        if (allowed.find(t) == std::string::npos) continue;
        const std::string name = std::string(base) + std::to_string(n) + suffix;
        out[name] = {attrib, n, t, false};
        out[name + "v"] = {attrib, n, t, true};
      }
    }
  };
  add("glVertex", 'v', {2, 3, 4}, "sifd");
  add("glNormal", 'n', {3}, "bsifd");
  add("glColor", 'c', {3, 4}, "bsifdBSU");
  add("glTexCoord", 't', {1, 2, 3, 4}, "sifd");
  return out;
}

}  // namespace

nlohmann::json DriverFrame::to_json() const {
  nlohmann::json out = {
      {"frame", index},
      {"swap_call", end_call},
      {"gl_calls", gl_calls},
      {"vertices", vertices},
      {"primitives", primitives},
      {"draws", scene.draws.size()},
      {"unsupported_used", features.any_unsupported()},
  };
  const nlohmann::json f = features.to_json();
  out["unsupported"] = f["unsupported"];
  out["ignored"] = f["ignored"];
  return out;
}

struct GlDriver::State {
  using Handler = std::function<void(State&, const TraceCall&)>;

  // The GL state machine.
  std::set<uint32_t> enabled{en::DITHER, en::MULTISAMPLE};
  std::unordered_map<uint32_t, std::string> cap_names;  // as the trace named them
  glm::vec4 color{1.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};
  std::array<GlLight, kMaxLights> lights;
  Material front, back;
  glm::vec4 model_ambient{0.2f, 0.2f, 0.2f, 1.0f};
  bool local_viewer = false, two_side = false, separate_specular = false;
  uint32_t color_material_face = en::FRONT_AND_BACK, color_material_mode = en::AMBIENT_AND_DIFFUSE;
  bool provoking_first = false;  // glProvokingVertex(GL_FIRST_VERTEX_CONVENTION)
  uint32_t shade_model = en::SMOOTH, front_face = en::CCW, cull_face = en::BACK;
  uint32_t polygon_front = en::FILL, polygon_back = en::FILL;
  uint32_t depth_func = en::LESS;
  bool depth_mask = true;
  uint32_t blend_src = en::ONE, blend_dst = en::ZERO, blend_eq = en::FUNC_ADD;
  bool blend_unsupported = false;  // glBlendFuncSeparate with differing factors, GL_CONSTANT_*
  std::array<bool, 4> color_mask{true, true, true, true};
  float offset_factor = 0.0f, offset_units = 0.0f, line_width = 1.0f, point_size = 1.0f;
  glm::vec4 clear_color{0.0f};
  float clear_depth = 1.0f;
  std::array<int64_t, 4> viewport{0, 0, 0, 0}, scissor{0, 0, 0, 0};
  bool scissor_set = false;  // by glScissor, before the window's size was known
  float depth_near = 0.0f, depth_far = 1.0f;
  uint32_t alpha_func = en::ALWAYS;
  uint32_t matrix_mode = en::MODELVIEW;
  MatrixStack modelview{32}, projection{32}, texture{10};
  bool window_known = false;
  int window_width = 0, window_height = 0;

  // Client arrays: vertex, normal, colour, texture coordinate.
  ClientArray vertex_array, normal_array, color_array, texcoord_array;
  bool buffer_bound = false;  // a vertex buffer object: the arrays are not in the trace

  // Display lists.
  std::unordered_map<uint32_t, std::vector<TraceCall>> lists;
  bool compiling = false, compile_and_execute = false;
  uint32_t compiling_list = 0;
  std::vector<TraceCall> list_calls;
  int list_depth = 0;
  uint32_t list_base = 0;

  // glBegin / glEnd.
  bool in_begin = false;
  uint32_t begin_mode = 0;
  std::vector<Vertex> begin_vertices;
  bool edge_flag_cleared = false;

  // The frame being built.
  DriverFrame frame;
  bool capture = true;
  uint32_t frame_index = 0;
  bool frame_lights_set = false;
  bool color_cleared = false, depth_cleared = false;
  // Draws later geometry may join: the last draw, or while calls are drawn
  // in two face passes, the front and back draws of those calls (their faces
  // never overlap where the depth test would not order them).
  std::vector<std::pair<DrawKey, size_t>> open_draws;
  bool open_two_pass = false;  // open_draws were made by two-pass calls
  bool two_pass_call = false;  // the emitting call is drawn in two face passes
  std::vector<int64_t> remap;  // the emitting call's vertex -> the open draw's
  uint64_t remap_serial = 0, emit_serial = 0;
  size_t remap_draw = 0;

  static constexpr float kUnitTolerance = 1e-3f;  // |normal| taken as 1 (0.26/255 at most)
  std::vector<float> normal_lengths;  // of the emitting call's vertices; empty: all unit
  bool mute_reports = false;          // while a call's second face pass repeats the first's checks

  std::unordered_map<std::string, Handler> handlers;
  std::unordered_map<std::string, AttribCall> attrib_calls = make_attrib_calls();

  State() {
    lights[0].diffuse = glm::vec4(1.0f);
    lights[0].specular = glm::vec4(1.0f);
    register_handlers();
  }

  void unsupported(const std::string& what) {
    if (!mute_reports) frame.features.add_unsupported(what);
  }
  void ignored(const std::string& what) { frame.features.add_ignored(what); }
  bool is_enabled(uint32_t cap) const { return enabled.count(cap) > 0; }
  MatrixStack& current_stack() {
    return matrix_mode == en::PROJECTION ? projection
           : matrix_mode == en::TEXTURE  ? texture
                                         : modelview;
  }
  std::string cap_name(uint32_t cap) const {
    const auto it = cap_names.find(cap);
    return it != cap_names.end() && !it->second.empty() ? it->second : hex(cap);
  }

  // ------------------------------------------------------------------ calls
  void execute(const TraceCall& c) {
    ++frame.gl_calls;
    run(c);
  }

  // A call without counting it (the calls an array draw expands into).
  void run(const TraceCall& c) {
    const auto h = handlers.find(c.function);
    if (h != handlers.end()) {
      h->second(*this, c);
      return;
    }
    const auto a = attrib_calls.find(c.function);
    if (a != attrib_calls.end()) {
      attribute(c, a->second);
      return;
    }
    unsupported(c.function);
  }

  // Whether a call is compiled into a display list (OpenGL 1.5, section 5.4:
  // the client-state, list-management and query commands execute at once).
  static bool compiled(const std::string& f) {
    static const std::set<std::string> immediate = {"glNewList",
                                                    "glEndList",
                                                    "glGenLists",
                                                    "glDeleteLists",
                                                    "glIsList",
                                                    "glFlush",
                                                    "glFinish",
                                                    "glVertexPointer",
                                                    "glNormalPointer",
                                                    "glColorPointer",
                                                    "glTexCoordPointer",
                                                    "glEnableClientState",
                                                    "glDisableClientState",
                                                    "glInterleavedArrays",
                                                    "glPixelStorei",
                                                    "glPixelStoref",
                                                    "glReadPixels",
                                                    "glGetError",
                                                    "glGetString",
                                                    "glGetIntegerv",
                                                    "glGetFloatv",
                                                    "glGetDoublev",
                                                    "glGetBooleanv",
                                                    "glIsEnabled",
                                                    "glRenderMode",
                                                    "glSelectBuffer",
                                                    "glFeedbackBuffer",
                                                    "glBindBuffer",
                                                    "glBufferData",
                                                    "glGenBuffers"};
    return f.rfind("glX", 0) != 0 && f.rfind("egl", 0) != 0 && immediate.count(f) == 0;
  }

  void dispatch(const TraceCall& c) {
    if (compiling && compiled(c.function)) {
      // Array draws dereference the arrays when compiled.
      if (c.function == "glDrawArrays" || c.function == "glDrawElements" ||
          c.function == "glDrawRangeElements" || c.function == "glArrayElement") {
        std::vector<TraceCall> expanded = expand_array_draw(c);
        for (TraceCall& e : expanded) {
          if (compile_and_execute) run(e);
          list_calls.push_back(std::move(e));
        }
        return;
      }
      list_calls.push_back(c);
      if (compile_and_execute) execute(c);
      return;
    }
    execute(c);
  }

  // ------------------------------------------------------------ attributes
  void attribute(const TraceCall& c, const AttribCall& a) {
    float v[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    std::vector<double> in;
    if (a.vector) {
      in = numbers_at_least(c, 0, static_cast<size_t>(a.count));
    } else {
      for (int i = 0; i < a.count; ++i) in.push_back(num_arg(c, static_cast<size_t>(i)));
    }
    const bool normalize = a.attrib == 'c' || a.attrib == 'n';
    for (int i = 0; i < a.count; ++i) {
      v[i] = normalize ? normalized(a.type, in[static_cast<size_t>(i)])
                       : static_cast<float>(in[static_cast<size_t>(i)]);
    }
    switch (a.attrib) {
      case 'v':
        vertex(c, glm::vec4(v[0], v[1], v[2], v[3]));
        break;
      case 'n':
        normal = glm::vec3(v[0], v[1], v[2]);
        break;
      case 'c':
        set_color(glm::vec4(v[0], v[1], v[2], a.count == 4 ? v[3] : 1.0f));
        break;
      default:  // texture coordinates: only texturing reads them
        if (!texturing()) ignored("glTexCoord* (texturing off)");
        break;
    }
  }

  bool texturing() const {
    return is_enabled(en::TEXTURE_1D) || is_enabled(en::TEXTURE_2D) || is_enabled(en::TEXTURE_3D) ||
           is_enabled(en::TEXTURE_CUBE_MAP);
  }

  void set_color(const glm::vec4& c) {
    color = c;
    if (is_enabled(en::COLOR_MATERIAL)) apply_color_material();
  }

  // GL_COLOR_MATERIAL: the current colour tracks the chosen material property.
  void apply_color_material() { apply_color_material(front, back); }
  void apply_color_material(Material& f, Material& b) const {
    const auto apply = [&](Material& m) {
      switch (color_material_mode) {
        case en::AMBIENT:
          m.ambient = color;
          break;
        case en::DIFFUSE:
          m.diffuse = color;
          break;
        case en::SPECULAR:
          m.specular = color;
          break;
        case en::EMISSION:
          m.emission = color;
          break;
        case en::AMBIENT_AND_DIFFUSE:
          m.ambient = color, m.diffuse = color;
          break;
        default:
          break;
      }
    };
    if (color_material_face != en::BACK) apply(f);
    if (color_material_face != en::FRONT) apply(b);
  }

  // A vertex with the current attributes. With GL_COLOR_MATERIAL on, the
  // tracked properties are the current colour whatever glMaterial set since
  // (Mesa's fixed-function vertex program reads them from the colour).
  Vertex make_vertex(const glm::vec4& p) const {
    Vertex v{p, normal, color, front, back};
    if (is_enabled(en::COLOR_MATERIAL)) apply_color_material(v.material, v.back_material);
    return v;
  }

  void vertex(const TraceCall& c, const glm::vec4& p) {
    if (!in_begin) {
      // Outside glBegin/glEnd a vertex is a GL error and draws nothing.
      ignored(c.function + " outside glBegin/glEnd (GL error)");
      return;
    }
    if (capture)
      begin_vertices.push_back(make_vertex(p));
    else
      ++frame.vertices;
  }

  // ------------------------------------------------------------ geometry
  // Which faces a draw of triangles shows: those GL's culling leaves, or only
  // the front or back ones (a call drawn in two passes, section "Two-sided
  // lighting" of docs/replay.md).
  enum class Faces { visible, front, back };

  // The part of the window a draw of the current state may write: the
  // scissor box (GL_SCISSOR_TEST) clipped to the window; nullopt: the whole
  // window; an empty rectangle: nothing.
  std::optional<PixelRect> scissor_box() const {
    if (!is_enabled(en::SCISSOR_TEST) || !window_known) return std::nullopt;
    const int64_t x0 = std::max<int64_t>(scissor[0], 0), y0 = std::max<int64_t>(scissor[1], 0);
    const int64_t x1 = std::min<int64_t>(scissor[0] + scissor[2], window_width);
    const int64_t y1 = std::min<int64_t>(scissor[1] + scissor[3], window_height);
    if (x0 == 0 && y0 == 0 && x1 == window_width && y1 == window_height) return std::nullopt;
    if (x1 <= x0 || y1 <= y0) return PixelRect{0, 0, 0, 0};
    return PixelRect{static_cast<int32_t>(x0), static_cast<int32_t>(y0),
                     static_cast<int32_t>(x1 - x0), static_cast<int32_t>(y1 - y0)};
  }

  // Viewport, depth range and scissor of a draw (docs/replay.md, "Viewport,
  // depth range, scissor"); false when GL draws nothing (an empty viewport or
  // scissor box). A viewport or scissor covering the window is left out, as
  // the GPU's default is the same rectangle.
  bool window_state(PrimitiveKind cls, uint32_t poly_mode, RenderState& rs) {
    rs.depth_near = depth_near, rs.depth_far = depth_far;
    if (!window_known) return true;  // reported by check_draw_state
    const std::optional<PixelRect> box = scissor_box();
    if (box && box->width == 0) return false;
    rs.scissor = box;
    if (viewport[2] <= 0 || viewport[3] <= 0) return false;
    const std::array<int64_t, 4> whole{0, 0, window_width, window_height};
    if (viewport == whole) return true;
    // The models' guard band holds viewports within this reach of the origin
    // (docs/pipeline-spec.md, section 4; the scene loader's limit).
    constexpr int64_t kReach = 16384;
    if (std::max({-viewport[0], -viewport[1], viewport[0] + viewport[2],
                  viewport[1] + viewport[3]}) > kReach) {
      unsupported("glViewport reaching beyond 16384 pixels from the window's origin");
      return false;
    }
    rs.viewport = PixelRect{static_cast<int32_t>(viewport[0]), static_cast<int32_t>(viewport[1]),
                            static_cast<int32_t>(viewport[2]), static_cast<int32_t>(viewport[3])};
    // GL draws a wide line's or big point's pixels past the viewport edge;
    // the GPU bounds every fragment to the viewport (section 8d). Only a
    // viewport leaving part of the window uncovered can differ.
    const bool covers = viewport[0] <= 0 && viewport[1] <= 0 &&
                        viewport[0] + viewport[2] >= window_width &&
                        viewport[1] + viewport[3] >= window_height;
    const bool tri = cls == PrimitiveKind::triangle;
    const bool lines = cls == PrimitiveKind::line || (tri && poly_mode == en::LINE);
    const bool points = cls == PrimitiveKind::point || (tri && poly_mode == en::POINT);
    if (!covers && ((lines && line_width > 1.0f) || (points && point_size > 1.0f))) {
      unsupported("wide lines or points larger than 1 with a glViewport smaller than the window");
    }
    return true;
  }

  // The RenderState of a draw of class `cls` from GL primitive `mode`; false
  // when GL draws nothing (triangles with GL_FRONT_AND_BACK culled).
  bool render_state(PrimitiveKind cls, uint32_t mode, Faces faces, RenderState& rs) {
    const bool tri = cls == PrimitiveKind::triangle;
    uint32_t poly_mode = polygon_front;
    if (tri && faces != Faces::visible) {
      rs.cull = faces == Faces::front ? CullMode::back : CullMode::front;
      poly_mode = faces == Faces::front ? polygon_front : polygon_back;
    } else if (tri && is_enabled(en::CULL_FACE)) {
      if (cull_face == en::FRONT_AND_BACK) return false;
      rs.cull = cull_face == en::FRONT ? CullMode::front : CullMode::back;
      poly_mode = cull_face == en::FRONT ? polygon_back : polygon_front;
    } else if (tri && polygon_front != polygon_back) {
      unsupported("glPolygonMode with different front and back modes (both faces visible)");
    }
    rs.front_face = front_face == en::CW ? FrontFace::cw : FrontFace::ccw;
    rs.depth_test = is_enabled(en::DEPTH_TEST);
    rs.depth_func = compare_func(depth_func).value_or(CompareFunc::less);
    rs.depth_write = depth_mask;
    rs.blend = is_enabled(en::BLEND);
    if (rs.blend) {
      const auto s = blend_factor(blend_src), d = blend_factor(blend_dst);
      const auto e = blend_equation(blend_eq);
      if (!s || !d || !e || blend_unsupported) {
        unsupported(
            "blend function or equation the GPU lacks (constant colour, min, max, separate)");
      }
      rs.blend_src = s.value_or(BlendFactor::one);
      rs.blend_dst = d.value_or(BlendFactor::zero);
      rs.blend_equation = e.value_or(BlendEquation::add);
    }
    rs.color_mask = color_mask;
    if (!window_state(cls, poly_mode, rs)) return false;
    rs.shading = shade_model == en::FLAT ? Shading::flat : Shading::gouraud;
    // The decomposition puts the last-vertex convention's provoking vertex
    // last (gl_primitive.h); the first-vertex convention's differs per mode,
    // and for quads is implementation-dependent. Smooth shading never reads it.
    if (shade_model == en::FLAT && provoking_first) {
      unsupported("glProvokingVertex(GL_FIRST_VERTEX_CONVENTION) with flat shading");
    }
    rs.line_width = std::clamp(line_width, 1.0f / 256.0f, kMaxLineWidth);
    rs.point_size = std::clamp(point_size, 1.0f / 256.0f, kMaxLineWidth);
    if (tri) {
      rs.polygon_mode = poly_mode == en::LINE    ? PolygonMode::line
                        : poly_mode == en::POINT ? PolygonMode::point
                                                 : PolygonMode::fill;
      const bool quads = mode == en::QUADS || mode == en::QUAD_STRIP || mode == en::POLYGON;
      if (poly_mode == en::LINE && quads) {
        unsupported(std::string("glPolygonMode(GL_LINE) with ") + gl_primitive_name(mode) +
                    " (the GPU would also draw the diagonals)");
      }
      if (poly_mode != en::FILL && edge_flag_cleared) unsupported("glEdgeFlag(GL_FALSE)");
      if (poly_mode == en::FILL && is_enabled(en::POLYGON_OFFSET_FILL)) {
        rs.offset_factor = offset_factor;
        rs.offset_units = offset_units;
      }
      if ((poly_mode == en::LINE && is_enabled(en::POLYGON_OFFSET_LINE)) ||
          (poly_mode == en::POINT && is_enabled(en::POLYGON_OFFSET_POINT))) {
        unsupported("GL_POLYGON_OFFSET_LINE or _POINT (offset of unfilled polygons)");
      }
      if (poly_mode == en::FILL && is_enabled(en::POLYGON_SMOOTH)) unsupported("GL_POLYGON_SMOOTH");
      if (poly_mode == en::LINE && is_enabled(en::LINE_SMOOTH)) unsupported("GL_LINE_SMOOTH");
      if (poly_mode == en::POINT && is_enabled(en::POINT_SMOOTH)) unsupported("GL_POINT_SMOOTH");
    } else if (cls == PrimitiveKind::line && is_enabled(en::LINE_SMOOTH)) {
      unsupported("GL_LINE_SMOOTH");
    } else if (cls == PrimitiveKind::point && is_enabled(en::POINT_SMOOTH)) {
      unsupported("GL_POINT_SMOOTH");
    }
    return true;
  }

  // Reports the enabled state and framebuffer settings the GPU lacks.
  void check_draw_state() {
    static const std::set<uint32_t> handled = {en::LIGHTING,
                                               en::COLOR_MATERIAL,
                                               en::NORMALIZE,
                                               en::RESCALE_NORMAL,
                                               en::CULL_FACE,
                                               en::DEPTH_TEST,
                                               en::BLEND,
                                               en::SCISSOR_TEST,
                                               en::POLYGON_OFFSET_FILL,
                                               en::POLYGON_OFFSET_LINE,
                                               en::POLYGON_OFFSET_POINT,
                                               en::DITHER,
                                               en::MULTISAMPLE,
                                               en::LINE_SMOOTH,
                                               en::POINT_SMOOTH,
                                               en::POLYGON_SMOOTH,
                                               en::ALPHA_TEST};
    for (uint32_t cap : enabled) {
      const bool light = cap >= en::LIGHT0 && cap < en::LIGHT0 + kMaxLights;
      if (!light && handled.count(cap) == 0) unsupported(cap_name(cap) + " enabled while drawing");
    }
    if (is_enabled(en::ALPHA_TEST) && alpha_func != en::ALWAYS) unsupported("GL_ALPHA_TEST");
    if (!window_known) {
      unsupported("drawing before any glViewport (window size unknown)");
      return;
    }
    if (!color_cleared) unsupported("frame drawn without glClear(GL_COLOR_BUFFER_BIT) first");
    if (is_enabled(en::DEPTH_TEST) && !depth_cleared) {
      unsupported("depth test without glClear(GL_DEPTH_BUFFER_BIT) first in the frame");
    }
  }

  // The enabled lights in eye space as the GPU takes them (docs/replay.md).
  std::vector<Light> gpu_lights() const {
    std::vector<Light> out;
    for (int i = 0; i < kMaxLights; ++i) {
      if (!is_enabled(en::LIGHT0 + static_cast<uint32_t>(i))) continue;
      const GlLight& g = lights[static_cast<size_t>(i)];
      Light l;
      l.ambient = g.ambient;
      l.diffuse = g.diffuse;
      l.specular = g.specular;
      if (g.position.w == 0.0f) {
        l.type = LightType::directional;
        const glm::vec3 d(g.position);
        const float len2 = d.x * d.x + d.y * d.y + d.z * d.z;
        l.vector = len2 > 0.0f ? d * (1.0f / std::sqrt(len2)) : d;
      } else {
        l.type = LightType::point;
        l.vector = glm::vec3(g.position) / g.position.w;
        l.constant_attenuation = g.kc;
        l.linear_attenuation = g.kl;
        l.quadratic_attenuation = g.kq;
      }
      out.push_back(l);
    }
    return out;
  }

  // Lighting state the GPU's equation cannot express, and the per-frame lights.
  void check_lighting(const std::vector<Vertex>& v, const glm::mat3& normal_matrix, bool singular) {
    if (local_viewer) unsupported("GL_LIGHT_MODEL_LOCAL_VIEWER");
    for (int i = 0; i < kMaxLights; ++i) {
      if (is_enabled(en::LIGHT0 + static_cast<uint32_t>(i)) &&
          lights[static_cast<size_t>(i)].spot_cutoff != 180.0f &&
          lights[static_cast<size_t>(i)].position.w != 0.0f) {
        unsupported("spot light (GL_SPOT_CUTOFF other than 180)");
      }
    }
    if (singular) unsupported("lighting with a singular modelview matrix");
    const std::vector<Light> l = gpu_lights();
    if (!frame_lights_set) {
      frame.scene.lights = l;
      frame.scene.global_ambient = model_ambient;
      frame_lights_set = true;
    } else {
      bool equal =
          l.size() == frame.scene.lights.size() && same(model_ambient, frame.scene.global_ambient);
      for (size_t i = 0; equal && i < l.size(); ++i) equal = same(l[i], frame.scene.lights[i]);
      if (!equal) unsupported("lights or light model changed between draws of a frame");
    }
    // The GPU normalises every normal; GL does so only with GL_NORMALIZE:
    // the eye-space lengths, for emit_pass to fold into the material.
    normal_lengths.clear();
    if (!is_enabled(en::NORMALIZE) && !singular) {
      float scale = 1.0f;
      if (is_enabled(en::RESCALE_NORMAL)) {
        const glm::vec3 row(normal_matrix[0][2], normal_matrix[1][2], normal_matrix[2][2]);
        scale = 1.0f / std::sqrt(glm::dot(row, row));
      }
      bool unit = true;
      for (const Vertex& x : v) {
        const glm::vec3 n = normal_matrix * x.normal * scale;
        normal_lengths.push_back(std::sqrt(glm::dot(n, n)));
        unit = unit && std::fabs(normal_lengths.back() - 1.0f) <= kUnitTolerance;
      }
      if (unit) normal_lengths.clear();
    }
  }

  // GL_NORMALIZE off, a primitive's eye-space normal of length s: GL's
  // diffuse term is s times the GPU's (unit normal) and its specular term
  // s^shininess times, so the material carries the factors (GL's f, n·L > 0,
  // keeps its sign). False when the factor does not fit a float.
  static bool fold_normal_length(float s, Material& m) {
    if (std::fabs(s - 1.0f) <= kUnitTolerance) return true;
    const float k = std::pow(s, m.shininess);
    if (!std::isfinite(k)) return false;
    for (int i = 0; i < 3; ++i) m.diffuse[i] *= s, m.specular[i] *= k;
    return true;
  }

  // Adds a call's geometry to the frame: GL_* primitive `mode` over `v`.
  void emit(uint32_t mode, const std::vector<Vertex>& v, const TraceCall& c) {
    const std::optional<GlAssembly> assembly =
        assemble_gl_primitive(mode, static_cast<uint32_t>(v.size()));
    frame.vertices += v.size();
    if (!assembly) {
      ignored(c.function + " with an invalid primitive mode (GL error)");
      return;
    }
    if (assembly->indices.empty()) return;
    const PrimitiveKind cls = primitive_kind_of(assembly->type);
    check_draw_state();
    DrawKey key;
    key.type = assembly->type;
    key.model_view = modelview.top();
    key.projection = projection.top();
    key.lighting = is_enabled(en::LIGHTING);
    const glm::mat3 upper(key.model_view);
    const bool singular = glm::determinant(upper) == 0.0f;
    const glm::mat3 normal_matrix =
        singular ? glm::mat3(1.0f) : glm::transpose(glm::inverse(upper));
    if (key.lighting) check_lighting(v, normal_matrix, singular);

    // Two-sided lighting and different front and back polygon modes: the GPU
    // has one material and one mode per draw, so a call showing both faces
    // is drawn twice, front faces (back ones culled) then back faces (front
    // ones culled) with the back material and negated normals.
    const bool tri = cls == PrimitiveKind::triangle, cull = is_enabled(en::CULL_FACE);
    const bool front_visible =
        !(cull && (cull_face == en::FRONT || cull_face == en::FRONT_AND_BACK));
    const bool back_visible = !(cull && (cull_face == en::BACK || cull_face == en::FRONT_AND_BACK));
    const bool two_sided = tri && key.lighting && two_side;
    std::vector<std::pair<Faces, bool>> passes;  // faces, back-lit
    if (tri && front_visible && back_visible && (two_sided || polygon_front != polygon_back)) {
      passes = {{Faces::front, false}, {Faces::back, two_sided}};
      if (!is_enabled(en::DEPTH_TEST) || is_enabled(en::BLEND)) {
        unsupported(
            "two-sided lighting or different front and back polygon modes without a depth test "
            "or with blending (front faces drawn before back faces)");
      }
    } else {
      passes = {{Faces::visible, two_sided && !front_visible}};
    }
    two_pass_call = passes.size() == 2;
    for (size_t pass = 0; pass < passes.size(); ++pass) {
      key.state = RenderState();
      key.back_lit = passes[pass].second;
      mute_reports = pass > 0;
      const bool drawn = render_state(cls, mode, passes[pass].first, key.state);
      mute_reports = false;
      if (drawn) emit_pass(key, *assembly, v, normal_matrix, pass == 0, c);
    }
  }

  // One pass of emit() over the call's primitives with `key`'s state.
  void emit_pass(DrawKey& key, const GlAssembly& assembly, const std::vector<Vertex>& v,
                 const glm::mat3& normal_matrix, bool count, const TraceCall& c) {
    const PrimitiveKind cls = primitive_kind_of(assembly.type);

    const bool strip =
        assembly.type == PrimitiveType::line_strip || assembly.type == PrimitiveType::line_loop;
    const size_t per = strip                            ? assembly.indices.size()
                       : cls == PrimitiveKind::triangle ? 3
                       : cls == PrimitiveKind::line     ? 2
                                                        : 1;
    const bool flat = shade_model == en::FLAT;
    bool mixed = false, uneven = false, unfoldable = false;
    ++emit_serial;
    const auto material_of = [&](const Vertex& x) -> const Material& {
      return key.back_lit ? x.back_material : x.material;
    };
    for (size_t first = 0; first + per <= assembly.indices.size(); first += per) {
      const uint32_t* idx = &assembly.indices[first];
      const Vertex& provoking = v[idx[per - 1]];
      key.material = material_of(provoking);
      if (key.lighting) {
        // One material per draw: a primitive whose vertices were lit with
        // different materials (glColor with GL_COLOR_MATERIAL, glMaterial
        // between vertices) keeps its provoking vertex's, exact when flat
        // shading reads only that vertex (and for line strips, every line's).
        for (size_t k = 0; k + 1 < per; ++k) {
          if (!same(material_of(v[idx[k]]), key.material) && (!flat || strip)) mixed = true;
        }
        if (!normal_lengths.empty()) {
          const float s = normal_lengths[idx[per - 1]];
          for (size_t k = 0; k + 1 < per; ++k) {
            const float d = std::fabs(normal_lengths[idx[k]] - s);
            if (d > kUnitTolerance * std::max(s, 1.0f) && (!flat || strip)) uneven = true;
          }
          if (!fold_normal_length(s, key.material)) unfoldable = true;
        }
      }
      if (count) frame.primitives += strip ? primitive_count(assembly.type, per) : 1;
      if (!capture) continue;
      add_primitive(key, idx, per, v, normal_matrix, !strip, c);
    }
    if (uneven && count) {
      unsupported(
          "normals of different eye-space lengths within a primitive with GL_NORMALIZE off");
    }
    if (unfoldable && count)
      unsupported("a normal too long for its shininess with GL_NORMALIZE off");
    if (mixed && count) {
      unsupported(
          "material varying within a primitive (GL_COLOR_MATERIAL or glMaterial between vertices)");
    }
  }

  void add_primitive(const DrawKey& key, const uint32_t* idx, size_t per,
                     const std::vector<Vertex>& v, const glm::mat3& normal_matrix, bool batchable,
                     const TraceCall& c) {
    std::vector<Draw>& draws = frame.scene.draws;
    size_t target = draws.size();  // none yet
    if (batchable) {
      for (const auto& [k, index] : open_draws) {
        const bool may_join = two_pass_call ? open_two_pass : index + 1 == draws.size();
        if (may_join && k == key) target = index;
      }
    }
    if (target == draws.size()) {
      Draw d;
      d.name = "frame " + std::to_string(frame_index) + " draw " + std::to_string(draws.size()) +
               " (call " + std::to_string(c.number) + " " + c.function + ")";
      d.primitive = key.type;
      d.lighting = key.lighting;
      d.material = key.material;
      d.model = key.model_view;  // the driver's world space is eye space
      d.model_view = key.model_view;
      d.projection = key.projection;
      d.mvp = key.projection * key.model_view;
      d.normal_matrix = normal_matrix;
      d.state = key.state;
      draws.push_back(std::move(d));
      if (!batchable || two_pass_call != open_two_pass) open_draws.clear();
      if (open_draws.size() == 2) open_draws.erase(open_draws.begin());
      if (batchable) open_draws.emplace_back(key, target);
      open_two_pass = two_pass_call;
    }
    Draw& d = draws[target];
    if (remap_serial != emit_serial || remap_draw != target + 1) {
      remap.assign(v.size(), -1);
      remap_serial = emit_serial;
      remap_draw = target + 1;
    }
    for (size_t k = 0; k < per; ++k) {
      const uint32_t i = idx[k];
      if (remap[i] < 0) {
        remap[i] = static_cast<int64_t>(d.positions.size());
        d.positions.push_back(v[i].position);
        if (key.lighting) {
          d.normals.push_back(key.back_lit ? -v[i].normal : v[i].normal);
        } else {
          d.colors.push_back(v[i].color);
        }
      }
      if (batchable) d.indices.push_back(static_cast<uint32_t>(remap[i]));
    }
  }

  // --------------------------------------------------------- client arrays
  static size_t type_size(uint32_t t) {
    switch (t) {
      case en::BYTE:
      case en::UNSIGNED_BYTE:
        return 1;
      case en::SHORT:
      case en::UNSIGNED_SHORT:
        return 2;
      case en::INT:
      case en::UNSIGNED_INT:
      case en::FLOAT:
        return 4;
      case en::DOUBLE:
        return 8;
      default:
        return 0;
    }
  }

  static char type_code(uint32_t t) {
    switch (t) {
      case en::BYTE:
        return 'b';
      case en::UNSIGNED_BYTE:
        return 'B';
      case en::SHORT:
        return 's';
      case en::UNSIGNED_SHORT:
        return 'S';
      case en::INT:
        return 'i';
      case en::UNSIGNED_INT:
        return 'U';
      case en::DOUBLE:
        return 'd';
      default:
        return 'f';
    }
  }

  static double read_component(const std::string& bytes, size_t offset, uint32_t type) {
    const char* p = bytes.data() + offset;
    switch (type) {
      case en::BYTE: {
        int8_t x;
        std::memcpy(&x, p, 1);
        return x;
      }
      case en::UNSIGNED_BYTE: {
        uint8_t x;
        std::memcpy(&x, p, 1);
        return x;
      }
      case en::SHORT: {
        int16_t x;
        std::memcpy(&x, p, 2);
        return x;
      }
      case en::UNSIGNED_SHORT: {
        uint16_t x;
        std::memcpy(&x, p, 2);
        return x;
      }
      case en::INT: {
        int32_t x;
        std::memcpy(&x, p, 4);
        return x;
      }
      case en::UNSIGNED_INT: {
        uint32_t x;
        std::memcpy(&x, p, 4);
        return x;
      }
      case en::DOUBLE: {
        double x;
        std::memcpy(&x, p, 8);
        return x;
      }
      default: {
        float x;
        std::memcpy(&x, p, 4);
        return x;
      }
    }
  }

  void set_pointer(ClientArray& a, const TraceCall& c, int size, size_t type_i, size_t stride_i,
                   size_t pointer_i) {
    a.size = size;
    a.type = enum_arg(c, type_i);
    a.stride = int_arg(c, stride_i);
    const TraceValue& p = arg(c, pointer_i);
    a.has_blob = p.kind == TraceValue::Kind::blob;
    a.bytes = a.has_blob ? p.bytes : std::string();
    if (!a.has_blob && buffer_bound) unsupported("vertex buffer objects (glBindBuffer)");
    if (type_size(a.type) == 0) bad_call(c, "unknown array type " + hex(a.type));
  }

  // Element i of an array as a synthesized attribute call; false when the
  // recorded memory does not hold it.
  bool array_element(const ClientArray& a, uint64_t i, const char* base, TraceCall& out) {
    const size_t ts = type_size(a.type);
    const uint64_t stride =
        a.stride > 0 ? static_cast<uint64_t>(a.stride) : ts * static_cast<uint64_t>(a.size);
    const uint64_t offset = i * stride;
    if (!a.has_blob || offset + ts * static_cast<uint64_t>(a.size) > a.bytes.size()) return false;
    out = TraceCall();
    const char t = type_code(a.type);
    const std::string suffix = t == 'B'   ? "ub"
                               : t == 'S' ? "us"
                               : t == 'U' ? "ui"
                                          : std::string(1, t);
    out.function = std::string(base) + std::to_string(a.size) + suffix;
    for (int k = 0; k < a.size; ++k) {
      TraceValue v;
      v.kind = TraceValue::Kind::float64;
      v.real = read_component(a.bytes, static_cast<size_t>(offset) + ts * static_cast<size_t>(k),
                              a.type);
      out.args.push_back(v);
    }
    return true;
  }

  // glDrawArrays / glDrawElements / glArrayElement as the calls OpenGL defines
  // them by (glBegin, then per element glNormal, glColor, glVertex, glEnd).
  std::vector<TraceCall> expand_array_draw(const TraceCall& c) {
    std::vector<uint64_t> elements;
    uint32_t mode = en::POINTS;
    bool begin_end = true;
    if (c.function == "glDrawArrays") {
      mode = enum_arg(c, 0);
      const int64_t first = int_arg(c, 1), count = int_arg(c, 2);
      for (int64_t i = 0; i < count; ++i) elements.push_back(static_cast<uint64_t>(first + i));
    } else if (c.function == "glArrayElement") {
      elements.push_back(static_cast<uint64_t>(int_arg(c, 0)));
      begin_end = false;
    } else {
      const bool range = c.function == "glDrawRangeElements";
      mode = enum_arg(c, 0);
      const int64_t count = int_arg(c, range ? 3 : 1);
      const uint32_t type = enum_arg(c, range ? 4 : 2);
      const TraceValue& ind = arg(c, range ? 5 : 3);
      const size_t ts = type_size(type);
      if (ind.kind == TraceValue::Kind::blob && ts > 0) {
        for (int64_t i = 0; i < count && (static_cast<size_t>(i) + 1) * ts <= ind.bytes.size();
             ++i) {
          elements.push_back(
              static_cast<uint64_t>(read_component(ind.bytes, static_cast<size_t>(i) * ts, type)));
        }
      } else if (ind.kind == TraceValue::Kind::array) {
        for (const TraceValue& e : ind.elements)
          elements.push_back(static_cast<uint64_t>(number(c, e)));
      } else {
        unsupported(c.function + " with indices in a buffer object");
        return {};
      }
    }
    std::vector<TraceCall> out;
    const auto make = [&](const char* f, std::vector<TraceValue> args) {
      TraceCall t;
      t.number = c.number;
      t.function = f;
      t.args = std::move(args);
      out.push_back(std::move(t));
    };
    if (!vertex_array.enabled) return out;  // nothing is drawn without positions
    if (texcoord_array.enabled && texturing())
      unsupported("texture coordinate arrays with texturing");
    if (begin_end) {
      TraceValue m;
      m.kind = TraceValue::Kind::enumeration;
      m.sint = mode;
      make("glBegin", {m});
    }
    bool short_array = false;
    for (uint64_t e : elements) {
      TraceCall a;
      if (normal_array.enabled) {
        if (array_element(normal_array, e, "glNormal", a))
          out.push_back(a);
        else
          short_array = true;
      }
      if (color_array.enabled) {
        if (array_element(color_array, e, "glColor", a))
          out.push_back(a);
        else
          short_array = true;
      }
      if (array_element(vertex_array, e, "glVertex", a)) {
        a.number = c.number;
        out.push_back(a);
      } else {
        short_array = true;
      }
    }
    for (TraceCall& t : out) t.number = c.number;
    if (short_array) unsupported(c.function + " reading past its recorded client memory");
    if (begin_end) make("glEnd", {});
    return out;
  }

  // --------------------------------------------------------------- lights
  void light(const TraceCall& c, bool vector) {
    const uint32_t which = enum_arg(c, 0) - en::LIGHT0;
    const uint32_t pname = enum_arg(c, 1);
    if (which >= kMaxLights) return ignored(c.function + " of an invalid light (GL error)");
    GlLight& l = lights[which];
    const bool is_int =
        c.function.back() == 'i' || c.function.substr(c.function.size() - 2) == "iv";
    const auto color4 = [&]() {
      std::vector<double> p = numbers_at_least(c, 2, 4);
      glm::vec4 out = vec4_of(p);
      if (is_int) {
        for (int k = 0; k < 4; ++k) out[k] = normalized('i', p[static_cast<size_t>(k)]);
      }
      return out;
    };
    const float s = vector ? static_cast<float>(numbers_at_least(c, 2, 1)[0]) : float_arg(c, 2);
    switch (pname) {
      case en::AMBIENT:
        l.ambient = color4();
        break;
      case en::DIFFUSE:
        l.diffuse = color4();
        break;
      case en::SPECULAR:
        l.specular = color4();
        break;
      case en::POSITION:
        l.position = modelview.top() * vec4_of(numbers_at_least(c, 2, 4));
        break;
      case en::SPOT_DIRECTION: {
        const std::vector<double> d = numbers_at_least(c, 2, 3);
        l.spot_direction =
            glm::mat3(modelview.top()) *
            glm::vec3(static_cast<float>(d[0]), static_cast<float>(d[1]), static_cast<float>(d[2]));
        break;
      }
      case en::SPOT_EXPONENT:
        l.spot_exponent = s;
        break;
      case en::SPOT_CUTOFF:
        l.spot_cutoff = s;
        break;
      case en::CONSTANT_ATTENUATION:
        l.kc = s;
        break;
      case en::LINEAR_ATTENUATION:
        l.kl = s;
        break;
      case en::QUADRATIC_ATTENUATION:
        l.kq = s;
        break;
      default:
        ignored(c.function + " with an invalid pname (GL error)");
        break;
    }
  }

  void material(const TraceCall& c, bool vector) {
    const uint32_t face = enum_arg(c, 0), pname = enum_arg(c, 1);
    const bool is_int =
        c.function.back() == 'i' || c.function.substr(c.function.size() - 2) == "iv";
    const auto apply = [&](Material& m) {
      if (pname == en::SHININESS) {
        m.shininess = vector ? static_cast<float>(numbers_at_least(c, 2, 1)[0]) : float_arg(c, 2);
        return;
      }
      if (pname == en::COLOR_INDEXES) return;
      std::vector<double> p = numbers_at_least(c, 2, 4);
      glm::vec4 v = vec4_of(p);
      if (is_int) {
        for (int k = 0; k < 4; ++k) v[k] = normalized('i', p[static_cast<size_t>(k)]);
      }
      switch (pname) {
        case en::AMBIENT:
          m.ambient = v;
          break;
        case en::DIFFUSE:
          m.diffuse = v;
          break;
        case en::SPECULAR:
          m.specular = v;
          break;
        case en::EMISSION:
          m.emission = v;
          break;
        case en::AMBIENT_AND_DIFFUSE:
          m.ambient = v, m.diffuse = v;
          break;
        default:
          ignored(c.function + " with an invalid pname (GL error)");
          break;
      }
    };
    if (face != en::BACK) apply(front);
    if (face != en::FRONT) apply(back);
  }

  void light_model(const TraceCall& c, bool vector) {
    const uint32_t pname = enum_arg(c, 0);
    if (pname == en::LIGHT_MODEL_AMBIENT) {
      model_ambient = vec4_of(numbers_at_least(c, 1, 4));
      return;
    }
    const double v = vector ? numbers_at_least(c, 1, 1)[0] : num_arg(c, 1);
    switch (pname) {
      case en::LIGHT_MODEL_LOCAL_VIEWER:
        local_viewer = v != 0.0;
        break;
      case en::LIGHT_MODEL_TWO_SIDE:
        two_side = v != 0.0;
        break;
      case en::LIGHT_MODEL_COLOR_CONTROL:
        separate_specular = static_cast<uint32_t>(v) == en::SEPARATE_SPECULAR_COLOR;
        break;
      default:
        ignored(c.function + " with an invalid pname (GL error)");
        break;
    }
  }

  // ---------------------------------------------------------------- lists
  void call_list(uint32_t id) {
    const auto it = lists.find(id);
    if (it == lists.end()) return;  // an undefined list draws nothing
    if (list_depth >= kMaxListNesting) {
      ignored("glCallList nested deeper than GL_MAX_LIST_NESTING");
      return;
    }
    ++list_depth;
    // Copy: a list may (pathologically) delete or redefine itself.
    const std::vector<TraceCall> calls = it->second;
    for (const TraceCall& c : calls) execute(c);
    --list_depth;
  }

  void call_lists(const TraceCall& c) {
    const int64_t n = int_arg(c, 0);
    const uint32_t type = enum_arg(c, 1);
    const TraceValue& names = arg(c, 2);
    std::vector<uint32_t> ids;
    if (names.kind == TraceValue::Kind::array) {
      for (const TraceValue& e : names.elements) ids.push_back(static_cast<uint32_t>(number(c, e)));
    } else if (names.kind == TraceValue::Kind::blob) {
      const size_t ts = type == en::TWO_BYTES     ? 2
                        : type == en::THREE_BYTES ? 3
                        : type == en::FOUR_BYTES  ? 4
                                                  : type_size(type);
      if (ts == 0) bad_call(c, "unknown list name type " + hex(type));
      for (size_t i = 0; (i + 1) * ts <= names.bytes.size() && ids.size() < static_cast<size_t>(n);
           ++i) {
        uint32_t id = 0;
        if (type == en::TWO_BYTES || type == en::THREE_BYTES || type == en::FOUR_BYTES) {
          for (size_t k = 0; k < ts; ++k)
            id = id * 256 + static_cast<uint8_t>(names.bytes[i * ts + k]);
        } else {
          id = static_cast<uint32_t>(read_component(names.bytes, i * ts, type));
        }
        ids.push_back(id);
      }
    }
    if (ids.size() > static_cast<size_t>(std::max<int64_t>(n, 0)))
      ids.resize(static_cast<size_t>(n));
    for (uint32_t id : ids) call_list(list_base + id);
  }

  // ------------------------------------------------------------- frames
  // glClear: before the frame's first draw it is the frame clear; after it, a
  // clear in the draw list (docs/pipeline-spec.md, section 15). GL clears
  // only inside the scissor box and only what the write masks let through:
  // a mask that shuts a buffer off drops that buffer from the clear, exactly;
  // a partial colour mask or a scissor box smaller than the window cannot be
  // expressed by the GPU's whole-buffer clears and is reported.
  void clear(const TraceCall& c) {
    const uint32_t mask = enum_arg(c, 0);
    if (mask & (en::STENCIL_BUFFER_BIT | en::ACCUM_BUFFER_BIT)) {
      ignored("glClear of the stencil or accumulation buffer");
    }
    const std::array<bool, 4> none{false, false, false, false}, all{true, true, true, true};
    const bool color = (mask & en::COLOR_BUFFER_BIT) && color_mask != none;
    const bool depth = (mask & en::DEPTH_BUFFER_BIT) && depth_mask;
    if (!color && !depth) return;
    const std::optional<PixelRect> box = scissor_box();
    if (box && box->width == 0) return;  // the scissor test rejects every pixel
    if (box) unsupported("glClear inside a scissor box smaller than the window");
    if (color && color_mask != all)
      unsupported("glClear with a glColorMask other than all or none");
    if (frame.scene.draws.empty()) {
      if (color) frame.scene.framebuffer.clear_color = clear_color;
      if (depth) frame.scene.framebuffer.clear_depth = clear_depth;
    } else {
      ClearState cs;
      cs.color = color, cs.depth = depth;
      // Only the cleared buffers' values: the others keep ClearState's defaults.
      if (color) cs.color_value = clear_color;
      if (depth) cs.depth_value = clear_depth;
      cs.before_draw = static_cast<uint32_t>(frame.scene.draws.size());
      frame.scene.clears.push_back(cs);
      // Later geometry must not join a draw from before the clear.
      open_draws.clear();
      open_two_pass = false;
    }
    color_cleared = color_cleared || color;
    depth_cleared = depth_cleared || depth;
  }

  void start_frame() {
    frame = DriverFrame();
    frame.index = frame_index;
    frame.scene.path = "frame " + std::to_string(frame_index);
    frame_lights_set = false;
    color_cleared = depth_cleared = false;
    open_draws.clear();
    open_two_pass = false;
    remap_draw = 0;
  }

  void end_frame(const TraceCall& c) {
    if (in_begin) unsupported("a swap inside glBegin/glEnd");
    frame.end_call = c.number;
    FramebufferDesc& fb = frame.scene.framebuffer;
    if (window_known) fb.width = window_width, fb.height = window_height;
    fb.color_format = ColorFormat::rgba8;
    fb.depth_format = DepthFormat::unorm24;
    frame.scene.resolved = {
        {"source", "gpusim replay"},
        {"framebuffer", {{"width", fb.width}, {"height", fb.height}}},
        {"lights", frame.scene.lights.size()},
    };
  }

  // ------------------------------------------------------------- handlers
  void register_handlers();
};

void GlDriver::State::register_handlers() {
  auto& h = handlers;
  const auto nothing = [](State&, const TraceCall&) {};
  // Window-system calls and queries change nothing that is drawn.
  for (const char* f : {"glXChooseVisual",
                        "glXCreateContext",
                        "glXCreateNewContext",
                        "glXChooseFBConfig",
                        "glXGetVisualFromFBConfig",
                        "glXCreateContextAttribsARB",
                        "glXMakeCurrent",
                        "glXMakeContextCurrent",
                        "glXDestroyContext",
                        "glXQueryExtension",
                        "glXQueryExtensionsString",
                        "glXQueryVersion",
                        "glXGetProcAddress",
                        "glXGetProcAddressARB",
                        "glXGetClientString",
                        "glXQueryServerString",
                        "glXGetConfig",
                        "glXGetFBConfigAttrib",
                        "glXGetCurrentContext",
                        "glXGetCurrentDisplay",
                        "glXGetCurrentDrawable",
                        "glXIsDirect",
                        "glXSwapIntervalEXT",
                        "glXSwapIntervalMESA",
                        "glXSwapIntervalSGI",
                        "glXWaitGL",
                        "glXWaitX",
                        "glXQueryDrawable",
                        "glXCreateWindow",
                        "glXDestroyWindow",
                        "eglGetDisplay",
                        "eglGetPlatformDisplay",
                        "eglGetPlatformDisplayEXT",
                        "eglInitialize",
                        "eglTerminate",
                        "eglChooseConfig",
                        "eglGetConfigs",
                        "eglGetConfigAttrib",
                        "eglBindAPI",
                        "eglCreateContext",
                        "eglDestroyContext",
                        "eglCreateWindowSurface",
                        "eglCreatePlatformWindowSurface",
                        "eglCreatePbufferSurface",
                        "eglDestroySurface",
                        "eglMakeCurrent",
                        "eglQuerySurface",
                        "eglQueryContext",
                        "eglQueryString",
                        "eglSwapInterval",
                        "eglGetError",
                        "eglGetProcAddress",
                        "eglGetCurrentContext",
                        "eglGetCurrentSurface",
                        "eglGetCurrentDisplay",
                        "eglReleaseThread",
                        "eglWaitClient",
                        "eglWaitGL",
                        "eglWaitNative",
                        "eglSurfaceAttrib",
                        "glGetError",
                        "glGetString",
                        "glGetStringi",
                        "glGetIntegerv",
                        "glGetFloatv",
                        "glGetDoublev",
                        "glGetBooleanv",
                        "glIsEnabled",
                        "glIsList",
                        "glFlush",
                        "glFinish",
                        "glHint",
                        "glPixelStorei",
                        "glPixelStoref",
                        "glDrawBuffer",
                        "glReadBuffer",
                        "glReadPixels",
                        "glGetTexLevelParameteriv",
                        "glClearStencil",
                        "glClearAccum",
                        "glClearIndex",
                        "glStencilMask"}) {
    h[f] = nothing;
  }
  // Texture, fog, stencil and other state whose effect is reported when it is
  // enabled while drawing (check_draw_state): setting it alone draws nothing.
  for (const char* f : {"glTexImage1D",
                        "glTexImage2D",
                        "glTexImage3D",
                        "glTexSubImage2D",
                        "glBindTexture",
                        "glGenTextures",
                        "glDeleteTextures",
                        "glTexParameteri",
                        "glTexParameterf",
                        "glTexParameteriv",
                        "glTexParameterfv",
                        "glTexEnvi",
                        "glTexEnvf",
                        "glTexEnviv",
                        "glTexEnvfv",
                        "glTexGeni",
                        "glTexGenf",
                        "glTexGeniv",
                        "glTexGenfv",
                        "glTexGend",
                        "glTexGendv",
                        "glFogf",
                        "glFogi",
                        "glFogfv",
                        "glFogiv",
                        "glStencilFunc",
                        "glStencilOp",
                        "glLineStipple",
                        "glPolygonStipple",
                        "glClipPlane",
                        "glLogicOp",
                        "glBuild2DMipmaps",
                        "gluBuild2DMipmaps",
                        "glPixelTransferf",
                        "glPixelTransferi",
                        "glActiveTexture",
                        "glClientActiveTexture"}) {
    h[f] = [](State& s, const TraceCall& c) {
      s.ignored(c.function + " (state used only when enabled)");
    };
  }
  h["glAlphaFunc"] = [](State& s, const TraceCall& c) { s.alpha_func = enum_arg(c, 0); };
  // A program that reads a matrix back tells the driver what OpenGL computed:
  // a driver matrix that differs (beyond float rounding) is reported, so a
  // state-tracking error cannot go unnoticed.
  h["glGetFloatv"] = h["glGetDoublev"] = [](State& s, const TraceCall& c) {
    const uint32_t pname = enum_arg(c, 0);
    if (pname != en::MODELVIEW_MATRIX && pname != en::PROJECTION_MATRIX) return;
    if (c.args.size() < 2 || c.args[1].kind != TraceValue::Kind::array) return;
    const std::vector<double> m = numbers(c, 1);
    if (m.size() != 16) return;
    const glm::mat4& ours = pname == en::MODELVIEW_MATRIX ? s.modelview.top() : s.projection.top();
    for (int i = 0; i < 16; ++i) {
      const double want = m[static_cast<size_t>(i)], got = ours[i / 4][i % 4];
      if (std::fabs(got - want) > 1e-4 * std::max(1.0, std::fabs(want))) {
        s.unsupported(
            std::string("driver matrix differs from the program's glGet of ") +
            (pname == en::MODELVIEW_MATRIX ? "GL_MODELVIEW_MATRIX" : "GL_PROJECTION_MATRIX"));
        return;
      }
    }
  };

  h["glViewport"] = [](State& s, const TraceCall& c) {
    if (int_arg(c, 2) < 0 || int_arg(c, 3) < 0) {
      return s.ignored(c.function + " with a negative size (GL error)");
    }
    s.viewport = {int_arg(c, 0), int_arg(c, 1), int_arg(c, 2), int_arg(c, 3)};
    // apitrace records a fake glViewport of the drawable's size after the
    // first make-current: the window size.
    if (!s.window_known && s.viewport[2] > 0 && s.viewport[3] > 0) {
      s.window_known = true;
      s.window_width = static_cast<int>(s.viewport[2]);
      s.window_height = static_cast<int>(s.viewport[3]);
      // GL's first make-current also sets the scissor box to the window.
      if (!s.scissor_set) s.scissor = s.viewport;
    }
  };
  h["glScissor"] = [](State& s, const TraceCall& c) {
    if (int_arg(c, 2) < 0 || int_arg(c, 3) < 0) {
      return s.ignored(c.function + " with a negative size (GL error)");
    }
    s.scissor = {int_arg(c, 0), int_arg(c, 1), int_arg(c, 2), int_arg(c, 3)};
    s.scissor_set = true;
  };
  h["glProvokingVertex"] = [](State& s, const TraceCall& c) {
    const uint32_t mode = enum_arg(c, 0);
    if (mode != en::FIRST_VERTEX_CONVENTION && mode != en::LAST_VERTEX_CONVENTION) {
      return s.ignored(c.function + " with an invalid mode (GL error)");
    }
    s.provoking_first = mode == en::FIRST_VERTEX_CONVENTION;
  };
  h["glProvokingVertexEXT"] = h["glProvokingVertex"];
  h["glDepthRange"] = [](State& s, const TraceCall& c) {
    // GL clamps both to [0, 1] when they are set.
    const auto unit = [](float v) { return v > 0.0f ? std::min(v, 1.0f) : 0.0f; };
    s.depth_near = unit(float_arg(c, 0)), s.depth_far = unit(float_arg(c, 1));
  };
  h["glDepthRangef"] = h["glDepthRange"];

  const auto enable = [](bool on) {
    return [on](State& s, const TraceCall& c) {
      const uint32_t cap = enum_arg(c, 0);
      if (on) {
        s.enabled.insert(cap);
        if (!c.args[0].name.empty()) s.cap_names[cap] = c.args[0].name;
        if (cap == en::COLOR_MATERIAL) s.apply_color_material();
      } else {
        s.enabled.erase(cap);
      }
    };
  };
  h["glEnable"] = enable(true);
  h["glDisable"] = enable(false);

  // Matrices.
  h["glMatrixMode"] = [](State& s, const TraceCall& c) { s.matrix_mode = enum_arg(c, 0); };
  h["glLoadIdentity"] = [](State& s, const TraceCall&) { s.current_stack().load_identity(); };
  const auto matrix_of = [](const TraceCall& c) {
    const std::vector<double> m = numbers_at_least(c, 0, 16);
    glm::mat4 out;
    for (int i = 0; i < 16; ++i) out[i / 4][i % 4] = static_cast<float>(m[static_cast<size_t>(i)]);
    return out;
  };
  for (const char* f : {"glLoadMatrixf", "glLoadMatrixd"}) {
    h[f] = [matrix_of](State& s, const TraceCall& c) { s.current_stack().load(matrix_of(c)); };
  }
  for (const char* f : {"glMultMatrixf", "glMultMatrixd"}) {
    h[f] = [matrix_of](State& s, const TraceCall& c) { s.current_stack().multiply(matrix_of(c)); };
  }
  for (const char* f : {"glRotatef", "glRotated"}) {
    h[f] = [](State& s, const TraceCall& c) {
      s.current_stack().rotate(float_arg(c, 0), float_arg(c, 1), float_arg(c, 2), float_arg(c, 3));
    };
  }
  for (const char* f : {"glTranslatef", "glTranslated"}) {
    h[f] = [](State& s, const TraceCall& c) {
      s.current_stack().translate(float_arg(c, 0), float_arg(c, 1), float_arg(c, 2));
    };
  }
  for (const char* f : {"glScalef", "glScaled"}) {
    h[f] = [](State& s, const TraceCall& c) {
      s.current_stack().scale(float_arg(c, 0), float_arg(c, 1), float_arg(c, 2));
    };
  }
  h["glFrustum"] = [](State& s, const TraceCall& c) {
    s.current_stack().frustum(float_arg(c, 0), float_arg(c, 1), float_arg(c, 2), float_arg(c, 3),
                              float_arg(c, 4), float_arg(c, 5));
  };
  h["glOrtho"] = [](State& s, const TraceCall& c) {
    s.current_stack().ortho(float_arg(c, 0), float_arg(c, 1), float_arg(c, 2), float_arg(c, 3),
                            float_arg(c, 4), float_arg(c, 5));
  };
  h["glPushMatrix"] = [](State& s, const TraceCall&) {
    if (!s.current_stack().push()) s.ignored("glPushMatrix overflowing the stack (GL error)");
  };
  h["glPopMatrix"] = [](State& s, const TraceCall&) {
    if (!s.current_stack().pop()) s.ignored("glPopMatrix underflowing the stack (GL error)");
  };

  // Immediate mode.
  h["glBegin"] = [](State& s, const TraceCall& c) {
    if (s.in_begin) return s.ignored("glBegin inside glBegin/glEnd (GL error)");
    s.in_begin = true;
    s.begin_mode = enum_arg(c, 0);
    s.begin_vertices.clear();
  };
  h["glEnd"] = [](State& s, const TraceCall& c) {
    if (!s.in_begin) return s.ignored("glEnd without glBegin (GL error)");
    s.in_begin = false;
    if (s.capture) s.emit(s.begin_mode, s.begin_vertices, c);
    s.begin_vertices.clear();
  };
  h["glEdgeFlag"] = [](State& s, const TraceCall& c) {
    s.edge_flag_cleared = num_arg(c, 0) == 0.0;
  };
  h["glRectf"] = [](State& s, const TraceCall& c) {
    const float x1 = float_arg(c, 0), y1 = float_arg(c, 1), x2 = float_arg(c, 2),
                y2 = float_arg(c, 3);
    std::vector<Vertex> v;
    for (const glm::vec2 p :
         {glm::vec2(x1, y1), glm::vec2(x2, y1), glm::vec2(x2, y2), glm::vec2(x1, y2)}) {
      v.push_back(s.make_vertex(glm::vec4(p, 0.0f, 1.0f)));
    }
    if (s.capture) s.emit(en::POLYGON, v, c);
  };
  h["glRecti"] = h["glRectd"] = h["glRects"] = h["glRectf"];

  // Client arrays.
  const auto client_state = [](bool on) {
    return [on](State& s, const TraceCall& c) {
      switch (enum_arg(c, 0)) {
        case en::VERTEX_ARRAY:
          s.vertex_array.enabled = on;
          break;
        case en::NORMAL_ARRAY:
          s.normal_array.enabled = on;
          break;
        case en::COLOR_ARRAY:
          s.color_array.enabled = on;
          break;
        case en::TEXTURE_COORD_ARRAY:
          s.texcoord_array.enabled = on;
          break;
        default:
          if (on) s.unsupported(c.function + "(" + hex(enum_arg(c, 0)) + ")");
          break;
      }
    };
  };
  h["glEnableClientState"] = client_state(true);
  h["glDisableClientState"] = client_state(false);
  h["glVertexPointer"] = [](State& s, const TraceCall& c) {
    s.set_pointer(s.vertex_array, c, static_cast<int>(int_arg(c, 0)), 1, 2, 3);
  };
  h["glColorPointer"] = [](State& s, const TraceCall& c) {
    s.set_pointer(s.color_array, c, static_cast<int>(int_arg(c, 0)), 1, 2, 3);
  };
  h["glTexCoordPointer"] = [](State& s, const TraceCall& c) {
    s.set_pointer(s.texcoord_array, c, static_cast<int>(int_arg(c, 0)), 1, 2, 3);
  };
  h["glNormalPointer"] = [](State& s, const TraceCall& c) {
    s.set_pointer(s.normal_array, c, 3, 0, 1, 2);
  };
  h["glBindBuffer"] = [](State& s, const TraceCall& c) { s.buffer_bound = int_arg(c, 1) != 0; };
  for (const char* f :
       {"glDrawArrays", "glDrawElements", "glDrawRangeElements", "glArrayElement"}) {
    h[f] = [](State& s, const TraceCall& c) {
      for (const TraceCall& e : s.expand_array_draw(c)) s.run(e);
    };
  }

  // Lighting.
  h["glLightf"] = h["glLighti"] = [](State& s, const TraceCall& c) { s.light(c, false); };
  h["glLightfv"] = h["glLightiv"] = [](State& s, const TraceCall& c) { s.light(c, true); };
  h["glMaterialf"] = h["glMateriali"] = [](State& s, const TraceCall& c) { s.material(c, false); };
  h["glMaterialfv"] = h["glMaterialiv"] = [](State& s, const TraceCall& c) { s.material(c, true); };
  h["glLightModelf"] =
      h["glLightModeli"] = [](State& s, const TraceCall& c) { s.light_model(c, false); };
  h["glLightModelfv"] =
      h["glLightModeliv"] = [](State& s, const TraceCall& c) { s.light_model(c, true); };
  h["glColorMaterial"] = [](State& s, const TraceCall& c) {
    s.color_material_face = enum_arg(c, 0);
    s.color_material_mode = enum_arg(c, 1);
    if (s.is_enabled(en::COLOR_MATERIAL)) s.apply_color_material();
  };

  // Rasterization and per-fragment state.
  h["glShadeModel"] = [](State& s, const TraceCall& c) { s.shade_model = enum_arg(c, 0); };
  h["glFrontFace"] = [](State& s, const TraceCall& c) { s.front_face = enum_arg(c, 0); };
  h["glCullFace"] = [](State& s, const TraceCall& c) { s.cull_face = enum_arg(c, 0); };
  h["glPolygonMode"] = [](State& s, const TraceCall& c) {
    const uint32_t face = enum_arg(c, 0), mode = enum_arg(c, 1);
    if (face != en::BACK) s.polygon_front = mode;
    if (face != en::FRONT) s.polygon_back = mode;
  };
  h["glDepthFunc"] = [](State& s, const TraceCall& c) { s.depth_func = enum_arg(c, 0); };
  h["glDepthMask"] = [](State& s, const TraceCall& c) { s.depth_mask = num_arg(c, 0) != 0.0; };
  h["glBlendFunc"] = [](State& s, const TraceCall& c) {
    s.blend_src = enum_arg(c, 0), s.blend_dst = enum_arg(c, 1);
    s.blend_unsupported = false;
  };
  h["glBlendFuncSeparate"] = [](State& s, const TraceCall& c) {
    s.blend_src = enum_arg(c, 0), s.blend_dst = enum_arg(c, 1);
    s.blend_unsupported = enum_arg(c, 2) != s.blend_src || enum_arg(c, 3) != s.blend_dst;
  };
  h["glBlendEquation"] = [](State& s, const TraceCall& c) { s.blend_eq = enum_arg(c, 0); };
  h["glColorMask"] = [](State& s, const TraceCall& c) {
    for (size_t i = 0; i < 4; ++i) s.color_mask[i] = num_arg(c, i) != 0.0;
  };
  h["glPolygonOffset"] = [](State& s, const TraceCall& c) {
    s.offset_factor = float_arg(c, 0), s.offset_units = float_arg(c, 1);
  };
  h["glLineWidth"] = [](State& s, const TraceCall& c) { s.line_width = float_arg(c, 0); };
  h["glPointSize"] = [](State& s, const TraceCall& c) { s.point_size = float_arg(c, 0); };
  h["glClearColor"] = [](State& s, const TraceCall& c) {
    for (int i = 0; i < 4; ++i) {
      s.clear_color[i] = std::clamp(float_arg(c, static_cast<size_t>(i)), 0.0f, 1.0f);
    }
  };
  h["glClearDepth"] = h["glClearDepthf"] = [](State& s, const TraceCall& c) {
    s.clear_depth = std::clamp(float_arg(c, 0), 0.0f, 1.0f);
  };
  h["glClear"] = [](State& s, const TraceCall& c) { s.clear(c); };

  // Display lists.
  h["glGenLists"] = nothing;  // names come back in the trace's return values
  h["glNewList"] = [](State& s, const TraceCall& c) {
    if (s.compiling) return s.ignored("glNewList inside glNewList (GL error)");
    s.compiling = true;
    s.compiling_list = static_cast<uint32_t>(int_arg(c, 0));
    s.compile_and_execute = enum_arg(c, 1) == en::COMPILE_AND_EXECUTE;
    s.list_calls.clear();
  };
  h["glEndList"] = [](State& s, const TraceCall&) {
    if (!s.compiling) return s.ignored("glEndList without glNewList (GL error)");
    s.compiling = false;
    s.lists[s.compiling_list] = std::move(s.list_calls);
    s.list_calls.clear();
  };
  h["glCallList"] = [](State& s, const TraceCall& c) {
    s.call_list(static_cast<uint32_t>(int_arg(c, 0)));
  };
  h["glCallLists"] = [](State& s, const TraceCall& c) { s.call_lists(c); };
  h["glListBase"] = [](State& s, const TraceCall& c) {
    s.list_base = static_cast<uint32_t>(int_arg(c, 0));
  };
  h["glDeleteLists"] = [](State& s, const TraceCall& c) {
    const int64_t first = int_arg(c, 0), range = int_arg(c, 1);
    for (int64_t i = 0; i < range; ++i) s.lists.erase(static_cast<uint32_t>(first + i));
  };
}

GlDriver::GlDriver() : m(std::make_unique<State>()) {
  m->start_frame();
}
GlDriver::~GlDriver() = default;

void GlDriver::set_capture(bool capture) {
  m->capture = capture;
}

bool GlDriver::call(const TraceCall& c) {
  if (ends_frame(c)) {
    ++m->frame.gl_calls;
    m->end_frame(c);
    return true;
  }
  m->dispatch(c);
  return false;
}

DriverFrame GlDriver::take_frame() {
  DriverFrame out = std::move(m->frame);
  ++m->frame_index;
  m->start_frame();
  return out;
}

}  // namespace gpusim::gl
