// The method of `uwcolmap model_aligner`: a model moved onto reference
// camera positions with one similarity, as `colmap model_aligner` does. The
// references come from COLMAP's ref_images.txt, a database's pose priors or
// a navigation log (camera centres through the lever arm, with their
// covariances); images are paired with them by name or, for cameras not
// synchronised with the navigation, with the closest point of the
// navigation path (path_association.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "colmap_plugins/align/alignment_plausibility.h"
#include "colmap_plugins/align/path_association.h"
#include "colmap_plugins/align/reference_positions.h"
#include "colmap_plugins/align/similarity.h"
#include "colmap_plugins/nav/pose_prior_import.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

enum class ReferenceAssociation {
  kName,          // each image with the reference of its name
  kClosestPoint,  // each image with the closest point of the --nav path
};
std::string ReferenceAssociationName(ReferenceAssociation association);
// "name" or "closest_point"; throws uw::Error naming --associate.
ReferenceAssociation ReferenceAssociationFromName(const std::string& name);

struct ModelAlignmentOptions {
  // Exactly one source of references.
  std::string ref_images_path;  // COLMAP's ref_images.txt
  // Its lines are 'image_name lat lon alt' (deg, m; COLMAP's --ref_is_gps
  // 1), put into local east-north-up metres at nav.log.origin (--origin)
  // or the automatic origin.
  bool ref_is_gps = false;
  std::string database_path;   // a database's pose priors
  PosePriorImportOptions nav;  // a navigation log (nav_path), or none
  ReferenceAssociation associate = ReferenceAssociation::kName;
  // Robust (RANSAC + Huber) with an automatic threshold, with scale.
  SimilarityOptions similarity;
  int min_common_images = 3;  // images with a reference, at least
  // Sigma (m, per axis) of references without a usable covariance
  // (ref_images.txt, a log without position sigmas), added to what they
  // have (a log's lever arm share), by name only; 0: such references
  // leave the fit unweighted.
  double position_sigma_m = 0.0;
  // What the similarity must look like (--min_range, --max_range,
  // --accept_implausible).
  AlignmentPlausibilityOptions plausibility;

  // One source, closest points on the navigation only, ref_is_gps with
  // ref_images_path only, at least 3 common images, a finite position
  // sigma >= 0, the similarity's own rules.
  void Check() const;
};

// What was aligned to what, for the printout and the alignment JSON.
struct ModelAlignment {
  std::string reference;  // where the reference positions came from
  ReferenceAssociation association = ReferenceAssociation::kName;
  std::vector<std::string> image_names;
  std::vector<Eigen::Vector3d> reference_positions;
  std::vector<double> path_times_s;  // closest_point only
  bool covariance_weighted = false;
  size_t num_references = 0;
  std::vector<std::string> unknown_names;  // references of no model image
  SimilarityResult similarity;             // reference_from_model
  int iterations = 0;                      // closest_point only
  bool converged = true;
  AlignmentPlausibility plausibility;
  // The frame of the references from a navigation log or geographic
  // references (world_frame.json's); none for metric ref_images.txt and
  // database priors, whose frame is theirs.
  std::optional<NavLogFrame> world_frame;
  // What the user must know about the result (centres on one line).
  std::vector<std::string> warnings;
};

// Camera-centre priors of the model's images from navigation, by name, and
// the images of the rows left out: a reconstruction rarely registers every
// image (LoadCameraPriors; AlignModel reports them as
// ModelAlignment::unknown_names).
struct NavigationReferenceSet {
  std::vector<ReferencePosition> references;
  std::vector<std::string> other_images;
  std::vector<std::string> warnings;  // LoadedCameraPriors::warnings
  NavLogFrame frame;
};
NavigationReferenceSet NavigationReferences(
    const PosePriorImportOptions& options, const Reconstruction& model);

// The navigation as a path of camera centres at the log's own times (with
// the covariances when every one is positive definite), and the frame the
// log was read into.
TimedPath NavigationPath(const PosePriorImportOptions& options,
                         NavLogFrame* frame);

// The similarity from the model's camera centres to the references of the
// same name (`source` names them in messages and the report).
ModelAlignment AlignByName(const Reconstruction& model,
                           const std::vector<ReferencePosition>& references,
                           const std::string& source,
                           const SimilarityOptions& options);

// The similarity from the model's camera centres to the closest points of
// the navigation path, the images in time order (image_times.csv) or in
// name order. Rigs are refused: associate the images of one camera.
ModelAlignment AlignByClosestPoints(const Reconstruction& model,
                                    const PosePriorImportOptions& nav,
                                    const SimilarityOptions& options);

// Reads the references `options` name and aligns `model` to them (the
// model is not moved: apply result.similarity.b_from_a). Throws uw::Error
// for fewer than options.min_common_images images with a reference, and
// for an implausible alignment (alignment_plausibility.h) unless accepted.
ModelAlignment AlignModel(const ModelAlignmentOptions& options,
                          const Reconstruction& model);

// The alignment JSON (--transform_path; docs/formats.md).
nlohmann::json ModelAlignmentJson(const ModelAlignment& alignment);

// What model_aligner prints about an alignment: references, weighting,
// robustness, inliers, the transform, residuals, outliers.
std::string FormatModelAlignment(const ModelAlignment& alignment);

}  // namespace uw
