#include "colmap_plugins/exe/align_commands.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>

#include "colmap_plugins/align/mesh_comparison.h"
#include "colmap_plugins/align/model_comparison.h"
#include "colmap_plugins/align/path_association.h"
#include "colmap_plugins/align/reference_positions.h"
#include "colmap_plugins/exe/legacy_nav_flags.h"
#include "colmap_plugins/nav/camera_prior.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"
#include "common/mesh/mesh.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// Camera-centre priors of the model's images from navigation, by name.
// Unlike pose_prior_importer, rows of images the model lacks are no error:
// a reconstruction rarely registers every image.
std::vector<ReferencePosition> NavigationReferences(
    const PosePriorImportOptions& options, const Reconstruction& model) {
  const std::vector<NavRecord> nav = ReadNavigationCsv(options.nav_path);
  NavigationSources sources;
  sources.nav = options.nav_path.string();
  std::optional<RigConfig> rig;
  if (!options.rig_config_path.empty()) {
    rig = ReadRigConfig(options.rig_config_path);
  }
  std::optional<std::vector<ImageTime>> image_times;
  if (!options.image_times_path.empty()) {
    sources.image_times = options.image_times_path.string();
    image_times = ReadImageTimesCsv(options.image_times_path);
  } else if (rig) {
    std::vector<std::string> names;
    for (const Image& image : model.Images()) names.push_back(image.name);
    image_times = RigImageTimes(nav, *rig, names);
  }
  std::vector<ReferencePosition> references;
  for (const CameraPrior& prior : CameraPriorsFromNavigation(
           nav, image_times ? &*image_times : nullptr, options.nav_to_camera,
           rig ? &*rig : nullptr, sources)) {
    references.push_back(
        {prior.image_name, prior.position, prior.position_covariance});
  }
  return references;
}

// The navigation as a path of camera centres at the log's own times.
TimedPath NavigationPath(const PosePriorImportOptions& options) {
  const std::string nav_path = options.nav_path.string();
  const std::vector<NavRecord> nav = ReadNavigationCsv(nav_path);
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

// What was aligned to what, for the report and sim3.json.
struct Alignment {
  std::string reference;    // where the reference positions came from
  std::string association;  // "name" or "closest_point"
  std::vector<std::string> image_names;
  std::vector<Eigen::Vector3d> reference_positions;
  std::vector<double> path_times_s;  // closest_point only
  bool covariance_weighted = false;
  size_t num_references = 0;
  std::vector<std::string> unknown_names;
  SimilarityResult similarity;
  int iterations = 0;  // closest_point only
  bool converged = true;
};

Alignment AlignByName(const Reconstruction& model,
                      const std::vector<ReferencePosition>& references,
                      const std::string& source,
                      const SimilarityOptions& options) {
  const ReferenceMatch match =
      MatchReferencePositions(model, references, source);
  Alignment alignment;
  alignment.reference = source;
  alignment.association = "name";
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

Alignment AlignByClosestPoints(const Reconstruction& model,
                               const PosePriorImportOptions& nav,
                               const SimilarityOptions& options) {
  if (!nav.rig_config_path.empty()) {
    throw ErrorAt(
        "--associate closest_point: --rig_config is not supported; "
        "associate the images of one camera");
  }
  const TimedPath path = NavigationPath(nav);
  // Image order: by time when the times are known, else by name.
  std::vector<std::pair<double, const Image*>> ordered;
  std::map<std::string, double> times;
  if (!nav.image_times_path.empty()) {
    for (const ImageTime& time : ReadImageTimesCsv(nav.image_times_path)) {
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
  Alignment alignment;
  alignment.reference = nav.nav_path.string() + " (path of " +
                        std::to_string(path.positions.size()) + " samples)";
  alignment.association = "closest_point";
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

nlohmann::json AlignmentJson(const Alignment& alignment) {
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
  nlohmann::json json = {{"format", "uwmetric-alignment"},
                         {"version", 1},
                         {"reference", alignment.reference},
                         {"association", alignment.association},
                         {"reference_from_model", ToJson(similarity.b_from_a)},
                         {"covariance_weighted", alignment.covariance_weighted},
                         {"robust", similarity.max_error_m > 0.0 ||
                                        similarity.max_mahalanobis > 0.0},
                         {"max_error_m", similarity.max_error_m},
                         {"max_mahalanobis", similarity.max_mahalanobis},
                         {"num_images", alignment.image_names.size()},
                         {"num_inliers", similarity.num_inliers},
                         {"rms_m", similarity.rms_m},
                         {"images", images}};
  if (alignment.association == "closest_point") {
    json["iterations"] = alignment.iterations;
    json["converged"] = alignment.converged;
  }
  return json;
}

void PrintAlignment(const Alignment& alignment) {
  const SimilarityResult& similarity = alignment.similarity;
  const Sim3d& sim3 = similarity.b_from_a;
  std::printf("Reference: %s\n", alignment.reference.c_str());
  if (alignment.association == "name") {
    std::printf("Images with a reference position: %zu (of %zu positions)\n",
                alignment.image_names.size(), alignment.num_references);
    if (!alignment.unknown_names.empty()) {
      std::printf("Reference positions of no model image: %zu (e.g. %s)\n",
                  alignment.unknown_names.size(),
                  alignment.unknown_names.front().c_str());
    }
  } else {
    std::printf(
        "Images associated with their closest path point: %zu (%d "
        "iterations, %s)\n",
        alignment.image_names.size(), alignment.iterations,
        alignment.converged ? "converged" : "NOT converged");
  }
  std::printf("Weighting: %s\n", alignment.covariance_weighted
                                     ? "by the reference covariances"
                                     : "none (unweighted)");
  if (similarity.max_mahalanobis > 0.0) {
    std::printf(
        "Robust: RANSAC (%d triples), inliers within Mahalanobis "
        "distance %.2f\n",
        similarity.ransac_iterations, similarity.max_mahalanobis);
  } else if (similarity.max_error_m > 0.0) {
    std::printf("Robust: RANSAC (%d triples), inliers within %.6g m\n",
                similarity.ransac_iterations, similarity.max_error_m);
  } else {
    std::printf("Robust: no (least squares over every image)\n");
  }
  std::printf("Inliers: %zu of %zu\n", similarity.num_inliers,
              similarity.inliers.size());
  std::printf(
      "Transform reference_from_model: scale %.10g, rotation (qw qx qy qz) "
      "%.10g %.10g %.10g %.10g, translation %.10g %.10g %.10g\n",
      sim3.scale, sim3.rotation.w(), sim3.rotation.x(), sim3.rotation.y(),
      sim3.rotation.z(), sim3.translation.x(), sim3.translation.y(),
      sim3.translation.z());
  size_t worst = 0;
  for (size_t k = 0; k < similarity.residuals.size(); ++k) {
    if (similarity.residuals[k].norm() > similarity.residuals[worst].norm()) {
      worst = k;
    }
  }
  std::printf("Residual RMS (inliers): %.6g m; largest %.6g m (%s)\n",
              similarity.rms_m, similarity.residuals[worst].norm(),
              alignment.image_names[worst].c_str());
  for (size_t k = 0; k < similarity.inliers.size(); ++k) {
    if (!similarity.inliers[k]) {
      std::printf("Outlier: %s, residual %.6g m\n",
                  alignment.image_names[k].c_str(),
                  similarity.residuals[k].norm());
    }
  }
}

void RefuseSameFolder(const std::string& input_path,
                      const std::string& output_path) {
  std::error_code ignored;
  if (fs::equivalent(input_path, output_path, ignored)) {
    throw ErrorAt("--output_path ", output_path,
                  " is the input folder; write to another folder");
  }
}

void WriteJson(const nlohmann::json& json, const fs::path& path) {
  WriteFilesAtomically(
      {{path, [&](std::ostream& out) { out << json.dump(2) << "\n"; }}}, false);
}

}  // namespace

int RunModelAligner(int argc, char** argv) {
  CLI::App app(
      "Moves a model onto reference camera positions with one similarity "
      "(scale, rotation, translation), as `colmap model_aligner` does, and "
      "writes it in the input's format. References: COLMAP's ref_images.txt, "
      "a database's pose priors, or a navigation log (camera centres through "
      "the lever arm; covariance-weighted). Robust by default: RANSAC over "
      "triples picks the inliers (threshold --alignment_max_error, or "
      "automatic), outliers are listed. Unsynchronised cameras: --associate "
      "closest_point matches each camera to the closest point of the "
      "navigation path (ICP). Relative geometry is unchanged: a similarity "
      "cannot undo a dome.\n\n"
      "Examples:\n"
      "  uwcolmap model_aligner --input_path sparse/0 --output_path aligned "
      "--ref_images_path ref_images.txt --robust_alignment 0\n"
      "  uwcolmap model_aligner --input_path sparse/0 --output_path aligned "
      "--nav nav.csv --mount down --lever_arm 0.6,0,-0.3 --boresight "
      "0.3,-0.5,0.8 --transform_path sim3.json\n"
      "  uwcolmap model_aligner --input_path sparse/0 --output_path aligned "
      "--nav nav.csv --image_times image_times.csv --associate closest_point",
      "uwcolmap model_aligner");
  std::string input_path;
  std::string output_path;
  std::string ref_images_path;
  std::string database_path;
  NavFlags nav;
  std::string robust_alignment = "1";
  double alignment_max_error = 0.0;
  std::string estimate_scale = "1";
  int min_common_images = 3;
  std::string associate = "name";
  std::string transform_path;
  std::string ref_is_gps = "0";
  std::string alignment_type = "custom";
  app.add_option("--input_path", input_path, "Model folder to align")
      ->required();
  app.add_option("--output_path", output_path,
                 "Folder for the aligned model (created if missing)")
      ->required();
  app.add_option("--ref_images_path", ref_images_path,
                 "Reference camera centres, one 'image_name x y z' per line "
                 "(as colmap model_aligner)");
  app.add_option("--database_path", database_path,
                 "COLMAP database whose pose priors (positions, and "
                 "covariances from COLMAP 3.11 on) are the references");
  nav.Add(app, false, "--rig_config");
  app.add_option("--robust_alignment", robust_alignment,
                 "1: RANSAC + Huber refinement, outliers reported; 0: least "
                 "squares over every image")
      ->default_val("1");
  app.add_option("--alignment_max_error,--robust_alignment_max_error",
                 alignment_max_error,
                 "Inlier threshold in metres (COLMAP 3.8 calls it "
                 "--robust_alignment_max_error); 0: automatic (Mahalanobis "
                 "4.03 with covariances, else 2.5 robust sigma)")
      ->default_val(0.0);
  app.add_option("--estimate_scale", estimate_scale,
                 "0: rigid transform (scale 1), for a model already in "
                 "metres")
      ->default_val("1");
  app.add_option("--min_common_images", min_common_images,
                 "Fewest images with a reference to align (>= 3)")
      ->default_val(3);
  app.add_option("--associate", associate,
                 "name: images paired with references by name; "
                 "closest_point: with the closest point of the --nav path")
      ->default_val("name");
  app.add_option("--transform_path", transform_path,
                 "Also write the similarity and the per-image residuals as "
                 "JSON (docs/formats.md)");
  app.add_option("--ref_is_gps", ref_is_gps,
                 "As in colmap; only 0 (metric references) is supported")
      ->default_val("0");
  app.add_option("--alignment_type", alignment_type,
                 "As in colmap; only custom is supported")
      ->default_val("custom");
  return RunCommand(app, argc, argv, [&] {
    if (ParseColmapBool(ref_is_gps, "ref_is_gps")) {
      throw ErrorAt(
          "--ref_is_gps 1: uwcolmap aligns to metric references "
          "only; convert GPS to a local frame (ENU), or use colmap "
          "model_aligner");
    }
    if (alignment_type != "custom") {
      throw ErrorAt("--alignment_type ", alignment_type,
                    ": only custom is supported; use colmap model_aligner "
                    "for plane, ecef and enu");
    }
    const int num_sources = !ref_images_path.empty() + !database_path.empty() +
                            !nav.nav_path.empty();
    if (num_sources != 1) {
      throw ErrorAt(
          "give exactly one of --ref_images_path, --database_path "
          "and --nav (got ",
          num_sources, ")");
    }
    if (associate != "name" && associate != "closest_point") {
      throw ErrorAt("--associate ", associate,
                    ": expected name or closest_point");
    }
    if (associate == "closest_point" && nav.nav_path.empty()) {
      throw ErrorAt("--associate closest_point needs --nav");
    }
    if (min_common_images < 3) {
      throw ErrorAt("--min_common_images ", min_common_images,
                    ": a similarity needs at least 3");
    }
    SimilarityOptions options;
    options.robust = ParseColmapBool(robust_alignment, "robust_alignment");
    options.max_error_m = alignment_max_error;
    options.estimate_scale = ParseColmapBool(estimate_scale, "estimate_scale");
    options.Check();
    RefuseSameFolder(input_path, output_path);

    const ModelFiles files = DetectModelFiles(input_path);
    Reconstruction model = ReadModel(input_path);
    Alignment alignment;
    if (associate == "closest_point") {
      alignment = AlignByClosestPoints(model, nav.ToOptions(), options);
    } else if (!ref_images_path.empty()) {
      alignment = AlignByName(model, ReadReferencePositions(ref_images_path),
                              ref_images_path, options);
    } else if (!database_path.empty()) {
      const Database database =
          Database::Open(database_path, Database::Mode::kReadOnly);
      alignment = AlignByName(model, ReferencePositionsFromDatabase(database),
                              database_path + " (pose priors)", options);
    } else {
      alignment =
          AlignByName(model, NavigationReferences(nav.ToOptions(), model),
                      nav.nav_path, options);
    }
    if (alignment.image_names.size() < static_cast<size_t>(min_common_images)) {
      throw ErrorAt(alignment.reference, ": ", alignment.image_names.size(),
                    " images of the model have a reference; "
                    "--min_common_images is ",
                    min_common_images);
    }
    std::printf("Model: %s (%zu images, %zu points)\n", input_path.c_str(),
                model.Images().size(), model.Points3D().size());
    PrintAlignment(alignment);
    TransformReconstruction(alignment.similarity.b_from_a, &model);
    WriteModel(model, output_path, files.format);
    std::printf("Wrote %s (%s)\n", output_path.c_str(),
                files.format == ModelFormat::kBinary ? "binary" : "text");
    if (!transform_path.empty()) {
      WriteJson(AlignmentJson(alignment), transform_path);
      std::printf("Wrote %s\n", transform_path.c_str());
    }
  });
}

namespace {

void PrintComparison(const ModelComparison& comparison,
                     const std::string& surface_path,
                     const ModelComparisonOptions& options) {
  std::printf(
      "Images: model %zu, reference %zu, common %zu (reference images "
      "missing from the model: %zu%s%s)\n",
      comparison.num_model_images, comparison.num_reference_images,
      comparison.cameras.size(), comparison.missing_images.size(),
      comparison.missing_images.empty() ? "" : ", e.g. ",
      comparison.missing_images.empty()
          ? ""
          : comparison.missing_images.front().c_str());
  const Sim3d& sim3 = comparison.alignment.b_from_a;
  if (comparison.aligned) {
    std::printf(
        "Alignment reference_from_model (%s%s): scale %.8g, %zu of %zu "
        "inliers\n",
        options.alignment.estimate_scale ? "similarity, " : "rigid, ",
        options.alignment.robust ? "robust" : "least squares", sim3.scale,
        comparison.alignment.num_inliers, comparison.cameras.size());
  } else {
    std::printf("Alignment: none (the model is compared where it is)\n");
  }
  std::printf(
      "Camera centres: RMSE %.6g m = %.4f %% of the %.4g m extent, max %.6g "
      "m\n",
      comparison.camera_rmse_m,
      100.0 * comparison.camera_rmse_m / comparison.reference_extent_m,
      comparison.reference_extent_m, comparison.camera_max_error_m);
  std::printf("Camera rotations: RMS %.6g deg, max %.6g deg\n",
              comparison.rotation_rmse_deg, comparison.rotation_max_deg);
  std::printf("Track: %.6g m along (%.4f, %.4f, %.4f)\n",
              comparison.axis.length, comparison.axis.direction.x(),
              comparison.axis.direction.y(), comparison.axis.direction.z());
  std::printf("%-8s %10s %10s %7s %10s %12s %10s\n", "segment", "from_m",
              "to_m", "images", "scale_3d", "scale_along", "tilt_deg");
  for (size_t s = 0; s < comparison.segments.size(); ++s) {
    const SegmentScale& segment = comparison.segments[s];
    std::printf("%-8c %10.3f %10.3f %7zu %10.5f %12.5f %10.3f\n",
                static_cast<char>('A' + s), segment.begin, segment.end,
                segment.num_images, segment.scale_3d, segment.scale_along_track,
                segment.view_tilt_deg);
  }
  const DistanceRatios& ratios = comparison.distance_ratios;
  std::printf(
      "Camera distance ratios model/reference (%zu pairs): median %.6g, max "
      "|r-1| %.4g, 95 %% |r-1| %.4g\n",
      ratios.num_pairs, ratios.median_ratio, ratios.max_abs_deviation,
      ratios.p95_abs_deviation);
  if (!comparison.surface) return;
  const SurfaceDeviation& surface = *comparison.surface;
  std::printf(
      "Surface %s: %zu of %zu points (error <= %g px), signed distance "
      "(+ towards the cameras): RMS %.6g m, mean %.6g m, median %.6g m, "
      "median |d| %.6g m, 95 %% |d| %.6g m, max |d| %.6g m\n",
      surface_path.c_str(), surface.num_points_used, surface.num_points,
      options.max_reprojection_error_px, surface.rms_m, surface.mean_m,
      surface.median_m, surface.median_abs_m, surface.p95_abs_m,
      surface.max_abs_m);
  std::printf("%-8s %10s %10s %8s %12s\n", "bin", "from_m", "to_m", "points",
              "median_m");
  for (size_t b = 0; b < surface.bins.size(); ++b) {
    const DeviationBin& bin = surface.bins[b];
    std::printf("%-8zu %10.3f %10.3f %8zu %12.6f\n", b + 1, bin.begin, bin.end,
                bin.count, bin.median_m);
  }
  if (surface.dome.valid) {
    std::printf(
        "Dome fit d(x) = %.4g + %.4g x + %.4g x^2: sagitta %.6g m = %.4f %% "
        "of the track (negative: the middle stands out towards the "
        "cameras)\n",
        surface.dome.coefficients[0], surface.dome.coefficients[1],
        surface.dome.coefficients[2], surface.dome.sagitta_m,
        surface.dome.sagitta_percent);
  } else {
    std::printf("Dome fit: fewer than 3 bins with %zu points\n",
                options.min_points_per_bin);
  }
}

void PrintMeshComparison(const MeshComparison& dense,
                         const std::string& dense_mesh_path) {
  std::printf("Dense surface: %s (after the alignment)\n",
              dense_mesh_path.c_str());
  std::printf(
      "  camera-scene distance (median along the optical axes): "
      "%.6g m\n",
      dense.camera_scene_distance);
  std::printf(
      "  distance to the reference surface over %zu samples: median "
      "%.6g m (%.3f %% of the camera-scene distance), 90 %% %.6g m, "
      "RMS %.6g m, signed mean %.6g m\n",
      dense.num_samples, dense.median,
      100.0 * dense.median / dense.camera_scene_distance, dense.p90, dense.rms,
      dense.mean_signed);
  std::printf(
      "  coverage: %.2f %% of the %.6g m^2 seen by >= %d reference "
      "images lie within %.4g m of the dense surface\n",
      100.0 * dense.coverage, dense.observed_area, dense.min_views,
      dense.coverage_tolerance);
}

}  // namespace

int RunModelComparer(int argc, char** argv) {
  CLI::App app(
      "Measures a model against a reference model or uwsim's truth: aligns "
      "the model's camera centres to the reference's by a similarity "
      "(images paired by name), then reports camera position and rotation "
      "errors, per-segment scale along the track (3D and along-track "
      "distances), ratios of camera distances, and, with a reference "
      "surface, the signed distance of the model's 3D points from it, "
      "binned along the track, with a quadratic dome fit and its sagitta. "
      "Definitions: docs/uwcolmap.md.\n\n"
      "Examples:\n"
      "  uwcolmap model_comparer --input_path sparse/0 --truth_dir sim "
      "--output_path compare.json\n"
      "  uwcolmap model_comparer --input_path sparse_nav --ref_path "
      "sparse_lambda2 --segments 6",
      "uwcolmap model_comparer");
  std::string input_path;
  std::string ref_path;
  std::string truth_dir;
  std::string mesh_path;
  std::string dense_mesh_path;
  MeshComparisonOptions dense_options;
  std::string output_path;
  std::string robust_alignment = "0";
  std::string alignment = "similarity";
  ModelComparisonOptions options;
  app.add_option("--input_path", input_path, "Model to measure")->required();
  app.add_option("--ref_path", ref_path, "Reference model");
  app.add_option("--truth_dir", truth_dir,
                 "uwsim output folder: truth/ is the reference model, "
                 "truth/mesh.ply the reference surface");
  app.add_option("--mesh_path", mesh_path,
                 "Reference surface (PLY triangle mesh in the reference's "
                 "frame); default with --truth_dir: truth/mesh.ply");
  app.add_option("--dense_mesh_path", dense_mesh_path,
                 "The model's dense surface (PLY/OBJ in the model's frame, "
                 "e.g. from dense_mesher): its accuracy and coverage against "
                 "the reference surface, after the alignment");
  app.add_option("--dense_min_views", dense_options.min_views,
                 "Reference images that must see a true triangle for it to "
                 "count as observed (coverage)")
      ->capture_default_str();
  app.add_option("--segments", options.num_segments,
                 "Segments along the track for the per-segment scale")
      ->default_val(6);
  app.add_option("--bins", options.num_bins,
                 "Along-track bins of the surface deviation")
      ->default_val(12);
  app.add_option("--max_reprojection_error", options.max_reprojection_error_px,
                 "Points with a larger stored error (px) are left out of the "
                 "surface deviation")
      ->default_val(2.0);
  app.add_option("--alignment", alignment,
                 "similarity: align the model's centres to the reference's; "
                 "rigid: without scale; none: compare in place (a model "
                 "already in the reference's frame: absolute errors)")
      ->default_val("similarity");
  app.add_option("--robust_alignment", robust_alignment,
                 "1: RANSAC (outlier cameras set aside); 0: least squares")
      ->default_val("0");
  app.add_option("--output_path", output_path,
                 "Also write the figures as JSON (docs/formats.md)");
  return RunCommand(app, argc, argv, [&] {
    if (ref_path.empty() == truth_dir.empty()) {
      throw ErrorAt("give exactly one of --ref_path and --truth_dir");
    }
    if (alignment != "similarity" && alignment != "rigid" &&
        alignment != "none") {
      throw ErrorAt("--alignment ", alignment,
                    ": expected similarity, rigid or none");
    }
    options.align = alignment != "none";
    options.alignment.estimate_scale = alignment == "similarity";
    options.alignment.robust =
        ParseColmapBool(robust_alignment, "robust_alignment");
    options.Check();
    const fs::path reference_path =
        truth_dir.empty() ? fs::path(ref_path) : fs::path(truth_dir) / "truth";
    if (mesh_path.empty() && !truth_dir.empty()) {
      mesh_path = (fs::path(truth_dir) / "truth" / "mesh.ply").string();
    }
    const Reconstruction model = ReadModel(input_path);
    const Reconstruction reference = ReadModel(reference_path);
    if (!dense_mesh_path.empty() && mesh_path.empty()) {
      throw Error(
          "--dense_mesh_path needs a reference surface: --truth_dir or "
          "--mesh_path");
    }
    TriangleMesh reference_mesh;
    std::optional<MeshDistance> surface;
    if (!mesh_path.empty()) {
      reference_mesh = ReadPly(mesh_path);
      surface.emplace(reference_mesh.vertices, reference_mesh.triangles);
    }
    const ModelComparison comparison =
        CompareModels(model, reference, surface ? &*surface : nullptr, options);
    std::printf("Model: %s\nReference: %s\n", input_path.c_str(),
                reference_path.c_str());
    PrintComparison(comparison, mesh_path, options);
    std::optional<MeshComparison> dense;
    if (!dense_mesh_path.empty()) {
      dense = CompareMeshes(TransformMesh(comparison.alignment.b_from_a,
                                          ReadMesh(dense_mesh_path)),
                            reference_mesh, reference, dense_options);
      PrintMeshComparison(*dense, dense_mesh_path);
    }
    if (!output_path.empty()) {
      nlohmann::json json = ToJson(comparison);
      json["model_path"] = input_path;
      json["reference_path"] = reference_path.string();
      json["mesh_path"] = mesh_path.empty() ? nlohmann::json(nullptr)
                                            : nlohmann::json(mesh_path);
      json["max_reprojection_error_px"] = options.max_reprojection_error_px;
      json["dense_mesh_path"] = dense_mesh_path.empty()
                                    ? nlohmann::json(nullptr)
                                    : nlohmann::json(dense_mesh_path);
      json["dense_surface"] = dense ? ToJson(*dense) : nlohmann::json(nullptr);
      WriteJson(json, output_path);
      std::printf("Wrote %s\n", output_path.c_str());
    }
  });
}

}  // namespace uw
