// What the navigation-fused BA needs from the navigation files, in the ids
// of a model: priors per registered image, image times, the soft rig.
#pragma once

#include <optional>
#include <unordered_map>
#include <vector>

#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/nav/camera_prior.h"
#include "colmap_plugins/nav/rig_config.h"
#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

struct NavInputs {
  std::vector<ImagePosePrior> priors;
  std::unordered_map<image_t, double> image_times;  // navigation clock
  std::optional<SoftRig> rig;
  size_t num_priors_without_image = 0;  // images not registered in the model
};

// Priors of the model's images. A prior whose position covariance is not
// positive definite (a zero sigma in the log) takes
// position_sigma_override_m (> 0) per axis, and so does every prior when
// override_all is set; otherwise it is an error naming the image.
// Rig cameras whose rig.json sigmas are 0 get the given ones.
NavInputs NavInputsForModel(const std::vector<CameraPrior>& priors,
                            const RigConfig* rig, const Reconstruction& model,
                            double position_sigma_override_m, bool override_all,
                            double rig_rotation_sigma_deg = 0.0,
                            double rig_translation_sigma_m = 0.0);

// Priors of the model's images read from a COLMAP database (positions and,
// from 3.11 on, covariances; a 3.8 database's rotation prior is not used:
// it has no covariance).
NavInputs NavInputsFromDatabase(const std::vector<PosePrior>& priors,
                                const Reconstruction& model,
                                double position_sigma_override_m,
                                bool override_all);

// The soft rig of rig.json (sigmas converted to radians); a zero sigma
// (an exact rig, as uwsim's truth/rig.json) is replaced by the given one.
SoftRig SoftRigFromConfig(const RigConfig& rig, double rotation_sigma_deg,
                          double translation_sigma_m);

}  // namespace uw
