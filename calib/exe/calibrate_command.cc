#include <fnmatch.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "calib/board.h"
#include "calib/calibration_report.h"
#include "calib/corners_vnl.h"
#include "calib/exe/commands.h"
#include "calib/mrcal_calibration.h"
#include "calib/projection_uncertainty.h"
#include "common/cli/command.h"
#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

// The frame of an image of a rig: the last run of digits in its name
// (left01.jpg and right01.jpg are frame 1), as mrcal-calibrate-cameras
// pairs them.
int FrameOfImage(const std::string& image) {
  const std::string stem = std::filesystem::path(image).stem().string();
  const size_t end = stem.find_last_of("0123456789");
  if (end == std::string::npos) {
    throw ErrorAt(image, ": a rig's image names need a frame number");
  }
  size_t begin = end;
  while (begin > 0 &&
         std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) {
    --begin;
  }
  return std::stoi(stem.substr(begin, std::min<size_t>(end - begin + 1, 9)));
}

// The views of each camera: the images matching its glob (the first glob
// that matches wins). One camera: every image, numbered in file order.
std::vector<RigCameraViews> SplitByCamera(
    const std::vector<BoardObservation>& observations,
    const std::vector<std::string>& globs, const std::string& where) {
  std::vector<RigCameraViews> cameras(globs.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    const BoardObservation& observation = observations[i];
    size_t c = 0;
    while (c < globs.size() &&
           fnmatch(globs[c].c_str(), observation.image.c_str(), 0) != 0) {
      ++c;
    }
    if (c == globs.size()) continue;  // not one of the cameras
    cameras[c].views.push_back(observation);
    cameras[c].frames.push_back(globs.size() == 1
                                    ? static_cast<int>(i)
                                    : FrameOfImage(observation.image));
  }
  for (size_t c = 0; c < globs.size(); ++c) {
    if (cameras[c].views.empty()) {
      throw ErrorAt(where, ": no image matches camera ", c, "'s glob '",
                    globs[c], "'");
    }
  }
  return cameras;
}

}  // namespace

int RunCalibrate(int argc, char** argv) {
  CLI::App app(
      "Calibrates a camera, or a synchronised rig (--cameras), from "
      "corners.vnl with mrcal's C library: the "
      "solve mrcal-calibrate-cameras runs (stereographic seed, geometry, "
      "core, then the lens model with regularization and outlier rejection, "
      "then the board's warp). Writes camera-N.cameramodel (mrcal's format; "
      "a rig's extrinsics are camera N from camera 0), calibration.json "
      "(RMS, outliers, residuals per image, projection uncertainty), "
      "residual plots and the projection-uncertainty map (mrcal's: the "
      "worst-direction 1-sigma of projecting a point at "
      "--uncertainty_distance through the solve's uncertain parameters) "
      "into --out (docs/uwcalib.md).\n\n"
      "Example:\n"
      "  uwcalib calibrate --board chessboard:9x6:0.025 --corners "
      "corners.vnl --lens_model LENSMODEL_OPENCV8 --focal 850 --imagersize "
      "1024,768 --out cal\n"
      "  uwcalib calibrate --board chessboard:9x6:0.025 --corners "
      "corners.vnl --cameras 'left*.jpg,right*.jpg' --lens_model "
      "LENSMODEL_OPENCV5 --focal 530 --imagersize 640,480 --out stereo",
      "uwcalib calibrate");
  std::string board_spec;
  std::string corners_path;
  std::string out;
  std::string imagersize;
  MrcalCalibrationOptions options;
  ProjectionUncertaintyOptions uncertainty;
  std::vector<std::string> camera_globs = {"*"};
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
  app.add_option("--cameras", camera_globs,
                 "A glob of image names per camera of a synchronised rig, "
                 "e.g. 'left*.jpg,right*.jpg'; the last number in a name is "
                 "its frame (the instant)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_flag("--skip_regularization", skip_regularization,
               "As mrcal-calibrate-cameras --skip-regularization");
  app.add_flag("--skip_outlier_rejection", skip_outlier_rejection,
               "As mrcal-calibrate-cameras --skip-outlier-rejection");
  app.add_flag("--skip_calobject_warp_solve", skip_calobject_warp,
               "As mrcal-calibrate-cameras --skip-calobject-warp-solve");
  app.add_option("--uncertainty_distance", uncertainty.distance,
                 "Distance of the points whose projection uncertainty is "
                 "mapped, in the board's units (metres); 0 is infinity, as "
                 "mrcal-show-projection-uncertainty's default")
      ->capture_default_str();
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
    uncertainty.Check();
    const CornersVnl corners = ReadCornersVnl(corners_path, board.NumCorners());
    const std::vector<RigCameraViews> cameras =
        SplitByCamera(corners.observations, camera_globs, corners_path);
    const MrcalRigCalibration result =
        CalibrateRigWithMrcal(cameras, board, options);

    std::ostringstream command;
    command << "uwcalib calibrate --board " << board.ToString()
            << " --lens_model " << options.lens_model;
    const std::filesystem::path dir(out);
    WriteCalibrationReport(result, camera_globs, command.str(), uncertainty,
                           dir);
    for (size_t c = 0; c < result.cameras.size(); ++c) {
      std::printf(
          "[calibrate] camera %zu: %zu views, %d outliers of %d "
          "corners%s\n",
          c, result.cameras[c].images.size(), result.cameras[c].num_outliers,
          result.cameras[c].num_corners_observed,
          c == 0 ? ""
                 : (", baseline " +
                    std::to_string(result.cam_from_rig[c].translation.norm()) +
                    " m")
                       .c_str());
    }
    for (size_t c = 0; c < result.cameras.size(); ++c) {
      const MrcalCalibration& camera = result.cameras[c];
      const double centre = ProjectionUncertaintyAtPixel(
          camera,
          {(camera.image_width - 1) / 2.0, (camera.image_height - 1) / 2.0},
          uncertainty.distance);
      if (uncertainty.distance > 0.0) {
        std::printf(
            "[calibrate] camera %zu: projection uncertainty at the centre "
            "%.3f px (1-sigma, worst direction), %g m out\n",
            c, centre, uncertainty.distance);
      } else {
        std::printf(
            "[calibrate] camera %zu: projection uncertainty at the centre "
            "%.3f px (1-sigma, worst direction), at infinity\n",
            c, centre);
      }
    }
    std::printf("[calibrate] RMS %.3f px; %s\n", result.rms_px,
                (dir / "camera-0.cameramodel").c_str());
  });
}

}  // namespace uw
