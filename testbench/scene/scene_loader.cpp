// load_scene(): parses a scene file (docs/scene-format.md), validates every
// value, and resolves it into what the models consume: matrices, eye-space
// lights, vertex arrays. Every problem becomes a one-line InputError naming the
// file and the JSON path, so a bad scene never reaches the models.
#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <initializer_list>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>

#include "testbench/scene/mesh_import.h"
#include "testbench/scene/scene.h"
#include "testbench/scene/texture_image.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;
// Ordered so unknown keys are reported in file order.
using Json = nlohmann::ordered_json;
using Out = nlohmann::json;

constexpr int64_t kMaxFramebufferSize = 8192;
constexpr int64_t kMaxSupersample = 8;
// How far from the render target's origin a viewport may reach, in pixels:
// half the guard band (hw/fixed_point.h), so the band always surrounds it.
constexpr int64_t kMaxViewportReach = 16384;
// The automatic camera (frame_meshes): its field of view, the direction from
// the meshes' centre to the eye (front, right and above: a three-quarter
// view) and its near and far planes' distance from the bounding sphere.
constexpr float kAutoFovy = 45.0f;
const glm::vec3 kAutoDirection{1.0f, 1.0f, 2.0f};
constexpr float kAutoDepthMargin = 1.1f;
// The format nests at most 5 deep; the limit keeps pathological files cheap.
constexpr size_t kMaxNesting = 32;

std::string member_path(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}
std::string element_path(const std::string& parent, size_t i) {
  return parent + "[" + std::to_string(i) + "]";
}

std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return s;
}

// A value as quoted in messages: scalars as written, containers summarised.
std::string describe(const Json& v) {
  if (v.is_array()) {
    return "an array of " + std::to_string(v.size()) + (v.size() == 1 ? " element" : " elements");
  }
  if (v.is_object()) return "an object";
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

// Floats go into the resolved JSON through their shortest decimal form, so
// stats.json shows 0.2 rather than 0.20000000298023224.
double tidy(float f) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, f);
  double d = f;
  std::from_chars(buf, r.ptr, d);
  return d;
}
Out out_vec(const glm::vec3& v) {
  return Out::array({tidy(v.x), tidy(v.y), tidy(v.z)});
}
Out out_vec(const glm::vec4& v) {
  return Out::array({tidy(v.x), tidy(v.y), tidy(v.z), tidy(v.w)});
}
// Rows, as matrices are written in scene files (glm is column-major: m[col][row]).
Out out_mat(const glm::mat4& m) {
  Out rows = Out::array();
  for (int r = 0; r < 4; ++r)
    rows.push_back(out_vec(glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r])));
  return rows;
}

bool all_finite(const glm::mat3& m) {
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) {
      if (!std::isfinite(m[c][r])) return false;
    }
  }
  return true;
}

// A JSON value and its path in the file ("draws[2].state.cull").
struct At {
  const Json& v;
  std::string path;
};

class SceneReader {
 public:
  explicit SceneReader(std::string file, SceneLoadStep step = {})
      : file_(std::move(file)), dir_(fs::path(file_).parent_path()), step_(std::move(step)) {}

  // The file named at construction.
  Scene read();
  // `text` as the contents of that file (mesh paths resolve against its
  // directory all the same).
  Scene read_text(const std::string& text);

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw InputError(one_line(file_ + ": " + (path.empty() ? "" : path + ": ") + problem));
  }
  [[noreturn]] void fail_value(const At& a, const std::string& expected) const {
    fail(a.path, expected + ", got " + describe(a.v));
  }

  Json parse(const std::string& text) const;

  // Structure.
  void expect_object(const At& a) const {
    if (!a.v.is_object()) fail_value(a, "expected an object");
  }
  void check_keys(const At& obj, std::initializer_list<std::string_view> allowed) const;
  bool has(const At& obj, std::string_view key) const { return obj.v.contains(key); }
  At member(const At& obj, std::string_view key) const {
    const auto it = obj.v.find(key);
    if (it == obj.v.end()) fail(obj.path, "missing key \"" + std::string(key) + "\"");
    return At{*it, member_path(obj.path, key)};
  }
  At element(const At& arr, size_t i) const { return At{arr.v[i], element_path(arr.path, i)}; }

  // Scalars and small vectors.
  float real(const At& a) const;
  int64_t integer(const At& a, int64_t lo, int64_t hi) const;
  bool boolean(const At& a) const {
    if (!a.v.is_boolean()) fail_value(a, "expected true or false");
    return a.v.get<bool>();
  }
  std::string string(const At& a) const {
    if (!a.v.is_string()) fail_value(a, "expected a string");
    return a.v.get<std::string>();
  }
  template <typename E>
  E enumeration(const At& a) const {
    const auto e = enum_from_string<E>(string(a));
    if (!e) fail_value(a, "expected one of " + enum_names<E>());
    return *e;
  }
  // `min`..`max` numbers; missing trailing ones are left as they are in `out`.
  void numbers(const At& a, size_t min, size_t max, float* out) const;
  glm::vec3 vec3(const At& a) const {
    glm::vec3 v;
    numbers(a, 3, 3, glm::value_ptr(v));
    return v;
  }
  glm::vec4 color(const At& a) const {
    glm::vec4 v;
    numbers(a, 4, 4, glm::value_ptr(v));
    return v;
  }
  glm::mat4 matrix(const At& a) const;

  // Sections.
  void read_framebuffer(const At& root, Scene& scene);
  // False when the camera is to be framed from the meshes (frame_meshes).
  bool read_camera(const At& root, Scene& scene);
  void set_look_at(Out& resolved, const glm::vec3& eye, const glm::vec3& target,
                   const glm::vec3& up);
  void set_perspective(Out& resolved, float fovy, float aspect, float near, float far);
  void frame_meshes(Scene& scene);
  void store_camera(Scene& scene, Out resolved) const;
  void read_lights(const At& root, Scene& scene);
  Light read_light(const At& a, Out& resolved);
  void place_lights(Scene& scene) const;
  void read_textures(const At& root, Scene& scene);
  Texture read_texture(const At& a, const std::string& name) const;
  // A level's texels, width x height of them in `format`.
  TextureImage read_texels(const At& texels, TextureFormat format, int width, int height) const;
  // A draw's "texture", "texcoords" and "texture_env" keys.
  void read_draw_texturing(const At& a, const Scene& scene, Draw& d) const;
  void read_draw(const At& a, Scene& scene);
  void read_clear(const At& a, Scene& scene);
  glm::mat4 read_transform(const At& a) const;
  Material read_material(const At& a) const;
  RenderState read_state(const At& a) const;
  // The state of a draw without "state": the frame's viewport and depth range.
  RenderState frame_state() const {
    RenderState s;
    s.viewport = frame_viewport_;
    s.depth_near = frame_depth_range_[0];
    s.depth_far = frame_depth_range_[1];
    return s;
  }
  // A viewport or a scissor: [x, y, width, height] in framebuffer pixels.
  PixelRect read_rect(const At& a, bool viewport) const;
  // A depth range [near, far], each in 0..1.
  std::array<float, 2> read_depth_range(const At& a) const;
  void finish_draw(Draw& d, const glm::mat4& model, const At& a, Scene& scene, Out resolved);
  void place_draws(Scene& scene) const;

  std::string file_;
  fs::path dir_;
  SceneLoadStep step_;
  glm::mat4 view_{1.0f};
  glm::mat4 projection_{1.0f};
  // What depends on the camera is resolved once every draw is read, since an
  // automatic camera frames the meshes: per light its direction or position,
  // per Draw its JSON path and whether it comes from a mesh file.
  std::vector<At> light_at_;
  // framebuffer.viewport and depth_range: every draw's defaults.
  std::optional<PixelRect> frame_viewport_;
  std::array<float, 2> frame_depth_range_{0.0f, 1.0f};
  unsigned supersample_ = 1;
  std::vector<std::string> draw_path_;
  std::vector<bool> draw_is_mesh_;
};

void SceneReader::check_keys(const At& obj, std::initializer_list<std::string_view> allowed) const {
  for (const auto& item : obj.v.items()) {
    bool known = false;
    for (auto k : allowed) known = known || item.key() == k;
    if (known) continue;
    std::string list;
    for (auto k : allowed) list += (list.empty() ? "" : ", ") + std::string(k);
    fail(member_path(obj.path, item.key()), "unknown key (allowed: " + list + ")");
  }
}

float SceneReader::real(const At& a) const {
  if (!a.v.is_number()) fail_value(a, "expected a number");
  const double d = a.v.get<double>();
  const float f = static_cast<float>(d);
  if (!std::isfinite(d) || !std::isfinite(f)) fail_value(a, "expected a number in float range");
  return f;
}

int64_t SceneReader::integer(const At& a, int64_t lo, int64_t hi) const {
  const std::string range =
      "expected an integer in " + std::to_string(lo) + ".." + std::to_string(hi);
  // nlohmann stores non-negative integers as unsigned, negative ones as signed.
  if (a.v.is_number_unsigned()) {
    const uint64_t u = a.v.get<uint64_t>();
    if (hi < 0 || u > static_cast<uint64_t>(hi) || static_cast<int64_t>(u) < lo) {
      fail_value(a, range);
    }
    return static_cast<int64_t>(u);
  }
  if (a.v.is_number_integer()) {
    const int64_t i = a.v.get<int64_t>();
    if (i < lo || i > hi) fail_value(a, range);
    return i;
  }
  fail_value(a, range);
}

void SceneReader::numbers(const At& a, size_t min, size_t max, float* out) const {
  const std::string count =
      min == max ? std::to_string(min) : std::to_string(min) + " or " + std::to_string(max);
  if (!a.v.is_array() || a.v.size() < min || a.v.size() > max) {
    fail_value(a, "expected an array of " + count + " numbers");
  }
  for (size_t i = 0; i < a.v.size(); ++i) out[i] = real(element(a, i));
}

glm::mat4 SceneReader::matrix(const At& a) const {
  if (!a.v.is_array() || a.v.size() != 4) fail_value(a, "expected 4 rows of 4 numbers");
  glm::mat4 m;
  for (int r = 0; r < 4; ++r) {
    glm::vec4 row;
    numbers(element(a, r), 4, 4, glm::value_ptr(row));
    for (int c = 0; c < 4; ++c) m[c][r] = row[c];
  }
  return m;
}

// Parses strict JSON, additionally rejecting duplicate keys (nlohmann would
// silently keep the last) and absurd nesting.
Json SceneReader::parse(const std::string& text) const {
  struct Frame {
    bool object = false;
    size_t index = 0;  // arrays: the element being parsed
    std::string key;   // objects: the member being parsed
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  // Path of the value being parsed, through the first `n` open containers.
  const auto path_of = [&](size_t n) {
    std::string p;
    for (size_t i = 0; i < n; ++i) {
      p = stack[i].object ? member_path(p, stack[i].key) : element_path(p, stack[i].index);
    }
    return p;
  };
  const auto element_done = [&] {
    if (!stack.empty() && !stack.back().object) ++stack.back().index;
  };
  const Json::parser_callback_t callback = [&](int, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
      case Json::parse_event_t::array_start:
        if (stack.size() >= kMaxNesting) fail(path_of(stack.size()), "nested too deeply");
        stack.emplace_back();
        stack.back().object = event == Json::parse_event_t::object_start;
        break;
      case Json::parse_event_t::key: {
        Frame& top = stack.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second) fail(path_of(stack.size()), "duplicate key");
        break;
      }
      case Json::parse_event_t::value:
        element_done();
        break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        stack.pop_back();
        element_done();
        break;
    }
    return true;
  };

  try {
    // `//` and `/* */` comments are allowed, as in GPU configurations
    // (hw/gpu_config.cpp); nlohmann counts lines and columns through them.
    return Json::parse(text, callback, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const Json::parse_error& e) {
    const std::string msg = e.what();
    // "[json.exception.parse_error.101] parse error at line 3, column 7: ..."
    const std::string at = "parse error at line ";
    const size_t p = msg.find(at);
    if (p != std::string::npos) fail("", msg.substr(p + at.size() - 5));
    const size_t b = msg.find("] ");
    fail("", "byte " + std::to_string(e.byte) + ": " +
                 (b == std::string::npos ? msg : msg.substr(b + 2)));
  } catch (const Json::exception& e) {
    // e.g. out_of_range.406 "number overflow parsing '1e400'", thrown while
    // reading the number, so `stack` still holds the path to it.
    const std::string msg = e.what();
    const size_t b = msg.find("] ");
    fail(path_of(stack.size()), b == std::string::npos ? msg : msg.substr(b + 2));
  }
}

Scene SceneReader::read() {
  std::error_code ec;
  if (fs::is_directory(file_, ec)) fail("", "is a directory, not a scene file");
  if (is_mesh_file_name(file_)) {
    // A mesh given as the scene: the mesh alone, framed by the automatic
    // camera and lit by one directional light travelling about as the
    // automatic camera looks (kAutoDirection), from a little above it.
    const nlohmann::json scene = {
        {"lights", {{{"type", "directional"}, {"direction", {-0.5, -1.5, -2.0}}}}},
        {"draws", {{{"mesh", fs::path(file_).filename().string()}}}}};
    Scene s = read_text(scene.dump());
    s.from_mesh_file = true;
    return s;
  }
  std::ifstream in(file_, std::ios::binary);
  if (!in) fail("", std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) fail("", "read error");
  return read_text(text.str());
}

Scene SceneReader::read_text(const std::string& text) {
  if (text.size() >= 2 &&
      ((text[0] == '\xFE' && text[1] == '\xFF') || (text[0] == '\xFF' && text[1] == '\xFE'))) {
    fail("", "is UTF-16 encoded; scene files are UTF-8 JSON");
  }
  // nlohmann reads a NUL byte as the end of the input: say what it is.
  const size_t nul = text.find('\0');
  // apitrace's files start with "at", then binary (its snappy container).
  if (nul != std::string::npos && text.compare(0, 2, "at") == 0) {
    fail("", "is an apitrace trace, not a scene file: gpusim replay renders it (docs/replay.md)");
  }
  if (nul != std::string::npos) {
    fail("", "byte " + std::to_string(nul) + " is NUL: not a JSON text file");
  }
  const Json json = parse(text);
  const At root{json, ""};
  expect_object(root);
  check_keys(root,
             {"framebuffer", "camera", "ambient", "lights", "textures", "draws", "visibility"});

  Scene scene;
  scene.path = file_;
  scene.resolved = Out::object();
  scene.resolved["file"] = file_;
  read_framebuffer(root, scene);
  scene.auto_camera = !read_camera(root, scene);
  if (has(root, "ambient")) scene.global_ambient = color(member(root, "ambient"));
  scene.resolved["ambient"] = out_vec(scene.global_ambient);
  read_lights(root, scene);
  if (has(root, "visibility")) {
    const At v = member(root, "visibility");
    const std::string name = string(v);
    if (name == "painter") {
      scene.visibility = Visibility::painter;
    } else if (name != "zbuffer") {
      fail_value(v, "expected one of zbuffer, painter");
    }
  }
  // Only a painter's frame says so: z-buffered frames' stats.json is unchanged.
  if (scene.visibility == Visibility::painter) scene.resolved["visibility"] = "painter";

  read_textures(root, scene);
  scene.resolved["draws"] = Out::array();
  if (has(root, "draws")) {
    const At draws = member(root, "draws");
    if (!draws.v.is_array()) fail_value(draws, "expected an array of draws");
    for (size_t i = 0; i < draws.v.size(); ++i) {
      const At entry = element(draws, i);
      if (entry.v.is_object() && has(entry, "clear")) {
        read_clear(entry, scene);
      } else {
        read_draw(entry, scene);
      }
    }
  }
  if (scene.auto_camera) frame_meshes(scene);
  place_lights(scene);
  place_draws(scene);
  return scene;
}

void SceneReader::read_framebuffer(const At& root, Scene& scene) {
  FramebufferDesc& fb = scene.framebuffer;
  if (has(root, "framebuffer")) {
    const At a = member(root, "framebuffer");
    expect_object(a);
    check_keys(a, {"width", "height", "samples", "supersample", "color_format", "depth_format",
                   "clear_color", "clear_depth", "viewport", "depth_range"});
    if (has(a, "width")) fb.width = integer(member(a, "width"), 1, kMaxFramebufferSize);
    if (has(a, "height")) fb.height = integer(member(a, "height"), 1, kMaxFramebufferSize);
    if (has(a, "color_format"))
      fb.color_format = enumeration<ColorFormat>(member(a, "color_format"));
    if (has(a, "depth_format"))
      fb.depth_format = enumeration<DepthFormat>(member(a, "depth_format"));
    if (has(a, "clear_color")) fb.clear_color = color(member(a, "clear_color"));
    if (has(a, "clear_depth")) {
      const At d = member(a, "clear_depth");
      fb.clear_depth = real(d);
      if (!(fb.clear_depth >= 0.0f && fb.clear_depth <= 1.0f)) fail_value(d, "expected 0..1");
    }
    if (has(a, "samples")) {
      const At s = member(a, "samples");
      fb.samples = static_cast<unsigned>(integer(s, 1, 16));
      if ((fb.samples & (fb.samples - 1)) != 0) fail_value(s, "expected 1, 2, 4, 8 or 16");
    }
    if (has(a, "supersample")) {
      const At k = member(a, "supersample");
      fb.supersample = static_cast<unsigned>(integer(k, 1, kMaxSupersample));
      // The render target is k times the image on each side.
      if (std::max(fb.width, fb.height) * int64_t{fb.supersample} > kMaxFramebufferSize) {
        fail(k.path, "a render target of " + std::to_string(fb.width * fb.supersample) + "x" +
                         std::to_string(fb.height * fb.supersample) + " exceeds " +
                         std::to_string(kMaxFramebufferSize) + " pixels on a side");
      }
    }
    supersample_ = fb.supersample;
    if (has(a, "viewport")) frame_viewport_ = read_rect(member(a, "viewport"), true);
    if (has(a, "depth_range")) frame_depth_range_ = read_depth_range(member(a, "depth_range"));
  }
  const PixelRect vp = frame_viewport_ ? *frame_viewport_ : PixelRect{0, 0, fb.width, fb.height};
  scene.resolved["framebuffer"] = {
      {"width", fb.width},
      {"height", fb.height},
      {"samples", fb.samples},
      {"supersample", fb.supersample},
      {"color_format", to_string(fb.color_format)},
      {"depth_format", to_string(fb.depth_format)},
      {"clear_color", out_vec(fb.clear_color)},
      {"clear_depth", tidy(fb.clear_depth)},
      {"viewport", {vp.x, vp.y, vp.width, vp.height}},
      {"depth_range", Out::array({tidy(frame_depth_range_[0]), tidy(frame_depth_range_[1])})}};
}

PixelRect SceneReader::read_rect(const At& a, bool viewport) const {
  if (!a.v.is_array() || a.v.size() != 4) {
    fail_value(a, "expected an array of 4 integers [x, y, width, height]");
  }
  // A viewport may start left of or below the framebuffer (OpenGL allows
  // it); a scissor outside it would only cut nothing, so it may not.
  const int64_t lo = viewport ? -kMaxFramebufferSize : 0;
  PixelRect r;
  r.x = static_cast<int32_t>(integer(element(a, 0), lo, kMaxFramebufferSize));
  r.y = static_cast<int32_t>(integer(element(a, 1), lo, kMaxFramebufferSize));
  r.width = static_cast<int32_t>(integer(element(a, 2), 1, kMaxFramebufferSize));
  r.height = static_cast<int32_t>(integer(element(a, 3), 1, kMaxFramebufferSize));
  // The guard band (docs/pipeline-spec.md, section 4) must hold the
  // viewport with room to spare in the render target: every edge within
  // +-kMaxViewportReach pixels of the origin once scaled by supersample.
  const int64_t k = supersample_;
  if (viewport && std::max({-r.x * k, -r.y * k, (int64_t{r.x} + r.width) * k,
                            (int64_t{r.y} + r.height) * k}) > kMaxViewportReach) {
    fail(a.path, "the viewport times supersample " + std::to_string(k) + " reaches beyond " +
                     std::to_string(kMaxViewportReach) + " pixels from the origin");
  }
  return r;
}

std::array<float, 2> SceneReader::read_depth_range(const At& a) const {
  if (!a.v.is_array() || a.v.size() != 2)
    fail_value(a, "expected an array of 2 numbers [near, far]");
  std::array<float, 2> r{};
  for (size_t i = 0; i < 2; ++i) {
    const At e = element(a, i);
    r[i] = real(e);
    if (!(r[i] >= 0.0f && r[i] <= 1.0f)) fail_value(e, "expected 0..1");
  }
  return r;
}

bool SceneReader::read_camera(const At& root, Scene& scene) {
  const FramebufferDesc& fb = scene.framebuffer;
  bool meshes = false;
  if (has(root, "draws") && root.v["draws"].is_array()) {
    for (const Json& d : root.v["draws"]) meshes = meshes || (d.is_object() && d.contains("mesh"));
  }
  Out resolved;
  if (!has(root, "camera")) {
    // Raw positions without a camera are clip coordinates, as always; meshes
    // come in their own units, so they are framed rather than left to chance.
    if (meshes) return false;
    resolved["type"] = "none";
  } else if (const At cam = member(root, "camera"); cam.v.is_string()) {
    if (cam.v.get<std::string>() != "auto") fail_value(cam, "expected an object or \"auto\"");
    if (!meshes) fail(cam.path, "\"auto\" frames the mesh draws, and the scene has none");
    return false;
  } else {
    if (!cam.v.is_object()) fail_value(cam, "expected an object or \"auto\"");
    if (has(cam, "type")) {
      const At type = member(cam, "type");
      const std::string t = string(type);
      const bool perspective = t == "perspective";
      if (!perspective && t != "orthographic") {
        fail_value(type, "expected one of perspective, orthographic");
      }
      if (perspective) {
        check_keys(cam, {"type", "fovy", "aspect", "near", "far", "eye", "target", "up"});
      } else {
        check_keys(
            cam, {"type", "left", "right", "bottom", "top", "near", "far", "eye", "target", "up"});
      }
      resolved["type"] = t;

      // Without eye/target/up the view is GL's default camera (identity).
      glm::vec3 eye{0.0f, 0.0f, 0.0f}, target{0.0f, 0.0f, -1.0f}, up{0.0f, 1.0f, 0.0f};
      if (has(cam, "eye")) eye = vec3(member(cam, "eye"));
      if (has(cam, "target")) target = vec3(member(cam, "target"));
      if (has(cam, "up")) up = vec3(member(cam, "up"));
      const glm::vec3 forward = target - eye;
      if (glm::length(forward) == 0.0f) fail(member_path(cam.path, "target"), "equals eye");
      if (glm::length(up) == 0.0f) fail(member_path(cam.path, "up"), "is the zero vector");
      if (glm::length(glm::cross(glm::normalize(forward), glm::normalize(up))) < 1e-6f) {
        fail(member_path(cam.path, "up"), "is parallel to the view direction (target - eye)");
      }
      set_look_at(resolved, eye, target, up);

      const At near_at = member(cam, "near"), far_at = member(cam, "far");
      const float near = real(near_at), far = real(far_at);
      if (!(far > near)) fail_value(far_at, "expected far > near (" + describe(near_at.v) + ")");
      if (perspective) {
        const At fovy_at = member(cam, "fovy");
        const float fovy = real(fovy_at);
        if (!(fovy > 0.0f && fovy < 180.0f)) fail_value(fovy_at, "expected degrees in (0, 180)");
        float aspect = static_cast<float>(fb.width) / static_cast<float>(fb.height);
        if (has(cam, "aspect")) {
          const At aspect_at = member(cam, "aspect");
          aspect = real(aspect_at);
          if (!(aspect > 0.0f)) fail_value(aspect_at, "expected a positive number");
        }
        if (!(near > 0.0f)) fail_value(near_at, "expected a positive number");
        set_perspective(resolved, fovy, aspect, near, far);
      } else {
        float box[4];
        const char* names[4] = {"left", "right", "bottom", "top"};
        for (int i = 0; i < 4; ++i) box[i] = real(member(cam, names[i]));
        if (!(box[1] > box[0])) fail_value(member(cam, "right"), "expected right > left");
        if (!(box[3] > box[2])) fail_value(member(cam, "top"), "expected top > bottom");
        projection_ = glm::ortho(box[0], box[1], box[2], box[3], near, far);
        for (int i = 0; i < 4; ++i) resolved[names[i]] = tidy(box[i]);
        resolved["near"] = tidy(near);
        resolved["far"] = tidy(far);
      }
    } else if (has(cam, "view") || has(cam, "projection")) {
      check_keys(cam, {"view", "projection"});
      view_ = matrix(member(cam, "view"));
      projection_ = matrix(member(cam, "projection"));
      resolved["type"] = "matrices";
    } else {
      fail(cam.path,
           "expected \"type\" (perspective, orthographic) or \"view\" and \"projection\" "
           "matrices");
    }
  }
  store_camera(scene, std::move(resolved));
  return true;
}

void SceneReader::set_look_at(Out& resolved, const glm::vec3& eye, const glm::vec3& target,
                              const glm::vec3& up) {
  view_ = glm::lookAt(eye, target, up);
  resolved["eye"] = out_vec(eye);
  resolved["target"] = out_vec(target);
  resolved["up"] = out_vec(up);
}

void SceneReader::set_perspective(Out& resolved, float fovy, float aspect, float near, float far) {
  projection_ = glm::perspective(glm::radians(fovy), aspect, near, far);
  resolved["fovy"] = tidy(fovy);
  resolved["aspect"] = tidy(aspect);
  resolved["near"] = tidy(near);
  resolved["far"] = tidy(far);
}

void SceneReader::store_camera(Scene& scene, Out resolved) const {
  resolved["view"] = out_mat(view_);
  resolved["projection"] = out_mat(projection_);
  scene.resolved["camera"] = std::move(resolved);
}

// The automatic camera (docs/scene-format.md, camera "auto"): a perspective
// camera whose view cone holds the sphere around the meshes' world box.
// Every value is a float written exactly into the resolved camera, so the
// camera copied into the scene renders the same frame.
void SceneReader::frame_meshes(Scene& scene) {
  Bounds box;
  for (size_t i = 0; i < scene.draws.size(); ++i) {
    if (draw_is_mesh_[i]) box.add(world_bounds(scene.draws[i]));
  }
  const glm::vec3 centre = (box.min + box.max) * 0.5f;
  float radius = glm::length(box.max - box.min) * 0.5f;
  if (!(radius > 0.0f)) radius = 1.0f;  // a single point: any size frames it
  if (!std::isfinite(radius) || !std::isfinite(glm::length(centre))) {
    fail("camera", "the meshes' bounding box overflows float: give the scene a camera");
  }
  const FramebufferDesc& fb = scene.framebuffer;
  const float fovy = kAutoFovy;
  const float aspect = static_cast<float>(fb.width) / static_cast<float>(fb.height);
  // Half the narrower of the two fields of view.
  const float half_y = glm::radians(fovy) * 0.5f;
  const float half = std::min(half_y, std::atan(aspect * std::tan(half_y)));
  const float distance = radius / std::sin(half);
  const glm::vec3 eye = centre + distance * glm::normalize(kAutoDirection);
  Out resolved;
  resolved["type"] = "perspective";
  resolved["auto"] = true;
  set_look_at(resolved, eye, centre, glm::vec3(0.0f, 1.0f, 0.0f));
  // The sphere spans distance -/+ radius in depth; the margin keeps its
  // nearest and farthest points off the planes after rounding.
  set_perspective(resolved, fovy, aspect, distance - kAutoDepthMargin * radius,
                  distance + kAutoDepthMargin * radius);
  store_camera(scene, std::move(resolved));
}

Out out_texture(const Texture& t) {
  return {{"format", std::string(to_string(t.format))},
          {"width", t.levels[0].width},
          {"height", t.levels[0].height},
          {"levels", t.levels.size()},
          {"wrap_s", std::string(to_string(t.sampler.wrap_s))},
          {"wrap_t", std::string(to_string(t.sampler.wrap_t))},
          {"min_filter", std::string(to_string(t.sampler.min_filter))},
          {"mag_filter", std::string(to_string(t.sampler.mag_filter))},
          {"lod_bias", tidy(t.sampler.lod_bias)},
          {"min_lod", tidy(t.sampler.min_lod)},
          {"max_lod", tidy(t.sampler.max_lod)}};
}

Out out_material(const Material& m) {
  return {{"ambient", out_vec(m.ambient)},
          {"diffuse", out_vec(m.diffuse)},
          {"specular", out_vec(m.specular)},
          {"emission", out_vec(m.emission)},
          {"shininess", tidy(m.shininess)}};
}

Out out_rect(const PixelRect& r) {
  return Out::array({r.x, r.y, r.width, r.height});
}

Out out_state(const RenderState& s, int width, int height) {
  Out blend = "off";
  if (s.blend) {
    blend = {{"src", std::string(to_string(s.blend_src))},
             {"dst", std::string(to_string(s.blend_dst))},
             {"equation", std::string(to_string(s.blend_equation))}};
  }
  return {{"cull", std::string(to_string(s.cull))},
          {"front_face", std::string(to_string(s.front_face))},
          {"depth_test", s.depth_test ? std::string(to_string(s.depth_func)) : "off"},
          {"depth_write", s.depth_write},
          {"polygon_offset", Out::array({tidy(s.offset_factor), tidy(s.offset_units)})},
          {"blend", blend},
          {"color_mask", s.color_mask},
          {"shading", std::string(to_string(s.shading))},
          {"line_width", tidy(s.line_width)},
          {"point_size", tidy(s.point_size)},
          {"line_rasterization", std::string(to_string(s.line_rasterization))},
          {"polygon_mode", std::string(to_string(s.polygon_mode))},
          {"viewport", out_rect(viewport_of(s, width, height))},
          {"depth_range", Out::array({tidy(s.depth_near), tidy(s.depth_far)})},
          {"scissor", s.scissor ? out_rect(*s.scissor) : Out("off")},
          {"provoking_vertex", std::string(to_string(s.provoking_vertex))},
          {"interpolation", std::string(to_string(s.interpolation))}};
}

void SceneReader::read_lights(const At& root, Scene& scene) {
  scene.resolved["lights"] = Out::array();
  if (!has(root, "lights")) return;
  const At lights = member(root, "lights");
  if (!lights.v.is_array()) fail_value(lights, "expected an array of lights");
  for (size_t i = 0; i < lights.v.size(); ++i) {
    Out resolved;
    scene.lights.push_back(read_light(element(lights, i), resolved));
    scene.resolved["lights"].push_back(resolved);
  }
}

Light SceneReader::read_light(const At& a, Out& resolved) {
  expect_object(a);
  const At type = member(a, "type");
  const std::string t = string(type);
  Light l;
  if (t == "directional") {
    check_keys(a, {"type", "direction", "ambient", "diffuse", "specular"});
    const At dir_at = member(a, "direction");
    const glm::vec3 dir = vec3(dir_at);
    // Scene files give the direction the light travels; the models want the
    // unit vector from the surface towards the light (place_lights).
    l.type = LightType::directional;
    l.vector = -dir;
    light_at_.push_back(dir_at);
    resolved["direction"] = out_vec(dir);
  } else if (t == "point") {
    check_keys(a, {"type", "position", "ambient", "diffuse", "specular", "attenuation"});
    const At pos_at = member(a, "position");
    const glm::vec3 pos = vec3(pos_at);
    l.type = LightType::point;
    l.vector = pos;  // to eye space in place_lights
    light_at_.push_back(pos_at);
    if (has(a, "attenuation")) {
      const At att = member(a, "attenuation");
      float k[3];
      numbers(att, 3, 3, k);
      if (k[0] < 0.0f || k[1] < 0.0f || k[2] < 0.0f || k[0] + k[1] + k[2] == 0.0f) {
        fail(att.path, "expected non-negative [constant, linear, quadratic], not all zero");
      }
      l.constant_attenuation = k[0];
      l.linear_attenuation = k[1];
      l.quadratic_attenuation = k[2];
    }
    resolved["position"] = out_vec(pos);
    resolved["attenuation"] = Out::array(
        {tidy(l.constant_attenuation), tidy(l.linear_attenuation), tidy(l.quadratic_attenuation)});
  } else {
    fail_value(type, "expected one of directional, point");
  }
  if (has(a, "ambient")) l.ambient = color(member(a, "ambient"));
  if (has(a, "diffuse")) l.diffuse = color(member(a, "diffuse"));
  if (has(a, "specular")) l.specular = color(member(a, "specular"));
  resolved["type"] = t;
  resolved["ambient"] = out_vec(l.ambient);
  resolved["diffuse"] = out_vec(l.diffuse);
  resolved["specular"] = out_vec(l.specular);
  return l;
}

// Lights to eye space, with the camera now known.
void SceneReader::place_lights(Scene& scene) const {
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    Light& l = scene.lights[i];
    if (l.type == LightType::directional) {
      const glm::vec3 towards = glm::mat3(view_) * l.vector;
      if (!(glm::length(towards) > 0.0f) || !std::isfinite(glm::length(towards))) {
        fail_value(light_at_[i], "expected a direction that is non-zero in eye space");
      }
      l.vector = glm::normalize(towards);
    } else {
      l.vector = glm::vec3(view_ * glm::vec4(l.vector, 1.0f));
      if (!std::isfinite(l.vector.x) || !std::isfinite(l.vector.y) || !std::isfinite(l.vector.z)) {
        fail_value(light_at_[i], "expected a position that is finite in eye space");
      }
    }
    scene.resolved["lights"][i]["eye_vector"] = out_vec(l.vector);
  }
}

glm::mat4 SceneReader::read_transform(const At& a) const {
  expect_object(a);
  if (has(a, "matrix")) {
    for (const auto& item : a.v.items()) {
      if (item.key() != "matrix") {
        fail(member_path(a.path, item.key()), "cannot be combined with \"matrix\"");
      }
    }
    return matrix(member(a, "matrix"));
  }
  check_keys(a, {"translate", "rotate", "scale", "matrix"});
  glm::mat4 t{1.0f}, r{1.0f}, s{1.0f};
  if (has(a, "translate")) t = glm::translate(glm::mat4(1.0f), vec3(member(a, "translate")));
  if (has(a, "rotate")) {
    const At rot = member(a, "rotate");
    const auto rotation = [&](const At& e) {
      float v[4];
      numbers(e, 4, 4, v);
      const glm::vec3 axis{v[1], v[2], v[3]};
      if (glm::length(axis) == 0.0f) fail(e.path, "the rotation axis is the zero vector");
      return glm::rotate(glm::mat4(1.0f), glm::radians(v[0]), axis);
    };
    if (!rot.v.is_array()) fail_value(rot, "expected [degrees, x, y, z] or a list of them");
    if (!rot.v.empty() && rot.v[0].is_number()) {
      r = rotation(rot);
    } else {
      // Listed order is the order the rotations act on the object, so each
      // later one multiplies from the left.
      for (size_t i = 0; i < rot.v.size(); ++i) r = rotation(element(rot, i)) * r;
    }
  }
  if (has(a, "scale")) {
    const At sc = member(a, "scale");
    const glm::vec3 k = sc.v.is_number() ? glm::vec3(real(sc)) : vec3(sc);
    s = glm::scale(glm::mat4(1.0f), k);
  }
  return t * r * s;
}

Material SceneReader::read_material(const At& a) const {
  expect_object(a);
  check_keys(a, {"color", "ambient", "diffuse", "specular", "emission", "shininess"});
  Material m;
  if (has(a, "color")) m.ambient = m.diffuse = color(member(a, "color"));
  if (has(a, "ambient")) m.ambient = color(member(a, "ambient"));
  if (has(a, "diffuse")) m.diffuse = color(member(a, "diffuse"));
  if (has(a, "specular")) m.specular = color(member(a, "specular"));
  if (has(a, "emission")) m.emission = color(member(a, "emission"));
  if (has(a, "shininess")) {
    const At sh = member(a, "shininess");
    m.shininess = real(sh);
    if (!(m.shininess >= 0.0f && m.shininess <= 128.0f)) fail_value(sh, "expected 0..128");
  }
  return m;
}

RenderState SceneReader::read_state(const At& a) const {
  expect_object(a);
  check_keys(
      a, {"cull", "front_face", "depth_test", "depth_write", "polygon_offset", "blend",
          "color_mask", "shading", "line_width", "point_size", "line_rasterization", "polygon_mode",
          "viewport", "depth_range", "scissor", "provoking_vertex", "interpolation"});
  RenderState s = frame_state();
  if (has(a, "viewport")) s.viewport = read_rect(member(a, "viewport"), true);
  if (has(a, "depth_range")) {
    const std::array<float, 2> r = read_depth_range(member(a, "depth_range"));
    s.depth_near = r[0];
    s.depth_far = r[1];
  }
  if (has(a, "scissor")) {
    const At c = member(a, "scissor");
    if (!(c.v.is_string() && c.v.get<std::string>() == "off")) {
      if (!c.v.is_array()) fail_value(c, "expected \"off\" or [x, y, width, height]");
      s.scissor = read_rect(c, false);
    }
  }
  if (has(a, "cull")) s.cull = enumeration<CullMode>(member(a, "cull"));
  if (has(a, "front_face")) s.front_face = enumeration<FrontFace>(member(a, "front_face"));
  if (has(a, "depth_test")) {
    const At d = member(a, "depth_test");
    const std::string name = string(d);
    if (name == "off") {
      s.depth_test = false;
    } else if (const auto f = enum_from_string<CompareFunc>(name)) {
      s.depth_func = *f;
    } else {
      fail_value(d, "expected one of off, " + enum_names<CompareFunc>());
    }
  }
  if (has(a, "depth_write")) s.depth_write = boolean(member(a, "depth_write"));
  if (has(a, "polygon_offset")) {
    float k[2];
    numbers(member(a, "polygon_offset"), 2, 2, k);
    s.offset_factor = k[0];
    s.offset_units = k[1];
  }
  if (has(a, "blend")) {
    const At b = member(a, "blend");
    const std::string expected = "expected \"off\" or an object {src, dst, equation}";
    if (b.v.is_object()) {
      check_keys(b, {"src", "dst", "equation"});
      s.blend = true;
      if (has(b, "src")) s.blend_src = enumeration<BlendFactor>(member(b, "src"));
      if (has(b, "dst")) s.blend_dst = enumeration<BlendFactor>(member(b, "dst"));
      if (has(b, "equation")) s.blend_equation = enumeration<BlendEquation>(member(b, "equation"));
    } else if (!(b.v.is_string() && b.v.get<std::string>() == "off")) {
      fail_value(b, expected);
    }
  }
  if (has(a, "color_mask")) {
    const At m = member(a, "color_mask");
    if (!m.v.is_array() || m.v.size() != 4) fail_value(m, "expected an array of 4 booleans");
    for (size_t i = 0; i < 4; ++i) s.color_mask[i] = boolean(element(m, i));
  }
  if (has(a, "shading")) s.shading = enumeration<Shading>(member(a, "shading"));
  for (auto [key, value] :
       {std::pair{"line_width", &s.line_width}, {"point_size", &s.point_size}}) {
    if (!has(a, key)) continue;
    const At w = member(a, key);
    *value = real(w);
    if (!(*value > 0.0f && *value <= kMaxLineWidth)) fail_value(w, "expected 0 < value <= 255");
  }
  if (has(a, "line_rasterization")) {
    s.line_rasterization = enumeration<LineRasterization>(member(a, "line_rasterization"));
  }
  if (has(a, "polygon_mode")) s.polygon_mode = enumeration<PolygonMode>(member(a, "polygon_mode"));
  if (has(a, "provoking_vertex")) {
    s.provoking_vertex = enumeration<ProvokingVertex>(member(a, "provoking_vertex"));
  }
  if (has(a, "interpolation")) {
    s.interpolation = enumeration<Interpolation>(member(a, "interpolation"));
  }
  return s;
}

// {"clear": {"color": [r, g, b, a], "depth": d}}, either key or both: placed
// after the Draws read so far. Its values are checked as the framebuffer's
// clear_color and clear_depth are.
void SceneReader::read_clear(const At& a, Scene& scene) {
  check_keys(a, {"clear"});
  const At c = member(a, "clear");
  expect_object(c);
  check_keys(c, {"color", "depth"});
  if (!has(c, "color") && !has(c, "depth")) {
    fail(c.path, "clears nothing: expected \"color\", \"depth\" or both");
  }
  ClearState clear;
  clear.before_draw = static_cast<uint32_t>(scene.draws.size());
  Out resolved = {{"before_draw", clear.before_draw}};
  if (has(c, "color")) {
    clear.color = true;
    clear.color_value = color(member(c, "color"));
    resolved["color"] = out_vec(clear.color_value);
  }
  if (has(c, "depth")) {
    const At d = member(c, "depth");
    clear.depth = true;
    clear.depth_value = real(d);
    if (!(clear.depth_value >= 0.0f && clear.depth_value <= 1.0f)) fail_value(d, "expected 0..1");
    resolved["depth"] = tidy(clear.depth_value);
  }
  if (!scene.resolved.contains("clears")) scene.resolved["clears"] = Out::array();
  scene.resolved["clears"].push_back(std::move(resolved));
  scene.clears.push_back(clear);
}

void SceneReader::read_textures(const At& root, Scene& scene) {
  if (!has(root, "textures")) return;
  const At textures = member(root, "textures");
  if (!textures.v.is_object()) fail_value(textures, "expected an object of named textures");
  Out resolved = Out::object();
  for (const auto& item : textures.v.items()) {
    const At a{item.value(), member_path(textures.path, item.key())};
    Texture t = read_texture(a, item.key());
    resolved[item.key()] = out_texture(t);
    scene.textures.push_back(std::move(t));
  }
  scene.resolved["textures"] = std::move(resolved);
}

TextureImage SceneReader::read_texels(const At& texels, TextureFormat format, int width,
                                      int height) const {
  TextureImage level;
  level.width = width;
  level.height = height;
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (!texels.v.is_array() || texels.v.size() != count) {
    fail_value(texels, "expected an array of " + std::to_string(count) + " texels (" +
                           std::to_string(width) + " x " + std::to_string(height) + ")");
  }
  const unsigned channels = channel_count(format);
  level.texels.reserve(count * texel_bytes(format));
  for (size_t i = 0; i < count; ++i) {
    const At texel = element(texels, i);
    if (!texel.v.is_array() || texel.v.size() != channels) {
      fail_value(texel, "expected " + std::to_string(channels) + " channels for format " +
                            std::string(to_string(format)));
    }
    std::array<unsigned, 4> v{};
    for (unsigned c = 0; c < channels; ++c) {
      v[c] =
          static_cast<unsigned>(integer(element(texel, c), 0, (1 << channel_bits(format, c)) - 1));
    }
    store_texel(format, v, level.texels);
  }
  return level;
}

Texture SceneReader::read_texture(const At& a, const std::string& name) const {
  expect_object(a);
  check_keys(a, {"file", "format", "width", "height", "texels", "mipmaps", "wrap", "wrap_s",
                 "wrap_t", "min_filter", "mag_filter", "lod_bias", "min_lod", "max_lod"});
  Texture t;
  t.name = name;
  std::optional<TextureFormat> format;
  if (has(a, "format")) format = enumeration<TextureFormat>(member(a, "format"));
  if (has(a, "file")) {
    // An image file: its size, and its channels' format unless "format" says.
    for (const char* key : {"width", "height", "texels"}) {
      if (has(a, key)) fail(member_path(a.path, key), "a texture from a \"file\" has its own");
    }
    const At f = member(a, "file");
    const std::string file_name = string(f);
    fs::path file = file_name;
    if (file.is_relative()) file = dir_ / file;
    try {
      t.levels.push_back(read_image_file(file.string(), format, &t.format));
    } catch (const TextureImageError& e) {
      fail(f.path, "cannot read \"" + file_name + "\": " + e.what());
    }
  } else {
    t.format = format.value_or(TextureFormat::rgba8);
    const int w = static_cast<int>(integer(member(a, "width"), 1, kMaxTextureSize));
    const int h = has(a, "height")
                      ? static_cast<int>(integer(member(a, "height"), 1, kMaxTextureSize))
                      : 1;  // a 1D texture
    // Inline texels: one array per texel, rows from the bottom, each with the
    // format's channels in its own precision (rgb565: [r 0..31, g 0..63,
    // b 0..31]; rgba4444: four of 0..15; the 8-bit formats 0..255 each).
    t.levels.push_back(read_texels(member(a, "texels"), t.format, w, h));
  }
  const int width = t.levels[0].width, height = t.levels[0].height;
  if (has(a, "mipmaps")) {
    // The rest of the chain down to 1 x 1: generated, or given level by level.
    const At m = member(a, "mipmaps");
    const auto more = [&t] {
      const TextureImage& last = t.levels.back();
      return last.width > 1 || last.height > 1;
    };
    if (m.v.is_string() && m.v.get<std::string>() == "generate") {
      generate_mipmaps(t);
    } else if (m.v.is_array()) {
      size_t expected = 0;  // levels after level 0 down to 1 x 1
      for (int w = width, h = height; w > 1 || h > 1;
           w = std::max(1, w / 2), h = std::max(1, h / 2))
        ++expected;
      if (m.v.size() != expected) {
        fail_value(m, "expected " + std::to_string(expected) +
                          " levels after level 0 (each half the last, down to 1 x 1)");
      }
      for (size_t i = 0; more(); ++i) {
        const TextureImage& last = t.levels.back();
        t.levels.push_back(read_texels(element(m, i), t.format, std::max(1, last.width / 2),
                                       std::max(1, last.height / 2)));
      }
    } else {
      fail_value(m, "expected \"generate\" or an array of levels (each an array of texels)");
    }
  }

  if (has(a, "wrap")) {
    t.sampler.wrap_s = t.sampler.wrap_t = enumeration<TextureWrap>(member(a, "wrap"));
  }
  if (has(a, "wrap_s")) t.sampler.wrap_s = enumeration<TextureWrap>(member(a, "wrap_s"));
  if (has(a, "wrap_t")) t.sampler.wrap_t = enumeration<TextureWrap>(member(a, "wrap_t"));
  // GL's default minification filter, NEAREST_MIPMAP_LINEAR, makes a texture
  // without a mipmap chain incomplete: such a texture minifies with LINEAR
  // unless it says otherwise.
  t.sampler.min_filter =
      t.levels.size() > 1 ? TextureFilter::nearest_mipmap_linear : TextureFilter::linear;
  if (has(a, "min_filter")) {
    const At m = member(a, "min_filter");
    t.sampler.min_filter = enumeration<TextureFilter>(m);
    if (uses_mipmaps(t.sampler.min_filter) && t.levels.size() == 1 &&
        (t.levels[0].width > 1 || t.levels[0].height > 1)) {
      fail_value(m,
                 "a mipmap filter needs \"mipmaps\" (\"generate\" or the levels); expected "
                 "nearest or linear");
    }
  }
  if (has(a, "mag_filter")) {
    const At m = member(a, "mag_filter");
    t.sampler.mag_filter = enumeration<TextureFilter>(m);
    if (uses_mipmaps(t.sampler.mag_filter)) fail_value(m, "expected nearest or linear");
  }
  const auto lod = [&](const char* key, float& out) {
    if (!has(a, key)) return;
    const At v = member(a, key);
    out = real(v);
    if (!(std::fabs(out) <= kDefaultLodLimit)) fail_value(v, "expected -1000..1000");
  };
  lod("lod_bias", t.sampler.lod_bias);
  lod("min_lod", t.sampler.min_lod);
  lod("max_lod", t.sampler.max_lod);
  // What the texture unit does not sample yet: say so rather than render it otherwise.
  for (const char* key : {"wrap", "wrap_s", "wrap_t"}) {
    if (!has(a, key)) continue;
    const At w = member(a, key);
    const TextureWrap mode = enumeration<TextureWrap>(w);
    if (mode != TextureWrap::repeat && mode != TextureWrap::clamp_to_edge) {
      fail_value(w,
                 "wrap modes clamp and mirrored_repeat are not supported yet; expected repeat "
                 "or clamp_to_edge");
    }
  }
  return t;
}

void SceneReader::read_draw_texturing(const At& a, const Scene& scene, Draw& d) const {
  if (!has(a, "texture")) {
    for (const char* key : {"texcoords", "texture_env"}) {
      if (has(a, key)) fail(member_path(a.path, key), "needs a \"texture\" in the same draw");
    }
    return;
  }
  const At tex = member(a, "texture");
  const std::string name = string(tex);
  const auto it = std::find_if(scene.textures.begin(), scene.textures.end(),
                               [&](const Texture& t) { return t.name == name; });
  if (it == scene.textures.end()) fail_value(tex, "expected the name of one of \"textures\"");
  d.texture = static_cast<int>(it - scene.textures.begin());
  const At tc = member(a, "texcoords");
  if (!tc.v.is_array() || tc.v.size() != d.positions.size()) {
    fail_value(tc, "expected an array of " + std::to_string(d.positions.size()) +
                       " texture coordinates [s, t] (one per position)");
  }
  for (size_t i = 0; i < tc.v.size(); ++i) {
    glm::vec2 st{0.0f};
    numbers(element(tc, i), 1, 2, glm::value_ptr(st));
    d.texcoords.push_back(st);
  }
  if (has(a, "texture_env")) {
    const At env = member(a, "texture_env");
    if (env.v.is_string()) {
      d.texture_env.mode = enumeration<TextureEnvMode>(env);
    } else {
      expect_object(env);
      check_keys(env, {"mode", "color"});
      d.texture_env.mode = enumeration<TextureEnvMode>(member(env, "mode"));
      if (has(env, "color")) d.texture_env.color = color(member(env, "color"));
    }
  }
}

void SceneReader::read_draw(const At& a, Scene& scene) {
  expect_object(a);
  const bool is_mesh = has(a, "mesh");
  if (is_mesh) {
    check_keys(a, {"name", "mesh", "transform", "material", "lighting", "textures", "state"});
  } else if (has(a, "positions") || has(a, "primitive")) {
    check_keys(a, {"name", "primitive", "positions", "colors", "indices", "texture", "texcoords",
                   "texture_env", "transform", "material", "state"});
  } else {
    fail(a.path, "expected a \"mesh\", \"positions\" or \"clear\" key");
  }
  // JSON has no comments: a name says what a draw is for, in the file and in
  // stats.json ("draws[2] wide lines").
  std::string label = a.path;
  if (has(a, "name")) {
    const At n = member(a, "name");
    const std::string name = string(n);
    const bool printable = std::all_of(name.begin(), name.end(), [](char c) {
      return static_cast<unsigned char>(c) >= 0x20 && c != 0x7F;
    });
    if (name.empty() || name.size() > 200 || !printable) {
      fail_value(n, "expected a name of 1..200 characters, no control characters");
    }
    label += " " + name;
  }
  // The cheap checks first, so a typo is reported before a slow mesh import.
  const glm::mat4 model =
      has(a, "transform") ? read_transform(member(a, "transform")) : glm::mat4(1.0f);
  std::optional<Material> material;
  if (has(a, "material")) material = read_material(member(a, "material"));
  const RenderState state = has(a, "state") ? read_state(member(a, "state")) : frame_state();

  if (!is_mesh) {
    Draw d;
    d.name = label;
    if (has(a, "primitive")) d.primitive = enumeration<PrimitiveType>(member(a, "primitive"));
    const At pos = member(a, "positions");
    if (!pos.v.is_array()) fail_value(pos, "expected an array of [x, y, z] or [x, y, z, w]");
    for (size_t i = 0; i < pos.v.size(); ++i) {
      glm::vec4 p{0.0f, 0.0f, 0.0f, 1.0f};
      numbers(element(pos, i), 3, 4, glm::value_ptr(p));
      d.positions.push_back(p);
    }
    if (has(a, "colors")) {
      const At col = member(a, "colors");
      if (!col.v.is_array() || col.v.size() != d.positions.size()) {
        fail_value(col, "expected an array of " + std::to_string(d.positions.size()) +
                            " colours (one per position)");
      }
      for (size_t i = 0; i < col.v.size(); ++i) d.colors.push_back(color(element(col, i)));
    }
    if (has(a, "indices")) {
      const At idx = member(a, "indices");
      if (!idx.v.is_array()) fail_value(idx, "expected an array of indices");
      // Not range-checked against positions: the pipeline drops triangles with
      // out-of-range indices, and scenes may test exactly that.
      for (size_t i = 0; i < idx.v.size(); ++i) {
        d.indices.push_back(static_cast<uint32_t>(
            integer(element(idx, i), 0, std::numeric_limits<uint32_t>::max())));
      }
    }
    read_draw_texturing(a, scene, d);
    d.lighting = false;  // no normals
    d.material = material.value_or(Material{});
    d.state = state;
    finish_draw(d, model, a, scene, Out{{"material_from", material ? "scene" : "default"}});
    return;
  }

  const At mesh_at = member(a, "mesh");
  const std::string mesh = string(mesh_at);
  if (mesh.empty()) fail_value(mesh_at, "expected a file name");
  std::optional<bool> lighting;
  if (has(a, "lighting")) lighting = boolean(member(a, "lighting"));
  fs::path file = mesh;
  if (file.is_relative()) file = dir_ / file;

  // The materials' textures are used unless the draw says otherwise.
  const bool textures = has(a, "textures") ? boolean(member(a, "textures")) : true;
  std::vector<ImportedMesh> meshes;
  if (step_) step_("importing " + file.string() + " (" + mesh_at.path + ")");
  try {
    meshes = import_mesh(file.string(), textures);
  } catch (const MeshImportError& e) {
    const std::string why = e.what();
    const bool texture = why.rfind("texture ", 0) == 0;
    fail(mesh_at.path, "cannot read \"" + mesh + "\": " + why +
                           (texture ? " (\"textures\": false in the draw leaves them out)" : ""));
  } catch (const std::exception& e) {
    fail(mesh_at.path, "cannot read \"" + mesh + "\": " + e.what());
  }
  const std::string base = fs::path(mesh).filename().string();
  for (ImportedMesh& m : meshes) {
    Draw d;
    d.name = label + " " + base + " mesh " + std::to_string(m.index);
    // Triangle draws keep the name they always had; the others say what they are.
    if (m.primitive != PrimitiveType::triangles)
      d.name += " " + std::string(to_string(m.primitive));
    d.primitive = m.primitive;
    d.positions = std::move(m.positions);
    d.normals = std::move(m.normals);
    d.colors = std::move(m.colors);
    d.indices = std::move(m.indices);
    if (m.texture) {
      // The material's texture, once per scene however many meshes use it.
      const auto same = [&](const Texture& t) { return t.name == m.texture->name; };
      auto it = std::find_if(scene.textures.begin(), scene.textures.end(), same);
      if (it == scene.textures.end()) {
        if (!scene.resolved.contains("textures")) scene.resolved["textures"] = Out::object();
        scene.resolved["textures"][m.texture->name] = out_texture(*m.texture);
        scene.textures.push_back(*m.texture);
        it = scene.textures.end() - 1;
      }
      d.texture = static_cast<int>(it - scene.textures.begin());
      d.texcoords = std::move(m.texcoords);
    }
    if (m.primitive != PrimitiveType::triangles && d.normals.empty()) {
      // assimp generates normals for triangles only, and a file rarely gives
      // lines or points any: such a draw is unlit whatever "lighting" says, so
      // that "lighting": true still lights the file's triangles.
      d.lighting = false;
    } else {
      d.lighting = lighting.value_or(!scene.lights.empty() && !d.normals.empty());
    }
    if (d.lighting && d.normals.empty()) {
      fail(member_path(a.path, "lighting"), "mesh " + std::to_string(m.index) + " has no normals");
    }
    d.material = material.value_or(m.material);
    d.state = state;
    finish_draw(d, model, a, scene,
                Out{{"mesh", file.string()}, {"material_from", material ? "scene" : "mesh file"}});
  }
}

void SceneReader::finish_draw(Draw& d, const glm::mat4& model, const At& a, Scene& scene,
                              Out resolved) {
  d.model = model;
  const size_t n = d.vertex_count();
  resolved["name"] = d.name;
  resolved["primitive"] = std::string(to_string(d.primitive));
  resolved["positions"] = d.positions.size();
  resolved["normals"] = d.normals.size();
  resolved["colors"] = d.colors.size();
  resolved["indices"] = d.indices.size();
  if (d.texture >= 0) {
    resolved["texture"] = scene.textures[static_cast<size_t>(d.texture)].name;
    resolved["texcoords"] = d.texcoords.size();
    resolved["texture_env"] = {{"mode", std::string(to_string(d.texture_env.mode))},
                               {"color", out_vec(d.texture_env.color)}};
  }
  resolved["primitives"] = primitive_count(d.primitive, n);
  resolved["lighting"] = d.lighting;
  resolved["material"] = out_material(d.material);
  resolved["state"] = out_state(d.state, scene.framebuffer.width, scene.framebuffer.height);
  resolved["model"] = out_mat(model);
  draw_path_.push_back(a.path);
  draw_is_mesh_.push_back(resolved.contains("mesh"));
  scene.resolved["draws"].push_back(std::move(resolved));
  scene.draws.push_back(std::move(d));
}

// The draws' matrices, with the camera now known.
void SceneReader::place_draws(Scene& scene) const {
  for (size_t i = 0; i < scene.draws.size(); ++i) {
    Draw& d = scene.draws[i];
    const std::string& path = draw_path_[i];
    d.model_view = view_ * d.model;
    d.projection = projection_;
    d.mvp = projection_ * d.model_view;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) {
        if (!std::isfinite(d.mvp[c][r]) || !std::isfinite(d.model_view[c][r])) {
          fail(path, "the transform and camera matrices overflow float");
        }
      }
    }
    const glm::mat3 upper(d.model_view);
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(upper));
    if (glm::determinant(upper) == 0.0f || !all_finite(normal_matrix)) {
      if (d.lighting) {
        fail(path,
             "the model-view matrix is singular, so a lit draw's normals cannot be "
             "transformed (check transform and camera)");
      }
      d.normal_matrix = glm::mat3(1.0f);  // unused without lighting
    } else {
      d.normal_matrix = normal_matrix;
    }
  }
}

}  // namespace

Bounds world_bounds(const Draw& d) {
  Bounds b;
  for (const glm::vec4& p : d.positions) {
    const glm::vec4 q = d.model * p;
    if (q.w != 0.0f) b.add(glm::vec3(q) / q.w);
  }
  return b;
}

Scene load_scene(const std::string& path, const SceneLoadStep& step) {
  return SceneReader(path, step).read();
}

Scene load_scene_from_string(const std::string& text, const std::string& path) {
  return SceneReader(path).read_text(text);
}

}  // namespace gpusim
