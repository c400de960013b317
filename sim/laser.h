// Laser scalers in uwsim: the set-ups of the thesis's chapter 3 [L2280-L2298]
// and the optics of their beams.
//
//  A  four lasers parallel to the optical axis, at the corners of a 20 cm
//     square centred on the camera (what Davis & Tusting's method needs);
//  B  four parallel lasers equidistant (15 cm) from the camera centre, in
//     a horizontal and a vertical pair, not along the axis (tilted 3 deg
//     right and 2 deg down);
//  C  like the SUBSAINTES ROV VICTOR set-up: four lasers ~16.5 cm from the
//     centre, the square rotated 3 deg about the optical axis, each beam
//     misaligned by 0.3-0.9 deg in its own direction.
//
// A beam is Gaussian: at t metres along it, its 1/e^2 radius is
// w(t) = waist_radius_m + t * divergence_mrad / 1000 and the irradiance on a
// plane across it is E(t) exp(-2 r^2 / w(t)^2) at r metres off its axis,
// E(t) = peak_level (w(1) / w(t))^2 (the power of the beam is conserved), in
// the units of the renderer's lamp: a white surface across the beam at 1 m
// in clear water reads peak_level on the linear sensor range at gain 1. Its
// light is one wavelength, that of its colour's strongest channel: the
// water attenuates it by that channel's coefficient on its way to the
// surface and back to the camera, in every channel alike (the small green
// and blue responses of a red laser fade with its red), so a spot keeps
// its colour at any range while the lamp-lit scene turns blue-green. Its
// footprint on a surface is that
// irradiance times the cosine of incidence, so a spot is elongated on an
// oblique surface, follows the relief, and is seen only where the camera
// sees the surface.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"
#include "laserscale/laser_setup.h"

namespace uw::sim {

// The defaults make spots like those of ROV images: ~8 px across at 2.5 m
// and 1024 px (a laser module's 3-5 mm beam plus the halo of forward
// scattering and the optics' blur, which this width stands in for), with a
// centre far brighter than the lamp lights the floor, saturated at short
// range in red water and attenuated below the texture's contrast at ~6 m.
struct BeamOptics {
  double waist_radius_m = 0.008;  // 1/e^2 radius at the origin
  double divergence_mrad = 1.5;   // growth of that radius per metre
  double peak_level = 60.0;       // see the header comment

  void Check() const;
};

// Everything about the laser images of a survey.
struct LaserOptions {
  // "A", "B", "C" (above) or "custom" (custom_lasers).
  std::string setup = "C";
  std::vector<Laser> custom_lasers;
  // Colour of the preset set-ups' lasers (linear RGB): a red laser is seen
  // a little in the green and blue of a Bayer sensor.
  Eigen::Vector3d colour{1.0, 0.15, 0.1};
  BeamOptics optics;
  // A laser image after every n-th survey image (0: none), placed
  // "between" that image and the next of its pass (halfway: a view of its
  // own) or "at" the survey image's pose (for the views survey, where each
  // view is a laser experiment).
  int every_nth_image = 3;
  std::string placement = "between";
  // The auxiliary image of each laser image (for the spot detector's
  // texture removal): taken after a small camera motion (a random
  // translation of aux_translation_m and rotation of aux_rotation_deg) with
  // the gain multiplied by aux_gain, and the lasers "absent" (switched off)
  // or "shifted" (on: the spots stay near the same pixels while the texture
  // moves under them).
  std::string auxiliary = "shifted";
  // Names of lasers switched off in the laser images and their auxes (a
  // laser that failed during the dive): lasers.json still lists them, and
  // truth/laser_images.json marks their spots "on": false. Any other
  // bright thing the detector reports for them is a false spot.
  std::vector<std::string> switched_off;
  double aux_translation_m = 0.05;
  double aux_rotation_deg = 0.5;
  double aux_gain = 1.15;
  // The calibration a user would have (OUT/lasers.json): the true geometry
  // perturbed with these standard deviations, which it reports as its
  // covariances (origins across the beam on Π, directions isotropically).
  double calibration_origin_sigma_m = 0.001;
  double calibration_direction_sigma_deg = 0.05;

  void Check() const;
};
void to_json(nlohmann::json& json, const LaserOptions& options);
void from_json(const nlohmann::json& json, LaserOptions& options);

// The true set-up (zero covariances), named after options.setup.
LaserSetup TrueLaserSetup(const LaserOptions& options);

// The set-up with calibration errors drawn from options' sigmas, and those
// sigmas as covariances; deterministic for a seed.
LaserSetup CalibratedLaserSetup(const LaserSetup& truth,
                                const LaserOptions& options, uint64_t seed);

// One beam in the world frame, for one frame's rendering.
struct LaserBeam {
  Eigen::Vector3d origin_in_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction_in_world = Eigen::Vector3d::UnitZ();  // unit
  Eigen::Vector3d colour = Eigen::Vector3d::Ones();
  // The channel of the laser's wavelength (its colour's strongest, RGB
  // order; the first of equals, so a white laser is rendered as red
  // light): the water attenuates its light by that channel's coefficient.
  int dominant_channel = 0;
  BeamOptics optics;

  LaserBeam() = default;
  LaserBeam(const Laser& laser, const BeamOptics& optics,
            const Rigid3d& cam_from_world);

  // Irradiance on a plane across the beam at `point` (before colour and
  // water attenuation); `along_m` receives the distance along the beam.
  // Zero behind the origin and beyond 3 w(t) off the axis (exp(-18)).
  double Irradiance(const Eigen::Vector3d& point, double* along_m) const {
    const Eigen::Vector3d from_origin = point - origin_in_world;
    const double along = from_origin.dot(direction_in_world);
    *along_m = along;
    if (along <= 0.0) return 0.0;
    const double divergence = 1e-3 * optics.divergence_mrad;
    const double radius = optics.waist_radius_m + along * divergence;
    const double off_axis_squared = from_origin.squaredNorm() - along * along;
    if (off_axis_squared > 9.0 * radius * radius) return 0.0;
    const double radius_at_1m = optics.waist_radius_m + divergence;
    const double relative = radius_at_1m / radius;
    return optics.peak_level * relative * relative *
           std::exp(-2.0 * off_axis_squared / (radius * radius));
  }
};

// Where a laser's axis meets the world, and whether and where the camera
// sees that point.
struct LaserSpotTruth {
  bool hit = false;      // the beam's axis meets the mesh
  bool visible = false;  // in front of the camera, in the image, unoccluded
  double range_m = 0.0;  // along the beam, from the laser's origin
  Eigen::Vector3d point_in_world = Eigen::Vector3d::Zero();
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // COLMAP convention
};
LaserSpotTruth TrueLaserSpot(const RayCaster& caster, const Camera& camera,
                             const Rigid3d& cam_from_world, const Laser& laser);

}  // namespace uw::sim
