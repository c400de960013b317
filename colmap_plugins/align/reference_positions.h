// Where the cameras of a model should be: the reference positions that
// `model_aligner` aligns a model to, from COLMAP's own sources — a
// ref_images.txt (`colmap model_aligner --ref_images_path`) or the pose
// priors of a database — or from navigation, paired with the model's images
// by name.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/nav/geodesy.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

struct ReferencePosition {
  std::string image_name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // camera centre, m
  std::optional<Eigen::Matrix3d> covariance;           // m²
};

// COLMAP's reference file: one `image_name x y z` per line, separated by
// white space (COLMAP 3.8 reads it so; names cannot hold spaces). Blank
// lines and lines starting with '#' are skipped. Throws uw::Error naming the
// file and line for a malformed line, a non-finite coordinate or a name
// given twice.
std::vector<ReferencePosition> ReadReferencePositions(
    const std::filesystem::path& path);

// The position priors of a database (in any COLMAP schema), with their
// covariances where the schema stores them and they are finite. WGS84
// priors are put into the local east-north-up frame at `origin` (or the
// automatic one), which `frame` receives, without their covariances
// (geographic_positions.h: `warnings` says so).
std::vector<ReferencePosition> ReferencePositionsFromDatabase(
    const Database& database, const std::optional<GeoOrigin>& origin,
    NavLogFrame* frame, std::vector<std::string>* warnings);

// The model's images that have a reference position, in name order.
struct ReferenceMatch {
  std::vector<std::string> image_names;
  std::vector<Eigen::Vector3d> model_centres;
  std::vector<Eigen::Vector3d> reference_positions;
  // One per match when every matched reference has a positive definite
  // covariance; empty otherwise (the alignment is then unweighted).
  std::vector<Eigen::Matrix3d> covariances;
  size_t num_without_covariance = 0;
  // Reference names that are no image of the model (not registered, or a
  // different naming), in the reference's order.
  std::vector<std::string> unknown_names;
};

// Throws uw::Error when fewer than 3 images match, giving the counts and an
// example name from each side, since a naming mismatch (a folder prefix) is
// the usual cause. `source` names the references in messages.
ReferenceMatch MatchReferencePositions(
    const Reconstruction& model,
    const std::vector<ReferencePosition>& references,
    const std::string& source);

}  // namespace uw
