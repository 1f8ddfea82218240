// A scene as the models consume it: framebuffer settings, lights in eye space,
// and draws with their vertex arrays, matrices and state, all resolved from the
// scene file (docs/scene-format.md) by load_scene().
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hw/draw_state.h"
#include "hw/input_error.h"
#include "hw/render_state.h"
#include "hw/texture_state.h"

namespace gpusim {

// A texture of the scene (docs/scene-format.md, "textures"): its stored
// texels level by level, each row-major from the bottom row, tightly packed
// in `format` (texel_bytes per texel), and its sampling state.
struct TextureImage {
  int width = 0, height = 0;
  std::vector<uint8_t> texels;
};
struct Texture {
  std::string name;
  TextureFormat format = TextureFormat::rgba8;
  TextureSampler sampler;
  std::vector<TextureImage> levels;  // level 0 first; at least one
};

struct Draw {
  std::string name;  // "draws[3] spider.obj mesh 0", "draws[2] wide lines": for stats
  PrimitiveType primitive = PrimitiveType::triangles;
  std::vector<glm::vec4> positions;  // object space
  std::vector<glm::vec3> normals;    // object space; empty, or one per position
  std::vector<glm::vec4> colors;     // empty, or one per position
  std::vector<uint32_t> indices;     // empty: non-indexed
  // Texturing (spec section 9c): the scene texture the draw samples (an
  // index into Scene::textures; -1: untextured), its texture coordinates
  // (s, t), one per position, and the texture environment.
  int texture = -1;
  std::vector<glm::vec2> texcoords;
  TextureEnv texture_env;
  // lighting: colours come from the lights and material (needs normals);
  // otherwise from `colors`, or the material's diffuse colour when empty.
  bool lighting = false;
  Material material;
  glm::mat4 model{1.0f};          // object -> world (the draw's transform)
  glm::mat4 model_view{1.0f};     // object -> eye
  glm::mat4 projection{1.0f};     // eye -> clip
  glm::mat4 mvp{1.0f};            // projection * model_view, computed in float by the loader
  glm::mat3 normal_matrix{1.0f};  // inverse transpose of model_view's upper 3x3
  RenderState state;

  // Vertices the draw references: indices.size() or positions.size().
  size_t vertex_count() const { return indices.empty() ? positions.size() : indices.size(); }
};

// An axis-aligned box; empty until a point is added.
struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};
  bool empty() const { return !(min.x <= max.x); }
  void add(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void add(const Bounds& b) {
    if (!b.empty()) add(b.min), add(b.max);
  }
};

// The box of a draw's positions after its transform (world space), each
// divided by its w (1 for meshes; raw positions may be homogeneous; w = 0 is
// skipped). Every position counts, referenced or not.
Bounds world_bounds(const Draw& d);

// How a frame resolves visibility: the models' depth test, or the driver's
// painter's algorithm (testbench/driver/painter_sort.h, docs/painter.md).
enum class Visibility : uint8_t { zbuffer, painter };

struct Scene {
  std::string path;  // the scene file, for messages
  FramebufferDesc framebuffer;
  // The loader chose the camera: the scene has mesh draws and no "camera"
  // key, or "camera": "auto" (docs/scene-format.md).
  bool auto_camera = false;
  // The file given was a mesh, not a scene file: the loader made the scene
  // (the mesh, the automatic camera, one light; docs/scene-format.md).
  bool from_mesh_file = false;
  glm::vec4 global_ambient{0.2f, 0.2f, 0.2f, 1.0f};
  std::vector<Light> lights;
  std::vector<Texture> textures;
  std::vector<Draw> draws;
  // Clear entries of the file's draw list, in order, each placed by its
  // before_draw (the number of Draws before it; a mesh entry may give
  // several). Every consumer that executes the draws executes these at
  // their places: the frame clear first, then, before draw i, every clear
  // with before_draw == i, and those with before_draw == draws.size() last.
  std::vector<ClearState> clears;
  Visibility visibility = Visibility::zbuffer;
  // The scene's settings with every default filled in, dumped into stats.json.
  nlohmann::json resolved;
};

// Told what the loader starts on that may take long (importing a mesh:
// assimp can spend seconds on a large one), for progress lines.
using SceneLoadStep = std::function<void(const std::string& what)>;

// Load and validate a scene file; throws InputError.
Scene load_scene(const std::string& path, const SceneLoadStep& step = {});
// The same for a scene file's contents: `path` names it in messages and mesh
// paths resolve against its directory (the scene parser's fuzz target).
Scene load_scene_from_string(const std::string& text, const std::string& path);

}  // namespace gpusim
