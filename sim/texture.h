// Surface appearance of synthetic worlds: a deterministic, multi-scale
// procedural albedo defined everywhere in 3D, so that any mesh (floor,
// chimney with overhangs, vertical wall) is textured without UV maps, and
// richly enough for SIFT at 1-5 m viewing distance.
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace uw::sim {

// A specular (Blinn-Phong) lobe: the renderer adds weight (n.h)^exponent
// times the light's irradiance to the Lambertian term, h the half vector
// between the directions to the light and to the camera.
struct Shine {
  float weight = 0.0f;
  float exponent = 100.0f;
};

class Texture {
 public:
  virtual ~Texture() = default;
  // Linear RGB albedo in [0, 1] of the surface at `point_in_world` whose unit
  // normal is `normal_in_world`. Must be thread-safe and deterministic.
  virtual Eigen::Vector3f Albedo(
      const Eigen::Vector3d& point_in_world,
      const Eigen::Vector3d& normal_in_world) const = 0;
  // Whether any surface shines; ShineAt is asked only then.
  virtual bool HasShine() const { return false; }
  virtual Shine ShineAt(const Eigen::Vector3d& /*point_in_world*/) const {
    return {};
  }
};

}  // namespace uw::sim
