#include "testbench/scene/binary_ply.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sstream>

namespace gpusim {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// One header line without its '\n'; false at end of file, on a '\r' (assimp
// reads those; this reader leaves them to it) or past 4 KiB.
bool read_line(std::FILE* f, std::string& line) {
  line.clear();
  for (int c; (c = std::fgetc(f)) != EOF;) {
    if (c == '\n') return true;
    if (c == '\r' || line.size() > 4096) return false;
    line.push_back(static_cast<char>(c));
  }
  return false;
}

// Bytes of a PLY integer type usable as a list count, 0 otherwise.
unsigned count_bytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32") return 4;
  return 0;
}

// The little-endian count of `bytes` bytes at `p`, as the PLY type gives it
// (signed types sign-extended, so a negative count is not 3).
int64_t read_count(const unsigned char* p, unsigned bytes, bool is_signed) {
  uint32_t u = 0;
  for (unsigned b = 0; b < bytes; ++b) u |= static_cast<uint32_t>(p[b]) << (8 * b);
  if (!is_signed) return u;
  if (bytes == 1) return static_cast<int8_t>(u);
  if (bytes == 2) return static_cast<int16_t>(u);
  return static_cast<int32_t>(u);
}

// assimp 5.2's JoinIdenticalVertices (areVerticesEqual): two vertices are
// one when the squared distance of their positions and of their normals
// (float arithmetic) are both at most (1e-5)^2; texture coordinates,
// tangents and bitangents are absent here, so equal. `a` and `b`: three
// floats each, a position or a normal.
bool assimp_close(const float* a, const float* b) {
  static const float kSquareEpsilon = 1e-5f * 1e-5f;
  const float dx = a[0] - b[0];
  const float dy = a[1] - b[1];
  const float dz = a[2] - b[2];
  return !(dx * dx + dy * dy + dz * dz > kSquareEpsilon);
}

// Whether JoinIdenticalVertices joins vertices a and b of `v` (six floats
// each: position, normal).
bool joinable(const std::vector<float>& v, uint32_t a, uint32_t b) {
  return assimp_close(&v[6 * size_t{a}], &v[6 * size_t{b}]) &&
         assimp_close(&v[6 * size_t{a} + 3], &v[6 * size_t{b} + 3]);
}

// A pair assimp joins has every |a_i - b_i| <= 1e-5 (up to float rounding:
// a 1% margin), so its projections onto a direction d differ by at most
// (sum |d_i|) * 1e-5 * 1.01, the direction's window.
constexpr double window(const double (&d)[3]) {
  return ((d[0] < 0 ? -d[0] : d[0]) + (d[1] < 0 ? -d[1] : d[1]) + (d[2] < 0 ? -d[2] : d[2])) *
         1e-5 * 1.01;
}
constexpr double kDir[3] = {0.8523, 0.34321, 0.5736};
constexpr double kDir2[3] = {-0.2817, 0.9315, -0.1391};  // any other direction

double project(const double (&d)[3], const float* p) {
  return d[0] * p[0] + d[1] * p[1] + d[2] * p[2];
}

// Whether some two vertices are equal for JoinIdenticalVertices, for any
// vertices: each is projected onto kDir and the projections sorted, so only
// neighbours inside kDir's window are compared. `v`: six floats per vertex
// (position, normal).
bool has_joinable_vertices_1d(const std::vector<float>& v, size_t count) {
  const double w = window(kDir);
  struct Key {
    double projection;
    uint32_t vertex;
  };
  std::vector<Key> keys(count);
  for (size_t i = 0; i < count; ++i) {
    keys[i] = {project(kDir, &v[6 * i]), static_cast<uint32_t>(i)};
  }
  std::sort(keys.begin(), keys.end(),
            [](const Key& a, const Key& b) { return a.projection < b.projection; });
  for (size_t i = 0; i < count; ++i) {
    for (size_t j = i + 1; j < count && keys[j].projection - keys[i].projection <= w; ++j) {
      if (joinable(v, keys[i].vertex, keys[j].vertex)) return true;
    }
  }
  return false;
}

// The same in two dimensions, for coordinates below 1e7: the vertices are
// cut into slabs by their kDir projection, slabs twice kDir's window thick,
// so a pair assimp joins lies in one slab or two adjacent ones; in a slab
// they are sorted by their kDir2 projection, and each vertex is compared
// with the ones of its slab after it and of the next slab within kDir2's
// window. On a dense mesh a slab holds a few dozen vertices far apart
// along kDir2, where kDir's window alone held dozens of neighbours per
// vertex (the 10 M-triangle grid: 0.5 s of its 1 s load, now about 0.2 s,
// the sort).
bool has_joinable_vertices(const std::vector<float>& v, size_t count) {
  const double thickness = 2 * window(kDir);
  const double w2 = window(kDir2);
  struct Key {
    double slab;        // floor(kDir projection / thickness), an integer
    double projection;  // onto kDir2
    uint32_t vertex;
  };
  std::vector<Key> keys(count);
  for (size_t i = 0; i < count; ++i) {
    const float* p = &v[6 * i];
    // Far from the origin the projections' rounding nears the windows' 1%
    // margin: the one-dimensional search, as before (below 1e7 the rounding
    // is under 1e-8 and the slab index, under 2^51, exact).
    if (!(std::fabs(p[0]) < 1e7f && std::fabs(p[1]) < 1e7f && std::fabs(p[2]) < 1e7f)) {
      return has_joinable_vertices_1d(v, count);
    }
    keys[i] = {std::floor(project(kDir, p) / thickness), project(kDir2, p),
               static_cast<uint32_t>(i)};
  }
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    return a.slab < b.slab || (a.slab == b.slab && a.projection < b.projection);
  });
  // Positions in sorted order, gathered once: fetching them scattered from
  // `v` for every comparison cost more than the comparisons.
  std::vector<float> positions(3 * count);
  for (size_t i = 0; i < count; ++i) {
    std::memcpy(&positions[3 * i], &v[6 * size_t{keys[i].vertex}], 3 * sizeof(float));
  }
  const auto close = [&](size_t i, size_t j) {
    return assimp_close(&positions[3 * i], &positions[3 * j]) &&
           assimp_close(&v[6 * size_t{keys[i].vertex} + 3], &v[6 * size_t{keys[j].vertex} + 3]);
  };
  size_t slab_end = 0;            // end of the slab of key i
  size_t next = 0, next_end = 0;  // the next slab's keys from kDir2's window below key i on
  for (size_t i = 0; i < count; ++i) {
    if (i == slab_end) {
      while (slab_end < count && keys[slab_end].slab == keys[i].slab) ++slab_end;
      next = next_end = slab_end;
      if (next < count && keys[next].slab == keys[i].slab + 1) {
        while (next_end < count && keys[next_end].slab == keys[next].slab) ++next_end;
      }
    }
    const double p = keys[i].projection;
    for (size_t j = i + 1; j < slab_end && keys[j].projection - p <= w2; ++j) {
      if (close(i, j)) return true;
    }
    while (next < next_end && p - keys[next].projection > w2) ++next;
    for (size_t j = next; j < next_end && keys[j].projection - p <= w2; ++j) {
      if (close(i, j)) return true;
    }
  }
  return false;
}

}  // namespace

std::optional<std::vector<ImportedMesh>> read_binary_ply(const std::string& file) {
  File f(std::fopen(file.c_str(), "rb"));
  if (!f) return std::nullopt;
  std::string line;
  if (!read_line(f.get(), line) || line != "ply") return std::nullopt;
  if (!read_line(f.get(), line) || line != "format binary_little_endian 1.0") return std::nullopt;

  // The header: `element vertex`, its six float properties, `element face`
  // and its one list, each exactly once and in that order.
  enum class Section { none, vertex, face };
  Section section = Section::none;
  bool seen_face = false;
  uint64_t vertices = 0, faces = 0;
  std::array<int, 6> slot;  // property order in the file -> x y z nx ny nz
  int properties = 0;
  unsigned count_size = 0;
  bool count_signed = false, index_signed = false, have_list = false;
  static const char* const kNames[6] = {"x", "y", "z", "nx", "ny", "nz"};
  for (;;) {
    if (!read_line(f.get(), line)) return std::nullopt;
    std::istringstream in(line);
    std::string word;
    in >> word;
    if (word == "end_header") break;
    if (word == "comment" || word == "obj_info") continue;
    std::string a, b, c, d, extra;
    if (word == "element") {
      uint64_t n = 0;
      if (!(in >> a >> n) || (in >> extra)) return std::nullopt;
      if (a == "vertex" && section == Section::none && !seen_face) {
        section = Section::vertex;
        vertices = n;
      } else if (a == "face" && section == Section::vertex && properties == 6) {
        section = Section::face;
        seen_face = true;
        faces = n;
      } else {
        return std::nullopt;
      }
    } else if (word == "property" && section == Section::vertex) {
      if (!(in >> a >> b) || (in >> extra) || (a != "float" && a != "float32")) return std::nullopt;
      const auto* name =
          std::find_if(std::begin(kNames), std::end(kNames), [&](const char* s) { return b == s; });
      const int k = static_cast<int>(name - std::begin(kNames));
      if (k == 6 || properties == 6) return std::nullopt;
      for (int i = 0; i < properties; ++i) {
        if (slot[i] == k) return std::nullopt;  // named twice
      }
      slot[properties++] = k;
    } else if (word == "property" && section == Section::face && !have_list) {
      if (!(in >> a >> b >> c >> d) || (in >> extra) || a != "list") return std::nullopt;
      if (d != "vertex_indices" && d != "vertex_index") return std::nullopt;
      count_size = count_bytes(b);
      if (count_size == 0 || count_bytes(c) != 4) return std::nullopt;
      count_signed = b[0] != 'u';
      index_signed = c[0] != 'u';
      have_list = true;
    } else {
      return std::nullopt;
    }
  }
  if (!have_list || vertices == 0 || faces == 0 || vertices > 0x7fffffffu ||
      faces > 0x7fffffffu / 3) {
    return std::nullopt;
  }

  // The vertices, decoded in blocks into x y z nx ny nz order.
  std::vector<float> v(6 * vertices);
  {
    constexpr size_t kBlock = 1 << 14;  // vertices per read
    std::vector<float> raw(6 * kBlock);
    for (size_t first = 0; first < vertices; first += kBlock) {
      const size_t n = std::min<size_t>(kBlock, vertices - first);
      if (std::fread(raw.data(), sizeof(float) * 6, n, f.get()) != n) return std::nullopt;
      for (size_t i = 0; i < n; ++i) {
        for (int p = 0; p < 6; ++p) v[6 * (first + i) + slot[p]] = raw[6 * i + p];
      }
    }
  }
  for (const float x : v) {
    if (!std::isfinite(x)) return std::nullopt;  // assimp's path names the vertex
  }

  // The faces: every one a triangle of in-range indices.
  std::vector<uint32_t> indices(3 * faces);
  std::vector<uint8_t> used(vertices, 0);
  {
    const size_t record = count_size + 12;
    constexpr size_t kBlock = 1 << 14;  // faces per read
    std::vector<unsigned char> raw(record * kBlock);
    for (size_t first = 0; first < faces; first += kBlock) {
      const size_t n = std::min<size_t>(kBlock, faces - first);
      if (std::fread(raw.data(), record, n, f.get()) != n) return std::nullopt;
      for (size_t i = 0; i < n; ++i) {
        const unsigned char* r = raw.data() + i * record;
        if (read_count(r, count_size, count_signed) != 3) return std::nullopt;
        for (int k = 0; k < 3; ++k) {
          const int64_t index = read_count(r + count_size + 4 * k, 4, index_signed);
          if (index < 0 || static_cast<uint64_t>(index) >= vertices) return std::nullopt;
          indices[3 * (first + i) + k] = static_cast<uint32_t>(index);
          used[static_cast<size_t>(index)] = 1;
        }
      }
    }
  }
  // Trailing bytes: not this layout.
  if (std::fgetc(f.get()) != EOF) return std::nullopt;
  f.reset();
  // JoinIdenticalVertices drops unused vertices and joins equal ones, which
  // renumbers the indices: that is assimp's to do.
  if (std::find(used.begin(), used.end(), 0) != used.end()) return std::nullopt;
  std::vector<uint8_t>().swap(used);
  if (has_joinable_vertices(v, vertices)) return std::nullopt;

  ImportedMesh m;
  m.index = 0;
  m.primitive = PrimitiveType::triangles;
  m.positions.resize(vertices);
  m.normals.resize(vertices);
  for (size_t i = 0; i < vertices; ++i) {
    const float* p = &v[6 * i];
    m.positions[i] = glm::vec4(p[0], p[1], p[2], 1.0f);
    m.normals[i] = glm::vec3(p[3], p[4], p[5]);
  }
  std::vector<float>().swap(v);
  m.indices = std::move(indices);
  // assimp's default PLY material (a file without a material element): white
  // diffuse, specular and ambient, as convert_material reads them.
  m.material.diffuse = glm::vec4(1.0f);
  m.material.specular = glm::vec4(1.0f);
  m.material.ambient = glm::vec4(1.0f);
  std::vector<ImportedMesh> out;
  out.push_back(std::move(m));
  return out;
}

}  // namespace gpusim
