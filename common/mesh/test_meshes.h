// Small meshes with a known answer for the sim tests.
#pragma once

#include "common/mesh/mesh.h"

namespace uw {

// Appends a grid of n_u x n_v quads over the parallelogram corner + [0,1] u
// + [0,1] v, counter-clockwise seen from the side u x v points to.
inline void AddGrid(const Eigen::Vector3d& corner, const Eigen::Vector3d& u,
                    const Eigen::Vector3d& v, int n_u, int n_v,
                    TriangleMesh* mesh) {
  const int first = static_cast<int>(mesh->vertices.size());
  for (int j = 0; j <= n_v; ++j) {
    for (int i = 0; i <= n_u; ++i) {
      mesh->vertices.push_back(corner + (static_cast<double>(i) / n_u) * u +
                               (static_cast<double>(j) / n_v) * v);
    }
  }
  const auto index = [&](int i, int j) { return first + j * (n_u + 1) + i; };
  for (int j = 0; j < n_v; ++j) {
    for (int i = 0; i < n_u; ++i) {
      mesh->triangles.emplace_back(index(i, j), index(i + 1, j),
                                   index(i + 1, j + 1));
      mesh->triangles.emplace_back(index(i, j), index(i + 1, j + 1),
                                   index(i, j + 1));
    }
  }
}

}  // namespace uw
