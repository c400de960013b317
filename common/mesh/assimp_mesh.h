// Meshes from other tools' formats (STL, glTF/GLB, COLLADA, FBX, OFF, 3DS,
// ...) through Assimp: what Metashape, OpenMVS or a CAD package exports.
// Assimp holds coordinates in single precision, so a mesh far from its
// origin (UTM coordinates) would silently lose millimetres to decimetres:
// such a mesh is refused rather than read wrong. PLY and OBJ are read by
// mesh.h's own double-precision readers.
#pragma once

#include <filesystem>

#include "common/mesh/mesh.h"

namespace uw {

// Every triangle of every mesh in the file, node transforms applied,
// identical vertices joined, polygons triangulated. Throws uw::Error naming
// the file when Assimp cannot read it, when it holds no triangle, or when
// its coordinates are so large against its extent that single precision
// loses more than 1e-5 of that extent (then re-export it centred, or as
// PLY in double).
TriangleMesh ReadAssimpMesh(const std::filesystem::path& path);

}  // namespace uw
