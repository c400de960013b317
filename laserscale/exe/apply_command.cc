#include <cstdio>

#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/exe/command.h"
#include "colmap_plugins/scene/model_io.h"
#include "colmap_plugins/util/error.h"
#include "laserscale/exe/commands.h"
#include "laserscale/scale_report.h"

namespace uw {

int RunApply(int argc, char** argv) {
  CLI::App app(
      "Scales a COLMAP model to metres by the scale s of `laserscale "
      "estimate` (about the world origin: points and camera centres times s, "
      "orientations unchanged). The input is never modified.\n\n"
      "Example:\n"
      "  laserscale apply --input_path sparse/0 --scale report/scale.json "
      "--output_path sparse_metric",
      "laserscale apply");
  std::string input_path;
  std::string scale_path;
  std::string output_path;
  std::string output_type = "BIN";
  app.add_option("--input_path", input_path, "COLMAP model")->required();
  app.add_option("--scale", scale_path, "scale.json of laserscale estimate")
      ->required();
  app.add_option("--output_path", output_path,
                 "Folder for the scaled model (created; must not be the input)")
      ->required();
  app.add_option("--output_type", output_type, "BIN or TXT")
      ->capture_default_str();
  return RunCommand(app, argc, argv, [&] {
    if (output_type != "BIN" && output_type != "TXT") {
      throw ErrorAt("--output_type must be BIN or TXT, got ", output_type);
    }
    if (std::filesystem::exists(output_path) &&
        std::filesystem::equivalent(input_path, output_path)) {
      throw ErrorAt("--output_path is the input model; choose another folder");
    }
    const double scale = ReadScaleFromJson(scale_path);
    Reconstruction model = ReadModel(input_path);
    Sim3d scaled_from_model;
    scaled_from_model.scale = scale;
    TransformReconstruction(scaled_from_model, &model);
    std::filesystem::create_directories(output_path);
    WriteModel(
        model, output_path,
        output_type == "BIN" ? ModelFormat::kBinary : ModelFormat::kText);
    std::printf("[apply] model scaled by %.6f into %s\n", scale,
                output_path.c_str());
  });
}

}  // namespace uw
