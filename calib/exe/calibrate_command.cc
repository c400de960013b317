#include "calib/exe/calibrate_command.h"

#include <filesystem>

#include <fmt/format.h>

#include "calib/calibration_report.h"
#include "calib/corners_vnl.h"
#include "calib/exe/board_flag.h"
#include "calib/rig_views.h"

namespace uw {
namespace {

void AddCalibrateFlags(CommandLine* cli, CalibrateOptions* options) {
  AddBoardFlag(cli, &options->board,
               "chessboard:COLSxROWS:SQUARE_M of corners.vnl");
  cli->Add("--corners", &options->corners_path,
           "corners.vnl (uwcalib detect, "
           "mrgingham)")
      ->required();
  cli->Add("--lens_model", &options->calibration.lens_model,
           "mrcal lens model");
  // Required: no default to show.
  cli->Add("--focal", &options->calibration.focal_px,
           "Seed focal length, pixels")
      ->required()
      ->default_str("");
  cli->AddIntegers("--imagersize",
                   {&options->calibration.image_width,
                    &options->calibration.image_height},
                   "WIDTH,HEIGHT", "WIDTH,HEIGHT in pixels")
      ->required()
      ->default_str("");
  cli->Add("--out", &options->out, "Folder for the outputs (created)")
      ->required();
  // CLI11's own list: a comma list or several arguments, as always.
  cli->Add<std::vector<std::string>>(
         "--cameras", &options->camera_globs,
         "A glob of image names per camera of a synchronised rig, "
         "e.g. 'left*.jpg,right*.jpg'; the last number in a name is "
         "its frame (the instant)")
      ->delimiter(',');
  cli->AddSwitch("--skip_regularization", &options->calibration.regularization,
                 false, "As mrcal-calibrate-cameras --skip-regularization");
  cli->AddSwitch("--skip_outlier_rejection",
                 &options->calibration.outlier_rejection, false,
                 "As mrcal-calibrate-cameras --skip-outlier-rejection");
  cli->AddSwitch("--skip_calobject_warp_solve",
                 &options->calibration.calobject_warp, false,
                 "As mrcal-calibrate-cameras --skip-calobject-warp-solve");
  cli->Add("--uncertainty_distance", &options->uncertainty.distance,
           "Distance of the points whose projection uncertainty is "
           "mapped, in the board's units (metres); 0 is infinity, as "
           "mrcal-show-projection-uncertainty's default");
}

void RunCalibrate(const CalibrateOptions& options) {
  const CornersVnl corners =
      ReadCornersVnl(options.corners_path, options.board.NumCorners());
  const std::vector<RigCameraViews> cameras = SplitViewsByCamera(
      corners.observations, options.camera_globs, options.corners_path);
  const MrcalRigCalibration result =
      CalibrateRigWithMrcal(cameras, options.board, options.calibration);
  const std::string command = "uwcalib calibrate --board " +
                              options.board.ToString() + " --lens_model " +
                              options.calibration.lens_model;
  const std::filesystem::path dir(options.out);
  WriteCalibrationReport(result, options.camera_globs, command,
                         options.uncertainty, dir);
  for (const std::string& line :
       DescribeRigCalibration(result, options.uncertainty)) {
    fmt::print("[calibrate] {}\n", line.c_str());
  }
  fmt::print("[calibrate] RMS {:.3f} px; {}\n", result.rms_px,
             (dir / "camera-0.cameramodel").c_str());
}

}  // namespace

Subcommand CalibrateCommand() {
  return MakeSubcommand<CalibrateOptions>(
      "calibrate",
      "calibrate a camera from corners.vnl with mrcal (.cameramodel)",
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
      AddCalibrateFlags, RunCalibrate);
}

}  // namespace uw
