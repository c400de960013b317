#include "colmap_plugins/exe/align_commands.h"

#include <optional>

#include <fmt/format.h>

#include "colmap_plugins/align/mesh_distance.h"
#include "colmap_plugins/align/mesh_frame.h"
#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/exe/nav_flags.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

void WriteJson(const nlohmann::json& json, const fs::path& path) {
  WriteFilesAtomically(
      {{path, [&](std::ostream& out) { out << json.dump(2) << "\n"; }}}, false);
}

void AddModelAlignerFlags(CommandLine* cli, ModelAlignerOptions* options) {
  ModelAlignmentOptions& alignment = options->alignment;
  cli->Add("--input_path", &options->input_path, "Model folder to align")
      ->required();
  cli->Add("--output_path", &options->output_path,
           "Folder for the aligned model (created if missing)")
      ->required();
  cli->Add("--ref_images_path", &alignment.ref_images_path,
           "Reference camera centres, one 'image_name x y z' per line (as "
           "colmap model_aligner)");
  cli->Add("--database_path", &alignment.database_path,
           "COLMAP database whose pose priors (positions, and covariances "
           "from COLMAP 3.11 on) are the references");
  AddNavFlags(cli, &alignment.nav, false, "--rig_config");
  cli->Add("--robust_alignment", &alignment.similarity.robust,
           "1: RANSAC + Huber refinement, outliers reported; 0: least "
           "squares over every image");
  cli->Add("--alignment_max_error,--robust_alignment_max_error",
           &alignment.similarity.max_error_m,
           "Inlier threshold in metres (COLMAP 3.8 calls it "
           "--robust_alignment_max_error); 0: automatic (Mahalanobis 4.03 "
           "with covariances, else 2.5 robust sigma)");
  cli->Add("--estimate_scale", &alignment.similarity.estimate_scale,
           "0: rigid transform (scale 1), for a model already in metres");
  cli->Add("--min_common_images", &alignment.min_common_images,
           "Fewest images with a reference to align (>= 3)");
  cli->Add("--position_sigma", &alignment.position_sigma_m,
           "Sigma (m, per axis) of references without a usable covariance "
           "(ref_images.txt, a log without position sigmas); they then "
           "weight the fit and the plausibility checks see them (by name)");
  AddPlausibilityFlags(cli, &alignment.plausibility, "--");
  cli->Add<ReferenceAssociation>(
      "--associate", &alignment.associate,
      "name: images paired with references by name; closest_point: with "
      "the closest point of the --nav path",
      ReferenceAssociationFromName, ReferenceAssociationName);
  cli->Add("--transform_path", &options->transform_path,
           "Also write the similarity and the per-image residuals as JSON "
           "(docs/formats.md)");
  cli->Add("--ref_is_gps", &alignment.ref_is_gps,
           "1: --ref_images_path lines are 'image_name lat lon alt' (deg, "
           "m), aligned to in local east-north-up metres at --origin (or "
           "the first reference rounded to 0.001 deg, printed); needs "
           "--alignment_type enu");
  cli->Add("--alignment_type", &options->alignment_type,
           "custom (references in metres), or enu with --ref_is_gps 1; "
           "colmap's plane and ecef are not supported");
}

void RunModelAligner(const ModelAlignerOptions& options) {
  const ModelFiles files = DetectModelFiles(options.input_path);
  Reconstruction model = ReadModel(options.input_path);
  const ModelAlignment alignment = AlignModel(options.alignment, model);
  fmt::print("Model: {} ({} images, {} points)\n{}", options.input_path,
             model.Images().size(), model.Points3D().size(),
             FormatModelAlignment(alignment));
  for (const std::string& warning : alignment.warnings) {
    fmt::print(stderr, "WARNING: {}\n", warning);
  }
  TransformReconstruction(alignment.similarity.b_from_a, &model);
  WriteModel(model, options.output_path, files.format);
  fmt::print("Wrote {} ({})\n", options.output_path,
             files.format == ModelFormat::kBinary ? "binary" : "text");
  // The model's frame beside it, in a form a GIS reads; a model in its
  // references' own frame has none (an earlier run's would lie).
  const fs::path frame_path =
      fs::path(options.output_path) / "world_frame.json";
  if (alignment.world_frame) {
    WriteJson(WorldFrameJson(*alignment.world_frame), frame_path);
    fmt::print("Wrote {}\n", frame_path.string());
  } else {
    fs::remove(frame_path);
  }
  if (!options.transform_path.empty()) {
    WriteJson(ModelAlignmentJson(alignment), options.transform_path);
    fmt::print("Wrote {}\n", options.transform_path);
  }
}

ComparisonAlignment ComparisonAlignmentFromName(const std::string& name) {
  if (name == "similarity") return ComparisonAlignment::kSimilarity;
  if (name == "rigid") return ComparisonAlignment::kRigid;
  if (name == "none") return ComparisonAlignment::kNone;
  throw ErrorAt("--alignment ", name, ": expected similarity, rigid or none");
}

std::string ComparisonAlignmentName(const ComparisonAlignment& alignment) {
  switch (alignment) {
    case ComparisonAlignment::kSimilarity:
      return "similarity";
    case ComparisonAlignment::kRigid:
      return "rigid";
    case ComparisonAlignment::kNone:
      break;
  }
  return "none";
}

void AddModelComparerFlags(CommandLine* cli, ModelComparerOptions* options) {
  cli->Add("--input_path", &options->input_path, "Model to measure")
      ->required();
  cli->Add("--ref_path", &options->ref_path, "Reference model");
  cli->Add("--truth_dir", &options->truth_dir,
           "uwsim output folder: truth/ is the reference model, "
           "truth/mesh.ply the reference surface");
  cli->Add("--mesh_path", &options->mesh_path,
           "Reference surface (PLY triangle mesh in the reference's frame); "
           "default with --truth_dir: truth/mesh.ply");
  cli->Add("--dense_mesh_path", &options->dense_mesh_path,
           "The model's dense surface (PLY, OBJ, STL, glTF, ... in the model's "
           "frame, e.g. "
           "from dense_mesher): its accuracy and coverage against the "
           "reference surface, after the alignment");
  cli->Add("--dense_min_views", &options->dense.min_views,
           "Reference images that must see a true triangle for it to count "
           "as observed (coverage)");
  cli->Add("--dense_max_range", &options->dense_max_range_m,
           "...and within this range (m) of them: how far the water lets "
           "them see; -1: with --truth_dir, the visible range uwsim states "
           "in truth/sim.json; 0: any range");
  ModelComparisonOptions& comparison = options->comparison;
  cli->Add("--segments", &comparison.num_segments,
           "Segments along the track for the per-segment scale");
  cli->Add("--bins", &comparison.num_bins,
           "Along-track bins of the surface deviation");
  cli->Add("--max_reprojection_error", &comparison.max_reprojection_error_px,
           "Points with a larger stored error (px) are left out of the "
           "surface deviation");
  cli->Add<ComparisonAlignment>(
      "--alignment", &options->alignment,
      "similarity: align the model's centres to the reference's; rigid: "
      "without scale; none: compare in place (a model already in the "
      "reference's frame: absolute errors)",
      ComparisonAlignmentFromName, ComparisonAlignmentName);
  cli->Add("--robust_alignment", &comparison.alignment.robust,
           "1: RANSAC (outlier cameras set aside); 0: least squares");
  cli->Add("--output_path", &options->output_path,
           "Also write the figures as JSON (docs/formats.md)");
}

void RunModelComparer(const ModelComparerOptions& options) {
  const ModelComparisonOptions comparison_options = options.Comparison();
  const fs::path reference_path = options.ReferencePath();
  const std::string mesh_path = options.SurfacePath();
  const Reconstruction model = ReadModel(options.input_path);
  const Reconstruction reference = ReadModel(reference_path);
  TriangleMesh reference_mesh;
  std::optional<MeshDistance> surface;
  if (!mesh_path.empty()) {
    reference_mesh = ReadPly(mesh_path);
    surface.emplace(reference_mesh.vertices, reference_mesh.triangles);
  }
  const ModelComparison comparison = CompareModels(
      model, reference, surface ? &*surface : nullptr, comparison_options);
  fmt::print("Model: {}\nReference: {}\n{}", options.input_path,
             reference_path.string(),
             FormatModelComparison(comparison, mesh_path, comparison_options));
  std::optional<MeshComparison> dense;
  if (!options.dense_mesh_path.empty()) {
    const TriangleMesh dense_mesh = ReadMesh(options.dense_mesh_path);
    RequireMeshInModelFrame(CheckMeshFrame(model, RayCaster(dense_mesh)),
                            options.dense_mesh_path, options.input_path);
    dense =
        CompareMeshes(TransformMesh(comparison.alignment.b_from_a, dense_mesh),
                      reference_mesh, reference, options.Dense());
    fmt::print("{}", FormatMeshComparison(*dense, options.dense_mesh_path));
  }
  if (options.output_path.empty()) return;
  const auto path_or_null = [](const std::string& path) {
    return path.empty() ? nlohmann::json(nullptr) : nlohmann::json(path);
  };
  nlohmann::json json = ToJson(comparison);
  json["model_path"] = options.input_path;
  json["reference_path"] = reference_path.string();
  json["mesh_path"] = path_or_null(mesh_path);
  json["max_reprojection_error_px"] =
      comparison_options.max_reprojection_error_px;
  json["dense_mesh_path"] = path_or_null(options.dense_mesh_path);
  json["dense_surface"] = dense ? ToJson(*dense) : nlohmann::json(nullptr);
  WriteJson(json, options.output_path);
  fmt::print("Wrote {}\n", options.output_path);
}

}  // namespace

void ModelAlignerOptions::Check() const {
  // colmap aligns GPS references into ECEF unless told enu: say which
  // frame the model lands in rather than pick one silently.
  if (alignment.ref_is_gps && alignment_type != "enu") {
    throw ErrorAt(
        "--ref_is_gps 1 aligns into local east-north-up metres: "
        "give --alignment_type enu (ECEF is not supported)");
  }
  if (!alignment.ref_is_gps && alignment_type != "custom") {
    throw ErrorAt("--alignment_type ", alignment_type,
                  alignment_type == "enu"
                      ? ": needs --ref_is_gps 1 (references in lat lon alt)"
                      : ": only custom, and enu with --ref_is_gps 1, are "
                        "supported; use colmap model_aligner for plane and "
                        "ecef");
  }
  alignment.Check();
  std::error_code ignored;
  if (fs::equivalent(input_path, output_path, ignored)) {
    throw ErrorAt("--output_path ", output_path,
                  " is the input folder; write to another folder");
  }
}

fs::path ModelComparerOptions::ReferencePath() const {
  return truth_dir.empty() ? fs::path(ref_path) : fs::path(truth_dir) / "truth";
}

std::string ModelComparerOptions::SurfacePath() const {
  if (!mesh_path.empty() || truth_dir.empty()) return mesh_path;
  return (fs::path(truth_dir) / "truth" / "mesh.ply").string();
}

MeshComparisonOptions ModelComparerOptions::Dense() const {
  MeshComparisonOptions options = dense;
  options.max_range_m = std::max(0.0, dense_max_range_m);
  const fs::path sim_json = fs::path(truth_dir) / "truth" / "sim.json";
  if (dense_max_range_m < 0.0 && !truth_dir.empty() &&
      fs::is_regular_file(sim_json)) {
    const nlohmann::json sim =
        ParseJsonText(ReadFileToString(sim_json), sim_json.string());
    // Folders from before uwsim stated it have none: any range.
    if (sim.contains("truth") && sim["truth"].contains("visible_range_m")) {
      options.max_range_m = sim["truth"]["visible_range_m"].get<double>();
    }
  }
  return options;
}

ModelComparisonOptions ModelComparerOptions::Comparison() const {
  ModelComparisonOptions options = comparison;
  options.align = alignment != ComparisonAlignment::kNone;
  options.alignment.estimate_scale =
      alignment == ComparisonAlignment::kSimilarity;
  return options;
}

void ModelComparerOptions::Check() const {
  if (ref_path.empty() == truth_dir.empty()) {
    throw ErrorAt("give exactly one of --ref_path and --truth_dir");
  }
  Comparison().Check();
  if (!dense_mesh_path.empty() && SurfacePath().empty()) {
    throw Error(
        "--dense_mesh_path needs a reference surface: --truth_dir or "
        "--mesh_path");
  }
}

Subcommand ModelAlignerCommand() {
  return MakeSubcommand<ModelAlignerOptions>(
      "model_aligner",
      "align a model to navigation or reference positions (similarity)",
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
      AddModelAlignerFlags, RunModelAligner);
}

Subcommand ModelComparerCommand() {
  return MakeSubcommand<ModelComparerOptions>(
      "model_comparer",
      "measure a model against another model or uwsim's truth",
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
      AddModelComparerFlags, RunModelComparer);
}

}  // namespace uw
