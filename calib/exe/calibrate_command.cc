#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "calib/board.h"
#include "calib/corners_vnl.h"
#include "calib/exe/commands.h"
#include "calib/mrcal_calibration.h"
#include "colmap_plugins/exe/command.h"
#include "colmap_plugins/util/error.h"
#include "colmap_plugins/util/file.h"

namespace uw {

int RunCalibrate(int argc, char** argv) {
  CLI::App app(
      "Calibrates one camera from corners.vnl with mrcal's C library: the "
      "solve mrcal-calibrate-cameras runs (stereographic seed, geometry, "
      "core, then the lens model with regularization and outlier rejection, "
      "then the board's warp). Writes camera-0.cameramodel (mrcal's format) "
      "and calibration.json (RMS, outliers, residuals per image) into --out "
      "(docs/uwcalib.md).\n\n"
      "Example:\n"
      "  uwcalib calibrate --board chessboard:9x6:0.025 --corners "
      "corners.vnl --lens_model LENSMODEL_OPENCV8 --focal 850 --imagersize "
      "1024,768 --out cal",
      "uwcalib calibrate");
  std::string board_spec;
  std::string corners_path;
  std::string out;
  std::string imagersize;
  MrcalCalibrationOptions options;
  bool skip_regularization = false;
  bool skip_outlier_rejection = false;
  bool skip_calobject_warp = false;
  app.add_option("--board", board_spec,
                 "chessboard:COLSxROWS:SQUARE_M of corners.vnl")
      ->required();
  app.add_option("--corners", corners_path,
                 "corners.vnl (uwcalib detect, "
                 "mrgingham)")
      ->required();
  app.add_option("--lens_model", options.lens_model, "mrcal lens model")
      ->capture_default_str();
  app.add_option("--focal", options.focal_px, "Seed focal length, pixels")
      ->required();
  app.add_option("--imagersize", imagersize, "WIDTH,HEIGHT in pixels")
      ->required();
  app.add_option("--out", out, "Folder for the outputs (created)")->required();
  app.add_flag("--skip_regularization", skip_regularization,
               "As mrcal-calibrate-cameras --skip-regularization");
  app.add_flag("--skip_outlier_rejection", skip_outlier_rejection,
               "As mrcal-calibrate-cameras --skip-outlier-rejection");
  app.add_flag("--skip_calobject_warp_solve", skip_calobject_warp,
               "As mrcal-calibrate-cameras --skip-calobject-warp-solve");
  return RunCommand(app, argc, argv, [&] {
    const CalibrationBoard board = ParseBoard(board_spec);
    const size_t comma = imagersize.find(',');
    try {
      if (comma == std::string::npos) throw 0;
      size_t used = 0;
      options.image_width = std::stoi(imagersize.substr(0, comma), &used);
      if (used != comma) throw 0;
      options.image_height = std::stoi(imagersize.substr(comma + 1), &used);
      if (used != imagersize.size() - comma - 1) throw 0;
    } catch (...) {
      throw ErrorAt("--imagersize must be WIDTH,HEIGHT, got '", imagersize,
                    "'");
    }
    options.regularization = !skip_regularization;
    options.outlier_rejection = !skip_outlier_rejection;
    options.calobject_warp = !skip_calobject_warp;
    options.Check();
    const CornersVnl corners = ReadCornersVnl(corners_path, board.NumCorners());
    const MrcalCalibration result =
        CalibrateWithMrcal(corners.observations, board, options);

    nlohmann::json images = nlohmann::json::array();
    for (size_t v = 0; v < result.images.size(); ++v) {
      double sum_squares = 0.0;
      int inliers = 0;
      int outliers = 0;
      for (size_t k = 0; k < result.residuals_px[v].size(); ++k) {
        if (result.outliers[v][k]) {
          ++outliers;
        } else {
          sum_squares += result.residuals_px[v][k].squaredNorm();
          ++inliers;
        }
      }
      images.push_back(
          {{"image", result.images[v]},
           {"rms_px", std::sqrt(sum_squares / std::max(inliers, 1))},
           {"outliers", outliers}});
    }
    const nlohmann::json report = {
        {"lens_model", result.lens_model},
        {"intrinsics", result.intrinsics},
        {"imagersize", {result.image_width, result.image_height}},
        {"pixel_convention",
         "mrcal/OpenCV: (0, 0) is the centre of the top-left pixel"},
        {"rms_px", result.rms_px},
        {"rms_px_meaning",
         "mrcal's: sqrt of the mean square measurement (per coordinate)"},
        {"corners_observed", result.num_corners_observed},
        {"outliers", result.num_outliers},
        {"calobject_warp_m",
         {result.calobject_warp.x(), result.calobject_warp.y()}},
        {"images", images}};
    std::ostringstream command;
    command << "uwcalib calibrate --board " << board.ToString()
            << " --lens_model " << options.lens_model;
    const std::filesystem::path dir(out);
    WriteFilesAtomically(
        {{dir / "camera-0.cameramodel",
          [&](std::ostream& stream) {
            stream << FormatCameraModel(
                result.lens_model, result.intrinsics, result.image_width,
                result.image_height,
                {"generated with " + command.str(),
                 "RMS reprojection error: " + std::to_string(result.rms_px) +
                     " pixels",
                 "Noutliers: " + std::to_string(result.num_outliers) +
                     " out of " + std::to_string(result.num_corners_observed)});
          }},
         {dir / "calibration.json",
          [&](std::ostream& stream) { stream << report.dump(1) << "\n"; }}},
        false);
    std::printf(
        "[calibrate] %zu views, RMS %.3f px, %d outliers of %d "
        "corners: %s\n",
        result.images.size(), result.rms_px, result.num_outliers,
        result.num_corners_observed, (dir / "camera-0.cameramodel").c_str());
  });
}

}  // namespace uw
