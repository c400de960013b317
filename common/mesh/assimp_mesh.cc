#include "common/mesh/assimp_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <assimp/Importer.hpp>

#include "common/util/error.h"

namespace uw {

TriangleMesh ReadAssimpMesh(const std::filesystem::path& path) {
  Assimp::Importer importer;
  // Points and lines are not surfaces.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(
      path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_PreTransformVertices |
                         aiProcess_SortByPType);
  if (scene == nullptr) {
    throw ErrorAt(path.string(),
                  ": cannot read the mesh: ", importer.GetErrorString());
  }
  TriangleMesh mesh;
  double largest = 0.0;
  Eigen::Vector3d low =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh& part = *scene->mMeshes[m];
    const int first = static_cast<int>(mesh.vertices.size());
    for (unsigned v = 0; v < part.mNumVertices; ++v) {
      const aiVector3D& p = part.mVertices[v];
      const Eigen::Vector3d vertex(p.x, p.y, p.z);
      mesh.vertices.push_back(vertex);
      largest = std::max(largest, vertex.cwiseAbs().maxCoeff());
      low = low.cwiseMin(vertex);
      high = high.cwiseMax(vertex);
    }
    for (unsigned f = 0; f < part.mNumFaces; ++f) {
      const aiFace& face = part.mFaces[f];
      if (face.mNumIndices != 3) continue;
      mesh.triangles.emplace_back(first + static_cast<int>(face.mIndices[0]),
                                  first + static_cast<int>(face.mIndices[1]),
                                  first + static_cast<int>(face.mIndices[2]));
    }
  }
  if (mesh.triangles.empty()) throw ErrorAt(path.string(), ": no triangles");
  // A float keeps 2^-24 of its magnitude.
  const double extent = (high - low).norm();
  const double lost = largest * std::ldexp(1.0, -24);
  if (lost > 1e-5 * extent) {
    throw ErrorAt(
        path.string(),
        fmt::format(": coordinates up to {:.6g} lose up to {:.3g} units in "
                    "the single precision its reader (Assimp) holds them "
                    "in, more than 1e-5 of the mesh's {:.4g}-unit extent; "
                    "export it centred on the survey, or as PLY (read in "
                    "double)",
                    largest, lost, extent));
  }
  return mesh;
}

}  // namespace uw
