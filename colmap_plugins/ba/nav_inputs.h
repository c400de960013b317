// What the navigation-fused BA needs from the navigation files, in the ids
// of a model: priors per registered image, image times, the soft rig.
#pragma once

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "colmap_plugins/align/alignment_plausibility.h"
#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/nav/camera_prior.h"
#include "colmap_plugins/nav/pose_prior_import.h"
#include "colmap_plugins/nav/rig_config.h"
#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

struct NavInputs {
  std::vector<ImagePosePrior> priors;
  std::unordered_map<image_t, double> image_times;  // navigation clock
  std::optional<SoftRig> rig;
  // Navigation rows (or image times) of images the model lacks: not
  // registered by the mapper, or not in the database.
  size_t num_priors_without_image = 0;
  // What the navigation log alone shows to be suspect.
  std::vector<std::string> warnings;
  // The priors' frame: a log's, or a database's WGS84 priors' local one;
  // none for a database's metric priors, whose frame is theirs.
  std::optional<NavLogFrame> world_frame;
};

// Where the priors of the navigation-fused adjustment come from
// (bundle_adjuster's and lcurve's --nav, --database_path, --Nav.* sigmas,
// --Rig.* sigmas).
struct NavInputOptions {
  // With `nav.nav_path`: the images whose names the navigation may use (the
  // model's when empty). Without it: the database whose pose priors are
  // the priors.
  std::string database_path;
  // The navigation log, image times, rig and camera on the vehicle; no
  // nav_path: none (priors from the database, or none at all).
  PosePriorImportOptions nav;
  // Per axis, m: the sigma of priors without a usable covariance, or of
  // every prior with override_sigma.
  double position_sigma_m = 0.0;
  bool override_sigma = false;
  // Sigmas of the rig cameras whose rig.json sigmas are 0 (deg, m).
  double rig_rotation_sigma_deg = 0.0;
  double rig_translation_sigma_m = 0.0;
  // What the model's first alignment onto the priors must look like
  // (--Nav.min_range, --Nav.max_range, --Nav.accept_implausible).
  AlignmentPlausibilityOptions plausibility;

  bool HasNavigation() const { return !nav.nav_path.empty(); }
  // Priors from anywhere: the navigation or the database.
  bool HasPriorSource() const {
    return HasNavigation() || !database_path.empty();
  }
  // The priors as messages name them: the log, or the database's priors.
  std::string PriorsName() const;
  // override_sigma needs a position sigma; the camera on the vehicle must be
  // finite; the plausibility's own rules.
  void Check() const;
};

// The priors of the model's images: from the navigation (its rows checked
// against the database's images or, without a database, the model's, named
// `model_name` in messages), else from the database's pose priors; none
// without either.
NavInputs LoadNavInputs(const NavInputOptions& options,
                        const Reconstruction& model,
                        const std::string& model_name);

// Priors of the model's images. A prior whose position covariance is not
// positive definite (a zero sigma in the log, or no sigma columns: then it
// holds only the lever arm's share) gets position_sigma_override_m (> 0)
// per axis added; every prior takes that sigma alone when override_all is
// set; without it, it is an error naming the image.
// Rig cameras whose rig.json sigmas are 0 get the given ones.
NavInputs NavInputsForModel(const std::vector<CameraPrior>& priors,
                            const RigConfig* rig, const Reconstruction& model,
                            double position_sigma_override_m, bool override_all,
                            double rig_rotation_sigma_deg = 0.0,
                            double rig_translation_sigma_m = 0.0);

// Priors of the model's images read from a COLMAP database (positions and,
// from 3.11 on, covariances; a 3.8 database's rotation prior is not used:
// it has no covariance). WGS84 priors must have been put into a local frame
// (geographic_positions.h; LoadNavInputs does); one left is an error.
NavInputs NavInputsFromDatabase(const std::vector<PosePrior>& priors,
                                const Reconstruction& model,
                                double position_sigma_override_m,
                                bool override_all);

// The soft rig of rig.json (sigmas converted to radians); a zero sigma
// (an exact rig, as uwsim's truth/rig.json) is replaced by the given one.
SoftRig SoftRigFromConfig(const RigConfig& rig, double rotation_sigma_deg,
                          double translation_sigma_m);

}  // namespace uw
