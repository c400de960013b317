// Distances from points to a triangle mesh (the true surface of a uwsim
// world, a laser-scanned or reference mesh): the closest point on the mesh,
// found through a bounding-volume hierarchy in double precision. Builds in
// about a second for a million triangles and answers ~10^5 queries a
// second per core, which is what comparing a sparse model with its truth
// needs.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace uw {

class MeshDistance {
 public:
  struct Closest {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    double distance = 0.0;
    // Unit normal of the closest triangle by its counter-clockwise winding.
    Eigen::Vector3d triangle_normal = Eigen::Vector3d::UnitZ();
    uint32_t triangle = 0;
  };

  // Throws uw::Error for a mesh without triangles of non-zero area or with an
  // index out of range or a non-finite vertex. Zero-area triangles are kept
  // (their edges still bound the surface).
  MeshDistance(std::vector<Eigen::Vector3d> vertices,
               std::vector<Eigen::Vector3i> triangles);

  Closest Query(const Eigen::Vector3d& point) const;

  // The distance signed by the side of the surface `viewpoint` is on:
  // positive when `point` lies on the viewpoint's side (in front of the
  // surface, seen from the cameras), negative behind it. Independent of the
  // mesh's winding.
  double SignedDistance(const Eigen::Vector3d& point,
                        const Eigen::Vector3d& viewpoint) const;

 private:
  struct Node {
    Eigen::Vector3d min;
    Eigen::Vector3d max;
    // Leaf: triangles [begin, end) of order_; inner: children left, right.
    uint32_t begin = 0;
    uint32_t end = 0;
    uint32_t left = 0;
    uint32_t right = 0;
    bool IsLeaf() const { return left == 0; }
  };

  uint32_t Build(uint32_t begin, uint32_t end,
                 const std::vector<Eigen::Vector3d>& centroids);
  Eigen::Vector3d ClosestOnTriangle(uint32_t triangle,
                                    const Eigen::Vector3d& point) const;

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Eigen::Vector3i> triangles_;
  std::vector<uint32_t> order_;
  std::vector<Node> nodes_;
};

}  // namespace uw
