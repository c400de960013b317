#include "calib/exe/export_command.h"

#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "calib/camera_export.h"
#include "calib/mrcal_calibration.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

void AddCalibExportFlags(CommandLine* cli, CalibExportOptions* options) {
  cli->Add("--cameramodel", &options->cameramodel_path, "mrcal .cameramodel")
      ->required();
  cli->Add("--to", &options->to, "colmap or opencv-yaml")->required();
  cli->Add("--output_path", &options->output_path,
           "colmap: folder for a COLMAP model holding the camera "
           "(created; no images, no points)");
  cli->Add("--output_type", &options->output_type, "colmap: BIN or TXT");
  cli->Add("--camera_id", &options->camera_id, "colmap: the camera's id");
  cli->Add("--out", &options->out, "opencv-yaml: the file to write");
}

void RunCalibExport(const CalibExportOptions& options) {
  const MrcalCameraModel model = ReadCameraModel(options.cameramodel_path);
  if (options.to == "opencv-yaml") {
    const std::string yaml =
        OpenCvYamlFromMrcal(model, options.cameramodel_path);
    WriteFilesAtomically(
        {{options.out, [&](std::ostream& stream) { stream << yaml; }}}, false);
    fmt::print("[export] {}\n", options.out.c_str());
    return;
  }
  Camera camera = ColmapCameraFromMrcal(model, options.cameramodel_path);
  camera.camera_id = options.camera_id;
  std::string line =
      fmt::format("{} {} {} {}", camera.camera_id, camera.ModelName(),
                  camera.width, camera.height);
  for (const double param : camera.params) {
    line += fmt::format(" {:.17g}", param);
  }
  fmt::print("{}\n", line.c_str());
  if (options.output_path.empty()) return;
  Reconstruction reconstruction;
  reconstruction.AddCamera(camera);
  std::filesystem::create_directories(options.output_path);
  WriteModel(
      reconstruction, options.output_path,
      options.output_type == "BIN" ? ModelFormat::kBinary : ModelFormat::kText);
  fmt::print(stderr, "[export] COLMAP model with camera {} in {}\n",
             camera.camera_id, options.output_path.c_str());
}

}  // namespace

void CalibExportOptions::Check() const {
  if (to == "colmap") {
    if (output_type != "BIN" && output_type != "TXT") {
      throw ErrorAt("--output_type must be BIN or TXT, got ", output_type);
    }
  } else if (to == "opencv-yaml") {
    if (out.empty()) throw Error("--to opencv-yaml needs --out FILE");
  } else {
    throw ErrorAt("--to must be colmap or opencv-yaml, got '", to, "'");
  }
}

Subcommand CalibExportCommand() {
  return MakeSubcommand<CalibExportOptions>(
      "export", "a .cameramodel as a COLMAP camera or OpenCV YAML",
      "Exports a .cameramodel (uwcalib calibrate, mrcal-calibrate-cameras) "
      "to COLMAP or OpenCV, projecting exactly as the model does: "
      "LENSMODEL_OPENCV4 -> OPENCV, OPENCV5/OPENCV8 -> FULL_OPENCV, "
      "PINHOLE -> PINHOLE (COLMAP's cx, cy are mrcal's + 0.5). Models "
      "without an equivalent are refused (docs/uwcalib.md).\n\n"
      "Examples:\n"
      "  uwcalib export --cameramodel cal/camera-0.cameramodel --to colmap "
      "--output_path sparse_camera\n"
      "  uwcalib export --cameramodel cal/camera-0.cameramodel --to "
      "opencv-yaml --out camera.yaml",
      AddCalibExportFlags, RunCalibExport);
}

}  // namespace uw
