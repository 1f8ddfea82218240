#include "testbench/scene/mesh_import.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>

namespace gpusim {
namespace {

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

bool finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// Replaces `out` only when the material has the key and its value is finite, so
// a file with odd values still gets the documented defaults.
void get_color(const aiMaterial& m, const char* key, unsigned type, unsigned idx, glm::vec4& out) {
  aiColor4D c;
  if (m.Get(key, type, idx, c) != aiReturn_SUCCESS) return;
  // Ambient/specular alpha is unused by the lighting equation; keep it 1.
  const glm::vec4 v{c.r, c.g, c.b, 1.0f};
  if (finite(v)) out = v;
}

Material convert_material(const aiMaterial& m) {
  Material out;
  get_color(m, AI_MATKEY_COLOR_DIFFUSE, out.diffuse);
  get_color(m, AI_MATKEY_COLOR_AMBIENT, out.ambient);
  get_color(m, AI_MATKEY_COLOR_SPECULAR, out.specular);
  float opacity = 1.0f;
  if (m.Get(AI_MATKEY_OPACITY, opacity) == aiReturn_SUCCESS && std::isfinite(opacity)) {
    out.diffuse.a = std::clamp(opacity, 0.0f, 1.0f);
  }
  float shininess = 0.0f;
  if (m.Get(AI_MATKEY_SHININESS, shininess) == aiReturn_SUCCESS && std::isfinite(shininess)) {
    // GL's specular exponent range; glTF roughness conversions can exceed it.
    out.shininess = std::clamp(shininess, 0.0f, 128.0f);
  }
  return out;
}

}  // namespace

std::vector<ImportedMesh> import_mesh(const std::string& file) {
  Assimp::Importer importer;
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_GenSmoothNormals | aiProcess_PreTransformVertices |
                         aiProcess_SortByPType;
  const aiScene* scene = importer.ReadFile(file, flags);
  if (scene == nullptr) throw MeshImportError(one_line(importer.GetErrorString()));

  std::vector<ImportedMesh> out;
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* mesh = scene->mMeshes[mi];
    if (mesh == nullptr || mesh->mVertices == nullptr) continue;
    ImportedMesh im;
    im.index = mi;
    // SortByPType leaves each mesh with one primitive type, but a face count
    // check costs nothing and keeps points and lines out whatever assimp does.
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (unsigned k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= mesh->mNumVertices) {
          throw MeshImportError("mesh " + std::to_string(mi) + " face " + std::to_string(f) +
                                " has an out-of-range vertex index");
        }
        im.indices.push_back(face.mIndices[k]);
      }
    }
    if (im.indices.empty()) continue;

    const auto where = [&](unsigned v) {
      return "mesh " + std::to_string(mi) + " vertex " + std::to_string(v);
    };
    im.positions.reserve(mesh->mNumVertices);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      const glm::vec4 pos{p.x, p.y, p.z, 1.0f};
      if (!finite(pos)) throw MeshImportError(where(v) + " has a non-finite position");
      im.positions.push_back(pos);
    }
    if (mesh->mNormals != nullptr) {
      im.normals.reserve(mesh->mNumVertices);
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D& n = mesh->mNormals[v];
        if (!finite(glm::vec4(n.x, n.y, n.z, 0.0f))) {
          throw MeshImportError(where(v) + " has a non-finite normal");
        }
        im.normals.emplace_back(n.x, n.y, n.z);
      }
    }
    if (mesh->mColors[0] != nullptr) {
      im.colors.reserve(mesh->mNumVertices);
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiColor4D& c = mesh->mColors[0][v];
        const glm::vec4 col{c.r, c.g, c.b, c.a};
        if (!finite(col)) throw MeshImportError(where(v) + " has a non-finite colour");
        im.colors.push_back(col);
      }
    }
    if (mesh->mMaterialIndex < scene->mNumMaterials &&
        scene->mMaterials[mesh->mMaterialIndex] != nullptr) {
      im.material = convert_material(*scene->mMaterials[mesh->mMaterialIndex]);
    }
    out.push_back(std::move(im));
  }
  if (out.empty()) throw MeshImportError("the file has no triangles");
  return out;
}

}  // namespace gpusim
