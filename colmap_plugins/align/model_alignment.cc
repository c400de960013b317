#include "colmap_plugins/align/model_alignment.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include <fmt/format.h>
#include <Eigen/Cholesky>

#include "colmap_plugins/align/track_metrics.h"
#include "colmap_plugins/nav/camera_prior.h"
#include "colmap_plugins/nav/geographic_positions.h"
#include "colmap_plugins/nav/image_times.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "common/util/error.h"
#include "common/util/json_fields.h"

namespace uw {

std::string ReferenceAssociationName(ReferenceAssociation association) {
  return association == ReferenceAssociation::kName ? "name" : "closest_point";
}

ReferenceAssociation ReferenceAssociationFromName(const std::string& name) {
  if (name == "name") return ReferenceAssociation::kName;
  if (name == "closest_point") return ReferenceAssociation::kClosestPoint;
  throw ErrorAt("--associate ", name, ": expected name or closest_point");
}

void ModelAlignmentOptions::Check() const {
  const bool has_nav = !nav.nav_path.empty();
  const int num_sources =
      !ref_images_path.empty() + !database_path.empty() + has_nav;
  if (num_sources != 1) {
    throw ErrorAt(
        "give exactly one of --ref_images_path, --database_path "
        "and --nav (got ",
        num_sources, ")");
  }
  if (nav.log.origin && !ref_images_path.empty() && !ref_is_gps) {
    throw ErrorAt(
        "--origin places geographic positions; --ref_images_path holds "
        "metric ones unless --ref_is_gps 1");
  }
  if (ref_is_gps && ref_images_path.empty()) {
    throw ErrorAt(
        "--ref_is_gps 1 reads --ref_images_path as 'image_name lat lon alt'; "
        "a database's WGS84 priors and a geographic --nav are recognised "
        "without it");
  }
  if (associate == ReferenceAssociation::kClosestPoint && !has_nav) {
    throw ErrorAt("--associate closest_point needs --nav");
  }
  if (associate == ReferenceAssociation::kClosestPoint &&
      position_sigma_m > 0.0) {
    throw ErrorAt(
        "--position_sigma applies to references paired by name, not to "
        "--associate closest_point");
  }
  if (!(position_sigma_m >= 0.0 && std::isfinite(position_sigma_m))) {
    throw ErrorAt("--position_sigma ", position_sigma_m,
                  ": expected a finite sigma >= 0 (m)");
  }
  if (min_common_images < 3) {
    throw ErrorAt("--min_common_images ", min_common_images,
                  ": a similarity needs at least 3");
  }
  similarity.Check();
  plausibility.Check();
}

namespace {

// References without a usable covariance get sigma² per axis on top of what
// they hold (a log without position sigmas still has its lever arm's
// share), as bundle_adjuster's --Nav.position_sigma does.
std::vector<ReferencePosition> WithPositionSigma(
    std::vector<ReferencePosition> references, double sigma_m) {
  if (!(sigma_m > 0.0)) return references;
  for (ReferencePosition& reference : references) {
    const Eigen::Matrix3d stated =
        reference.covariance.value_or(Eigen::Matrix3d::Zero());
    if (reference.covariance &&
        Eigen::LLT<Eigen::Matrix3d>(stated).info() == Eigen::Success) {
      continue;
    }
    reference.covariance = Eigen::Matrix3d(
        stated + sigma_m * sigma_m * Eigen::Matrix3d::Identity());
  }
  return references;
}

}  // namespace

NavigationReferenceSet NavigationReferences(
    const PosePriorImportOptions& options, const Reconstruction& model) {
  std::vector<std::pair<std::string, camera_t>> images;
  for (const Image& image : model.Images()) {
    images.emplace_back(image.name, image.camera_id);
  }
  const LoadedCameraPriors loaded =
      LoadCameraPriors(options, images, "the model");
  NavigationReferenceSet set;
  for (const CameraPrior& prior : loaded.priors) {
    set.references.push_back(
        {prior.image_name, prior.position, prior.position_covariance});
  }
  set.other_images = loaded.other_images;
  set.warnings = loaded.warnings;
  set.frame = loaded.frame;
  return set;
}

TimedPath NavigationPath(const PosePriorImportOptions& options,
                         NavLogFrame* frame) {
  const std::string nav_path = options.nav_path.string();
  const std::vector<NavRecord> nav =
      ReadNavigationLog(nav_path, options.log, frame);
  std::vector<ImageTime> samples;
  for (const NavRecord& row : nav) {
    samples.push_back({nav_path + ":" + std::to_string(row.line), row.time_s,
                       row.dive, row.line});
  }
  NavToCameraOptions at_row_times = options.nav_to_camera;
  at_row_times.time_offset_s = 0.0;
  TimedPath path;
  bool has_covariances = true;
  for (const CameraPrior& prior : CameraPriorsFromNavigation(
           nav, &samples, at_row_times, nullptr, {nav_path, nav_path})) {
    path.times_s.push_back(prior.time_s);
    path.positions.push_back(prior.position);
    path.covariances.push_back(prior.position_covariance);
    path.dives.push_back(prior.dive);
    has_covariances =
        has_covariances && prior.position_covariance.determinant() > 0.0;
  }
  if (!has_covariances) path.covariances.clear();
  return path;
}

ModelAlignment AlignByName(const Reconstruction& model,
                           const std::vector<ReferencePosition>& references,
                           const std::string& source,
                           const SimilarityOptions& options) {
  const ReferenceMatch match =
      MatchReferencePositions(model, references, source);
  ModelAlignment alignment;
  alignment.reference = source;
  alignment.association = ReferenceAssociation::kName;
  alignment.image_names = match.image_names;
  alignment.reference_positions = match.reference_positions;
  alignment.covariance_weighted = !match.covariances.empty();
  alignment.num_references = references.size();
  alignment.unknown_names = match.unknown_names;
  alignment.similarity = EstimateSimilarity(
      match.model_centres, match.reference_positions,
      alignment.covariance_weighted ? &match.covariances : nullptr, options);
  return alignment;
}

ModelAlignment AlignByClosestPoints(const Reconstruction& model,
                                    const PosePriorImportOptions& nav,
                                    const SimilarityOptions& options) {
  if (!nav.rig_config_path.empty()) {
    throw ErrorAt(
        "--associate closest_point: --rig_config is not supported; "
        "associate the images of one camera");
  }
  NavLogFrame frame;
  const TimedPath path = NavigationPath(nav, &frame);
  // Image order: by time when the times are known, else by name.
  std::vector<std::pair<double, const Image*>> ordered;
  std::map<std::string, double> times;
  if (!nav.image_times_path.empty()) {
    std::set<std::string> names;
    for (const Image& image : model.Images()) names.insert(image.name);
    std::vector<ImageTime> image_times;
    for (const ImageTime& time :
         ReadImageTimesCsv(nav.image_times_path, nav.log.time_zone_offset_s)) {
      // Images the mapper dropped may lie anywhere in time.
      if (names.count(time.image_name) != 0) image_times.push_back(time);
    }
    // Times only start the association; days off, they would start it at
    // one end of the path and the closest points would do the rest.
    CheckImageClock(ReadNavigationLog(nav.nav_path, nav.log), image_times,
                    nav.nav_to_camera,
                    {nav.nav_path.string(), nav.image_times_path.string()});
    for (const ImageTime& time : image_times) {
      times[time.image_name] = time.time_s + nav.nav_to_camera.time_offset_s;
    }
  }
  for (const Image& image : model.Images()) {
    const auto it = times.find(image.name);
    if (!times.empty() && it == times.end()) {
      throw ErrorAt(nav.image_times_path.string(), ": no time for image '",
                    image.name, "' of the model");
    }
    ordered.emplace_back(times.empty() ? 0.0 : it->second, &image);
  }
  std::stable_sort(ordered.begin(), ordered.end(),
                   [&](const auto& lhs, const auto& rhs) {
                     return times.empty() ? lhs.second->name < rhs.second->name
                                          : lhs.first < rhs.first;
                   });
  ModelAlignment alignment;
  alignment.reference = nav.nav_path.string() + " (path of " +
                        std::to_string(path.positions.size()) + " samples)";
  alignment.association = ReferenceAssociation::kClosestPoint;
  alignment.world_frame = frame;
  alignment.num_references = path.positions.size();
  alignment.covariance_weighted = !path.covariances.empty();
  std::vector<Eigen::Vector3d> centres;
  std::vector<double> centre_times;
  for (const auto& [time, image] : ordered) {
    alignment.image_names.push_back(image->name);
    centres.push_back(image->ProjectionCenter());
    centre_times.push_back(time);
  }
  PathAssociationOptions association_options;
  association_options.similarity = options;
  const PathAssociationResult result = AlignToPathByClosestPoints(
      centres, times.empty() ? nullptr : &centre_times, path,
      association_options);
  alignment.reference_positions = result.associated_positions;
  alignment.path_times_s = result.associated_times_s;
  alignment.similarity = result.similarity;
  alignment.iterations = result.iterations;
  alignment.converged = result.converged;
  return alignment;
}

ModelAlignment AlignModel(const ModelAlignmentOptions& options,
                          const Reconstruction& model) {
  options.Check();
  ModelAlignment alignment;
  std::vector<std::string> log_warnings;
  if (options.associate == ReferenceAssociation::kClosestPoint) {
    alignment = AlignByClosestPoints(model, options.nav, options.similarity);
  } else if (!options.ref_images_path.empty()) {
    std::vector<ReferencePosition> references =
        ReadReferencePositions(options.ref_images_path);
    NavLogFrame frame;
    if (options.ref_is_gps) {
      std::vector<Eigen::Vector3d> positions;
      std::vector<std::string> names;
      for (const ReferencePosition& reference : references) {
        positions.push_back(reference.position);
        names.push_back(reference.image_name);
      }
      const std::vector<Eigen::Vector3d> local =
          GeographicToLocal(positions, names, options.nav.log.origin,
                            options.ref_images_path + " (lat lon alt)", &frame);
      for (size_t i = 0; i < references.size(); ++i) {
        references[i].position = local[i];
      }
    }
    alignment = AlignByName(
        model, WithPositionSigma(references, options.position_sigma_m),
        options.ref_images_path, options.similarity);
    if (frame.origin) alignment.world_frame = frame;
  } else if (!options.database_path.empty()) {
    const Database database =
        Database::Open(options.database_path, Database::Mode::kReadOnly);
    NavLogFrame frame;
    alignment = AlignByName(
        model,
        WithPositionSigma(
            ReferencePositionsFromDatabase(database, options.nav.log.origin,
                                           &frame, &log_warnings),
            options.position_sigma_m),
        options.database_path + " (pose priors)", options.similarity);
    if (frame.origin) alignment.world_frame = frame;
  } else {
    const NavigationReferenceSet navigation =
        NavigationReferences(options.nav, model);
    log_warnings = navigation.warnings;
    alignment = AlignByName(
        model,
        WithPositionSigma(navigation.references, options.position_sigma_m),
        options.nav.nav_path.string(), options.similarity);
    alignment.num_references += navigation.other_images.size();
    alignment.unknown_names = navigation.other_images;
    alignment.world_frame = navigation.frame;
  }
  if (alignment.image_names.size() <
      static_cast<size_t>(options.min_common_images)) {
    throw ErrorAt(alignment.reference, ": ", alignment.image_names.size(),
                  " images of the model have a reference; "
                  "--min_common_images is ",
                  options.min_common_images);
  }
  alignment.plausibility = CheckAlignmentPlausibility(
      model, alignment.similarity, alignment.reference_positions,
      alignment.reference, options.plausibility);
  alignment.warnings = log_warnings;
  for (const std::string& warning :
       PlausibilityWarnings(alignment.plausibility, options.plausibility,
                            "--accept_implausible")) {
    alignment.warnings.push_back(warning);
  }
  std::map<std::string, Eigen::Vector3d> centre_of;
  for (const Image& image : model.Images()) {
    centre_of[image.name] = image.ProjectionCenter();
  }
  std::vector<Eigen::Vector3d> centres;
  for (const std::string& name : alignment.image_names) {
    centres.push_back(centre_of.at(name));
  }
  if (const auto line = DescribeOneLineTrack(centres)) {
    alignment.warnings.push_back(
        "the aligned " + *line +
        ". bundle_adjuster --nav ... --Nav.use_attitude 1 fixes it with the "
        "log's roll, pitch and heading, when it has them");
  }
  return alignment;
}

nlohmann::json ModelAlignmentJson(const ModelAlignment& alignment) {
  const SimilarityResult& similarity = alignment.similarity;
  nlohmann::json images = nlohmann::json::array();
  for (size_t k = 0; k < alignment.image_names.size(); ++k) {
    nlohmann::json image = {
        {"name", alignment.image_names[k]},
        {"reference_position", ToJson(alignment.reference_positions[k])},
        {"residual_m", ToJson(similarity.residuals[k])},
        {"residual_norm_m", similarity.residuals[k].norm()},
        {"inlier", static_cast<bool>(similarity.inliers[k])}};
    if (!similarity.mahalanobis.empty()) {
      image["mahalanobis"] = similarity.mahalanobis[k];
    }
    if (!alignment.path_times_s.empty()) {
      image["path_time_s"] = alignment.path_times_s[k];
    }
    images.push_back(image);
  }
  nlohmann::json json = {
      {"format", "uwmetric-alignment"},
      {"version", 1},
      {"reference", alignment.reference},
      {"association", ReferenceAssociationName(alignment.association)},
      {"reference_from_model", ToJson(similarity.b_from_a)},
      {"covariance_weighted", alignment.covariance_weighted},
      {"robust",
       similarity.max_error_m > 0.0 || similarity.max_mahalanobis > 0.0},
      {"max_error_m", similarity.max_error_m},
      {"max_mahalanobis", similarity.max_mahalanobis},
      {"num_images", alignment.image_names.size()},
      {"num_inliers", similarity.num_inliers},
      {"rms_m", similarity.rms_m},
      {"plausibility", PlausibilityJson(alignment.plausibility)},
      {"warnings", alignment.warnings},
      {"world_frame",
       alignment.world_frame ? WorldFrameText(*alignment.world_frame) : ""},
      {"images", images}};
  if (alignment.association == ReferenceAssociation::kClosestPoint) {
    json["iterations"] = alignment.iterations;
    json["converged"] = alignment.converged;
  }
  return json;
}

std::string FormatModelAlignment(const ModelAlignment& alignment) {
  const SimilarityResult& similarity = alignment.similarity;
  const Sim3d& sim3 = similarity.b_from_a;
  std::string text = fmt::format("Reference: {}\n", alignment.reference);
  if (alignment.world_frame) {
    text += fmt::format("World frame: {}\n",
                        WorldFrameText(*alignment.world_frame));
  }
  if (alignment.association == ReferenceAssociation::kName) {
    text +=
        fmt::format("Images with a reference position: {} (of {} positions)\n",
                    alignment.image_names.size(), alignment.num_references);
    if (!alignment.unknown_names.empty()) {
      text += fmt::format(
          "Reference positions of no model image: {} (e.g. "
          "{})\n",
          alignment.unknown_names.size(), alignment.unknown_names.front());
    }
  } else {
    text += fmt::format(
        "Images associated with their closest path point: {} ({} "
        "iterations, {})\n",
        alignment.image_names.size(), alignment.iterations,
        alignment.converged ? "converged" : "NOT converged");
  }
  text += fmt::format("Weighting: {}\n", alignment.covariance_weighted
                                             ? "by the reference covariances"
                                             : "none (unweighted)");
  if (similarity.max_mahalanobis > 0.0) {
    text += fmt::format(
        "Robust: RANSAC ({} triples), inliers within Mahalanobis distance "
        "{:.2f}\n",
        similarity.ransac_iterations, similarity.max_mahalanobis);
  } else if (similarity.max_error_m > 0.0) {
    text +=
        fmt::format("Robust: RANSAC ({} triples), inliers within {:.6g} m\n",
                    similarity.ransac_iterations, similarity.max_error_m);
  } else {
    text += "Robust: no (least squares over every image)\n";
  }
  text += fmt::format("Inliers: {} of {}\n", similarity.num_inliers,
                      similarity.inliers.size());
  text += fmt::format(
      "Transform reference_from_model: scale {:.10g}, rotation (qw qx qy qz) "
      "{:.10g} {:.10g} {:.10g} {:.10g}, translation {:.10g} {:.10g} {:.10g}\n",
      sim3.scale, sim3.rotation.w(), sim3.rotation.x(), sim3.rotation.y(),
      sim3.rotation.z(), sim3.translation.x(), sim3.translation.y(),
      sim3.translation.z());
  size_t worst = 0;
  for (size_t k = 0; k < similarity.residuals.size(); ++k) {
    if (similarity.residuals[k].norm() > similarity.residuals[worst].norm()) {
      worst = k;
    }
  }
  text +=
      fmt::format("Residual RMS (inliers): {:.6g} m; largest {:.6g} m ({})\n",
                  similarity.rms_m, similarity.residuals[worst].norm(),
                  alignment.image_names[worst]);
  text += PlausibilityText(alignment.plausibility);
  for (size_t k = 0; k < similarity.inliers.size(); ++k) {
    if (!similarity.inliers[k]) {
      text +=
          fmt::format("Outlier: {}, residual {:.6g} m\n",
                      alignment.image_names[k], similarity.residuals[k].norm());
    }
  }
  return text;
}

}  // namespace uw
