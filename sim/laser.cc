#include "sim/laser.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/json_fields.h"
#include "common/util/random.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

Eigen::Vector3d TiltedAxis(double right_deg, double down_deg) {
  return Eigen::Vector3d(std::tan(right_deg * kDegToRad),
                         std::tan(down_deg * kDegToRad), 1.0)
      .normalized();
}

Laser MakeLaser(int index, const Eigen::Vector2d& origin,
                const Eigen::Vector3d& direction,
                const Eigen::Vector3d& colour) {
  Laser laser;
  laser.name = "L" + std::to_string(index);
  laser.origin_in_cam = {origin.x(), origin.y(), 0.0};
  laser.direction_in_cam = direction;
  laser.colour = colour;
  return laser;
}

// Two unit vectors across `direction`, completing a right-handed frame.
void AcrossBeam(const Eigen::Vector3d& direction, Eigen::Vector3d* first,
                Eigen::Vector3d* second) {
  *first = direction.cross(Eigen::Vector3d::UnitY()).normalized();
  *second = direction.cross(*first);
}

}  // namespace

void BeamOptics::Check() const {
  if (!(waist_radius_m > 0.0 && waist_radius_m < 0.1)) {
    throw ErrorAt("laser optics waist_radius_m = ", waist_radius_m,
                  ": must be in (0, 0.1) m");
  }
  if (!(divergence_mrad >= 0.0 && divergence_mrad < 100.0)) {
    throw ErrorAt("laser optics divergence_mrad = ", divergence_mrad,
                  ": must be in [0, 100)");
  }
  if (!(peak_level >= 0.0 && std::isfinite(peak_level))) {
    throw ErrorAt("laser optics peak_level = ", peak_level,
                  ": must be finite and >= 0");
  }
}

void LaserOptions::Check() const {
  if (setup != "A" && setup != "B" && setup != "C" && setup != "custom") {
    throw ErrorAt("lasers.setup = \"", setup,
                  "\": expected \"A\", \"B\", \"C\" or \"custom\"");
  }
  if (setup == "custom" && custom_lasers.empty()) {
    throw ErrorAt("lasers.setup \"custom\" needs lasers.custom_lasers");
  }
  if (setup != "custom" && !custom_lasers.empty()) {
    throw ErrorAt("lasers.custom_lasers given with setup \"", setup,
                  "\"; use setup \"custom\"");
  }
  if (!(colour.minCoeff() >= 0.0 && colour.maxCoeff() <= 1.0)) {
    throw ErrorAt("lasers.colour must be in [0, 1]");
  }
  optics.Check();
  if (every_nth_image < 0) {
    throw ErrorAt("lasers.every_nth_image = ", every_nth_image,
                  ": must be >= 0");
  }
  if (placement != "between" && placement != "at") {
    throw ErrorAt("lasers.placement = \"", placement,
                  "\": expected \"between\" or \"at\"");
  }
  if (auxiliary != "absent" && auxiliary != "shifted") {
    throw ErrorAt("lasers.auxiliary = \"", auxiliary,
                  "\": expected \"absent\" or \"shifted\"");
  }
  const LaserSetup lasers = TrueLaserSetup(*this);
  for (const std::string& name : switched_off) {
    if (std::none_of(lasers.lasers.begin(), lasers.lasers.end(),
                     [&](const Laser& laser) { return laser.name == name; })) {
      std::string names;
      for (const Laser& laser : lasers.lasers) {
        names += (names.empty() ? "" : ", ") + laser.name;
      }
      throw ErrorAt("lasers.switched_off: no laser \"", name, "\" in set-up ",
                    setup, " (its lasers: ", names, ")");
    }
  }
  const auto check_range = [](const char* name, double value, double max) {
    if (!(value >= 0.0 && value <= max)) {
      throw ErrorAt("lasers.", name, " = ", value, ": must be in [0, ", max,
                    "]");
    }
  };
  check_range("aux_translation_m", aux_translation_m, 1.0);
  check_range("aux_rotation_deg", aux_rotation_deg, 10.0);
  check_range("calibration_origin_sigma_m", calibration_origin_sigma_m, 0.1);
  check_range("calibration_direction_sigma_deg",
              calibration_direction_sigma_deg, 5.0);
  if (!(aux_gain > 0.0 && aux_gain <= 10.0)) {
    throw ErrorAt("lasers.aux_gain = ", aux_gain, ": must be in (0, 10]");
  }
  TrueLaserSetup(*this).Check();
}

void to_json(nlohmann::json& json, const LaserOptions& options) {
  nlohmann::json custom = nlohmann::json::array();
  for (const Laser& laser : options.custom_lasers) {
    custom.push_back(LaserJson(laser));
  }
  json = {{"setup", options.setup},
          {"custom_lasers", custom},
          {"colour", ToJson(options.colour)},
          {"optics",
           {{"waist_radius_m", options.optics.waist_radius_m},
            {"divergence_mrad", options.optics.divergence_mrad},
            {"peak_level", options.optics.peak_level}}},
          {"every_nth_image", options.every_nth_image},
          {"placement", options.placement},
          {"auxiliary", options.auxiliary},
          {"switched_off", options.switched_off},
          {"aux_translation_m", options.aux_translation_m},
          {"aux_rotation_deg", options.aux_rotation_deg},
          {"aux_gain", options.aux_gain},
          {"calibration_origin_sigma_m", options.calibration_origin_sigma_m},
          {"calibration_direction_sigma_deg",
           options.calibration_direction_sigma_deg}};
}

void from_json(const nlohmann::json& json, LaserOptions& options) {
  JsonFields fields(json, "lasers");
  fields.Read("setup", &options.setup);
  nlohmann::json custom;
  fields.Read("custom_lasers", &custom);
  if (!custom.is_null()) {
    if (!custom.is_array()) {
      throw ErrorAt("lasers.custom_lasers: expected an array");
    }
    options.custom_lasers.clear();
    for (size_t i = 0; i < custom.size(); ++i) {
      options.custom_lasers.push_back(LaserFromJson(
          custom[i], "lasers.custom_lasers[" + std::to_string(i) + "]"));
    }
  }
  fields.Read("colour", &options.colour);
  fields.Section("optics", [&](JsonFields& optics) {
    optics.Read("waist_radius_m", &options.optics.waist_radius_m);
    optics.Read("divergence_mrad", &options.optics.divergence_mrad);
    optics.Read("peak_level", &options.optics.peak_level);
  });
  fields.Read("every_nth_image", &options.every_nth_image);
  fields.Read("placement", &options.placement);
  fields.Read("auxiliary", &options.auxiliary);
  fields.Read("switched_off", &options.switched_off);
  fields.Read("aux_translation_m", &options.aux_translation_m);
  fields.Read("aux_rotation_deg", &options.aux_rotation_deg);
  fields.Read("aux_gain", &options.aux_gain);
  fields.Read("calibration_origin_sigma_m",
              &options.calibration_origin_sigma_m);
  fields.Read("calibration_direction_sigma_deg",
              &options.calibration_direction_sigma_deg);
  fields.RejectUnknown();
}

LaserSetup TrueLaserSetup(const LaserOptions& options) {
  LaserSetup setup;
  setup.name = options.setup;
  const Eigen::Vector3d& colour = options.colour;
  if (options.setup == "A") {
    const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    setup.lasers = {MakeLaser(0, {-0.1, -0.1}, axis, colour),
                    MakeLaser(1, {0.1, -0.1}, axis, colour),
                    MakeLaser(2, {0.1, 0.1}, axis, colour),
                    MakeLaser(3, {-0.1, 0.1}, axis, colour)};
  } else if (options.setup == "B") {
    const Eigen::Vector3d tilted = TiltedAxis(3.0, 2.0);
    setup.lasers = {MakeLaser(0, {-0.15, 0.0}, tilted, colour),
                    MakeLaser(1, {0.15, 0.0}, tilted, colour),
                    MakeLaser(2, {0.0, -0.15}, tilted, colour),
                    MakeLaser(3, {0.0, 0.15}, tilted, colour)};
  } else if (options.setup == "C") {
    // Radii and misalignments of a hand-mounted set-up: none exact.
    const double radii[4] = {0.166, 0.163, 0.167, 0.164};
    const double right_deg[4] = {0.6, -0.4, 0.8, -0.5};
    const double down_deg[4] = {-0.3, -0.7, 0.5, 0.9};
    for (int i = 0; i < 4; ++i) {
      const double angle = (45.0 + 90.0 * i + 3.0) * kDegToRad;
      setup.lasers.push_back(MakeLaser(
          i, radii[i] * Eigen::Vector2d(std::cos(angle), std::sin(angle)),
          TiltedAxis(right_deg[i], down_deg[i]), colour));
    }
  } else {
    setup.lasers = options.custom_lasers;
  }
  return setup;
}

LaserSetup CalibratedLaserSetup(const LaserSetup& truth,
                                const LaserOptions& options, uint64_t seed) {
  SplitMix64Stream random(SplitMix64(seed ^ 0x1A5E8CA1B0000000ull));
  const double sigma_origin = options.calibration_origin_sigma_m;
  const double sigma_direction =
      options.calibration_direction_sigma_deg * kDegToRad;
  LaserSetup calibrated = truth;
  for (Laser& laser : calibrated.lasers) {
    laser.origin_in_cam.x() += sigma_origin * random.Gaussian();
    laser.origin_in_cam.y() += sigma_origin * random.Gaussian();
    laser.origin_cov = Eigen::Vector3d(sigma_origin * sigma_origin,
                                       sigma_origin * sigma_origin, 0.0)
                           .asDiagonal();
    Eigen::Vector3d first, second;
    AcrossBeam(laser.direction_in_cam, &first, &second);
    const double a = sigma_direction * random.Gaussian();
    const double b = sigma_direction * random.Gaussian();
    laser.direction_in_cam =
        (laser.direction_in_cam + std::tan(a) * first + std::tan(b) * second)
            .normalized();
    laser.direction_cov =
        IsotropicDirectionCovariance(laser.direction_in_cam, sigma_direction);
  }
  calibrated.Check();
  return calibrated;
}

LaserBeam::LaserBeam(const Laser& laser, const BeamOptics& beam_optics,
                     const Rigid3d& cam_from_world)
    : colour(laser.colour), optics(beam_optics) {
  colour.maxCoeff(&dominant_channel);
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  origin_in_world = world_from_cam * laser.origin_in_cam;
  direction_in_world =
      (world_from_cam.RotationMatrix() * laser.direction_in_cam).normalized();
}

LaserSpotTruth TrueLaserSpot(const RayCaster& caster, const Camera& camera,
                             const Rigid3d& cam_from_world,
                             const Laser& laser) {
  const LaserBeam beam(laser, BeamOptics(), cam_from_world);
  LaserSpotTruth truth;
  const std::optional<RayCaster::Hit> hit =
      caster.Intersect(beam.origin_in_world, beam.direction_in_world);
  if (!hit) return truth;
  truth.hit = true;
  truth.range_m = hit->distance;
  truth.point_in_world = hit->point_in_world;
  const Eigen::Vector3d point_in_cam = cam_from_world * hit->point_in_world;
  if (point_in_cam.z() <= 0.0) return truth;
  truth.pixel = camera.ImgFromCam(point_in_cam);
  if (!(truth.pixel.x() >= 0.0 &&
        truth.pixel.x() < static_cast<double>(camera.width) &&
        truth.pixel.y() >= 0.0 &&
        truth.pixel.y() < static_cast<double>(camera.height))) {
    return truth;
  }
  // Seen if the camera's ray towards the point meets nothing before it (the
  // first hit is the point itself, up to the mesh's float resolution).
  const Eigen::Vector3d centre = cam_from_world.Inverse().translation;
  const Eigen::Vector3d to_point = hit->point_in_world - centre;
  const double distance = to_point.norm();
  const std::optional<RayCaster::Hit> seen =
      caster.Intersect(centre, to_point / distance);
  truth.visible =
      seen && seen->distance > distance - 4.0 * caster.SurfaceEpsilon();
  return truth;
}

}  // namespace uw::sim
