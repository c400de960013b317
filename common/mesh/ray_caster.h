// Ray casting against a triangle mesh with Embree 3, exact in double.
//
// Embree works in single precision: it decides which triangle a ray meets
// first. The distance is then recomputed in double against that triangle's
// plane, so a returned point lies on the ray to rounding and on the surface to
// double precision; tests and acceptance checks reproject hits to < 1e-6 px.
// Vertices are handed to Embree relative to the centre of the mesh's bounding
// box, so float precision is set by the mesh's size, not by its distance from
// the world origin (a 300 m wall at 1e5 m).
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/mesh/mesh.h"

namespace uw {

struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit length
};

// Thread-safe for concurrent queries once constructed. Non-copyable; a
// moved-from RayCaster may only be destroyed or assigned to.
class RayCaster {
 public:
  struct Hit {
    // Along the ray, in units of the direction's length (metres for a unit
    // direction). Slightly negative (by < SurfaceEpsilon()) only when the
    // origin lies on the surface.
    double distance = 0.0;
    // origin + distance * direction, evaluated in double.
    Eigen::Vector3d point_in_world = Eigen::Vector3d::Zero();
    // Unit geometric normal of the hit triangle by its counter-clockwise
    // winding (into the water for TriangleMesh), whichever side was hit.
    Eigen::Vector3d normal_in_world = Eigen::Vector3d::UnitZ();
    // Unit normal for shading: the angle-weighted vertex normals of the
    // triangle interpolated at the hit (Phong), on the same side of the
    // mesh as normal_in_world's winding.
    Eigen::Vector3d shading_normal_in_world = Eigen::Vector3d::UnitZ();
    uint32_t triangle_id = 0;
  };

  // Throws uw::Error for a mesh without triangles, with an index out of range
  // or a non-finite vertex, without any triangle of non-zero area, or when
  // Embree reports an error. Zero-area triangles are kept (so triangle ids
  // stay the mesh's) but can never be hit: they cover no surface.
  explicit RayCaster(const TriangleMesh& mesh);
  ~RayCaster();
  RayCaster(RayCaster&& other) noexcept;
  RayCaster& operator=(RayCaster&& other) noexcept;
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // First hit along the ray within [0, max_distance], front or back face.
  std::optional<Hit> Intersect(
      const Eigen::Vector3d& origin, const Eigen::Vector3d& unit_direction,
      double max_distance = std::numeric_limits<double>::infinity()) const;
  std::optional<Hit> Intersect(
      const Ray& ray,
      double max_distance = std::numeric_limits<double>::infinity()) const {
    return Intersect(ray.origin, ray.direction, max_distance);
  }

  // Whether any surface lies along the ray within [0, max_distance]. Decided
  // by Embree in float: agrees with Intersect except for surfaces within
  // about SurfaceEpsilon() of either end.
  bool Occluded(const Eigen::Vector3d& origin,
                const Eigen::Vector3d& unit_direction,
                double max_distance) const;

  // Intersect for every ray, all with the same max_distance: hits[k] is
  // Intersect(rays[k], max_distance) but for which of two triangles is
  // reported for a ray through their common edge. Several times faster than
  // one call per ray when consecutive rays are coherent (neighbouring pixels,
  // the samples of one pixel), as Embree then traces them in packets.
  void IntersectMany(
      const std::vector<Ray>& rays, std::vector<std::optional<Hit>>* hits,
      double max_distance = std::numeric_limits<double>::infinity()) const;

  // Occluded for every ray and its max_distances[k] (same size as rays).
  void OccludedMany(const std::vector<Ray>& rays,
                    const std::vector<double>& max_distances,
                    std::vector<bool>* occluded) const;

  // Distance (metres) below which single-precision positions of this mesh
  // cannot be told apart. A ray leaving the surface (a shadow ray) must start
  // at least this far off it, or it may hit the surface it starts on.
  double SurfaceEpsilon() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uw
