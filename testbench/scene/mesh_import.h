// Mesh files (anything assimp reads) turned into triangle, line and point lists
// for the scene loader. Kept apart from scene_loader.cpp so assimp's headers stay here.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
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

// One assimp mesh's triangles, lines or points, after pre-transforming the node
// hierarchy. assimp's SortByPType gives each aiMesh one kind of primitive; an
// aiMesh that still mixed kinds would give one ImportedMesh per kind.
struct ImportedMesh {
  unsigned index = 0;  // the aiMesh's index in the post-processed scene
  // triangles, lines or points: the faces of 3, 2 or 1 indices (assimp splits
  // an OBJ polyline `l 1 2 3` into the lines (1, 2) and (2, 3)).
  PrimitiveType primitive = PrimitiveType::triangles;
  std::vector<glm::vec4> positions;
  std::vector<glm::vec3> normals;  // one per position, or empty (lines and points
                                   // have normals only when the file gives them)
  std::vector<glm::vec4> colors;   // colour set 0, or empty
  std::vector<uint32_t> indices;   // three per triangle, two per line, one per point
  Material material;               // from the file's material (see docs/scene-format.md)
  // The material's diffuse (glTF: base colour) texture, from an image file
  // beside the mesh or embedded in it, with generated mipmaps, shared by the
  // meshes that use it; null without one, or without texture coordinates.
  std::shared_ptr<const Texture> texture;
  std::vector<glm::vec2> texcoords;  // the texture's UV channel, one per position
};

// Reads `file`; throws MeshImportError (one line) when assimp cannot read it,
// it has no triangles, lines or points, its data is unusable (non-finite
// values), or a material's texture cannot be read. Each aiMesh's triangles come before its lines
// and its points. A binary PLY of the layout in binary_ply.h is read directly, with the same
// result.
// With `textures` false the materials' textures are not read (no mesh has one).
std::vector<ImportedMesh> import_mesh(const std::string& file, bool textures = true);
// Whether `file`'s name ends in an extension assimp imports (".obj", ".glb",
// ".ply", ...; not ".json"): what `gpusim run` renders as a scene of its own.
bool is_mesh_file_name(const std::string& file);
// The same through assimp for every file (the direct PLY path's tests
// compare the two).
std::vector<ImportedMesh> import_mesh_with_assimp(const std::string& file, bool textures = true);

}  // namespace gpusim
