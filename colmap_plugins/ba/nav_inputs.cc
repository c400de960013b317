#include "colmap_plugins/ba/nav_inputs.h"

#include <cmath>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "colmap_plugins/nav/geographic_positions.h"
#include "common/util/error.h"

namespace uw {
namespace {

bool IsPositiveDefinite(const Eigen::Matrix3d& covariance) {
  return covariance.allFinite() &&
         Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance)
                 .eigenvalues()
                 .minCoeff() > 0.0;
}

Eigen::Matrix3d PositionCovariance(const Eigen::Matrix3d& stated,
                                   double override_sigma_m, bool override_all,
                                   const std::string& image_name) {
  if (!override_all && IsPositiveDefinite(stated)) return stated;
  if (!(override_sigma_m > 0.0)) {
    throw ErrorAt("the prior of image ", image_name,
                  " has no positive-definite position covariance (a zero "
                  "sigma in the log?); give --Nav.position_sigma");
  }
  const Eigen::Matrix3d given =
      override_sigma_m * override_sigma_m * Eigen::Matrix3d::Identity();
  // A log without position sigmas still has the lever arm's share (its
  // circle without yaw, the attitude's through it): kept, the given sigma
  // standing in for the vehicle's only.
  return override_all ? given : Eigen::Matrix3d(stated + given);
}

std::unordered_map<std::string, const Image*> ImagesByName(
    const Reconstruction& model) {
  std::unordered_map<std::string, const Image*> images;
  for (const Image& image : model.Images()) images[image.name] = &image;
  return images;
}

}  // namespace

void NavInputOptions::Check() const {
  if (override_sigma && !(position_sigma_m > 0.0)) {
    throw ErrorAt("--Nav.override_sigma 1 needs --Nav.position_sigma > 0");
  }
  if (HasNavigation()) nav.Check();
  plausibility.Check();
}

std::string NavInputOptions::PriorsName() const {
  return HasNavigation() ? nav.nav_path.string()
                         : database_path + " (pose priors)";
}

NavInputs LoadNavInputs(const NavInputOptions& options,
                        const Reconstruction& model,
                        const std::string& model_name) {
  options.Check();
  if (options.HasNavigation()) {
    std::vector<std::pair<std::string, camera_t>> images;
    if (!options.database_path.empty()) {
      const Database database =
          Database::Open(options.database_path, Database::Mode::kReadOnly);
      for (const DatabaseImage& image : database.ReadAllImages()) {
        images.emplace_back(image.name, image.camera_id);
      }
    } else {
      for (const Image& image : model.Images()) {
        images.emplace_back(image.name, image.camera_id);
      }
    }
    // A mapper rarely registers every image (colmap's model of the scarp
    // survey lacked 13 of 268): the rows of the others are left out and
    // counted, here and by NavInputsForModel.
    const std::string source = options.database_path.empty()
                                   ? "the model " + model_name
                                   : options.database_path;
    const LoadedCameraPriors loaded =
        LoadCameraPriors(options.nav, images, source);
    NavInputs inputs = NavInputsForModel(
        loaded.priors, loaded.rig.cameras.empty() ? nullptr : &loaded.rig,
        model, options.position_sigma_m, options.override_sigma,
        options.rig_rotation_sigma_deg, options.rig_translation_sigma_m);
    if (inputs.priors.empty()) {
      throw ErrorAt(options.nav.nav_path.string(), ": none of its ",
                    loaded.priors.size(),
                    " priors is of an image of the model ", model_name, " (",
                    model.Images().size(),
                    " images): a log of another survey, or image names "
                    "spelt otherwise?");
    }
    inputs.num_priors_without_image += loaded.other_images.size();
    inputs.warnings = loaded.warnings;
    inputs.world_frame = loaded.frame;
    return inputs;
  }
  if (!options.database_path.empty()) {
    const Database database =
        Database::Open(options.database_path, Database::Mode::kReadOnly);
    NavLogFrame frame;
    std::vector<std::string> warnings;
    NavInputs inputs = NavInputsFromDatabase(
        WithLocalPositions(database.ReadAllPosePriors(), options.nav.log.origin,
                           options.database_path, &frame, &warnings),
        model, options.position_sigma_m, options.override_sigma);
    inputs.warnings = warnings;
    if (frame.origin) inputs.world_frame = frame;
    return inputs;
  }
  return {};
}

NavInputs NavInputsForModel(const std::vector<CameraPrior>& priors,
                            const RigConfig* rig, const Reconstruction& model,
                            double position_sigma_override_m, bool override_all,
                            double rig_rotation_sigma_deg,
                            double rig_translation_sigma_m) {
  const auto images = ImagesByName(model);
  NavInputs inputs;
  for (const CameraPrior& camera_prior : priors) {
    const auto it = images.find(camera_prior.image_name);
    if (it == images.end()) {
      ++inputs.num_priors_without_image;
      continue;
    }
    ImagePosePrior prior;
    prior.image_id = it->second->image_id;
    prior.dive = camera_prior.dive;
    prior.position_in_world = camera_prior.position;
    prior.position_covariance = PositionCovariance(
        camera_prior.position_covariance, position_sigma_override_m,
        override_all, camera_prior.image_name);
    prior.cam_from_world_rotation = camera_prior.cam_from_world_rotation;
    prior.rotation_covariance = camera_prior.rotation_covariance;
    if (!IsPositiveDefinite(prior.rotation_covariance)) {
      prior.cam_from_world_rotation.reset();
    }
    inputs.priors.push_back(prior);
    inputs.image_times[prior.image_id] = camera_prior.time_s;
  }
  if (rig != nullptr) {
    inputs.rig = SoftRigFromConfig(*rig, rig_rotation_sigma_deg,
                                   rig_translation_sigma_m);
  }
  return inputs;
}

NavInputs NavInputsFromDatabase(const std::vector<PosePrior>& priors,
                                const Reconstruction& model,
                                double position_sigma_override_m,
                                bool override_all) {
  NavInputs inputs;
  for (const PosePrior& database_prior : priors) {
    const Image* image = model.FindImage(database_prior.image_id);
    if (image == nullptr || !database_prior.HasPosition()) {
      ++inputs.num_priors_without_image;
      continue;
    }
    if (database_prior.coordinate_system == PosePriorCoordinateSystem::kWGS84) {
      throw ErrorAt("the database prior of image ", image->name,
                    " is in WGS84 (latitude, longitude): put the priors into "
                    "a local frame first (WithLocalPositions)");
    }
    ImagePosePrior prior;
    prior.image_id = image->image_id;
    prior.position_in_world = database_prior.position;
    prior.position_covariance = PositionCovariance(
        database_prior.HasPositionCovariance()
            ? database_prior.position_covariance
            : Eigen::Matrix3d::Zero(),
        position_sigma_override_m, override_all, image->name);
    inputs.priors.push_back(prior);
  }
  return inputs;
}

SoftRig SoftRigFromConfig(const RigConfig& rig, double rotation_sigma_deg,
                          double translation_sigma_m) {
  rig.Check();
  SoftRig soft;
  soft.reference_camera_id = rig.cameras.front().camera_id;
  for (size_t i = 1; i < rig.cameras.size(); ++i) {
    const RigCameraConfig& camera = rig.cameras[i];
    SoftRigCamera soft_camera;
    soft_camera.camera_id = camera.camera_id;
    soft_camera.cam_from_rig = camera.cam_from_rig;
    soft_camera.rotation_sigma_rad =
        (camera.rotation_sigma_deg > 0.0 ? camera.rotation_sigma_deg
                                         : rotation_sigma_deg) *
        M_PI / 180.0;
    soft_camera.translation_sigma_m = camera.translation_sigma_m > 0.0
                                          ? camera.translation_sigma_m
                                          : translation_sigma_m;
    soft.cameras.push_back(soft_camera);
  }
  return soft;
}

}  // namespace uw
