// The direct binary-PLY reader (testbench/scene/binary_ply.h) against assimp:
// on every file it takes, its meshes must equal import_mesh_with_assimp's
// bit for bit; every file outside its layout must go to assimp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "testbench/scene/binary_ply.h"
#include "testbench/scene/mesh_import.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

template <typename T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool same_bytes(const glm::vec4& a, const glm::vec4& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

void expect_same(const std::vector<ImportedMesh>& a, const std::vector<ImportedMesh>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE("mesh " + std::to_string(i));
    EXPECT_EQ(a[i].index, b[i].index);
    EXPECT_EQ(a[i].primitive, b[i].primitive);
    EXPECT_TRUE(same_bytes(a[i].positions, b[i].positions));
    EXPECT_TRUE(same_bytes(a[i].normals, b[i].normals));
    EXPECT_TRUE(same_bytes(a[i].colors, b[i].colors));
    EXPECT_TRUE(same_bytes(a[i].indices, b[i].indices));
    const Material& m = a[i].material;
    const Material& n = b[i].material;
    EXPECT_TRUE(same_bytes(m.ambient, n.ambient));
    EXPECT_TRUE(same_bytes(m.diffuse, n.diffuse));
    EXPECT_TRUE(same_bytes(m.specular, n.specular));
    EXPECT_TRUE(same_bytes(m.emission, n.emission));
    EXPECT_EQ(std::memcmp(&m.shininess, &n.shininess, sizeof(float)), 0);
  }
}

// A binary PLY written field by field, so that each test can bend one rule.
struct Ply {
  std::vector<std::string> vertex_properties = {"x", "y", "z", "nx", "ny", "nz"};
  std::vector<std::vector<float>> vertices;  // one value per property
  std::string list = "property list uchar uint vertex_indices";
  std::vector<std::vector<uint32_t>> faces;
  std::string format = "binary_little_endian";
  std::string trailing;

  // scripts/bench's height field (write_grid_ply), n x n vertices.
  static Ply grid(int n) {
    Ply p;
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const double u = double(i) / (n - 1), v = double(j) / (n - 1);
        const double h = 0.08 * std::sin(u * 40.0) * std::cos(v * 33.0);
        const double nx = -0.08 * 40.0 * std::cos(u * 40.0) * std::cos(v * 33.0);
        const double ny = 0.08 * 33.0 * std::sin(u * 40.0) * std::sin(v * 33.0);
        const double inv = 1.0 / std::sqrt(nx * nx + ny * ny + 1.0);
        p.vertices.push_back({float(u * 2 - 1), float(v * 2 - 1), float(h), float(nx * inv),
                              float(ny * inv), float(inv)});
      }
    }
    for (int j = 0; j + 1 < n; ++j) {
      for (int i = 0; i + 1 < n; ++i) {
        const uint32_t a = uint32_t(j * n + i);
        p.faces.push_back({a, a + 1, a + uint32_t(n) + 1});
        p.faces.push_back({a, a + uint32_t(n) + 1, a + uint32_t(n)});
      }
    }
    return p;
  }

  void write(const std::string& path, unsigned count_bytes = 1) const {
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat " << format << " 1.0\ncomment written by scene_binary_ply_test\n"
        << "element vertex " << vertices.size() << "\n";
    for (const std::string& p : vertex_properties) out << "property float " << p << "\n";
    out << "element face " << faces.size() << "\n" << list << "\nend_header\n";
    for (const auto& v : vertices) out.write(reinterpret_cast<const char*>(v.data()), 4 * v.size());
    for (const auto& f : faces) {
      const uint32_t n = uint32_t(f.size());
      out.write(reinterpret_cast<const char*>(&n), count_bytes);
      out.write(reinterpret_cast<const char*>(f.data()), 4 * f.size());
    }
    out << trailing;
  }
};

class BinaryPlyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("gpusim_ply_test_" + std::to_string(getpid())) /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `ply`; expects the direct reader to take it (or not) and
  // import_mesh to give assimp's meshes either way.
  void check(const Ply& ply, bool direct, unsigned count_bytes = 1) {
    const std::string path = (dir_ / "mesh.ply").string();
    ply.write(path, count_bytes);
    const std::optional<std::vector<ImportedMesh>> fast = read_binary_ply(path);
    EXPECT_EQ(fast.has_value(), direct);
    const std::vector<ImportedMesh> assimp = import_mesh_with_assimp(path);
    if (fast) expect_same(*fast, assimp);
    expect_same(import_mesh(path), assimp);
  }

  fs::path dir_;
};

TEST_F(BinaryPlyTest, BenchGridEqualsAssimp) {
  const Ply grid = Ply::grid(60);  // 3600 vertices, 6962 triangles
  check(grid, true);
  // Non-empty and as written: the comparison above compared something.
  const std::string path = (dir_ / "mesh.ply").string();
  const auto meshes = read_binary_ply(path);
  ASSERT_TRUE(meshes);
  ASSERT_EQ(meshes->size(), 1u);
  EXPECT_EQ((*meshes)[0].positions.size(), 3600u);
  EXPECT_EQ((*meshes)[0].indices.size(), 3u * 2u * 59u * 59u);
  EXPECT_EQ((*meshes)[0].indices[5], 60u);  // the second triangle's last corner: a + n
  EXPECT_EQ((*meshes)[0].positions[61].x, grid.vertices[61][0]);
}

TEST_F(BinaryPlyTest, PropertyOrderCountAndIndexTypes) {
  Ply p = Ply::grid(12);
  // Normals first: the reader must map properties by name.
  p.vertex_properties = {"nx", "ny", "nz", "x", "y", "z"};
  p.list = "property list ushort int vertex_index";
  check(p, true, 2);
}

TEST_F(BinaryPlyTest, JoinableVerticesGoToAssimp) {
  Ply p = Ply::grid(12);
  // Vertex 5 a copy of vertex 4: JoinIdenticalVertices joins them and
  // renumbers the indices, which only assimp does.
  p.vertices[5] = p.vertices[4];
  check(p, false);
  // (assimp did join them: the test is about a real difference.)
  EXPECT_EQ(import_mesh_with_assimp((dir_ / "mesh.ply").string())[0].positions.size(),
            p.vertices.size() - 1);
  // 4e-6 apart, within assimp's 1e-5: assimp 5.2 joins such a pair only when
  // its hash table puts both in one bucket; the reader leaves every such
  // pair to assimp.
  p.vertices[5][0] += 4e-6f;
  check(p, false);
  // 2e-5 apart: never joined, so the direct path applies.
  p.vertices[5] = p.vertices[4];
  p.vertices[5][0] += 2e-5f;
  check(p, true);
  // One position, normals 2e-5 apart: not joined, so the direct path applies
  // (the normals are compared only once the positions match).
  p.vertices[5] = p.vertices[4];
  p.vertices[5][3] += 2e-5f;
  check(p, true);
  // One position, normals 4e-6 apart: joinable, left to assimp.
  p.vertices[5] = p.vertices[4];
  p.vertices[5][4] += 4e-6f;
  check(p, false);
}

// Whether assimp's JoinIdenticalVertices test (areVerticesEqual, float
// arithmetic) holds for some two vertices, by comparing every pair.
bool some_pair_joinable(const Ply& p) {
  const float eps = 1e-5f * 1e-5f;
  const auto close = [&](const std::vector<float>& a, const std::vector<float>& b, int k) {
    const float dx = a[k] - b[k], dy = a[k + 1] - b[k + 1], dz = a[k + 2] - b[k + 2];
    return !(dx * dx + dy * dy + dz * dz > eps);
  };
  for (size_t i = 0; i < p.vertices.size(); ++i) {
    for (size_t j = i + 1; j < p.vertices.size(); ++j) {
      if (close(p.vertices[i], p.vertices[j], 0) && close(p.vertices[i], p.vertices[j], 3)) {
        return true;
      }
    }
  }
  return false;
}

// The reader's search for joinable pairs (sorted projections, slabs) against
// every pair: in each trial one vertex moved next to another, within 6e-6
// (mostly joinable) or 1.5e-5 (mostly not) on each coordinate of position
// and normal in random directions, so that about a quarter of the pairs
// straddle a boundary of the search's slabs; also far from the origin,
// where the reader searches in one dimension.
TEST_F(BinaryPlyTest, JoinableSearchMatchesEveryPair) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_int_distribution<int> pick(0, 10 * 10 - 1);
  int joinable = 0, direct = 0;
  for (int trial = 0; trial < 240; ++trial) {
    Ply p = Ply::grid(10);
    const float scale = trial % 8 == 7 ? 1e8f : 1.0f;  // past the slabs' 1e7 bound
    for (auto& v : p.vertices) {
      for (int k = 0; k < 3; ++k) v[k] *= scale;
    }
    const int a = pick(rng), b = (a + 1 + pick(rng) % 99) % 100;
    const float reach = trial % 2 ? 6e-6f : 1.5e-5f;
    p.vertices[b] = p.vertices[a];
    for (int k = 0; k < 6; ++k) {
      if (scale == 1.0f || k >= 3) p.vertices[b][k] += reach * unit(rng);
    }
    const bool expected = some_pair_joinable(p);
    joinable += expected;
    direct += !expected;
    SCOPED_TRACE("trial " + std::to_string(trial));
    check(p, !expected);
  }
  // Both outcomes are exercised.
  EXPECT_GT(joinable, 60);
  EXPECT_GT(direct, 60);
}

TEST_F(BinaryPlyTest, OtherLayoutsGoToAssimp) {
  const Ply grid = Ply::grid(8);
  {
    Ply p = grid;  // an unused vertex: assimp drops it and renumbers
    p.vertices.insert(p.vertices.begin(), {5, 5, 5, 0, 0, 1});
    for (auto& f : p.faces) {
      for (uint32_t& i : f) ++i;
    }
    check(p, false);
    EXPECT_EQ(import_mesh_with_assimp((dir_ / "mesh.ply").string())[0].indices[0], 0u);
  }
  {
    Ply p = grid;  // a quad: assimp triangulates it
    p.faces[0] = {0, 1, 9, 8};
    check(p, false);
  }
  {
    Ply p = grid;  // no normals: assimp generates them
    p.vertex_properties = {"x", "y", "z"};
    for (auto& v : p.vertices) v.resize(3);
    check(p, false);
  }
  {
    Ply p = grid;  // a property the reader does not know (texture coordinate)
    p.vertex_properties.push_back("s");
    for (auto& v : p.vertices) v.push_back(0.5f);
    check(p, false);
  }
  {
    Ply p = grid;  // bytes after the last face
    p.trailing = "extra";
    check(p, false);
  }
  {
    // An out-of-range index and a truncated file: assimp's errors stand.
    Ply p = grid;
    p.faces[3][1] = 1000;
    const std::string path = (dir_ / "bad.ply").string();
    p.write(path);
    EXPECT_FALSE(read_binary_ply(path));
    fs::resize_file(path, fs::file_size(path) - 7);
    EXPECT_FALSE(read_binary_ply(path));
  }
}

// Every PLY among assimp's test models: import_mesh gives what assimp gives
// (or fails with the same message).
TEST_F(BinaryPlyTest, AssimpTestModelsUnchanged) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator("/usr/share/assimp/models/PLY")) {
    if (entry.path().extension() != ".ply") continue;
    SCOPED_TRACE(entry.path().string());
    ++files;
    std::string fast_error, assimp_error;
    std::vector<ImportedMesh> fast, assimp;
    try {
      fast = import_mesh(entry.path().string());
    } catch (const MeshImportError& e) {
      fast_error = e.what();
    }
    try {
      assimp = import_mesh_with_assimp(entry.path().string());
    } catch (const MeshImportError& e) {
      assimp_error = e.what();
    }
    EXPECT_EQ(fast_error, assimp_error);
    expect_same(fast, assimp);
  }
  EXPECT_GE(files, 5);
}

}  // namespace
}  // namespace gpusim
