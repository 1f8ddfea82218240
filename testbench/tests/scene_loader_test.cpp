// load_scene(): values are checked against numbers derived independently of
// the loader (hand-computed matrices, counts read straight from the OBJ file),
// and every class of bad input against its one-line message.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <set>
#include <sstream>

#include "testbench/scene/scene.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

const std::string kSpider = "/usr/share/assimp/models/OBJ/spider.obj";

class SceneLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("gpusim_scene_test_" + std::to_string(getpid())) /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  Scene load(const std::string& json) { return load_scene(write("scene.json", json)); }

  // The message of the InputError `json` must raise; checks the one-line
  // "<file>: ..." shape common to all of them.
  std::string error_of(const std::string& json) {
    const std::string path = write("bad.json", json);
    try {
      load_scene(path);
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      return msg.substr(path.size() + 2);
    }
    ADD_FAILURE() << "no InputError for " << json;
    return "";
  }

  fs::path dir_;
};

void expect_near(const glm::vec4& got, const glm::vec4& want, float tol = 1e-5f) {
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(got[i], want[i], tol) << "component " << i;
}
void expect_near(const glm::vec3& got, const glm::vec3& want, float tol = 1e-5f) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], tol) << "component " << i;
}

// ---------------------------------------------------------------- meshes

TEST_F(SceneLoaderTest, SpiderMatchesObjFile) {
  // Read the OBJ directly: positions, triangles after fan triangulation, the
  // materials used, and the Kd of each material in the .mtl.
  std::vector<glm::vec3> obj_vertices, obj_normals;
  std::set<int> referenced;
  size_t obj_triangles = 0;
  std::set<std::string> used_materials;
  {
    std::ifstream in(kSpider);
    ASSERT_TRUE(in) << kSpider;
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream ls(line);
      std::string tag;
      ls >> tag;
      if (tag == "v") {
        glm::vec3 v;
        ls >> v.x >> v.y >> v.z;
        obj_vertices.push_back(v);
      } else if (tag == "vn") {
        glm::vec3 n;
        ls >> n.x >> n.y >> n.z;
        obj_normals.push_back(n);
      } else if (tag == "f") {
        std::string corner;
        size_t n = 0;
        while (ls >> corner) {
          referenced.insert(std::stoi(corner) - 1);  // "12/3/4" -> 12
          ++n;
        }
        obj_triangles += n - 2;
      } else if (tag == "usemtl") {
        std::string m;
        ls >> m;
        used_materials.insert(m);
      }
    }
  }
  std::map<std::string, glm::vec3> kd;
  {
    std::ifstream in("/usr/share/assimp/models/OBJ/spider.mtl");
    std::string line, current;
    while (std::getline(in, line)) {
      std::istringstream ls(line);
      std::string tag;
      ls >> tag;
      if (tag == "newmtl") ls >> current;
      if (tag == "Kd") ls >> kd[current].x >> kd[current].y >> kd[current].z;
    }
  }
  ASSERT_EQ(obj_vertices.size(), 762u);  // sanity of the parse above
  ASSERT_EQ(used_materials.size(), 4u);

  const Scene s = load(R"({"lights": [{"type": "directional", "direction": [0, 0, -1]}],
                           "draws": [{"mesh": ")" +
                       kSpider + R"("}]})");
  // PreTransformVertices merges the meshes sharing a material.
  ASSERT_EQ(s.draws.size(), used_materials.size());
  size_t triangles = 0;
  std::set<size_t> found;  // OBJ vertices the loaded positions match
  std::set<std::string> diffuse_seen;
  for (size_t i = 0; i < s.draws.size(); ++i) {
    const Draw& d = s.draws[i];
    EXPECT_EQ(d.name.rfind("draws[0] spider.obj mesh ", 0), 0u) << d.name;
    EXPECT_EQ(d.primitive, PrimitiveType::triangles);
    ASSERT_EQ(d.indices.size() % 3, 0u);
    triangles += d.indices.size() / 3;
    for (uint32_t idx : d.indices) ASSERT_LT(idx, d.positions.size());
    ASSERT_EQ(d.normals.size(), d.positions.size());
    // The file has normals (one of them zero), so assimp keeps them as they are.
    for (const glm::vec3& n : d.normals) {
      float best = 1e30f;
      for (const glm::vec3& f : obj_normals) best = std::min(best, glm::length(n - f));
      EXPECT_LT(best, 1e-4f) << "loaded normal not in the OBJ file";
    }
    EXPECT_TRUE(d.lighting);
    for (const glm::vec4& p : d.positions) {
      EXPECT_EQ(p.w, 1.0f);
      size_t best = 0;
      float best_dist = 1e30f;
      for (size_t k = 0; k < obj_vertices.size(); ++k) {
        const float dist = glm::length(glm::vec3(p) - obj_vertices[k]);
        if (dist < best_dist) best_dist = dist, best = k;
      }
      EXPECT_LT(best_dist, 1e-4f) << "loaded position not in the OBJ file";
      found.insert(best);
    }
    // The material comes from the .mtl: Kd of one of the used materials, Ka 0.2.
    bool matched = false;
    for (const auto& name : used_materials) {
      if (glm::length(glm::vec3(d.material.diffuse) - kd[name]) < 1e-5f) matched = true;
    }
    EXPECT_TRUE(matched) << d.name;
    expect_near(d.material.ambient, glm::vec4(0.2f, 0.2f, 0.2f, 1.0f));
    diffuse_seen.insert(std::to_string(d.material.diffuse.x));
  }
  EXPECT_EQ(triangles, obj_triangles);
  EXPECT_EQ(triangles, 1368u);
  // Every vertex a face uses made it into some draw (distinct OBJ vertices
  // can share a position, hence matching by nearest rather than by index).
  for (int r : referenced) {
    bool any = false;
    for (size_t f : found) any = any || glm::length(obj_vertices[f] - obj_vertices[r]) < 1e-4f;
    EXPECT_TRUE(any) << "OBJ vertex " << r + 1 << " missing";
  }
  // Skin, HLeibTex and BeinTex/Augentex (both 0.8) give three distinct Kd.
  EXPECT_EQ(diffuse_seen.size(), 3u);
  ASSERT_EQ(s.resolved["draws"].size(), s.draws.size());
  EXPECT_EQ(s.resolved["draws"][0]["mesh"], kSpider);
  EXPECT_EQ(s.resolved["draws"][0]["material_from"], "mesh file");
}

TEST_F(SceneLoaderTest, RelativeObjIsTriangulated) {
  // A quad and a pentagon: 2 + 3 triangles.
  write("shapes.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "v 2 0 0\nv 3 0 0\nv 3.5 1 0\nv 2.5 2 0\nv 1.5 1 0\n"
        "f 1 2 3 4\nf 5 6 7 8 9\n");
  const Scene s = load(R"({"draws": [{"mesh": "shapes.obj"}]})");
  ASSERT_EQ(s.draws.size(), 1u);
  const Draw& d = s.draws[0];
  EXPECT_EQ(d.primitive, PrimitiveType::triangles);
  EXPECT_EQ(d.indices.size(), 15u);
  EXPECT_EQ(d.positions.size(), 9u);
  EXPECT_EQ(d.normals.size(), 9u);  // generated (the file has none)
  EXPECT_FALSE(d.lighting);         // no lights in the scene
  EXPECT_EQ(s.resolved["draws"][0]["primitives"], 5);
  EXPECT_EQ(fs::path(s.resolved["draws"][0]["mesh"].get<std::string>()), dir_ / "shapes.obj");
  // Generated normals of a flat mesh in the z = 0 plane wound CCW point to +z.
  for (const glm::vec3& n : d.normals) expect_near(n, glm::vec3(0, 0, 1), 1e-5f);
}

// The OBJ file's faces, polylines and points, read by the test itself: what
// the loader's triangles, lines and points draws must hold, as positions.
struct ObjPrimitives {
  std::multiset<std::vector<float>> triangles, lines, points;  // x, y, z of each corner
};

ObjPrimitives read_obj_primitives(const std::string& text) {
  std::vector<std::vector<float>> v;
  ObjPrimitives out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      float x, y, z;
      ls >> x >> y >> z;
      v.push_back({x, y, z});
      continue;
    }
    std::vector<int> ids;
    for (int i; ls >> i;) ids.push_back(i - 1);
    const auto join = [&](std::initializer_list<int> corners) {
      std::vector<float> key;
      for (int c : corners) key.insert(key.end(), v[c].begin(), v[c].end());
      return key;
    };
    // OBJ: a face is a polygon (fan-triangulated), `l` a polyline, `p` points.
    if (tag == "f") {
      for (size_t i = 1; i + 1 < ids.size(); ++i) {
        out.triangles.insert(join({ids[0], ids[i], ids[i + 1]}));
      }
    }
    if (tag == "l") {
      for (size_t i = 0; i + 1 < ids.size(); ++i) out.lines.insert(join({ids[i], ids[i + 1]}));
    }
    if (tag == "p") {
      for (int i : ids) out.points.insert(join({i}));
    }
  }
  return out;
}

// A draw's primitives as positions, in the same form as read_obj_primitives.
std::multiset<std::vector<float>> draw_primitives(const Draw& d, size_t corners) {
  std::multiset<std::vector<float>> out;
  for (size_t i = 0; i + corners <= d.indices.size(); i += corners) {
    std::vector<float> key;
    for (size_t k = 0; k < corners; ++k) {
      const glm::vec4 p = d.positions.at(d.indices[i + k]);
      key.insert(key.end(), {p.x, p.y, p.z});
    }
    out.insert(key);
  }
  return out;
}

TEST_F(SceneLoaderTest, MeshLinesAndPointsBecomeDraws) {
  // A quad, a polyline of 4 vertices, a single segment, and 3 + 1 points.
  const std::string obj =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 3 1 0\nv 4 0 0\n"
      "f 1 2 3 4\n"
      "l 5 6 7 5\n"
      "l 1 3\n"
      "p 2 4 6\n"
      "p 7\n";
  write("mixed.obj", obj);
  const ObjPrimitives want = read_obj_primitives(obj);
  ASSERT_EQ(want.triangles.size(), 2u);  // the test's own reading, checked by hand
  ASSERT_EQ(want.lines.size(), 4u);
  ASSERT_EQ(want.points.size(), 4u);
  // "lighting": true lights the triangles; lines and points have no normals.
  const Scene s = load(R"({"lights": [{"type": "directional", "direction": [0, 0, -1]}],
      "draws": [{"mesh": "mixed.obj", "lighting": true, "transform": {"translate": [0, 0, -2]},
                 "material": {"color": [1, 0.5, 0, 1]},
                 "state": {"line_width": 3, "point_size": 5, "shading": "flat"}}]})");
  ASSERT_EQ(s.draws.size(), 3u);
  ASSERT_EQ(s.resolved["draws"].size(), 3u);
  int seen[3] = {0, 0, 0};
  for (size_t i = 0; i < s.draws.size(); ++i) {
    const Draw& d = s.draws[i];
    const nlohmann::json& r = s.resolved["draws"][i];
    SCOPED_TRACE(d.name);
    // Every part of the mesh draw shares its transform, material and state.
    EXPECT_EQ(d.model[3][2], -2.0f);
    expect_near(d.material.diffuse, glm::vec4(1, 0.5f, 0, 1));
    EXPECT_EQ(d.state.line_width, 3.0f);
    EXPECT_EQ(d.state.point_size, 5.0f);
    EXPECT_EQ(d.state.shading, Shading::flat);
    EXPECT_EQ(r["mesh"], (dir_ / "mixed.obj").string());
    EXPECT_EQ(r["primitive"], std::string(to_string(d.primitive)));
    EXPECT_EQ(d.name.rfind("draws[0] mixed.obj mesh ", 0), 0u);
    switch (d.primitive) {
      case PrimitiveType::triangles:
        ++seen[0];
        EXPECT_EQ(draw_primitives(d, 3), want.triangles);
        EXPECT_EQ(r["primitives"], want.triangles.size());
        EXPECT_TRUE(d.lighting);
        EXPECT_EQ(d.name.find("lines"), std::string::npos);
        break;
      case PrimitiveType::lines:
        ++seen[1];
        EXPECT_EQ(draw_primitives(d, 2), want.lines);
        EXPECT_EQ(r["primitives"], want.lines.size());
        EXPECT_FALSE(d.lighting);
        EXPECT_TRUE(d.normals.empty());
        EXPECT_EQ(r["lighting"], false);
        EXPECT_EQ(d.name.substr(d.name.size() - 6), " lines");
        break;
      case PrimitiveType::points:
        ++seen[2];
        EXPECT_EQ(draw_primitives(d, 1), want.points);
        EXPECT_EQ(r["primitives"], want.points.size());
        EXPECT_FALSE(d.lighting);
        EXPECT_EQ(d.name.substr(d.name.size() - 7), " points");
        break;
      default:
        ADD_FAILURE() << "unexpected primitive " << to_string(d.primitive);
    }
  }
  EXPECT_EQ(seen[0], 1);
  EXPECT_EQ(seen[1], 1);
  EXPECT_EQ(seen[2], 1);
}

TEST_F(SceneLoaderTest, MeshOfLinesOnly) {
  // A file of nothing but a polyline, which used to be "no triangles".
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\n";
  write("lines.obj", obj);
  const Scene s = load(R"({"draws": [{"mesh": "lines.obj"}]})");
  ASSERT_EQ(s.draws.size(), 1u);
  EXPECT_EQ(s.draws[0].primitive, PrimitiveType::lines);
  EXPECT_EQ(draw_primitives(s.draws[0], 2), read_obj_primitives(obj).lines);
  EXPECT_EQ(s.resolved["draws"][0]["primitives"], 2);
  EXPECT_EQ(s.draws[0].name, "draws[0] lines.obj mesh 0 lines");
}

TEST_F(SceneLoaderTest, PlyVertexColoursAndLightingOverride) {
  write("tri.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n");
  const Scene s = load(R"({"lights": [{"type": "point", "position": [0, 0, 1]}],
      "draws": [{"mesh": "tri.ply"}, {"mesh": "tri.ply", "lighting": false}]})");
  ASSERT_EQ(s.draws.size(), 2u);
  EXPECT_TRUE(s.draws[0].lighting);  // lights present and the mesh has normals
  EXPECT_FALSE(s.draws[1].lighting);
  EXPECT_EQ(s.draws[1].name, "draws[1] tri.ply mesh 0");
  const Draw& d = s.draws[0];
  ASSERT_EQ(d.colors.size(), 3u);
  ASSERT_EQ(d.indices.size(), 3u);
  // Map each corner's position to its colour, whatever order assimp keeps.
  for (uint32_t i : d.indices) {
    const glm::vec4 p = d.positions[i];
    const glm::vec4 want = p.x == 1.0f   ? glm::vec4(0, 1, 0, 1)
                           : p.y == 1.0f ? glm::vec4(0, 0, 1, 1)
                                         : glm::vec4(1, 0, 0, 1);
    expect_near(d.colors[i], want);
  }
}

TEST_F(SceneLoaderTest, MeshErrors) {
  // Vertices and no elements: assimp's validator refuses the empty mesh.
  write("vertices.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\n");
  write("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(error_of(R"({"draws": [{"mesh": "vertices.obj"}]})")
                .rfind("draws[0].mesh: cannot read \"vertices.obj\": Validation failed: ", 0),
            0u);
  const std::string missing = error_of(R"({"draws": [{"mesh": "missing.obj"}]})");
  EXPECT_EQ(missing.rfind("draws[0].mesh: cannot read \"missing.obj\": ", 0), 0u) << missing;
  EXPECT_GT(missing.size(), std::string("draws[0].mesh: cannot read \"missing.obj\": ").size());
  EXPECT_EQ(error_of(R"({"draws": [{"mesh": ""}]})"),
            "draws[0].mesh: expected a file name, got \"\"");
  // A lit mesh needs the inverse of its model-view matrix.
  EXPECT_NE(error_of(R"({"draws": [{"mesh": "flat.obj", "lighting": true,
                                     "transform": {"scale": [1, 0, 1]}}]})")
                .find("draws[0]: the model-view matrix is singular"),
            std::string::npos);
  // Unlit, the same transform is fine.
  const Scene s = load(R"({"draws": [{"mesh": "flat.obj", "transform": {"scale": [1, 0, 1]}}]})");
  EXPECT_EQ(s.draws.size(), 1u);
  EXPECT_EQ(s.draws[0].model_view[1][1], 0.0f);
}

// ---------------------------------------------------------------- cameras, transforms

TEST_F(SceneLoaderTest, PerspectiveMvpMatchesHandComputation) {
  // fovy 90 => cot(fovy/2) = 1; aspect 2; near 1, far 10. Eye on +z looking at
  // the origin, so view is a translation by -5 in z.
  // Model: scale 2 takes (1,0,0) to (2,0,0), rotating 90 degrees about z to
  // (0,2,0), translating to (1,2,0); eye space (1,2,-5).
  // clip = (x/aspect, y, (-(f+n)/(f-n)) z - 2fn/(f-n), -z)
  //      = (0.5, 2, 55/9 - 20/9, 5).
  for (const char* aspect : {R"("aspect": 2,)", ""}) {
    const Scene s = load(std::string(R"({"framebuffer": {"width": 200, "height": 100},
        "camera": {"type": "perspective", "fovy": 90, )") +
                         aspect + R"( "near": 1, "far": 10,
                   "eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
        "draws": [{"positions": [[1, 0, 0]], "transform":
                   {"translate": [1, 0, 0], "rotate": [90, 0, 0, 1], "scale": 2}}]})");
    ASSERT_EQ(s.draws.size(), 1u);
    const Draw& d = s.draws[0];
    expect_near(d.model_view * d.positions[0], glm::vec4(1, 2, -5, 1));
    expect_near(d.mvp * d.positions[0], glm::vec4(0.5f, 2.0f, 35.0f / 9.0f, 5.0f));
    expect_near(d.projection * (d.model_view * d.positions[0]), d.mvp * d.positions[0]);
    EXPECT_FLOAT_EQ(s.resolved["camera"]["aspect"].get<float>(), 2.0f);
    EXPECT_EQ(s.resolved["camera"]["type"], "perspective");
  }
}

TEST_F(SceneLoaderTest, OrthographicAndDefaultEye) {
  // Default eye/target/up give an identity view. x: 2/(r-l) * 1 = 0.5;
  // y: 2/(t-b) * 0.5 = 0.5; z: -2/(f-n) * -6 - (f+n)/(f-n) = 1.2 - 1.2 = 0.
  const Scene s = load(R"({"camera": {"type": "orthographic", "left": -2, "right": 2,
      "bottom": -1, "top": 1, "near": 1, "far": 11},
      "draws": [{"positions": [[1, 0.5, -6]]}]})");
  expect_near(s.draws[0].mvp * s.draws[0].positions[0], glm::vec4(0.5f, 0.5f, 0.0f, 1.0f));
  expect_near(s.draws[0].model_view[3], glm::vec4(0, 0, 0, 1));
}

TEST_F(SceneLoaderTest, MatricesAreWrittenAsRows) {
  // view translates by (10,20,30); projection adds 2y to x; the model matrix
  // scales x by 3. (1,2,3) -> (3,2,3) -> (13,22,33) -> (13+44, 22, 33, 1).
  const Scene s = load(R"({"camera": {
        "view": [[1,0,0,10],[0,1,0,20],[0,0,1,30],[0,0,0,1]],
        "projection": [[1,2,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]},
      "draws": [{"positions": [[1, 2, 3]],
                 "transform": {"matrix": [[3,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}}]})");
  expect_near(s.draws[0].model_view * s.draws[0].positions[0], glm::vec4(13, 22, 33, 1));
  expect_near(s.draws[0].mvp * s.draws[0].positions[0], glm::vec4(57, 22, 33, 1));
  EXPECT_EQ(s.resolved["camera"]["view"][0][3], 10.0);
  EXPECT_EQ(s.resolved["draws"][0]["model"][0][0], 3.0);
}

TEST_F(SceneLoaderTest, NoCameraMeansClipSpace) {
  const Scene s = load(R"({"draws": [{"positions": [[0.5, -0.5, 0.25], [1, 2, 3, 4]]}]})");
  const Draw& d = s.draws[0];
  expect_near(d.positions[0], glm::vec4(0.5f, -0.5f, 0.25f, 1.0f));
  expect_near(d.positions[1], glm::vec4(1, 2, 3, 4));
  expect_near(d.mvp * d.positions[1], glm::vec4(1, 2, 3, 4));
  EXPECT_EQ(s.resolved["camera"]["type"], "none");
}

// ---------------------------------------------------------------- automatic camera

// A cube with corners at +-1, 12 triangles.
const char* kCubeObj =
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

glm::vec3 json_vec3(const nlohmann::json& v) {
  return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
}

// The symptom of issue 16: a mesh without a camera rendered black. Now the
// loader frames it: the cube scaled by 2 about its centre and moved to (10,
// -5, 3) spans [8, 12] x [-7, -3] x [1, 5]; every corner of that box must
// land inside the view volume of the camera stats.json records, rebuilt here
// with glm from those values, and the box must fill a fair part of the frame.
TEST_F(SceneLoaderTest, MeshWithoutCameraIsFramed) {
  write("cube.obj", kCubeObj);
  const Scene s = load(R"({"framebuffer": {"width": 320, "height": 200},
      "lights": [{"type": "point", "position": [0, 10, 0]}],
      "draws": [{"mesh": "cube.obj", "transform": {"translate": [10, -5, 3], "scale": 2}}]})");
  EXPECT_TRUE(s.auto_camera);
  const nlohmann::json& cam = s.resolved["camera"];
  EXPECT_EQ(cam["type"], "perspective");
  EXPECT_EQ(cam["auto"], true);
  EXPECT_EQ(cam["fovy"], 45.0);
  EXPECT_FLOAT_EQ(cam["aspect"].get<float>(), 1.6f);
  const glm::vec3 eye = json_vec3(cam["eye"]), target = json_vec3(cam["target"]);
  const glm::vec3 up = json_vec3(cam["up"]);
  expect_near(target, glm::vec3(10, -5, 3));
  expect_near(up, glm::vec3(0, 1, 0));
  // The documented rule: eye along (1, 1, 2) from the centre, at the distance
  // where the sphere around the box (radius sqrt(3) * 2, half the diagonal)
  // fits the narrower field of view, here the vertical 45 degrees.
  const float radius = 2.0f * std::sqrt(3.0f);
  const float distance = radius / std::sin(glm::radians(22.5f));
  expect_near(eye, target + distance * glm::normalize(glm::vec3(1, 1, 2)), 1e-4f);
  EXPECT_NEAR(cam["near"].get<float>(), distance - 1.1f * radius, 1e-4f);
  EXPECT_NEAR(cam["far"].get<float>(), distance + 1.1f * radius, 1e-4f);

  const glm::mat4 view = glm::lookAt(eye, target, up);
  const glm::mat4 proj =
      glm::perspective(glm::radians(cam["fovy"].get<float>()), cam["aspect"].get<float>(),
                       cam["near"].get<float>(), cam["far"].get<float>());
  float extent = 0.0f;  // the largest |x| or |y| in NDC
  for (int i = 0; i < 8; ++i) {
    const glm::vec4 corner{i & 1 ? 12 : 8, i & 2 ? -3 : -7, i & 4 ? 5 : 1, 1};
    const glm::vec4 c = proj * view * corner;
    ASSERT_GT(c.w, 0.0f);
    for (int k = 0; k < 3; ++k) EXPECT_LT(std::abs(c[k]), c.w) << "corner " << i << " axis " << k;
    extent = std::max({extent, std::abs(c.x / c.w), std::abs(c.y / c.w)});
    // The loader's matrices are the same camera.
    ASSERT_EQ(s.draws.size(), 1u);
    const glm::vec4 object{i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1, 1};
    expect_near(s.draws[0].mvp * object, c, 1e-3f);
  }
  EXPECT_GT(extent, 0.5f);  // not a speck in the middle
  // Lights are in world space: the point light's eye position is view * p.
  expect_near(json_vec3(s.resolved["lights"][0]["eye_vector"]),
              glm::vec3(view * glm::vec4(0, 10, 0, 1)), 1e-4f);

  // "auto" given explicitly is the same camera; copying the resolved values
  // into the scene gives the very same matrices.
  const Scene same = load(R"({"framebuffer": {"width": 320, "height": 200}, "camera": "auto",
      "draws": [{"mesh": "cube.obj", "transform": {"translate": [10, -5, 3], "scale": 2}}]})");
  EXPECT_TRUE(same.auto_camera);
  EXPECT_EQ(same.draws[0].mvp, s.draws[0].mvp);
  nlohmann::json copied = {{"framebuffer", {{"width", 320}, {"height", 200}}}, {"camera", cam}};
  copied["draws"] = {
      {{"mesh", "cube.obj"}, {"transform", {{"matrix", s.resolved["draws"][0]["model"]}}}}};
  for (const char* k : {"auto", "view", "projection"}) copied["camera"].erase(k);
  const Scene copy = load(copied.dump());
  EXPECT_FALSE(copy.auto_camera);
  EXPECT_EQ(copy.draws[0].mvp, s.draws[0].mvp);
}

TEST_F(SceneLoaderTest, AutoCameraOnlyForMeshes) {
  // Raw positions without a camera stay clip coordinates, next to nothing else.
  const Scene raw = load(R"({"draws": [{"positions": [[0.5, 0, 0], [0, 0.5, 0], [0, 0, 0]]}]})");
  EXPECT_FALSE(raw.auto_camera);
  EXPECT_EQ(raw.draws[0].mvp, glm::mat4(1.0f));
  EXPECT_EQ(raw.resolved["camera"]["type"], "none");
  EXPECT_FALSE(raw.resolved["camera"].contains("auto"));
  // A mesh squashed to a point still gets a camera (radius 1 around it).
  write("cube.obj", kCubeObj);
  const Scene point = load(
      R"({"draws": [{"mesh": "cube.obj", "transform": {"translate": [2, 2, 2], "scale": 0}}]})");
  EXPECT_TRUE(point.auto_camera);
  expect_near(json_vec3(point.resolved["camera"]["target"]), glm::vec3(2, 2, 2));
  EXPECT_EQ(error_of(R"({"camera": "auto", "draws": [{"positions": []}]})"),
            "camera: \"auto\" frames the mesh draws, and the scene has none");
  EXPECT_EQ(error_of(R"({"camera": "fisheye"})"),
            "camera: expected an object or \"auto\", got \"fisheye\"");
  EXPECT_EQ(error_of(R"({"camera": 3})"), "camera: expected an object or \"auto\", got 3");
}

TEST_F(SceneLoaderTest, RotationsApplyInListedOrder) {
  // About z then about x: (1,0,0) -> (0,1,0) -> (0,0,1). The other order would
  // give (0,1,0).
  const Scene s = load(R"({"draws": [
      {"positions": [[1, 0, 0]], "transform": {"rotate": [[90, 0, 0, 1], [90, 1, 0, 0]]}},
      {"positions": [[1, 0, 0]], "transform": {"rotate": [90, 0, 0, 2]}},
      {"positions": [[1, 1, 1]], "transform": {"scale": [1, 2, 3], "translate": [0, 0, -1]}}]})");
  expect_near(s.draws[0].mvp * s.draws[0].positions[0], glm::vec4(0, 0, 1, 1));
  expect_near(s.draws[1].mvp * s.draws[1].positions[0], glm::vec4(0, 1, 0, 1));
  expect_near(s.draws[2].mvp * s.draws[2].positions[0], glm::vec4(1, 2, 2, 1));
}

TEST_F(SceneLoaderTest, NormalMatrixIsInverseTranspose) {
  // Scaling x by 2 must halve normals' x (before renormalisation).
  const Scene s = load(R"({"draws": [{"positions": [[0, 0, 0]],
                                       "transform": {"scale": [2, 1, 1]}}]})");
  const glm::mat3& n = s.draws[0].normal_matrix;
  expect_near(n * glm::vec3(1, 1, 1), glm::vec3(0.5f, 1.0f, 1.0f));
}

TEST_F(SceneLoaderTest, LightsAreInEyeSpace) {
  // Eye at +x looking at the origin: world +x is eye +z, world +y is eye +y.
  const Scene s = load(R"({"camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 100,
                                      "eye": [5, 0, 0], "target": [0, 0, 0]},
      "lights": [
        {"type": "directional", "direction": [-3, 0, 0]},
        {"type": "point", "position": [5, 3, 0], "attenuation": [0.5, 0.25, 0.125],
         "ambient": [0.1, 0.2, 0.3, 1], "diffuse": [0.4, 0.5, 0.6, 1], "specular": [0.7, 0.8, 0.9, 1]},
        {"type": "point", "position": [0, 0, 0]},
        {"type": "directional", "direction": [0, -1, 0]}],
      "draws": []})");
  ASSERT_EQ(s.lights.size(), 4u);
  EXPECT_EQ(s.lights[0].type, LightType::directional);
  expect_near(s.lights[0].vector, glm::vec3(0, 0, 1));  // towards the light, unit length
  // Defaults of a light without colours: ambient black, diffuse/specular white.
  expect_near(s.lights[0].ambient, glm::vec4(0, 0, 0, 1));
  expect_near(s.lights[0].diffuse, glm::vec4(1, 1, 1, 1));
  expect_near(s.lights[0].specular, glm::vec4(1, 1, 1, 1));
  EXPECT_EQ(s.lights[1].type, LightType::point);
  expect_near(s.lights[1].vector, glm::vec3(0, 3, 0));
  EXPECT_EQ(s.lights[1].constant_attenuation, 0.5f);
  EXPECT_EQ(s.lights[1].linear_attenuation, 0.25f);
  EXPECT_EQ(s.lights[1].quadratic_attenuation, 0.125f);
  expect_near(s.lights[1].ambient, glm::vec4(0.1f, 0.2f, 0.3f, 1));
  expect_near(s.lights[1].diffuse, glm::vec4(0.4f, 0.5f, 0.6f, 1));
  expect_near(s.lights[1].specular, glm::vec4(0.7f, 0.8f, 0.9f, 1));
  expect_near(s.lights[2].vector, glm::vec3(0, 0, -5));
  EXPECT_EQ(s.lights[2].constant_attenuation, 1.0f);
  EXPECT_EQ(s.lights[2].linear_attenuation, 0.0f);
  expect_near(s.lights[3].vector, glm::vec3(0, 1, 0));
  EXPECT_EQ(s.resolved["lights"][1]["position"][1], 3.0);
}

// ---------------------------------------------------------------- state, material, defaults

TEST_F(SceneLoaderTest, EveryStateValueParses) {
  struct Case {
    std::string state;
    std::function<bool(const RenderState&)> check;
  };
  const std::vector<Case> cases = {
      {R"("cull": "none")", [](auto& s) { return s.cull == CullMode::none; }},
      {R"("cull": "back")", [](auto& s) { return s.cull == CullMode::back; }},
      {R"("cull": "front")", [](auto& s) { return s.cull == CullMode::front; }},
      {R"("front_face": "ccw")", [](auto& s) { return s.front_face == FrontFace::ccw; }},
      {R"("front_face": "cw")", [](auto& s) { return s.front_face == FrontFace::cw; }},
      {R"("depth_test": "off")", [](auto& s) { return !s.depth_test; }},
      {R"("depth_test": "never")",
       [](auto& s) { return s.depth_test && s.depth_func == CompareFunc::never; }},
      {R"("depth_test": "less")",
       [](auto& s) { return s.depth_test && s.depth_func == CompareFunc::less; }},
      {R"("depth_test": "lequal")",
       [](auto& s) { return s.depth_test && s.depth_func == CompareFunc::lequal; }},
      {R"("depth_test": "equal")",
       [](auto& s) { return s.depth_test && s.depth_func == CompareFunc::equal; }},
      {R"("depth_test": "greater")",
       [](auto& s) { return s.depth_test && s.depth_func == CompareFunc::greater; }},
      {R"("depth_test": "gequal")",
       [](auto& s) { return s.depth_test && s.depth_func == CompareFunc::gequal; }},
      {R"("depth_test": "notequal")",
       [](auto& s) { return s.depth_test && s.depth_func == CompareFunc::notequal; }},
      {R"("depth_test": "always")",
       [](auto& s) { return s.depth_test && s.depth_func == CompareFunc::always; }},
      {R"("depth_write": false)", [](auto& s) { return !s.depth_write; }},
      {R"("depth_write": true)", [](auto& s) { return s.depth_write; }},
      {R"("polygon_offset": [1.5, -2])",
       [](auto& s) { return s.offset_factor == 1.5f && s.offset_units == -2.0f; }},
      {R"("blend": "off")", [](auto& s) { return !s.blend; }},
      {R"("blend": {})",
       [](auto& s) {
         return s.blend && s.blend_src == BlendFactor::one && s.blend_dst == BlendFactor::zero &&
                s.blend_equation == BlendEquation::add;
       }},
      {R"("blend": {"src": "zero", "dst": "one", "equation": "subtract"})",
       [](auto& s) {
         return s.blend && s.blend_src == BlendFactor::zero && s.blend_dst == BlendFactor::one &&
                s.blend_equation == BlendEquation::subtract;
       }},
      {R"("blend": {"equation": "reverse_subtract"})",
       [](auto& s) { return s.blend_equation == BlendEquation::reverse_subtract; }},
      {R"("blend": {"equation": "add"})",
       [](auto& s) { return s.blend_equation == BlendEquation::add; }},
      {R"("color_mask": [true, false, true, false])",
       [](auto& s) {
         return s.color_mask == std::array<bool, 4>{true, false, true, false};
       }},
      {R"("shading": "flat")", [](auto& s) { return s.shading == Shading::flat; }},
      {R"("shading": "gouraud")", [](auto& s) { return s.shading == Shading::gouraud; }},
      {R"("shading": "phong")", [](auto& s) { return s.shading == Shading::phong; }},
      // Widths and sizes: any number in (0, 255], fractions kept as written.
      {R"("line_width": 0.25)", [](auto& s) { return s.line_width == 0.25f; }},
      {R"("line_width": 255)", [](auto& s) { return s.line_width == 255.0f; }},
      {R"("line_width": 7)", [](auto& s) { return s.line_width == 7.0f && s.point_size == 1.0f; }},
      {R"("point_size": 0.5)", [](auto& s) { return s.point_size == 0.5f; }},
      {R"("point_size": 255)", [](auto& s) { return s.point_size == 255.0f; }},
      {R"("point_size": 64)",
       [](auto& s) { return s.point_size == 64.0f && s.line_width == 1.0f; }},
      {R"("line_rasterization": "diamond_exit")",
       [](auto& s) { return s.line_rasterization == LineRasterization::diamond_exit; }},
      {R"("line_rasterization": "bresenham")",
       [](auto& s) { return s.line_rasterization == LineRasterization::bresenham; }},
      {R"("polygon_mode": "fill")", [](auto& s) { return s.polygon_mode == PolygonMode::fill; }},
      {R"("polygon_mode": "line")", [](auto& s) { return s.polygon_mode == PolygonMode::line; }},
      {R"("polygon_mode": "point")", [](auto& s) { return s.polygon_mode == PolygonMode::point; }},
      {R"("provoking_vertex": "first")",
       [](auto& s) { return s.provoking_vertex == ProvokingVertex::first; }},
      {R"("provoking_vertex": "last")",
       [](auto& s) { return s.provoking_vertex == ProvokingVertex::last; }},
      {R"("interpolation": "screen")",
       [](auto& s) { return s.interpolation == Interpolation::screen; }},
      {R"("interpolation": "perspective")",
       [](auto& s) { return s.interpolation == Interpolation::perspective; }},
  };
  const std::vector<std::pair<std::string, BlendFactor>> factors = {
      {"zero", BlendFactor::zero},
      {"one", BlendFactor::one},
      {"src_color", BlendFactor::src_color},
      {"one_minus_src_color", BlendFactor::one_minus_src_color},
      {"dst_color", BlendFactor::dst_color},
      {"one_minus_dst_color", BlendFactor::one_minus_dst_color},
      {"src_alpha", BlendFactor::src_alpha},
      {"one_minus_src_alpha", BlendFactor::one_minus_src_alpha},
      {"dst_alpha", BlendFactor::dst_alpha},
      {"one_minus_dst_alpha", BlendFactor::one_minus_dst_alpha},
      {"src_alpha_saturate", BlendFactor::src_alpha_saturate},
  };
  for (const Case& c : cases) {
    const Scene s = load(R"({"draws": [{"positions": [], "state": {)" + c.state + "}}]}");
    EXPECT_TRUE(c.check(s.draws[0].state)) << c.state;
    // The resolved state gives the key back with the value as written.
    const nlohmann::json written = nlohmann::json::parse("{" + c.state + "}");
    const std::string key = written.begin().key();
    if (key != "depth_test" && key != "blend") {  // these two are rewritten (see below)
      EXPECT_EQ(s.resolved["draws"][0]["state"][key], written.begin().value()) << c.state;
    }
  }
  for (const auto& [name, factor] : factors) {
    const Scene s = load(R"({"draws": [{"positions": [], "state": {"blend": {"src": ")" + name +
                         R"(", "dst": ")" + name + R"("}}}]})");
    EXPECT_EQ(s.draws[0].state.blend_src, factor) << name;
    EXPECT_EQ(s.draws[0].state.blend_dst, factor) << name;
    EXPECT_EQ(s.resolved["draws"][0]["state"]["blend"]["src"], name);
  }
}

TEST_F(SceneLoaderTest, DefaultsAreFilledIn) {
  const Scene s = load(R"({"draws": [{"positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}]})");
  EXPECT_EQ(s.framebuffer.width, 256);
  EXPECT_EQ(s.framebuffer.height, 256);
  EXPECT_EQ(s.framebuffer.color_format, ColorFormat::rgba8);
  EXPECT_EQ(s.framebuffer.depth_format, DepthFormat::unorm24);
  expect_near(s.framebuffer.clear_color, glm::vec4(0, 0, 0, 1));
  EXPECT_EQ(s.framebuffer.clear_depth, 1.0f);
  expect_near(s.global_ambient, glm::vec4(0.2f, 0.2f, 0.2f, 1.0f));
  EXPECT_TRUE(s.lights.empty());
  ASSERT_EQ(s.draws.size(), 1u);
  const Draw& d = s.draws[0];
  EXPECT_EQ(d.name, "draws[0]");
  EXPECT_EQ(d.primitive, PrimitiveType::triangles);
  EXPECT_FALSE(d.lighting);
  EXPECT_TRUE(d.colors.empty());
  EXPECT_TRUE(d.indices.empty());
  EXPECT_TRUE(d.normals.empty());
  expect_near(d.material.ambient, glm::vec4(0.2f, 0.2f, 0.2f, 1));
  expect_near(d.material.diffuse, glm::vec4(0.8f, 0.8f, 0.8f, 1));
  expect_near(d.material.specular, glm::vec4(0, 0, 0, 1));
  expect_near(d.material.emission, glm::vec4(0, 0, 0, 1));
  EXPECT_EQ(d.material.shininess, 0.0f);
  EXPECT_EQ(d.state.cull, CullMode::none);
  EXPECT_EQ(d.state.front_face, FrontFace::ccw);
  EXPECT_TRUE(d.state.depth_test);
  EXPECT_EQ(d.state.depth_func, CompareFunc::less);
  EXPECT_TRUE(d.state.depth_write);
  EXPECT_FALSE(d.state.blend);
  EXPECT_EQ(d.state.shading, Shading::gouraud);
  EXPECT_EQ(d.state.line_width, 1.0f);
  EXPECT_EQ(d.state.point_size, 1.0f);
  EXPECT_EQ(d.state.line_rasterization, LineRasterization::diamond_exit);
  EXPECT_EQ(d.state.polygon_mode, PolygonMode::fill);
  EXPECT_EQ(d.state.provoking_vertex, ProvokingVertex::last);
  EXPECT_EQ(d.state.interpolation, Interpolation::perspective);
  EXPECT_EQ(d.mvp, glm::mat4(1.0f));

  // The resolved settings name everything as a scene file would.
  const nlohmann::json& r = s.resolved;
  EXPECT_EQ(r["framebuffer"]["width"], 256);
  EXPECT_EQ(r["framebuffer"]["color_format"], "rgba8");
  EXPECT_EQ(r["framebuffer"]["depth_format"], "unorm24");
  EXPECT_EQ(r["ambient"], nlohmann::json::parse("[0.2, 0.2, 0.2, 1.0]"));
  const nlohmann::json& rd = r["draws"][0];
  EXPECT_EQ(rd["name"], "draws[0]");
  EXPECT_EQ(rd["primitive"], "triangles");
  EXPECT_EQ(rd["positions"], 3);
  EXPECT_EQ(rd["primitives"], 1);
  EXPECT_EQ(rd["lighting"], false);
  EXPECT_EQ(rd["state"]["depth_test"], "less");
  EXPECT_EQ(rd["state"]["blend"], "off");
  EXPECT_EQ(rd["state"]["cull"], "none");
  EXPECT_EQ(rd["state"]["line_width"], 1);
  EXPECT_EQ(rd["state"]["point_size"], 1);
  EXPECT_EQ(rd["state"]["line_rasterization"], "diamond_exit");
  EXPECT_EQ(rd["state"]["polygon_mode"], "fill");
  EXPECT_EQ(rd["state"]["provoking_vertex"], "last");
  EXPECT_EQ(rd["state"]["interpolation"], "perspective");
  EXPECT_EQ(rd["material"]["diffuse"], nlohmann::json::parse("[0.8, 0.8, 0.8, 1.0]"));
}

TEST_F(SceneLoaderTest, ViewportDepthRangeAndScissor) {
  const Scene s = load(R"({
    "framebuffer": {"width": 100, "height": 50, "viewport": [-3, 4, 60, 40],
                    "depth_range": [0.25, 0.5]},
    "draws": [
      {"positions": []},
      {"positions": [], "state": {"viewport": [1, 2, 3, 4], "depth_range": [1, 0],
                                  "scissor": [5, 6, 7, 8]}},
      {"positions": [], "state": {"scissor": "off", "cull": "back"}}
    ]})");
  ASSERT_EQ(s.draws.size(), 3u);
  // The frame's viewport and depth range are every draw's defaults.
  for (const size_t d : {size_t{0}, size_t{2}}) {
    ASSERT_TRUE(s.draws[d].state.viewport.has_value());
    EXPECT_EQ(*s.draws[d].state.viewport, (PixelRect{-3, 4, 60, 40}));
    EXPECT_EQ(s.draws[d].state.depth_near, 0.25f);
    EXPECT_EQ(s.draws[d].state.depth_far, 0.5f);
    EXPECT_FALSE(s.draws[d].state.scissor.has_value());
  }
  EXPECT_EQ(*s.draws[1].state.viewport, (PixelRect{1, 2, 3, 4}));
  EXPECT_EQ(s.draws[1].state.depth_near, 1.0f);
  EXPECT_EQ(s.draws[1].state.depth_far, 0.0f);
  EXPECT_EQ(*s.draws[1].state.scissor, (PixelRect{5, 6, 7, 8}));
  const nlohmann::json& r = s.resolved;
  EXPECT_EQ(r["framebuffer"]["viewport"], nlohmann::json::parse("[-3, 4, 60, 40]"));
  EXPECT_EQ(r["framebuffer"]["depth_range"], nlohmann::json::parse("[0.25, 0.5]"));
  EXPECT_EQ(r["draws"][1]["state"]["scissor"], nlohmann::json::parse("[5, 6, 7, 8]"));
  EXPECT_EQ(r["draws"][2]["state"]["scissor"], "off");
  EXPECT_EQ(r["draws"][1]["state"]["depth_range"], nlohmann::json::parse("[1, 0]"));

  // Without the keys: no viewport (the whole framebuffer), range [0, 1].
  const Scene plain = load(R"({"framebuffer": {"width": 30, "height": 20},
                              "draws": [{"positions": []}]})");
  EXPECT_FALSE(plain.draws[0].state.viewport.has_value());
  EXPECT_EQ(plain.draws[0].state, RenderState{});
  EXPECT_EQ(plain.resolved["draws"][0]["state"]["viewport"],
            nlohmann::json::parse("[0, 0, 30, 20]"));
  EXPECT_EQ(plain.resolved["framebuffer"]["depth_range"], nlohmann::json::parse("[0, 1]"));
}

TEST_F(SceneLoaderTest, ExplicitSettingsAndCounts) {
  const Scene s = load(R"({
      "framebuffer": {"width": 640, "height": 8192, "color_format": "rgba16f",
                      "depth_format": "float32", "clear_color": [0.1, 0.2, 0.3, 0.4],
                      "clear_depth": 0.5},
      "ambient": [0.5, 0.25, 0, 1],
      "draws": [
        {"primitive": "triangle_strip", "positions": [[0,0,0],[1,0,0],[0,1,0],[1,1,0],[2,1,0]],
         "colors": [[1,0,0,1],[0,1,0,1],[0,0,1,1],[1,1,1,1],[0,0,0,0]]},
        {"primitive": "triangle_fan", "positions": [[0,0,0],[1,0,0],[0,1,0]],
         "indices": [0, 1, 2, 2, 7, 4294967295]},
        {"primitive": "triangles", "positions": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]],
         "indices": [0, 1, 2, 3, 2, 1, 0],
         "material": {"color": [0.1, 0.2, 0.3, 0.5], "diffuse": [0.9, 0.9, 0.9, 1],
                      "specular": [1, 1, 1, 1], "emission": [0, 0.5, 0, 1], "shininess": 128}}]})");
  EXPECT_EQ(s.framebuffer.width, 640);
  EXPECT_EQ(s.framebuffer.height, 8192);
  EXPECT_EQ(s.framebuffer.color_format, ColorFormat::rgba16f);
  EXPECT_EQ(s.framebuffer.depth_format, DepthFormat::float32);
  expect_near(s.framebuffer.clear_color, glm::vec4(0.1f, 0.2f, 0.3f, 0.4f));
  EXPECT_EQ(s.framebuffer.clear_depth, 0.5f);
  expect_near(s.global_ambient, glm::vec4(0.5f, 0.25f, 0, 1));
  ASSERT_EQ(s.draws.size(), 3u);
  EXPECT_EQ(s.draws[0].primitive, PrimitiveType::triangle_strip);
  ASSERT_EQ(s.draws[0].colors.size(), 5u);
  expect_near(s.draws[0].colors[2], glm::vec4(0, 0, 1, 1));
  EXPECT_EQ(s.draws[1].primitive, PrimitiveType::triangle_fan);
  // Indices are not range-checked: the pipeline drops such triangles.
  EXPECT_EQ(s.draws[1].indices, (std::vector<uint32_t>{0, 1, 2, 2, 7, 4294967295u}));
  const Material& m = s.draws[2].material;
  expect_near(m.ambient, glm::vec4(0.1f, 0.2f, 0.3f, 0.5f));  // from "color"
  expect_near(m.diffuse, glm::vec4(0.9f, 0.9f, 0.9f, 1));     // "diffuse" overrides "color"
  expect_near(m.specular, glm::vec4(1, 1, 1, 1));
  expect_near(m.emission, glm::vec4(0, 0.5f, 0, 1));
  EXPECT_EQ(m.shininess, 128.0f);
  // strip: n - 2; fan: n - 2 of the 6 indices; triangles: floor(7 / 3).
  EXPECT_EQ(s.resolved["draws"][0]["primitives"], 3);
  EXPECT_EQ(s.resolved["draws"][1]["primitives"], 4);
  EXPECT_EQ(s.resolved["draws"][1]["indices"], 6);
  EXPECT_EQ(s.resolved["draws"][2]["primitives"], 2);
  EXPECT_EQ(s.resolved["draws"][0]["material_from"], "default");
  EXPECT_EQ(s.resolved["draws"][2]["material_from"], "scene");
  EXPECT_EQ(s.resolved["framebuffer"]["depth_format"], "float32");
}

TEST_F(SceneLoaderTest, DrawNamesLabelDraws) {
  write("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 2\n");
  const Scene s = load(R"({"draws": [{"name": "wide lines", "primitive": "lines", "positions": []},
      {"positions": []}, {"name": "the floor", "mesh": "flat.obj"}]})");
  ASSERT_EQ(s.draws.size(), 4u);
  EXPECT_EQ(s.draws[0].name, "draws[0] wide lines");
  EXPECT_EQ(s.resolved["draws"][0]["name"], "draws[0] wide lines");
  EXPECT_EQ(s.draws[1].name, "draws[1]");
  std::set<std::string> mesh_names = {s.draws[2].name, s.draws[3].name};
  EXPECT_EQ(mesh_names.count("draws[2] the floor flat.obj mesh 1"), 1u) << s.draws[2].name;
  EXPECT_EQ(mesh_names.count("draws[2] the floor flat.obj mesh 0 lines"), 1u) << s.draws[3].name;
  EXPECT_EQ(error_of(R"({"draws": [{"name": "", "positions": []}]})"),
            "draws[0].name: expected a name of 1..200 characters, no control characters, got \"\"");
  EXPECT_EQ(error_of(R"({"draws": [{"name": 3, "positions": []}]})"),
            "draws[0].name: expected a string, got 3");
  EXPECT_EQ(error_of(R"({"draws": [{"name": "a\nb", "positions": []}]})")
                .rfind("draws[0].name: expected a name of 1..200 characters", 0),
            0u);
  EXPECT_EQ(
      error_of(R"({"draws": [{"name": ")" + std::string(201, 'x') + R"(", "positions": []}]})")
          .rfind("draws[0].name: expected a name of 1..200 characters", 0),
      0u);
}

TEST_F(SceneLoaderTest, PointAndLinePrimitiveCounts) {
  // GL's assembly (docs/pipeline-spec.md section 3), counted by hand for n
  // vertex slots = 0, 1, 2, 3, 5: points n; lines pairs; a strip n - 1
  // segments; a loop the strip plus the closing segment (two lines for n = 2).
  const std::vector<int> slots = {0, 1, 2, 3, 5};
  const std::map<std::string, std::vector<int>> want = {{"points", {0, 1, 2, 3, 5}},
                                                        {"lines", {0, 0, 1, 1, 2}},
                                                        {"line_strip", {0, 0, 1, 2, 4}},
                                                        {"line_loop", {0, 0, 2, 3, 5}}};
  for (const auto& [primitive, counts] : want) {
    for (size_t k = 0; k < slots.size(); ++k) {
      const int n = slots[k];
      // Non-indexed: n positions. Indexed: 2 positions and n indices, so the
      // count follows the indices, not the positions.
      std::string positions, indices;
      for (int i = 0; i < n; ++i) {
        positions += std::string(i ? ", " : "") + "[" + std::to_string(i) + ", 0, 0]";
        indices += std::string(i ? ", " : "") + std::to_string(i % 2);
      }
      const Scene s =
          load(R"({"draws": [{"primitive": ")" + primitive + R"(", "positions": [)" + positions +
               R"(]}, {"primitive": ")" + primitive +
               R"(", "positions": [[0, 0, 0], [1, 1, 0]], "indices": [)" + indices + "]}]}");
      ASSERT_EQ(s.draws.size(), 2u);
      EXPECT_EQ(s.draws[0].primitive, enum_from_string<PrimitiveType>(primitive)) << primitive;
      EXPECT_EQ(s.resolved["draws"][0]["primitive"], primitive);
      EXPECT_EQ(s.resolved["draws"][0]["primitives"], counts[k]) << primitive << " n=" << n;
      EXPECT_EQ(s.resolved["draws"][1]["indices"], n);
      // An empty index list is no index list (Draw::indices), so the 2 positions count.
      const int indexed = n == 0 ? want.at(primitive)[2] : counts[k];
      EXPECT_EQ(s.resolved["draws"][1]["primitives"], indexed) << primitive << " indexed n=" << n;
    }
  }
}

TEST_F(SceneLoaderTest, ShippedScenesLoad) {
  for (const char* name :
       {"default.json", "spider.json", "quad_clipspace.json", "lines_points.json"}) {
    const std::string path = std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + name;
    Scene s;
    ASSERT_NO_THROW(s = load_scene(path)) << name;
    EXPECT_FALSE(s.draws.empty()) << name;
    // Every vertex of every draw lies in front of the camera and inside the
    // view volume, i.e. the objects are framed.
    for (const Draw& d : s.draws) {
      for (const glm::vec4& p : d.positions) {
        const glm::vec4 c = d.mvp * p;
        ASSERT_GT(c.w, 0.0f) << d.name;
        EXPECT_LE(std::abs(c.z), c.w) << d.name;
        if (d.lighting) {  // the lit meshes are the subjects: wholly on screen
          EXPECT_LE(std::abs(c.x), c.w) << d.name;
          EXPECT_LE(std::abs(c.y), c.w) << d.name;
        }
      }
    }
  }
  const Scene def = load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/default.json");
  EXPECT_EQ(def.framebuffer.width, 640);
  EXPECT_EQ(def.framebuffer.height, 480);
  ASSERT_EQ(def.lights.size(), 2u);
  EXPECT_EQ(def.lights[0].type, LightType::directional);
  EXPECT_EQ(def.lights[1].type, LightType::point);
  int lit = 0, blended = 0;
  for (const Draw& d : def.draws) {
    lit += d.lighting;
    blended += d.state.blend;
  }
  EXPECT_EQ(lit, 1);
  EXPECT_EQ(blended, 1);
}

// ---------------------------------------------------------------- errors

TEST_F(SceneLoaderTest, MalformedJsonReportsLineAndColumn) {
  // The second comma is line 3, column 18.
  const std::string msg = error_of("{\n  \"framebuffer\": {\n    \"width\": 256,,\n  }\n}\n");
  EXPECT_EQ(msg.rfind("line 3, column 18: ", 0), 0u) << msg;
  EXPECT_EQ(error_of("").rfind("line 1, column 1: ", 0), 0u);
  // Beyond double: nlohmann refuses it while parsing; the message names where.
  EXPECT_EQ(error_of(R"({"ambient": [0, 1e400, 0, 1]})"),
            "ambient[1]: number overflow parsing '1e400'");
  EXPECT_EQ(error_of(R"({"draws": [{"positions": [], "state": {"point_size": -1e999}}]})"),
            "draws[0].state.point_size: number overflow parsing '-1e999'");
  EXPECT_EQ(error_of("1e400"), "number overflow parsing '1e400'");
}

// Scene files take the same comments as GPU configurations (docs/scene-format.md,
// docs/gpu-config.md); they used to be a syntax error at the first `/`.
TEST_F(SceneLoaderTest, CommentsAreAllowed) {
  const Scene scene = load(
      "// a 64x32 frame\n"
      "{\n"
      "  /* the framebuffer,\n"
      "     in pixels */\n"
      "  \"framebuffer\": {\"width\": 64, /* wide */ \"height\": 32}  // tall enough\n"
      "}\n");
  EXPECT_EQ(scene.framebuffer.width, 64);
  EXPECT_EQ(scene.framebuffer.height, 32);
  // An error after comments still names its own line and column: the second
  // comma is line 4, column 27.
  const std::string msg =
      error_of("{\n  // one line\n  /* two\n   lines */ \"ambient\": [0,, 0, 0, 1]\n}\n");
  EXPECT_EQ(msg.rfind("line 4, column 27: ", 0), 0u) << msg;
  // A comment that never ends is a syntax error.
  const std::string open = error_of("{\n  /* never closed\n}\n");
  EXPECT_NE(open.find("syntax error"), std::string::npos) << open;
}

TEST_F(SceneLoaderTest, FileErrors) {
  const std::string missing = (dir_ / "nope.json").string();
  try {
    load_scene(missing);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(missing + ": cannot open: ", 0), 0u) << e.what();
  }
  EXPECT_THROW(load_scene(dir_.string()), InputError);
}

TEST_F(SceneLoaderTest, StructuralErrors) {
  EXPECT_EQ(error_of("[1, 2]"), "expected an object, got an array of 2 elements");
  EXPECT_EQ(error_of(R"({"framebuffer": {"widht": 256}})"),
            "framebuffer.widht: unknown key (allowed: width, height, samples, supersample, "
            "color_format, depth_format, clear_color, clear_depth, viewport, depth_range)");
  EXPECT_EQ(error_of(R"({"framebuffer": {"samples": 3}})"),
            "framebuffer.samples: expected 1, 2, 4, 8 or 16, got 3");
  EXPECT_EQ(error_of(R"({"framebuffer": {"samples": 32}})"),
            "framebuffer.samples: expected an integer in 1..16, got 32");
  EXPECT_EQ(error_of(R"({"framebuffer": {"width": 4096, "supersample": 3}})"),
            "framebuffer.supersample: a render target of 12288x768 exceeds 8192 pixels on a side");
  EXPECT_EQ(error_of(R"({"framebuffer": {"width": 1, "width": 2}})"),
            "framebuffer.width: duplicate key");
  EXPECT_EQ(error_of(R"({"draws": [{}, {"positions": [], "colors": [[1,1,1,1]]}]})"),
            "draws[0]: expected a \"mesh\", \"positions\" or \"clear\" key");
  EXPECT_EQ(error_of(R"({"draws": [{"positions": [], "lighting": true}]})")
                .rfind("draws[0].lighting: unknown key", 0),
            0u);
  EXPECT_EQ(error_of(R"({"draws": [{"mesh": "a.obj", "positions": []}]})")
                .rfind("draws[0].positions: unknown key", 0),
            0u);
  EXPECT_EQ(error_of(R"({"draws": {"positions": []}})"),
            "draws: expected an array of draws, got an object");
  EXPECT_EQ(error_of(R"({"draws": [{"positions": [], "transform": {"matrix":
              [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "translate": [1, 2, 3]}}]})"),
            "draws[0].transform.translate: cannot be combined with \"matrix\"");
  EXPECT_EQ(error_of(R"({"camera": {"fovy": 60}})"),
            "camera: expected \"type\" (perspective, orthographic) or \"view\" and "
            "\"projection\" matrices");
  EXPECT_EQ(error_of(R"({"camera": {"view": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}})"),
            "camera: missing key \"projection\"");
  EXPECT_EQ(error_of(R"({"camera": {"type": "perspective", "near": 1, "far": 2}})"),
            "camera: missing key \"fovy\"");
  EXPECT_EQ(error_of(std::string(40, '[') + std::string(40, ']'))
                .rfind("[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]"
                       "[0][0][0][0][0][0][0]: nested too deeply",
                       0),
            0u);
}

TEST_F(SceneLoaderTest, TypeAndRangeErrors) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"framebuffer": {"width": "256"}})",
       R"(framebuffer.width: expected an integer in 1..8192, got "256")"},
      {R"({"framebuffer": {"width": 0}})",
       "framebuffer.width: expected an integer in 1..8192, got 0"},
      {R"({"framebuffer": {"height": 8193}})",
       "framebuffer.height: expected an integer in 1..8192, got 8193"},
      {R"({"framebuffer": {"height": 12.5}})",
       "framebuffer.height: expected an integer in 1..8192, got 12.5"},
      {R"({"framebuffer": {"color_format": "rgb8"}})",
       R"(framebuffer.color_format: expected one of rgba8, rgba16f, got "rgb8")"},
      {R"({"framebuffer": {"clear_depth": 1.5}})",
       "framebuffer.clear_depth: expected 0..1, got 1.5"},
      {R"({"framebuffer": {"clear_color": [0, 0, 0]}})",
       "framebuffer.clear_color: expected an array of 4 numbers, got an array of 3 elements"},
      {R"({"ambient": [0, "x", 0, 1]})", R"(ambient[1]: expected a number, got "x")"},
      {R"({"ambient": [0, 0, 0, 1e39]})",
       "ambient[3]: expected a number in float range, got 1e+39"},
      {R"({"camera": {"type": "fisheye"}})",
       R"(camera.type: expected one of perspective, orthographic, got "fisheye")"},
      {R"({"camera": {"type": "perspective", "fovy": 180, "near": 1, "far": 2}})",
       "camera.fovy: expected degrees in (0, 180), got 180"},
      {R"({"camera": {"type": "perspective", "fovy": 0, "near": 1, "far": 2}})",
       "camera.fovy: expected degrees in (0, 180), got 0"},
      {R"({"camera": {"type": "perspective", "fovy": 60, "near": 0, "far": 2}})",
       "camera.near: expected a positive number, got 0"},
      {R"({"camera": {"type": "perspective", "fovy": 60, "near": 2, "far": 2}})",
       "camera.far: expected far > near (2), got 2"},
      {R"({"camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 2, "aspect": -1}})",
       "camera.aspect: expected a positive number, got -1"},
      {R"({"camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 2,
                      "eye": [0, 5, 0], "target": [0, 0, 0]}})",
       "camera.up: is parallel to the view direction (target - eye)"},
      {R"({"camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 2,
                      "eye": [1, 1, 1], "target": [1, 1, 1]}})",
       "camera.target: equals eye"},
      {R"({"camera": {"type": "orthographic", "left": 1, "right": -1, "bottom": -1, "top": 1,
                      "near": -1, "far": 1}})",
       "camera.right: expected right > left, got -1"},
      {R"({"camera": {"view": [[1,0,0,0],[0,1,0,0],[0,0,1,0]], "projection": []}})",
       "camera.view: expected 4 rows of 4 numbers, got an array of 3 elements"},
      {R"({"lights": [{"type": "spot"}]})",
       R"(lights[0].type: expected one of directional, point, got "spot")"},
      {R"({"lights": [{"type": "directional", "direction": [0, 0, 0]}]})",
       "lights[0].direction: expected a direction that is non-zero in eye space, got an array "
       "of 3 elements"},
      {R"({"lights": [{"type": "point", "position": [0, 0, 0], "attenuation": [0, 0, 0]}]})",
       "lights[0].attenuation: expected non-negative [constant, linear, quadratic], not all zero"},
      {R"({"lights": [{"type": "point", "position": [0, 0, 0], "direction": [0, 0, 1]}]})",
       "lights[0].direction: unknown key (allowed: type, position, ambient, diffuse, specular, "
       "attenuation)"},
      {R"({"draws": [{"positions": [[0, 0]]}]})",
       "draws[0].positions[0]: expected an array of 3 or 4 numbers, got an array of 2 elements"},
      {R"({"draws": [{"primitive": "quads", "positions": []}]})",
       R"(draws[0].primitive: expected one of triangles, triangle_strip, triangle_fan, points, lines, line_strip, line_loop, got "quads")"},
      {R"({"draws": [{"positions": [[0,0,0],[0,0,0],[0,0,0]], "colors": [[1,1,1,1]]}]})",
       "draws[0].colors: expected an array of 3 colours (one per position), got an array of 1 "
       "element"},
      {R"({"draws": [{"positions": [], "indices": [0, -1]}]})",
       "draws[0].indices[1]: expected an integer in 0..4294967295, got -1"},
      {R"({"draws": [{"positions": [], "indices": [4294967296]}]})",
       "draws[0].indices[0]: expected an integer in 0..4294967295, got 4294967296"},
      {R"({"draws": [{"positions": [], "indices": [1.5]}]})",
       "draws[0].indices[0]: expected an integer in 0..4294967295, got 1.5"},
      {R"({"draws": [{"positions": [], "material": {"shininess": 129}}]})",
       "draws[0].material.shininess: expected 0..128, got 129"},
      {R"({"draws": [{"positions": [], "material": {"colour": [1, 1, 1, 1]}}]})",
       "draws[0].material.colour: unknown key (allowed: color, ambient, diffuse, specular, "
       "emission, shininess)"},
      {R"({"draws": [{"positions": [], "transform": {"rotate": [90, 0, 0, 0]}}]})",
       "draws[0].transform.rotate: the rotation axis is the zero vector"},
      {R"({"draws": [{"positions": [], "transform": {"rotate": [[90, 1, 0, 0], [90, 1]]}}]})",
       "draws[0].transform.rotate[1]: expected an array of 4 numbers, got an array of 2 "
       "elements"},
      {R"({"draws": [{"positions": [], "transform": {"scale": "big"}}]})",
       R"(draws[0].transform.scale: expected an array of 3 numbers, got "big")"},
      {R"({"draws": [{"positions": []}, {"positions": []}, {"positions": [],
                      "state": {"cull": "sideways"}}]})",
       R"(draws[2].state.cull: expected one of none, back, front, got "sideways")"},
      {R"({"draws": [{"positions": [], "state": {"depth_test": "on"}}]})",
       R"(draws[0].state.depth_test: expected one of off, never, less, equal, lequal, greater, )"
       R"(notequal, gequal, always, got "on")"},
      {R"({"draws": [{"positions": [], "state": {"depth_write": 1}}]})",
       "draws[0].state.depth_write: expected true or false, got 1"},
      {R"({"draws": [{"positions": [], "state": {"blend": "on"}}]})",
       R"(draws[0].state.blend: expected "off" or an object {src, dst, equation}, got "on")"},
      {R"({"draws": [{"positions": [], "state": {"blend": {"src": "alpha"}}}]})",
       R"(draws[0].state.blend.src: expected one of zero, one, src_color, one_minus_src_color, )"
       R"(dst_color, one_minus_dst_color, src_alpha, one_minus_src_alpha, dst_alpha, )"
       R"(one_minus_dst_alpha, src_alpha_saturate, got "alpha")"},
      {R"({"draws": [{"positions": [], "state": {"blend": {"equation": "max"}}}]})",
       R"(draws[0].state.blend.equation: expected one of add, subtract, reverse_subtract, got "max")"},
      {R"({"draws": [{"positions": [], "state": {"color_mask": [true, true, true]}}]})",
       "draws[0].state.color_mask: expected an array of 4 booleans, got an array of 3 elements"},
      {R"({"draws": [{"positions": [], "state": {"shading": "blinn"}}]})",
       R"(draws[0].state.shading: expected one of flat, gouraud, phong, got "blinn")"},
      {R"({"draws": [{"positions": [], "state": {"polygon_offset": [1]}}]})",
       "draws[0].state.polygon_offset: expected an array of 2 numbers, got an array of 1 "
       "element"},
      // Line width and point size: 0 < value <= 255, a number.
      {R"({"draws": [{"positions": [], "state": {"line_width": 0}}]})",
       "draws[0].state.line_width: expected 0 < value <= 255, got 0"},
      {R"({"draws": [{"positions": [], "state": {"line_width": -1}}]})",
       "draws[0].state.line_width: expected 0 < value <= 255, got -1"},
      {R"({"draws": [{"positions": [], "state": {"line_width": 256}}]})",
       "draws[0].state.line_width: expected 0 < value <= 255, got 256"},
      {R"({"draws": [{"positions": [], "state": {"line_width": 255.5}}]})",
       "draws[0].state.line_width: expected 0 < value <= 255, got 255.5"},
      {R"({"draws": [{"positions": [], "state": {"line_width": "wide"}}]})",
       R"(draws[0].state.line_width: expected a number, got "wide")"},
      {R"({"draws": [{"positions": [], "state": {"line_width": [2]}}]})",
       "draws[0].state.line_width: expected a number, got an array of 1 element"},
      {R"({"draws": [{"positions": [], "state": {"point_size": "NaN"}}]})",
       R"(draws[0].state.point_size: expected a number, got "NaN")"},
      {R"({"draws": [{"positions": [], "state": {"point_size": "inf"}}]})",
       R"(draws[0].state.point_size: expected a number, got "inf")"},
      {R"({"draws": [{"positions": [], "state": {"point_size": "4"}}]})",
       R"(draws[0].state.point_size: expected a number, got "4")"},
      {R"({"draws": [{"positions": [], "state": {"point_size": 1e39}}]})",
       "draws[0].state.point_size: expected a number in float range, got 1e+39"},
      {R"({"draws": [{"positions": [], "state": {"point_size": 0}}]})",
       "draws[0].state.point_size: expected 0 < value <= 255, got 0"},
      {R"({"draws": [{"positions": [], "state": {"point_size": null}}]})",
       "draws[0].state.point_size: expected a number, got null"},
      {R"({"draws": [{"positions": [], "state": {"line_rasterization": "dda"}}]})",
       R"(draws[0].state.line_rasterization: expected one of diamond_exit, bresenham, got "dda")"},
      {R"({"draws": [{"positions": [], "state": {"polygon_mode": "wireframe"}}]})",
       R"(draws[0].state.polygon_mode: expected one of fill, line, point, got "wireframe")"},
      {R"({"draws": [{"positions": [], "state": {"polygon_mode": "lines"}}]})",
       R"(draws[0].state.polygon_mode: expected one of fill, line, point, got "lines")"},
      {R"({"draws": [{"positions": [], "state": {"line_stipple": 1}}]})",
       "draws[0].state.line_stipple: unknown key (allowed: cull, front_face, depth_test, "
       "depth_write, polygon_offset, blend, color_mask, shading, line_width, point_size, "
       "line_rasterization, polygon_mode, viewport, depth_range, scissor, "
       "provoking_vertex, interpolation)"},
      {R"({"draws": [{"positions": [], "state": {"provoking_vertex": "centre"}}]})",
       R"(draws[0].state.provoking_vertex: expected one of last, first, got "centre")"},
      {R"({"draws": [{"positions": [], "state": {"interpolation": "noperspective"}}]})",
       R"(draws[0].state.interpolation: expected one of perspective, screen, got "noperspective")"},
  };
  for (const auto& [json, want] : cases) EXPECT_EQ(error_of(json), want) << json;
}

// Clear entries of the draw list (docs/scene-format.md, "Clears"): each is
// placed by the number of Draws before it; a mesh entry counts for the
// Draws it gives (spider.obj: one per mesh of the file).
TEST_F(SceneLoaderTest, ClearEntriesArePlacedAmongTheDraws) {
  const Scene s = load(R"({"camera": {"type": "perspective", "fovy": 60, "near": 1, "far": 10},
    "draws": [
      {"clear": {"depth": 0.25}},
      {"positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
      {"clear": {"color": [0.5, 0.25, 1, 0]}},
      {"clear": {"color": [0, 0, 0, 1], "depth": 0}},
      {"mesh": ")" + kSpider +
                       R"("},
      {"clear": {"depth": 1}}]})");
  ASSERT_EQ(s.clears.size(), 4u);
  const size_t draws = s.draws.size();
  ASSERT_GT(draws, 2u);  // spider.obj has several meshes
  EXPECT_EQ(s.clears[0].before_draw, 0u);
  EXPECT_TRUE(s.clears[0].depth);
  EXPECT_FALSE(s.clears[0].color);
  EXPECT_EQ(s.clears[0].depth_value, 0.25f);
  EXPECT_EQ(s.clears[1].before_draw, 1u);
  EXPECT_TRUE(s.clears[1].color);
  EXPECT_FALSE(s.clears[1].depth);
  EXPECT_EQ(s.clears[1].color_value, glm::vec4(0.5f, 0.25f, 1.0f, 0.0f));
  EXPECT_EQ(s.clears[2].before_draw, 1u);
  EXPECT_TRUE(s.clears[2].color && s.clears[2].depth);
  EXPECT_EQ(s.clears[2].depth_value, 0.0f);
  EXPECT_EQ(s.clears[3].before_draw, draws);  // after the last draw
  // The resolved settings list them with their places.
  const nlohmann::json& resolved = s.resolved.at("clears");
  ASSERT_EQ(resolved.size(), 4u);
  EXPECT_EQ(resolved[1].at("before_draw"), 1);
  EXPECT_EQ(resolved[1].at("color"), nlohmann::json::array({0.5, 0.25, 1, 0}));
  EXPECT_FALSE(resolved[1].contains("depth"));
  EXPECT_EQ(resolved[3].at("before_draw"), draws);
  // No clear entries: no "clears" key, as before they existed.
  EXPECT_FALSE(load(R"({"draws": []})").resolved.contains("clears"));
}

TEST_F(SceneLoaderTest, ClearEntryErrors) {
  const std::pair<std::string, std::string> cases[] = {
      {R"({"draws": [{"clear": {}}]})",
       "draws[0].clear: clears nothing: expected \"color\", \"depth\" or both"},
      {R"({"draws": [{"clear": true}]})", "draws[0].clear: expected an object, got true"},
      {R"({"draws": [{"clear": {"depth": 1}, "name": "x"}]})",
       "draws[0].name: unknown key (allowed: clear)"},
      {R"({"draws": [{"clear": {"depth": 1, "stencil": 0}}]})",
       "draws[0].clear.stencil: unknown key (allowed: color, depth)"},
      {R"({"draws": [{"clear": {"depth": 1.5}}]})", "draws[0].clear.depth: expected 0..1, got 1.5"},
      {R"({"draws": [{"clear": {"depth": "far"}}]})",
       "draws[0].clear.depth: expected a number, got \"far\""},
      {R"({"draws": [{"positions": []}, {"clear": {"color": [1, 0, 0]}}]})",
       "draws[1].clear.color: expected an array of 4 numbers, got an array of 3 elements"},
      {R"({"draws": [{"clear": {"color": [1, 0, 0, null]}}]})",
       "draws[0].clear.color[3]: expected a number, got null"},
  };
  for (const auto& [json, want] : cases) EXPECT_EQ(error_of(json), want) << json;
}

}  // namespace
}  // namespace gpusim

// ---------------------------------------------------------------- textures

namespace gpusim {
namespace {

constexpr const char* kTexturedDraw =
    R"("draws": [{"positions": [[0,0,0],[1,0,0],[0,1,0]], "texture": "t",
                  "texcoords": [[0,0],[1,0],[0,1]]}])";

TEST_F(SceneLoaderTest, TextureTexelsAreStoredInTheirFormat) {
  const Scene s = load(std::string(R"({"textures": {"t": {"format": "rgb565", "width": 2,
      "texels": [[31, 0, 1], [0, 63, 0]], "wrap_s": "clamp_to_edge",
      "min_filter": "nearest", "mag_filter": "nearest"}}, )") +
                       kTexturedDraw + "}");
  ASSERT_EQ(s.textures.size(), 1u);
  const Texture& t = s.textures[0];
  EXPECT_EQ(t.levels[0].width, 2);
  EXPECT_EQ(t.levels[0].height, 1);
  // 31 << 11 | 1 = 0xF801, 63 << 5 = 0x07E0, little endian.
  EXPECT_EQ(t.levels[0].texels, (std::vector<uint8_t>{0x01, 0xF8, 0xE0, 0x07}));
  EXPECT_EQ(t.sampler.wrap_s, TextureWrap::clamp_to_edge);
  EXPECT_EQ(t.sampler.wrap_t, TextureWrap::repeat);
  EXPECT_EQ(t.sampler.mag_filter, TextureFilter::nearest);
  ASSERT_EQ(s.draws.size(), 1u);
  EXPECT_EQ(s.draws[0].texture, 0);
  EXPECT_EQ(s.draws[0].texcoords[1], glm::vec2(1.0f, 0.0f));
  EXPECT_EQ(s.draws[0].texture_env.mode, TextureEnvMode::modulate);
}

TEST_F(SceneLoaderTest, GeneratedMipmapsAreBoxFilteredPerStoredChannel) {
  // 3 x 2 luminance_alpha8: level 1 is 1 x 1, the mean of texels (0, 0),
  // (1, 0), (0, 1), (1, 1) (the third column has no pair), rounded half up.
  const Scene s = load(R"({"textures": {"t": {"format": "luminance_alpha8", "width": 3,
      "height": 2, "texels": [[10, 0], [11, 1], [99, 99], [12, 2], [13, 4], [99, 99]],
      "mipmaps": "generate"}}})");
  const Texture& t = s.textures.at(0);
  ASSERT_EQ(t.levels.size(), 2u);
  EXPECT_EQ(t.levels[1].width, 1);
  EXPECT_EQ(t.levels[1].height, 1);
  // (10 + 11 + 12 + 13 + 2) / 4 = 12, (0 + 1 + 2 + 4 + 2) / 4 = 2.
  EXPECT_EQ(t.levels[1].texels, (std::vector<uint8_t>{12, 2}));
  EXPECT_EQ(t.sampler.min_filter, TextureFilter::nearest_mipmap_linear);  // GL's default
}

TEST_F(SceneLoaderTest, TextureMistakesAreOneLineErrors) {
  const std::string tex = R"({"textures": {"t": {"width": 2, "texels": [[1,2,3,4],[5,6,7,8]]}}, )";
  EXPECT_NE(error_of(tex + R"("draws": [{"positions": [[0,0,0]], "texture": "t",
                               "texcoords": [[0,0],[1,1]]}]})")
                .find("expected an array of 1 texture coordinates"),
            std::string::npos);
  EXPECT_NE(error_of(tex + R"("draws": [{"positions": [[0,0,0]], "texture": "u",
                               "texcoords": [[0,0]]}]})")
                .find("expected the name of one of \"textures\""),
            std::string::npos);
  EXPECT_NE(error_of(tex + R"("draws": [{"positions": [[0,0,0]], "texcoords": [[0,0]]}]})")
                .find("needs a \"texture\""),
            std::string::npos);
  EXPECT_NE(error_of(R"({"textures": {"t": {"width": 2, "texels": [[1,2,3,4]]}}})")
                .find("expected an array of 2 texels"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"textures": {"t": {"width": 1, "texels": [[1,2,3,256]]}}})")
                .find("textures.t.texels[0][3]"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"textures": {"t": {"width": 5000, "texels": []}}})").find("width"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"textures": {"t": {"width": 1, "texels": [[1,2,3,4]],
                                            "wrap": "mirrored_repeat"}}})")
                .find("not supported yet"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"textures": {"t": {"width": 2, "texels": [[1,2,3,4],[1,2,3,4]],
                                            "min_filter": "linear_mipmap_linear"}}})")
                .find("a mipmap filter needs \"mipmaps\""),
            std::string::npos);
  EXPECT_NE(error_of(R"({"textures": {"t": {"width": 4, "texels": [[1],[2],[3],[4]],
                                            "format": "luminance8", "mipmaps": [[[1],[2]]]}}})")
                .find("expected 2 levels after level 0"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"textures": {"t": {"width": 1, "texels": [[1,2,3,4]],
                                            "lod_bias": 2000}}})")
                .find("expected -1000..1000"),
            std::string::npos);
}

}  // namespace
}  // namespace gpusim

// ---------------------------------------------------------------- texture files

namespace gpusim {
namespace {

// Writes a width x height image of `channels` 8-bit channels, pixel (x, y)
// from the top row having channel c = 10 y + x + 100 c.
void write_image(const std::string& path, int width, int height, int channels) {
  std::vector<uint8_t> pixels;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c)
        pixels.push_back(static_cast<uint8_t>(10 * y + x + 100 * c));
    }
  }
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path, OIIO::ImageSpec(width, height, channels, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  out->close();
}

TEST_F(SceneLoaderTest, TextureFileRowsRunFromTheBottom) {
  write_image((dir_ / "t.png").string(), 3, 2, 3);
  const Scene s = load(R"({"textures": {"t": {"file": "t.png", "mipmaps": "generate"}}})");
  const Texture& t = s.textures.at(0);
  EXPECT_EQ(t.format, TextureFormat::rgb8);  // three channels
  ASSERT_EQ(t.levels.size(), 2u);
  EXPECT_EQ(t.levels[0].width, 3);
  EXPECT_EQ(t.levels[0].height, 2);
  // t = 0 is the image's bottom row (y = 1 from the top): 10 + x + 100 c.
  EXPECT_EQ(t.levels[0].texels[0], 10);
  EXPECT_EQ(t.levels[0].texels[1], 110);
  EXPECT_EQ(t.levels[0].texels[3], 11);
  EXPECT_EQ(t.levels[0].texels[9], 0);  // row t = 1 is the top row
  // "format" converts: 8 bits to rgb565 rounded, (v 31 + 127) / 255.
  const Scene f = load(R"({"textures": {"t": {"file": "t.png", "format": "rgb565"}}})");
  const unsigned v = f.textures.at(0).levels[0].texels[0] | f.textures.at(0).levels[0].texels[1]
                                                                << 8;
  EXPECT_EQ(v >> 11, (10u * 31 + 127) / 255);
  EXPECT_EQ(v >> 5 & 63, (110u * 63 + 127) / 255);
}

TEST_F(SceneLoaderTest, TextureFileProblemsAreOneLineErrors) {
  EXPECT_NE(error_of(R"({"textures": {"t": {"file": "missing.png"}}})")
                .find("textures.t.file: cannot read \"missing.png\""),
            std::string::npos);
  write_image((dir_ / "wide.png").string(), 5000, 1, 1);
  EXPECT_NE(error_of(R"({"textures": {"t": {"file": "wide.png"}}})")
                .find("5000 x 1 pixels: a texture is 1 to 4096 texels on a side"),
            std::string::npos);
  write_image((dir_ / "t.png").string(), 2, 2, 1);
  EXPECT_NE(error_of(R"({"textures": {"t": {"file": "t.png", "width": 2}}})")
                .find("a texture from a \"file\" has its own"),
            std::string::npos);
}

TEST_F(SceneLoaderTest, MeshesBringTheirMaterialsTextures) {
  const std::string box = "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb";
  const Scene s = load(R"({"draws": [{"mesh": ")" + box + R"("}]})");
  ASSERT_EQ(s.textures.size(), 1u);  // its embedded PNG, once
  const Texture& t = s.textures[0];
  EXPECT_EQ(t.sampler.min_filter, TextureFilter::linear_mipmap_linear);
  EXPECT_EQ(t.levels.back().width, 1);
  for (const Draw& d : s.draws) {
    EXPECT_EQ(d.texture, 0);
    EXPECT_EQ(d.texcoords.size(), d.positions.size());
  }
  const Scene off = load(R"({"draws": [{"mesh": ")" + box + R"(", "textures": false}]})");
  EXPECT_TRUE(off.textures.empty());
  for (const Draw& d : off.draws) EXPECT_EQ(d.texture, -1);
}

}  // namespace
}  // namespace gpusim
