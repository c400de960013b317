#include "laserscale/exe/apply_command.h"

#include <filesystem>

#include <fmt/format.h>

#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"
#include "common/util/error.h"
#include "laserscale/scale_report.h"

namespace uw {
namespace {

void AddApplyFlags(CommandLine* cli, ApplyOptions* options) {
  cli->Add("--input_path", &options->input_path, "COLMAP model")->required();
  cli->Add("--scale", &options->scale_path, "scale.json of laserscale estimate")
      ->required();
  cli->Add("--output_path", &options->output_path,
           "Folder for the scaled model (created; must not be the input)")
      ->required();
  cli->Add("--output_type", &options->output_type, "BIN or TXT");
  cli->Add("--input_mesh", &options->input_mesh,
           "The model's mesh (PLY or OBJ, model frame) to scale too");
  cli->Add("--output_mesh", &options->output_mesh,
           "PLY for the scaled mesh (with --input_mesh)");
}

void RunApply(const ApplyOptions& options) {
  const ScaleJson scale_json = ReadScaleFromJson(options.scale_path);
  const double scale = scale_json.scale;
  if (scale_json.navigation && !scale_json.navigation->consistent) {
    fmt::print(stderr,
               "[apply] WARNING: the laser scale {:.5f} and the navigation's "
               "own scale of this fused model disagree by {:.1f} sigma "
               "(|z| > 3): one of them is wrong (laser calibration, spots, "
               "navigation). Check before publishing anything measured in "
               "the scaled model.\n",
               scale, scale_json.navigation->z);
  }
  if (scale_json.num_model_draws == 0) {
    fmt::print(stderr,
               "[apply] warning: {} took the model as exact (no "
               "--covariance): its interval leaves out the model's own "
               "error.\n",
               options.scale_path.c_str());
  }
  Reconstruction model = ReadModel(options.input_path);
  Sim3d scaled_from_model;
  scaled_from_model.scale = scale;
  TransformReconstruction(scaled_from_model, &model);
  std::filesystem::create_directories(options.output_path);
  WriteModel(
      model, options.output_path,
      options.output_type == "BIN" ? ModelFormat::kBinary : ModelFormat::kText);
  fmt::print("[apply] model scaled by {:.6f} into {}\n", scale,
             options.output_path.c_str());
  if (!options.input_mesh.empty()) {
    TriangleMesh mesh = ReadMesh(options.input_mesh);
    for (Eigen::Vector3d& vertex : mesh.vertices) {
      vertex = scaled_from_model * vertex;
    }
    WritePly(mesh, options.output_mesh,
             fmt::format("laserscale apply: {} scaled by s = {:.6f}, the "
                         "laser scale's metres, in its model's frame",
                         options.input_mesh, scale));
    fmt::print("[apply] mesh scaled by {:.6f} into {}\n", scale,
               options.output_mesh.c_str());
  }
}

}  // namespace

void ApplyOptions::Check() const {
  if (output_type != "BIN" && output_type != "TXT") {
    throw ErrorAt("--output_type must be BIN or TXT, got ", output_type);
  }
  if (std::filesystem::exists(output_path) &&
      std::filesystem::equivalent(input_path, output_path)) {
    throw ErrorAt("--output_path is the input model; choose another folder");
  }
  if (input_mesh.empty() != output_mesh.empty()) {
    throw Error("--input_mesh and --output_mesh go together");
  }
  if (!input_mesh.empty() && std::filesystem::exists(output_mesh) &&
      std::filesystem::equivalent(input_mesh, output_mesh)) {
    throw ErrorAt("--output_mesh is the input mesh; choose another file");
  }
}

Subcommand ApplyCommand() {
  return MakeSubcommand<ApplyOptions>(
      "apply", "scale a COLMAP model to metres",
      "Scales a COLMAP model to metres by the scale s of `laserscale "
      "estimate` (about the world origin: points and camera centres times s, "
      "orientations unchanged), and optionally its mesh (vertices times s). "
      "The inputs are never modified.\n\n"
      "Example:\n"
      "  laserscale apply --input_path sparse/0 --scale report/scale.json "
      "--output_path sparse_metric --input_mesh mesh.ply --output_mesh "
      "mesh_metric.ply",
      AddApplyFlags, RunApply);
}

}  // namespace uw
