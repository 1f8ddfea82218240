// Mesh files (anything assimp reads) turned into triangle lists for the scene
// loader. Kept apart from scene_loader.cpp so assimp's headers stay here.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "testbench/scene/scene.h"

namespace gpusim {

// A problem with a mesh file; the loader prefixes the scene file and JSON path.
class MeshImportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One assimp mesh with triangles, after pre-transforming the node hierarchy.
struct ImportedMesh {
  unsigned index = 0;  // the aiMesh's index in the post-processed scene
  std::vector<glm::vec4> positions;
  std::vector<glm::vec3> normals;  // one per position, or empty
  std::vector<glm::vec4> colors;   // colour set 0, or empty
  std::vector<uint32_t> indices;   // three per triangle
  Material material;               // from the file's material (see docs/scene-format.md)
};

// Reads `file`; throws MeshImportError (one line) when assimp cannot read it,
// it has no triangles, or its data is unusable (non-finite values).
std::vector<ImportedMesh> import_mesh(const std::string& file);

}  // namespace gpusim
