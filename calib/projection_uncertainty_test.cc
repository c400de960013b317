#include "calib/projection_uncertainty.h"
#include "calib/calibration_testing.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>

#include "calib/chessboard_detector.h"
#include "calib/corners_vnl.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/random.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;
using testing_calibration::Options;
using testing_calibration::TrueCamera;

// OpenCV's real stereo sample, both sides, detected once per process: frame
// n is the image's number.
const std::vector<RigCameraViews>& RealStereoViews() {
  static const std::vector<RigCameraViews> cameras = [] {
    const fs::path dir =
        fs::path(UW_REALDATA_DIR) / "opencv_chessboard_stereo_640x480";
    const CalibrationBoard board = ParseBoard("chessboard:9x6:1");
    std::vector<RigCameraViews> sides(2);
    for (int side = 0; side < 2; ++side) {
      for (int n = 1; n <= 14; ++n) {
        if (n == 10) continue;
        char name[32];
        std::snprintf(name, sizeof(name), "%s%02d.jpg",
                      side == 0 ? "left" : "right", n);
        const cv::Mat image = cv::imread((dir / name).string());
        if (image.empty()) throw Error(std::string("cannot read ") + name);
        sides[side].views.push_back(DetectChessboard(image, board, name));
        sides[side].frames.push_back(n);
      }
    }
    return sides;
  }();
  return cameras;
}

// The pixels compared with mrcal: the image's corners, edges' middles and
// centre, and two between.
std::vector<Eigen::Vector2d> ComparedPixels(int width, int height) {
  std::vector<Eigen::Vector2d> pixels;
  for (const double y : {0.0, (height - 1) / 2.0, height - 1.0}) {
    for (const double x : {0.0, (width - 1) / 2.0, width - 1.0}) {
      pixels.emplace_back(x, y);
    }
  }
  pixels.emplace_back(0.16 * width, 0.83 * height);
  pixels.emplace_back(0.78 * width, 0.21 * height);
  return pixels;
}

// Runs Debian's mrcal-calibrate-cameras on the cameras' views (one
// corners.vnl, a glob a camera), then mrcal.projection_uncertainty() on
// camera `camera`'s model (it keeps the solve's optimization_inputs) at
// `pixels`, `distance` away (0: at infinity), worst direction: one value a
// pixel. Also mrcal's σ of the corners' noise.
std::vector<double> MrcalsUncertainty(
    const std::vector<RigCameraViews>& cameras, const CalibrationBoard& board,
    const MrcalCalibrationOptions& options,
    const std::vector<std::string>& globs, int camera,
    const std::vector<Eigen::Vector2d>& pixels, double distance,
    double* observed_pixel_sigma) {
  const fs::path dir = FreshTestDir("uw_projection_uncertainty_test");
  std::ostringstream pixel_list;
  for (const Eigen::Vector2d& pixel : pixels) {
    pixel_list << pixel.x() << " " << pixel.y() << "\n";
  }
  // The distance ≤ 0 asks for infinity, as the tool's default.
  const std::string script =
      "import sys, numpy as np, mrcal\n"
      "m = mrcal.cameramodel(sys.argv[1])\n"
      "q = np.loadtxt(sys.argv[2], ndmin=2)\n"
      "d = float(sys.argv[3])\n"
      "v = mrcal.unproject(q, *m.intrinsics(), normalize=True)\n"
      "u = mrcal.projection_uncertainty(v * (d if d > 0 else 1.0), m,\n"
      "    atinfinity=d <= 0, what='worstdirection-stdev')\n"
      "o = m.optimization_inputs()\n"
      "print('sigma %.17g' % np.std(mrcal.residuals_chessboard(o).ravel()))\n"
      "for x in np.atleast_1d(u): print('%.17g' % x)\n";
  WriteFilesAtomically(
      {{dir / "pixels.txt",
        [&](std::ostream& out) { out << pixel_list.str(); }},
       {dir / "uncertainty.py", [&](std::ostream& out) { out << script; }}},
      false);
  testing_calibration::RunMrcalCalibrateCameras(cameras, board, options, globs,
                                                dir);
  const ProcessResult python = RunProcess(
      "cd " + Quoted(dir) + " && /usr/bin/python3 uncertainty.py camera-" +
          std::to_string(camera) + ".cameramodel pixels.txt " +
          std::to_string(distance),
      false);
  if (python.exit_code != 0) throw Error("mrcal's Python: " + python.output);
  std::istringstream lines(python.output);
  std::string word;
  lines >> word >> *observed_pixel_sigma;
  std::vector<double> values;
  double value = 0.0;
  while (lines >> value) values.push_back(value);
  if (values.size() != pixels.size()) {
    throw Error("mrcal's Python printed " + python.output);
  }
  return values;
}

// Ours against mrcal's Python on the same corners, at infinity and at
// `distance`; returns the worst relative difference.
double CompareWithMrcal(const std::vector<RigCameraViews>& cameras,
                        const std::vector<std::string>& globs, int camera,
                        double distance) {
  const CalibrationBoard board = ParseBoard("chessboard:9x6:1");
  const MrcalCalibrationOptions options =
      Options("LENSMODEL_OPENCV5", 530.0, 640, 480);
  const MrcalRigCalibration ours =
      CalibrateRigWithMrcal(cameras, board, options);
  const std::vector<Eigen::Vector2d> pixels = ComparedPixels(640, 480);
  double worst = 0.0;
  for (const double at : {0.0, distance}) {
    double their_sigma = 0.0;
    const std::vector<double> theirs = MrcalsUncertainty(
        cameras, board, options, globs, camera, pixels, at, &their_sigma);
    std::printf(
        "[ figures ] camera %d of %zu, %s: corners' noise ours %.5f px, "
        "mrcal %.5f px\n",
        camera, cameras.size(),
        at == 0.0 ? "at infinity"
                  : ("at " + std::to_string(at) + " squares").c_str(),
        ours.cameras[camera].covariance.observed_pixel_sigma, their_sigma);
    EXPECT_NEAR(ours.cameras[camera].covariance.observed_pixel_sigma,
                their_sigma, 0.01 * their_sigma);
    for (size_t k = 0; k < pixels.size(); ++k) {
      const double mine =
          ProjectionUncertaintyAtPixel(ours.cameras[camera], pixels[k], at);
      const double relative = std::abs(mine / theirs[k] - 1.0);
      worst = std::max(worst, relative);
      std::printf(
          "[ figures ]   (%6.1f, %6.1f): ours %.5f px, mrcal %.5f px "
          "(%+.2e)\n",
          pixels[k].x(), pixels[k].y(), mine, theirs[k], mine / theirs[k] - 1);
      EXPECT_LT(relative, 0.05) << "at (" << pixels[k].transpose() << "): ours "
                                << mine << " px, mrcal " << theirs[k] << " px";
    }
  }
  return worst;
}

TEST(ProjectionUncertainty, LikeMrcalsOnTheRealLeftCamera) {
  const double worst =
      CompareWithMrcal({RealStereoViews()[0]}, {"left*.jpg"}, 0, 20.0);
  std::printf("[ figures ] left camera: worst relative difference %.2e\n",
              worst);
}

// Camera 1 of the stereo pair: its pose in the rig is uncertain too.
TEST(ProjectionUncertainty, LikeMrcalsOnTheRealStereoPairsRightCamera) {
  const double worst =
      CompareWithMrcal(RealStereoViews(), {"left*.jpg", "right*.jpg"}, 1, 20.0);
  std::printf("[ figures ] right camera: worst relative difference %.2e\n",
              worst);
}

// Views of a 10x7 board (4 cm) of the known OPENCV camera held near the
// optical axis, 0.6-0.9 m away: it covers the image's middle third and
// never its corners.
std::vector<BoardObservation> CentralViews(const CalibrationBoard& board,
                                           int num_views, double sigma_px,
                                           uint64_t seed) {
  const Camera camera = TrueCamera();
  SplitMix64Stream random(seed);
  const Eigen::Vector3d middle =
      0.5 * Eigen::Vector3d((board.grid_width - 1) * board.spacing_m,
                            (board.grid_height - 1) * board.spacing_m, 0.0);
  std::vector<Rigid3d> poses;
  for (int v = 0; v < num_views; ++v) {
    const Eigen::Vector3d axis(random.Uniform(-1, 1), random.Uniform(-1, 1),
                               0.2 * random.Uniform(-1, 1));
    const double angle = random.Uniform(5.0, 35.0) * M_PI / 180.0;
    Rigid3d cam_from_board;
    cam_from_board.rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
    const Eigen::Vector3d centre(random.Uniform(-0.04, 0.04),
                                 random.Uniform(-0.03, 0.03),
                                 random.Uniform(0.6, 0.9));
    cam_from_board.translation = centre - cam_from_board.rotation * middle;
    poses.push_back(cam_from_board);
  }
  return testing_calibration::ViewsWithNoise(camera, board, poses, sigma_px,
                                             seed + 1000);
}

struct Figures {
  double centre = 0.0;
  double halfway = 0.0;  // halfway from the centre to the top-left corner
  double corner = 0.0;   // the top-left corner
  double sigma = 0.0;
};

Figures Calibrate(const std::vector<BoardObservation>& views,
                  const CalibrationBoard& board) {
  const MrcalCalibration camera = CalibrateWithMrcal(
      views, board, Options("LENSMODEL_OPENCV4", 800.0, 1024, 768));
  Figures figures;
  figures.centre = ProjectionUncertaintyAtPixel(camera, {511.5, 383.5}, 0.0);
  figures.halfway = ProjectionUncertaintyAtPixel(camera, {255.75, 191.75}, 0.0);
  figures.corner = ProjectionUncertaintyAtPixel(camera, {0.0, 0.0}, 0.0);
  figures.sigma = camera.covariance.observed_pixel_sigma;
  return figures;
}

TEST(ProjectionUncertainty,
     GrowsAwayFromTheBoardsShrinksWithViewsScalesWithNoise) {
  const CalibrationBoard board = ParseBoard("chessboard:10x7:0.04");
  const Figures few = Calibrate(CentralViews(board, 15, 0.3, 1), board);
  const Figures many = Calibrate(CentralViews(board, 60, 0.3, 2), board);
  std::printf(
      "[ figures ] boards in the middle, 0.3 px noise, at infinity: 15 "
      "views: centre %.4f, halfway %.4f, corner %.4f px; 60 views: %.4f, "
      "%.4f, %.4f px (ratios %.2f, %.2f, %.2f)\n",
      few.centre, few.halfway, few.corner, many.centre, many.halfway,
      many.corner, few.centre / many.centre, few.halfway / many.halfway,
      few.corner / many.corner);
  // Away from where the boards were, the lens model extrapolates.
  for (const Figures& figures : {few, many}) {
    EXPECT_LT(figures.centre, figures.halfway);
    EXPECT_LT(3.0 * figures.halfway, figures.corner);
  }
  // Four times the views: about half the uncertainty.
  for (const double ratio :
       {few.centre / many.centre, few.halfway / many.halfway,
        few.corner / many.corner}) {
    EXPECT_GT(ratio, 1.4);
    EXPECT_LT(ratio, 3.0);
  }

  // The same views with the same noise twice as large: twice the
  // uncertainty. Only twice σ, to first order: the solution moves with the
  // noise, and with it the covariance per unit noise, most where the lens
  // model extrapolates (at the corner, 2 % for 0.1 -> 0.2 px, 4 % for
  // 0.2 -> 0.4 px; 0.1 % within the boards).
  const Figures quiet = Calibrate(CentralViews(board, 30, 0.1, 3), board);
  const Figures loud = Calibrate(CentralViews(board, 30, 0.2, 3), board);
  std::printf(
      "[ figures ] 30 views, noise 0.1 -> 0.2 px: corners' noise %.4f -> "
      "%.4f px; uncertainty ratios centre %.4f, halfway %.4f, corner %.4f\n",
      quiet.sigma, loud.sigma, loud.centre / quiet.centre,
      loud.halfway / quiet.halfway, loud.corner / quiet.corner);
  EXPECT_NEAR(loud.sigma / quiet.sigma, 2.0, 0.01);
  EXPECT_NEAR(loud.centre / quiet.centre, 2.0, 0.01);
  EXPECT_NEAR(loud.halfway / quiet.halfway, 2.0, 0.01);
  EXPECT_NEAR(loud.corner / quiet.corner, 2.0, 0.1);
}

TEST(ProjectionUncertainty, MapOverTheImageAndBadInput) {
  const CalibrationBoard board = ParseBoard("chessboard:10x7:0.04");
  const MrcalCalibration camera =
      CalibrateWithMrcal(CentralViews(board, 20, 0.3, 7), board,
                         Options("LENSMODEL_OPENCV4", 800.0, 1024, 768));
  ProjectionUncertaintyOptions options;
  options.grid_width = 9;
  options.grid_height = 7;
  options.distance = 0.75;
  const ProjectionUncertaintyMap map =
      MapProjectionUncertainty(camera, options);
  ASSERT_EQ(map.stdev_px.rows(), 7);
  ASSERT_EQ(map.stdev_px.cols(), 9);
  EXPECT_EQ(map.x_px.front(), 0.0);
  EXPECT_EQ(map.x_px.back(), 1023.0);
  EXPECT_EQ(map.y_px.back(), 767.0);
  EXPECT_DOUBLE_EQ(map.stdev_px(6, 8),
                   ProjectionUncertaintyAtPixel(camera, {1023.0, 767.0}, 0.75));
  EXPECT_DOUBLE_EQ(map.at_centre_px, map.stdev_px(3, 4));
  EXPECT_DOUBLE_EQ(map.MaxPx(), map.stdev_px.maxCoeff());
  // Where the boards were, a point at their distance is better known than
  // one at infinity: the boards' own poses pin it down.
  EXPECT_LT(map.at_centre_px,
            ProjectionUncertaintyAtPixel(camera, {511.5, 383.5}, 0.0));
  const double worst =
      WorstDirectionStdev((Eigen::Matrix2d() << 4.0, 0.0, 0.0, 1.0).finished());
  EXPECT_DOUBLE_EQ(worst, 2.0);

  options.distance = -1.0;
  EXPECT_THROW(MapProjectionUncertainty(camera, options), Error);
  options.distance = 0.0;
  options.grid_width = 1;
  EXPECT_THROW(MapProjectionUncertainty(camera, options), Error);
  MrcalCalibration without = camera;
  without.covariance = MrcalSolveCovariance();
  EXPECT_THROW(ProjectionUncertaintyAtPixel(without, {1.0, 1.0}, 0.0), Error);
}

}  // namespace
}  // namespace uw
