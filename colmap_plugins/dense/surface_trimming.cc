#include "colmap_plugins/dense/surface_trimming.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "common/util/error.h"

namespace uw {

void TrimmingOptions::Check() const {
  if (!(max_distance > 0.0 && std::isfinite(max_distance))) {
    throw ErrorAt("Trimming.max_distance must be > 0, got ", max_distance);
  }
  if (!(max_edge_factor > 1.0)) {
    throw ErrorAt("Trimming.max_edge_factor must be > 1, got ",
                  max_edge_factor);
  }
  if (!(min_component_fraction >= 0.0 && min_component_fraction <= 1.0)) {
    throw ErrorAt("Trimming.min_component_fraction must be in [0, 1], got ",
                  min_component_fraction);
  }
}

namespace {

using CellKey = Eigen::Matrix<int64_t, 3, 1>;

struct CellKeyHash {
  size_t operator()(const CellKey& key) const {
    return static_cast<size_t>(key.x() * 73856093LL ^ key.y() * 19349663LL ^
                               key.z() * 83492791LL);
  }
};

// Points bucketed in cells of the query radius: a query looks at 27 cells.
class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector3d>& points, double radius)
      : points_(points), radius_(radius) {
    for (size_t i = 0; i < points.size(); ++i) {
      cells_[Key(points[i])].push_back(i);
    }
  }

  bool AnyWithin(const Eigen::Vector3d& query) const {
    const CellKey center = Key(query);
    const double radius_sq = radius_ * radius_;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto found = cells_.find(center + CellKey(dx, dy, dz));
          if (found == cells_.end()) {
            continue;
          }
          for (const size_t i : found->second) {
            if ((points_[i] - query).squaredNorm() <= radius_sq) {
              return true;
            }
          }
        }
      }
    }
    return false;
  }

 private:
  CellKey Key(const Eigen::Vector3d& point) const {
    return (point / radius_).array().floor().cast<int64_t>().matrix();
  }

  const std::vector<Eigen::Vector3d>& points_;
  double radius_;
  std::unordered_map<CellKey, std::vector<size_t>, CellKeyHash> cells_;
};

size_t Find(std::vector<size_t>& parent, size_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

TriangleMesh TrimUnsupported(const TriangleMesh& mesh,
                             const std::vector<Eigen::Vector3d>& points,
                             const TrimmingOptions& options) {
  options.Check();
  const int num_vertices = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    if (triangle.minCoeff() < 0 || triangle.maxCoeff() >= num_vertices) {
      throw ErrorAt(
          "TrimUnsupported: a triangle has a vertex index out of "
          "range (",
          num_vertices, " vertices)");
    }
  }
  const size_t num_triangles = mesh.triangles.size();
  std::vector<double> edges;
  edges.reserve(3 * num_triangles);
  auto longest_edge = [&](const Eigen::Vector3i& t) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& c = mesh.vertices[t[2]];
    return std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()});
  };
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      edges.push_back(
          (mesh.vertices[t[k]] - mesh.vertices[t[(k + 1) % 3]]).norm());
    }
  }
  double max_edge = std::numeric_limits<double>::infinity();
  if (!edges.empty()) {
    std::nth_element(edges.begin(), edges.begin() + edges.size() / 2,
                     edges.end());
    max_edge = options.max_edge_factor * edges[edges.size() / 2];
  }

  const PointGrid grid(points, options.max_distance);
  std::vector<bool> keep(num_triangles, false);
  for (size_t i = 0; i < num_triangles; ++i) {
    const Eigen::Vector3i& t = mesh.triangles[i];
    const Eigen::Vector3d centroid =
        (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
    keep[i] = longest_edge(t) <= max_edge && grid.AnyWithin(centroid);
  }

  // Components of kept triangles through shared vertices.
  std::vector<size_t> parent(mesh.vertices.size());
  std::iota(parent.begin(), parent.end(), size_t{0});
  for (size_t i = 0; i < num_triangles; ++i) {
    if (!keep[i]) {
      continue;
    }
    const Eigen::Vector3i& t = mesh.triangles[i];
    for (int k = 1; k < 3; ++k) {
      parent[Find(parent, t[k])] = Find(parent, t[0]);
    }
  }
  std::unordered_map<size_t, size_t> component_size;
  size_t largest = 0;
  for (size_t i = 0; i < num_triangles; ++i) {
    if (keep[i]) {
      largest = std::max(largest,
                         ++component_size[Find(parent, mesh.triangles[i][0])]);
    }
  }
  const double min_size =
      options.min_component_fraction * static_cast<double>(largest);

  TriangleMesh trimmed;
  std::vector<int> new_index(mesh.vertices.size(), -1);
  for (size_t i = 0; i < num_triangles; ++i) {
    if (!keep[i] ||
        static_cast<double>(
            component_size[Find(parent, mesh.triangles[i][0])]) < min_size) {
      continue;
    }
    Eigen::Vector3i triangle;
    for (int k = 0; k < 3; ++k) {
      int& index = new_index[mesh.triangles[i][k]];
      if (index < 0) {
        index = static_cast<int>(trimmed.vertices.size());
        trimmed.vertices.push_back(mesh.vertices[mesh.triangles[i][k]]);
      }
      triangle[k] = index;
    }
    trimmed.triangles.push_back(triangle);
  }
  return trimmed;
}

}  // namespace uw
