#include "colmap_plugins/exe/model_commands.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "colmap_plugins/exe/command.h"
#include "colmap_plugins/scene/model_io.h"
#include "colmap_plugins/scene/model_stats.h"
#include "colmap_plugins/util/error.h"

namespace uw {

int RunModelConverter(int argc, char** argv) {
  CLI::App app(
      "Converts a COLMAP sparse model between .bin and .txt (both COLMAP "
      "3.x and 4.x layouts; the layout read is the layout written).\n"
      "Records keep their order, so BIN -> BIN is byte-identical.\n\n"
      "Example:\n"
      "  uwcolmap model_converter --input_path sparse/0 "
      "--output_path sparse_txt --output_type TXT",
      "uwcolmap model_converter");
  std::string input_path;
  std::string output_path;
  std::string output_type;
  std::string skip_distortion = "0";
  app.add_option("--input_path", input_path, "Model folder to read")
      ->required();
  app.add_option("--output_path", output_path,
                 "Folder to write (created if missing)")
      ->required();
  app.add_option("--output_type", output_type, "BIN or TXT")->required();
  app.add_option("--skip_distortion", skip_distortion,
                 "Accepted for COLMAP compatibility; only used by export "
                 "formats uwcolmap does not write")
      ->default_val("0");
  return RunCommand(app, argc, argv, [&] {
    ParseColmapBool(skip_distortion, "skip_distortion");
    std::string type = output_type;
    std::transform(type.begin(), type.end(), type.begin(), ::tolower);
    ModelFormat format;
    if (type == "bin") {
      format = ModelFormat::kBinary;
    } else if (type == "txt") {
      format = ModelFormat::kText;
    } else {
      throw ErrorAt("--output_type ", output_type,
                    ": uwcolmap writes BIN or TXT; use `colmap "
                    "model_converter` for NVM, Bundler, VRML, PLY, R3D, CAM");
    }
    // Converting in place would rewrite the input (COLMAP-normalised
    // quaternions, other format's files left behind); never touch inputs.
    std::error_code ignored;
    if (std::filesystem::equivalent(input_path, output_path, ignored)) {
      throw ErrorAt("--output_path ", output_path,
                    " is the input folder; write to another folder");
    }
    const Reconstruction reconstruction = ReadModel(input_path);
    WriteModel(reconstruction, output_path, format);
  });
}

int RunModelAnalyzer(int argc, char** argv) {
  CLI::App app(
      "Prints what `colmap model_analyzer` prints about a model (same lines, "
      "same format), then the reprojection error recomputed from poses, "
      "cameras and points with uwmetric's camera models.\n\n"
      "Example:\n"
      "  uwcolmap model_analyzer --path sparse/0",
      "uwcolmap model_analyzer");
  std::string path;
  app.add_option("--path", path, "Model folder (.bin or .txt)")->required();
  return RunCommand(app, argc, argv, [&] {
    const ModelFiles files = DetectModelFiles(path);
    const Reconstruction reconstruction =
        files.format == ModelFormat::kBinary
            ? ReadModelBinary(path, files.layout)
            : ReadModelText(path, files.layout);
    std::cout << FormatModelAnalyzerReport(ComputeModelStats(reconstruction));
    const ReprojectionErrors errors =
        RecomputeReprojectionErrors(reconstruction);
    std::printf(
        "Layout: %s, %s files\n"
        "Recomputed mean reprojection error: %fpx (per observation %fpx, "
        "max |recomputed - stored| per point %.3gpx, %zu of %zu "
        "observations behind the camera)\n",
        ModelLayoutName(files.layout).c_str(),
        files.format == ModelFormat::kBinary ? "binary" : "text",
        errors.mean_point_error, errors.mean_observation_error,
        errors.max_stored_error_difference, errors.num_behind_camera,
        errors.num_observations);
  });
}

}  // namespace uw
