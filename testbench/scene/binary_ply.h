// A direct reader for the one mesh layout that dominates large inputs: a
// binary little-endian PLY of float positions and normals and an indexed
// triangle list (scripts/bench's 10 M-triangle grid is 250 MB of it).
//
// Why: assimp reads such a file into a per-value DOM and then runs
// JoinIdenticalVertices over it; for the 10 M-triangle grid that is about
// 8 s of CPU and a 3.7 GB peak (docs/benchmarks.md, "Profile"), to return
// the file's own arrays. This reader decodes the file straight into the
// ImportedMesh arrays (one copy, no DOM) and returns exactly what
// import_mesh's assimp path returns for the file: the same positions,
// normals, indices, material and mesh index.
//
// It only takes files where that equality holds by construction and leaves
// every other file to assimp (returns nullopt): the header must be
// `format binary_little_endian 1.0`, then `element vertex` with float
// properties x, y, z, nx, ny, nz (any order, nothing else), then
// `element face` with one list `vertex_indices` (or `vertex_index`) of
// char/uchar/short/ushort/int/uint counts and int/uint indices, and nothing
// after; every face must have 3 indices in range, every vertex must be used
// and finite, and no two vertices may be equal within assimp's
// JoinIdenticalVertices tolerance (squared distance <= 1e-10 in position
// and normal), so that the step would keep every vertex in file order. A
// file that fails any of these (including a damaged one) goes to assimp,
// which gives the result or the error message it always gave.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "testbench/scene/mesh_import.h"

namespace gpusim {

// The file's mesh when it has the layout above, else nullopt (also when the
// file cannot be opened or is short: assimp then reports why).
std::optional<std::vector<ImportedMesh>> read_binary_ply(const std::string& file);

}  // namespace gpusim
