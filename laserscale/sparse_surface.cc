#include "laserscale/sparse_surface.h"

#include <cmath>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "common/util/error.h"

namespace uw {

void SparseSurfaceOptions::Check() const {
  if (!std::isfinite(grid_spacing)) {
    throw ErrorAt("sparse surface: grid_spacing must be finite");
  }
  if (min_track_length < 2) {
    throw ErrorAt("sparse surface: min_track_length must be >= 2");
  }
  if (!(max_reprojection_error_px > 0.0)) {
    throw ErrorAt("sparse surface: max_reprojection_error_px must be > 0");
  }
  if (min_points_per_node < 1) {
    throw ErrorAt("sparse surface: min_points_per_node must be >= 1");
  }
}

TriangleMesh SparseSurfaceMesh(const Reconstruction& model,
                               const SparseSurfaceOptions& options) {
  options.Check();
  std::vector<Eigen::Vector3d> points;
  for (const Point3D& point : model.Points3D()) {
    if (static_cast<int>(point.track.size()) < options.min_track_length) {
      continue;
    }
    if (point.HasError() && point.error > options.max_reprojection_error_px) {
      continue;
    }
    points.push_back(point.xyz);
  }
  if (points.size() < 10) {
    throw ErrorAt("sparse surface: ", points.size(),
                  " well-observed points, fewer than 10");
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) {
    scatter += (p - centroid) * (p - centroid).transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  if (!(eigen.eigenvalues()(1) > 1e-12 * eigen.eigenvalues()(2))) {
    throw ErrorAt("sparse surface: the points are collinear");
  }
  Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  Eigen::Vector3d camera_side = Eigen::Vector3d::Zero();
  for (const Image& image : model.Images()) {
    camera_side += image.ProjectionCenter() - centroid;
  }
  if (camera_side.dot(normal) < 0.0) normal = -normal;
  const Eigen::Vector3d axis_u = eigen.eigenvectors().col(2);
  const Eigen::Vector3d axis_v = normal.cross(axis_u);  // right-handed

  double u_min = INFINITY, u_max = -INFINITY, v_min = INFINITY,
         v_max = -INFINITY;
  std::vector<Eigen::Vector3d> local;  // (u, v, height)
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d d = p - centroid;
    local.emplace_back(d.dot(axis_u), d.dot(axis_v), d.dot(normal));
    u_min = std::min(u_min, local.back().x());
    u_max = std::max(u_max, local.back().x());
    v_min = std::min(v_min, local.back().y());
    v_max = std::max(v_max, local.back().y());
  }
  double spacing = options.grid_spacing;
  if (spacing <= 0.0) {
    const double area = std::max((u_max - u_min) * (v_max - v_min), 1e-300);
    spacing = 2.0 * std::sqrt(area / static_cast<double>(points.size()));
  }
  const double radius = 1.5 * spacing;
  const int nu = static_cast<int>(std::ceil((u_max - u_min) / spacing)) + 1;
  const int nv = static_cast<int>(std::ceil((v_max - v_min) / spacing)) + 1;
  if (static_cast<double>(nu) * nv > 5e7) {
    throw ErrorAt("sparse surface: a ", nu, " x ", nv,
                  " grid is too fine; raise grid_spacing");
  }
  // Points bucketed by grid cell, for the neighbourhood queries.
  std::unordered_map<int64_t, std::vector<int>> buckets;
  const auto key = [&](int i, int j) {
    return static_cast<int64_t>(i) * (nv + 2) + j;
  };
  for (size_t k = 0; k < local.size(); ++k) {
    const int i =
        static_cast<int>(std::floor((local[k].x() - u_min) / spacing));
    const int j =
        static_cast<int>(std::floor((local[k].y() - v_min) / spacing));
    buckets[key(i, j)].push_back(static_cast<int>(k));
  }
  TriangleMesh mesh;
  std::vector<int> node_vertex(static_cast<size_t>(nu) * nv, -1);
  const double sigma = 0.75 * spacing;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = u_min + i * spacing;
      const double v = v_min + j * spacing;
      double weight_sum = 0.0;
      double height_sum = 0.0;
      int count = 0;
      for (int di = -2; di <= 1; ++di) {
        for (int dj = -2; dj <= 1; ++dj) {
          const auto bucket = buckets.find(key(i + di, j + dj));
          if (bucket == buckets.end()) continue;
          for (const int k : bucket->second) {
            const double d2 =
                (local[k].head<2>() - Eigen::Vector2d(u, v)).squaredNorm();
            if (d2 > radius * radius) continue;
            const double w = std::exp(-0.5 * d2 / (sigma * sigma));
            weight_sum += w;
            height_sum += w * local[k].z();
            ++count;
          }
        }
      }
      if (count < options.min_points_per_node) continue;
      node_vertex[static_cast<size_t>(i) * nv + j] =
          static_cast<int>(mesh.vertices.size());
      mesh.vertices.push_back(centroid + u * axis_u + v * axis_v +
                              (height_sum / weight_sum) * normal);
    }
  }
  // Counter-clockwise seen from the normal side: (u, v, normal) is
  // right-handed, so (i, j) -> (i + 1, j) -> (i + 1, j + 1) turns left.
  for (int i = 0; i + 1 < nu; ++i) {
    for (int j = 0; j + 1 < nv; ++j) {
      const int a = node_vertex[static_cast<size_t>(i) * nv + j];
      const int b = node_vertex[static_cast<size_t>(i + 1) * nv + j];
      const int c = node_vertex[static_cast<size_t>(i + 1) * nv + j + 1];
      const int d = node_vertex[static_cast<size_t>(i) * nv + j + 1];
      if (a >= 0 && b >= 0 && c >= 0) mesh.triangles.emplace_back(a, b, c);
      if (a >= 0 && c >= 0 && d >= 0) mesh.triangles.emplace_back(a, c, d);
    }
  }
  if (mesh.triangles.empty()) {
    throw ErrorAt(
        "sparse surface: no grid cell has enough points; lower "
        "min_points_per_node or raise grid_spacing");
  }
  return mesh;
}

}  // namespace uw
