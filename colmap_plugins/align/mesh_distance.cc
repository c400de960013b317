#include "colmap_plugins/align/mesh_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Geometry>

#include "common/util/error.h"

namespace uw {
namespace {

// Triangles per leaf: small leaves make queries cheap, the tree stays small.
constexpr uint32_t kMaxLeafSize = 4;

double SquaredDistanceToBox(const Eigen::Vector3d& point,
                            const Eigen::Vector3d& min,
                            const Eigen::Vector3d& max) {
  const Eigen::Vector3d outside =
      (min - point).cwiseMax(point - max).cwiseMax(0.0);
  return outside.squaredNorm();
}

Eigen::Vector3d ClosestOnSegment(const Eigen::Vector3d& point,
                                 const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double squared_length = ab.squaredNorm();
  if (squared_length == 0.0) return a;
  return a + std::clamp((point - a).dot(ab) / squared_length, 0.0, 1.0) * ab;
}

}  // namespace

MeshDistance::MeshDistance(std::vector<Eigen::Vector3d> vertices,
                           std::vector<Eigen::Vector3i> triangles)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  for (size_t v = 0; v < vertices_.size(); ++v) {
    if (!vertices_[v].allFinite()) {
      throw ErrorAt("mesh: vertex ", v, " is not finite");
    }
  }
  bool has_area = false;
  std::vector<Eigen::Vector3d> centroids;
  for (size_t t = 0; t < triangles_.size(); ++t) {
    const Eigen::Vector3i& triangle = triangles_[t];
    if ((triangle.array() < 0).any() ||
        (triangle.array() >= static_cast<int>(vertices_.size())).any()) {
      throw ErrorAt("mesh: triangle ", t, " has a vertex index out of range (",
                    vertices_.size(), " vertices)");
    }
    const Eigen::Vector3d& a = vertices_[triangle(0)];
    const Eigen::Vector3d& b = vertices_[triangle(1)];
    const Eigen::Vector3d& c = vertices_[triangle(2)];
    has_area = has_area || (b - a).cross(c - a).squaredNorm() > 0.0;
    centroids.push_back((a + b + c) / 3.0);
  }
  if (!has_area) {
    throw ErrorAt("mesh: no triangle of non-zero area (", triangles_.size(),
                  " triangles)");
  }
  if (triangles_.size() >= std::numeric_limits<uint32_t>::max()) {
    throw ErrorAt("mesh: ", triangles_.size(), " triangles is too many");
  }
  order_.resize(triangles_.size());
  std::iota(order_.begin(), order_.end(), 0u);
  nodes_.reserve(2 * triangles_.size() / kMaxLeafSize + 1);
  Build(0, static_cast<uint32_t>(order_.size()), centroids);
}

// Splits at the median centroid along the longest axis of the centroids'
// box; returns the node's index. The root is node 0, so a child index of 0
// marks a leaf.
uint32_t MeshDistance::Build(uint32_t begin, uint32_t end,
                             const std::vector<Eigen::Vector3d>& centroids) {
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box;
  Eigen::AlignedBox3d centroid_box;
  for (uint32_t k = begin; k < end; ++k) {
    const Eigen::Vector3i& triangle = triangles_[order_[k]];
    for (int corner = 0; corner < 3; ++corner) {
      box.extend(vertices_[triangle(corner)]);
    }
    centroid_box.extend(centroids[order_[k]]);
  }
  nodes_[index].min = box.min();
  nodes_[index].max = box.max();
  nodes_[index].begin = begin;
  nodes_[index].end = end;
  if (end - begin <= kMaxLeafSize) return index;

  int axis = 0;
  centroid_box.sizes().maxCoeff(&axis);
  const uint32_t middle = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + middle,
                   order_.begin() + end, [&](uint32_t lhs, uint32_t rhs) {
                     return centroids[lhs](axis) < centroids[rhs](axis);
                   });
  const uint32_t left = Build(begin, middle, centroids);
  const uint32_t right = Build(middle, end, centroids);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

// Ericson, Real-Time Collision Detection, §5.1.5: the Voronoi region of the
// point decides between a vertex, an edge and the face. Zero-area triangles
// reduce to their edges.
Eigen::Vector3d MeshDistance::ClosestOnTriangle(
    uint32_t triangle, const Eigen::Vector3d& point) const {
  const Eigen::Vector3d& a = vertices_[triangles_[triangle](0)];
  const Eigen::Vector3d& b = vertices_[triangles_[triangle](1)];
  const Eigen::Vector3d& c = vertices_[triangles_[triangle](2)];
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  if (ab.cross(ac).squaredNorm() == 0.0) {
    Eigen::Vector3d best = ClosestOnSegment(point, a, b);
    for (const Eigen::Vector3d& candidate :
         {ClosestOnSegment(point, b, c), ClosestOnSegment(point, c, a)}) {
      if ((candidate - point).squaredNorm() < (best - point).squaredNorm()) {
        best = candidate;
      }
    }
    return best;
  }
  const Eigen::Vector3d ap = point - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = point - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = point - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

MeshDistance::Closest MeshDistance::Query(const Eigen::Vector3d& point) const {
  double best_squared = std::numeric_limits<double>::infinity();
  uint32_t best_triangle = 0;
  Eigen::Vector3d best_point = Eigen::Vector3d::Zero();
  // Depth-first, nearer child first, pruning boxes beyond the best so far.
  std::vector<uint32_t> stack = {0};
  while (!stack.empty()) {
    const Node& node = nodes_[stack.back()];
    stack.pop_back();
    if (SquaredDistanceToBox(point, node.min, node.max) >= best_squared) {
      continue;
    }
    if (node.IsLeaf()) {
      for (uint32_t k = node.begin; k < node.end; ++k) {
        const Eigen::Vector3d closest = ClosestOnTriangle(order_[k], point);
        const double squared = (closest - point).squaredNorm();
        if (squared < best_squared) {
          best_squared = squared;
          best_triangle = order_[k];
          best_point = closest;
        }
      }
      continue;
    }
    const Node& left = nodes_[node.left];
    const Node& right = nodes_[node.right];
    const bool left_first = SquaredDistanceToBox(point, left.min, left.max) <=
                            SquaredDistanceToBox(point, right.min, right.max);
    stack.push_back(left_first ? node.right : node.left);
    stack.push_back(left_first ? node.left : node.right);
  }
  Closest closest;
  closest.point = best_point;
  closest.distance = std::sqrt(best_squared);
  closest.triangle = best_triangle;
  const Eigen::Vector3i& triangle = triangles_[best_triangle];
  closest.triangle_normal =
      (vertices_[triangle(1)] - vertices_[triangle(0)])
          .cross(vertices_[triangle(2)] - vertices_[triangle(0)])
          .normalized();
  return closest;
}

double MeshDistance::SignedDistance(const Eigen::Vector3d& point,
                                    const Eigen::Vector3d& viewpoint) const {
  const Closest closest = Query(point);
  Eigen::Vector3d facing = closest.triangle_normal;
  if (facing.dot(viewpoint - closest.point) < 0.0) facing = -facing;
  return (point - closest.point).dot(facing) < 0.0 ? -closest.distance
                                                   : closest.distance;
}

}  // namespace uw
