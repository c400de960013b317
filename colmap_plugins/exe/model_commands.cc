#include "colmap_plugins/exe/model_commands.h"

#include <algorithm>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "colmap_plugins/scene/model_stats.h"
#include "common/util/error.h"

namespace uw {
namespace {

void AddModelConverterFlags(CommandLine* cli, ModelConverterOptions* options) {
  cli->Add("--input_path", &options->input_path, "Model folder to read")
      ->required();
  cli->Add("--output_path", &options->output_path,
           "Folder to write (created if missing)")
      ->required();
  cli->Add("--output_type", &options->output_type, "BIN or TXT")->required();
  cli->Add("--skip_distortion", &options->skip_distortion,
           "Accepted for COLMAP compatibility; only used by export formats "
           "uwcolmap does not write");
}

void RunModelConverter(const ModelConverterOptions& options) {
  WriteModel(ReadModel(options.input_path), options.output_path,
             options.OutputFormat());
}

void AddModelAnalyzerFlags(CommandLine* cli, ModelAnalyzerOptions* options) {
  cli->Add("--path", &options->path, "Model folder (.bin or .txt)")->required();
}

void RunModelAnalyzer(const ModelAnalyzerOptions& options) {
  const ModelFiles files = DetectModelFiles(options.path);
  const Reconstruction reconstruction =
      files.format == ModelFormat::kBinary
          ? ReadModelBinary(options.path, files.layout)
          : ReadModelText(options.path, files.layout);
  std::cout << FormatModelAnalyzerReport(ComputeModelStats(reconstruction));
  const ReprojectionErrors errors = RecomputeReprojectionErrors(reconstruction);
  fmt::print(
      "Layout: {}, {} files\n"
      "Recomputed mean reprojection error: {:f}px (per observation {:f}px, "
      "max |recomputed - stored| per point {:.3g}px, {} of {} "
      "observations behind the camera)\n",
      ModelLayoutName(files.layout),
      files.format == ModelFormat::kBinary ? "binary" : "text",
      errors.mean_point_error, errors.mean_observation_error,
      errors.max_stored_error_difference, errors.num_behind_camera,
      errors.num_observations);
}

}  // namespace

ModelFormat ModelConverterOptions::OutputFormat() const {
  std::string type = output_type;
  std::transform(type.begin(), type.end(), type.begin(), ::tolower);
  if (type == "bin") return ModelFormat::kBinary;
  if (type == "txt") return ModelFormat::kText;
  throw ErrorAt("--output_type ", output_type,
                ": uwcolmap writes BIN or TXT; use `colmap "
                "model_converter` for NVM, Bundler, VRML, PLY, R3D, CAM");
}

void ModelConverterOptions::Check() const {
  OutputFormat();
  // Converting in place would rewrite the input (COLMAP-normalised
  // quaternions, other format's files left behind); never touch inputs.
  std::error_code ignored;
  if (std::filesystem::equivalent(input_path, output_path, ignored)) {
    throw ErrorAt("--output_path ", output_path,
                  " is the input folder; write to another folder");
  }
}

Subcommand ModelConverterCommand() {
  return MakeSubcommand<ModelConverterOptions>(
      "model_converter",
      "convert a model between BIN and TXT, keeping record order",
      "Converts a COLMAP sparse model between .bin and .txt (both COLMAP "
      "3.x and 4.x layouts; the layout read is the layout written).\n"
      "Records keep their order, so BIN -> BIN is byte-identical.\n\n"
      "Example:\n"
      "  uwcolmap model_converter --input_path sparse/0 "
      "--output_path sparse_txt --output_type TXT",
      AddModelConverterFlags, RunModelConverter);
}

Subcommand ModelAnalyzerCommand() {
  return MakeSubcommand<ModelAnalyzerOptions>(
      "model_analyzer",
      "print statistics of a model (as colmap model_analyzer)",
      "Prints what `colmap model_analyzer` prints about a model (same lines, "
      "same format), then the reprojection error recomputed from poses, "
      "cameras and points with uwmetric's camera models.\n\n"
      "Example:\n"
      "  uwcolmap model_analyzer --path sparse/0",
      AddModelAnalyzerFlags, RunModelAnalyzer);
}

}  // namespace uw
