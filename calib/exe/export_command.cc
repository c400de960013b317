#include <cstdio>
#include <filesystem>
#include <sstream>

#include "calib/camera_export.h"
#include "calib/exe/commands.h"
#include "calib/mrcal_calibration.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"
#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {

int RunCalibExport(int argc, char** argv) {
  CLI::App app(
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
      "uwcalib export");
  std::string model_path;
  std::string to;
  std::string output_path;
  std::string output_type = "TXT";
  std::string out;
  uint32_t camera_id = 1;
  app.add_option("--cameramodel", model_path, "mrcal .cameramodel")->required();
  app.add_option("--to", to, "colmap or opencv-yaml")->required();
  app.add_option("--output_path", output_path,
                 "colmap: folder for a COLMAP model holding the camera "
                 "(created; no images, no points)");
  app.add_option("--output_type", output_type, "colmap: BIN or TXT")
      ->capture_default_str();
  app.add_option("--camera_id", camera_id, "colmap: the camera's id")
      ->capture_default_str();
  app.add_option("--out", out, "opencv-yaml: the file to write");
  return RunCommand(app, argc, argv, [&] {
    const MrcalCameraModel model = ReadCameraModel(model_path);
    if (to == "colmap") {
      if (output_type != "BIN" && output_type != "TXT") {
        throw ErrorAt("--output_type must be BIN or TXT, got ", output_type);
      }
      Camera camera = ColmapCameraFromMrcal(model, model_path);
      camera.camera_id = camera_id;
      std::ostringstream line;
      line.precision(17);
      line << camera.camera_id << " " << camera.ModelName() << " "
           << camera.width << " " << camera.height;
      for (const double param : camera.params) line << " " << param;
      std::printf("%s\n", line.str().c_str());
      if (!output_path.empty()) {
        Reconstruction reconstruction;
        reconstruction.AddCamera(camera);
        std::filesystem::create_directories(output_path);
        WriteModel(
            reconstruction, output_path,
            output_type == "BIN" ? ModelFormat::kBinary : ModelFormat::kText);
        std::fprintf(stderr, "[export] COLMAP model with camera %u in %s\n",
                     camera.camera_id, output_path.c_str());
      }
    } else if (to == "opencv-yaml") {
      if (out.empty()) throw Error("--to opencv-yaml needs --out FILE");
      const std::string yaml = OpenCvYamlFromMrcal(model, model_path);
      WriteFilesAtomically(
          {{out, [&](std::ostream& stream) { stream << yaml; }}}, false);
      std::printf("[export] %s\n", out.c_str());
    } else {
      throw ErrorAt("--to must be colmap or opencv-yaml, got '", to, "'");
    }
  });
}

}  // namespace uw
