#include "calib/mrcal_calibration.h"
#include "calib/calibration_testing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "calib/chessboard_detector.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/random.h"
#include "common/util/subprocess.h"
#include "sim/board_images.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;
using testing_calibration::Options;
using testing_calibration::TrueCamera;

// Views of a board 0.4-0.9 m away, tilted up to 45 deg, with their exact
// corners plus Gaussian noise: boards close enough to fill much of the image,
// as mrcal's docs advise (at 0.5-1.2 m with a 10x8 board of 4 cm, 30 views
// left the principal point 1.4 px off: the data, not the solver).
std::vector<BoardObservation> NoisyViews(const Camera& camera,
                                         const CalibrationBoard& board,
                                         int num_views, double sigma_px,
                                         uint64_t seed) {
  return testing_calibration::ViewsWithNoise(
      camera, board,
      sim::RandomBoardPoses(camera, board, num_views, 0.4, 0.9, 45.0, seed),
      sigma_px, seed + 1);
}

TEST(CalibrateWithMrcal, RecoversKnownIntrinsicsFromNoisyCorners) {
  const Camera camera = TrueCamera();
  const CalibrationBoard board = ParseBoard("chessboard:14x10:0.04");
  const std::vector<BoardObservation> views =
      NoisyViews(camera, board, 60, 0.3, 11);
  const MrcalCalibrationOptions options =
      Options("LENSMODEL_OPENCV4", 800.0, 1024, 768);
  const MrcalCalibration result = CalibrateWithMrcal(views, board, options);
  const std::vector<double>& k = result.intrinsics;
  const std::vector<double>& t = camera.params;
  std::printf(
      "[ figures ] fx %.3f (%.3f) fy %.3f (%.3f) cx %.3f (%.3f) cy "
      "%.3f (%.3f) k1 %.5f (%.5f) k2 %.5f (%.5f); RMS %.4f px for "
      "0.3 px noise; %d outliers\n",
      k[0], t[0], k[1], t[1], k[2], t[2] - 0.5, k[3], t[3] - 0.5, k[4], t[4],
      k[5], t[5], result.rms_px, result.num_outliers);
  EXPECT_NEAR(k[0] / t[0], 1.0, 1e-3);
  EXPECT_NEAR(k[1] / t[1], 1.0, 1e-3);
  EXPECT_NEAR(k[2], t[2] - 0.5, 0.5);
  EXPECT_NEAR(k[3], t[3] - 0.5, 0.5);
  EXPECT_NEAR(result.rms_px / 0.3, 1.0, 0.1);
  EXPECT_EQ(result.images.size(), 60u);
}

// Runs Debian's mrcal-calibrate-cameras on the cameras' views (written as
// one corners.vnl, a glob a camera) and checks that CalibrateRigWithMrcal
// finds the same intrinsics, extrinsics and outliers.
void ExpectSameAsMrcalTool(const std::vector<RigCameraViews>& cameras,
                           const CalibrationBoard& board,
                           const MrcalCalibrationOptions& options,
                           const std::vector<std::string>& globs) {
  const fs::path dir = FreshTestDir("uw_mrcal_calibration_test");
  const std::string tool_output = testing_calibration::RunMrcalCalibrateCameras(
      cameras, board, options, globs, dir);
  const MrcalRigCalibration ours =
      CalibrateRigWithMrcal(cameras, board, options);
  double worst = 0.0;
  for (size_t c = 0; c < cameras.size(); ++c) {
    const MrcalCameraModel theirs = ReadCameraModel(
        (dir / ("camera-" + std::to_string(c) + ".cameramodel")).string());
    ASSERT_EQ(theirs.lens_model, options.lens_model);
    const std::vector<double>& intrinsics = ours.cameras[c].intrinsics;
    ASSERT_EQ(theirs.intrinsics.size(), intrinsics.size());
    for (size_t i = 0; i < intrinsics.size(); ++i) {
      const double relative = std::abs(intrinsics[i] - theirs.intrinsics[i]) /
                              std::max(std::abs(theirs.intrinsics[i]), 1e-300);
      worst = std::max(worst, relative);
      EXPECT_LT(relative, 1e-4)
          << "camera " << c << " intrinsic " << i << ": ours " << intrinsics[i]
          << ", mrcal-calibrate-cameras " << theirs.intrinsics[i];
    }
    // Their extrinsics are camera-from-camera-0 too: compare the baseline.
    const double baseline = ours.cam_from_rig[c].translation.norm();
    const double their_baseline = theirs.rt_cam_ref.tail<3>().norm();
    EXPECT_NEAR(baseline, their_baseline, 1e-4 * std::max(their_baseline, 1e-9))
        << "camera " << c;
  }
  std::smatch match;
  const std::regex noutliers("Noutliers: ([0-9]+) out of ([0-9]+)");
  ASSERT_TRUE(std::regex_search(tool_output, match, noutliers)) << tool_output;
  int missing = 0;
  for (const RigCameraViews& camera : cameras) {
    for (const BoardObservation& view : camera.views) {
      if (view.Found()) missing += board.NumCorners() - view.NumFoundCorners();
    }
  }
  std::printf(
      "[ figures ] vs mrcal-calibrate-cameras (%zu camera(s)): worst "
      "relative intrinsic difference %.2e; outliers %d (theirs %s, "
      "of which %d missing on input); RMS %.4f px\n",
      cameras.size(), worst, ours.num_outliers, match[1].str().c_str(), missing,
      ours.rms_px);
  EXPECT_EQ(ours.num_outliers + missing, std::stoi(match[1].str()));
}

RigCameraViews OneCamera(const std::vector<BoardObservation>& views) {
  RigCameraViews camera;
  camera.views = views;
  for (size_t i = 0; i < views.size(); ++i) {
    camera.frames.push_back(static_cast<int>(i));
  }
  return camera;
}

TEST(CalibrateWithMrcal, SameSolutionAsMrcalCalibrateCamerasWithOutliers) {
  const Camera camera = TrueCamera();
  const CalibrationBoard board = ParseBoard("chessboard:14x10:0.04");
  std::vector<BoardObservation> views = NoisyViews(camera, board, 30, 0.3, 5);
  // Gross detector errors mrcal must throw out, and a corner not found.
  views[3].pixels[17] += Eigen::Vector2d(6.0, -4.0);
  views[8].pixels[40] += Eigen::Vector2d(-5.0, 5.0);
  views[12].pixels[139] += Eigen::Vector2d(0.0, 8.0);
  views[15].weights[5] = -1.0;
  // The lens model of the truth: OPENCV8's rational terms are not
  // determined by these views, and mrcal-calibrate-cameras' own random
  // distortion seed then lands it in different places run by run.
  const MrcalCalibrationOptions options =
      Options("LENSMODEL_OPENCV4", 800.0, 1024, 768);
  ExpectSameAsMrcalTool({OneCamera(views)}, board, options, {"frame*.png"});
  const MrcalCalibration ours = CalibrateWithMrcal(views, board, options);
  EXPECT_TRUE(ours.outliers[3][17]);
  EXPECT_TRUE(ours.outliers[8][40]);
  EXPECT_TRUE(ours.outliers[12][139]);
  EXPECT_FALSE(ours.outliers[15][5]);  // missing is not an outlier
}

// OpenCV's real stereo sample, one side ("left" or "right"), frame n = the
// image's number; detected once per process.
RigCameraViews DetectRealViews(const std::string& side) {
  const fs::path dir =
      fs::path(UW_REALDATA_DIR) / "opencv_chessboard_stereo_640x480";
  const CalibrationBoard board = ParseBoard("chessboard:9x6:1");
  RigCameraViews camera;
  for (int n = 1; n <= 14; ++n) {
    if (n == 10) continue;
    char name[32];
    std::snprintf(name, sizeof(name), "%s%02d.jpg", side.c_str(), n);
    const cv::Mat image = cv::imread((dir / name).string());
    if (image.empty()) throw Error(std::string("cannot read ") + name);
    camera.views.push_back(DetectChessboard(image, board, name));
    camera.frames.push_back(n);
  }
  return camera;
}

const RigCameraViews& RealViews(const std::string& side) {
  static std::map<std::string, RigCameraViews> detected;
  auto it = detected.find(side);
  if (it == detected.end()) {
    it = detected.emplace(side, DetectRealViews(side)).first;
  }
  return it->second;
}

TEST(CalibrateWithMrcal, RealChessboardLikeOpenCvAndLikeTheMrcalTool) {
  const std::vector<BoardObservation> views = RealViews("left").views;
  const CalibrationBoard board = ParseBoard("chessboard:9x6:1");
  const MrcalCalibrationOptions options =
      Options("LENSMODEL_OPENCV5", 530.0, 640, 480);
  const MrcalCalibration ours = CalibrateWithMrcal(views, board, options);

  // OpenCV's calibrateCamera on the same corners (5 coefficients, as
  // LENSMODEL_OPENCV5): its RMS is per corner (the 2D error's norm).
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (const BoardObservation& view : views) {
    if (!view.Found()) continue;
    object_points.emplace_back();
    image_points.emplace_back();
    const std::vector<Eigen::Vector3d> corners = board.CornersInBoard();
    for (size_t k = 0; k < corners.size(); ++k) {
      object_points.back().emplace_back(corners[k].x(), corners[k].y(), 0.f);
      image_points.back().emplace_back(view.pixels[k].x(), view.pixels[k].y());
    }
  }
  cv::Mat camera_matrix;
  cv::Mat distortion;
  std::vector<cv::Mat> rvecs;
  std::vector<cv::Mat> tvecs;
  const double opencv_rms =
      cv::calibrateCamera(object_points, image_points, cv::Size(640, 480),
                          camera_matrix, distortion, rvecs, tvecs);
  double sum_squares = 0.0;
  int count = 0;
  for (const std::vector<Eigen::Vector2d>& residuals : ours.residuals_px) {
    for (const Eigen::Vector2d& residual : residuals) {
      sum_squares += residual.squaredNorm();
      ++count;
    }
  }
  const double our_rms = std::sqrt(sum_squares / count);
  std::printf(
      "[ figures ] left camera, %zu views: RMS per corner ours %.4f "
      "px (all corners, %d outliers), OpenCV calibrateCamera %.4f px; "
      "fx ours %.2f OpenCV %.2f\n",
      object_points.size(), our_rms, ours.num_outliers, opencv_rms,
      ours.intrinsics[0], camera_matrix.at<double>(0, 0));
  EXPECT_EQ(object_points.size(), 13u);
  EXPECT_LT(std::abs(our_rms / opencv_rms - 1.0), 0.10);
  ExpectSameAsMrcalTool({OneCamera(views)}, board, options, {"left*.jpg"});
}

// The stereo pair: mrcal's rig solve against OpenCV's stereoCalibrate on the
// same corners (each camera seeded by its own calibrateCamera, then
// everything refined), and against mrcal-calibrate-cameras with two globs.
TEST(CalibrateRigWithMrcal, StereoBaselineLikeOpenCvAndLikeTheMrcalTool) {
  const std::vector<RigCameraViews> cameras = {RealViews("left"),
                                               RealViews("right")};
  const CalibrationBoard board = ParseBoard("chessboard:9x6:1");
  const MrcalCalibrationOptions options =
      Options("LENSMODEL_OPENCV5", 530.0, 640, 480);
  const MrcalRigCalibration ours =
      CalibrateRigWithMrcal(cameras, board, options);

  std::vector<std::vector<cv::Point3f>> object_points;
  std::array<std::vector<std::vector<cv::Point2f>>, 2> image_points;
  const std::vector<Eigen::Vector3d> corners = board.CornersInBoard();
  for (size_t i = 0; i < cameras[0].views.size(); ++i) {
    if (!cameras[0].views[i].Found() || !cameras[1].views[i].Found()) continue;
    object_points.emplace_back();
    for (const Eigen::Vector3d& corner : corners) {
      object_points.back().emplace_back(corner.x(), corner.y(), 0.f);
    }
    for (int c = 0; c < 2; ++c) {
      image_points[c].emplace_back();
      for (const Eigen::Vector2d& pixel : cameras[c].views[i].pixels) {
        image_points[c].back().emplace_back(pixel.x(), pixel.y());
      }
    }
  }
  std::array<cv::Mat, 2> matrices;
  std::array<cv::Mat, 2> distortions;
  for (int c = 0; c < 2; ++c) {
    std::vector<cv::Mat> rvecs;
    std::vector<cv::Mat> tvecs;
    cv::calibrateCamera(object_points, image_points[c], cv::Size(640, 480),
                        matrices[c], distortions[c], rvecs, tvecs);
  }
  cv::Mat rotation;
  cv::Mat translation;
  cv::Mat essential;
  cv::Mat fundamental;
  const double opencv_rms = cv::stereoCalibrate(
      object_points, image_points[0], image_points[1], matrices[0],
      distortions[0], matrices[1], distortions[1], cv::Size(640, 480), rotation,
      translation, essential, fundamental, cv::CALIB_USE_INTRINSIC_GUESS);
  const double opencv_baseline = cv::norm(translation);
  const double our_baseline = ours.cam_from_rig[1].translation.norm();
  std::printf(
      "[ figures ] stereo pair, %zu common views: baseline ours %.5f "
      "squares, OpenCV stereoCalibrate %.5f (RMS %.4f px); ratio "
      "%.5f; ours: RMS %.4f px, %d outliers\n",
      object_points.size(), our_baseline, opencv_baseline, opencv_rms,
      our_baseline / opencv_baseline, ours.rms_px, ours.num_outliers);
  EXPECT_EQ(object_points.size(), 13u);
  EXPECT_NEAR(our_baseline / opencv_baseline, 1.0, 0.01);
  ExpectSameAsMrcalTool(cameras, board, options, {"left*.jpg", "right*.jpg"});
}

TEST(CalibrateRigWithMrcal, CamerasWithoutACommonFrameAreAnError) {
  RigCameraViews left = RealViews("left");
  RigCameraViews right = RealViews("right");
  for (int& frame : right.frames) frame += 100;
  const CalibrationBoard board = ParseBoard("chessboard:9x6:1");
  try {
    CalibrateRigWithMrcal({left, right}, board,
                          Options("LENSMODEL_OPENCV4", 530.0, 640, 480));
    ADD_FAILURE() << "calibrated a rig without common views";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("camera 1 shares no board view"),
              std::string::npos)
        << error.what();
  }
}

// A Kalibr AprilGrid (6x6 tags of 4 cm, gap 0.3), 10 % of its tags missing
// in each view: mrcal 2.2 gets the corners on their 76x76 lattice. With
// exact corners the solve (no regularization, whose pull is a bias, and no
// outlier rejection, meaningless without noise) lands on the true
// intrinsics: the lattice puts every corner where the grid has it.
TEST(CalibrateWithMrcal, AprilGridOnItsLatticeIsExact) {
  const Camera camera = TrueCamera();
  const CalibrationBoard grid = ParseBoard("aprilgrid:6x6:0.04:0.3");
  std::vector<BoardObservation> views = NoisyViews(camera, grid, 30, 0.0, 17);
  SplitMix64Stream random(99);
  for (BoardObservation& view : views) {
    for (int tag = 0; tag < 36; ++tag) {
      if (random.Uniform() > 0.1) continue;
      const int lower_left = 2 * (tag / 6) * 12 + 2 * (tag % 6);
      for (const int k :
           {lower_left, lower_left + 1, lower_left + 12, lower_left + 13}) {
        view.weights[k] = -1.0;
      }
    }
  }
  MrcalCalibrationOptions options =
      Options("LENSMODEL_OPENCV4", 800.0, 1024, 768);
  options.regularization = false;
  options.outlier_rejection = false;
  const MrcalCalibration result = CalibrateWithMrcal(views, grid, options);
  double worst = 0.0;
  for (size_t i = 0; i < 8; ++i) {
    const double truth = camera.params[i] - (i == 2 || i == 3 ? 0.5 : 0.0);
    worst = std::max(worst, std::abs(result.intrinsics[i] / truth - 1.0));
  }
  std::printf(
      "[ figures ] AprilGrid on its lattice, exact corners: worst "
      "relative intrinsic error %.2e\n",
      worst);
  EXPECT_LT(worst, 1e-6);
  ASSERT_EQ(result.residuals_px[0].size(), 144u);  // per corner again
  EXPECT_EQ(result.num_outliers, 0);
  // The missing tags' corners have no residual: they must not count.
  int found = 0;
  for (const std::vector<bool>& view : result.found) {
    found += static_cast<int>(std::count(view.begin(), view.end(), true));
  }
  EXPECT_EQ(found, result.num_corners_observed);
  EXPECT_LT(found, 30 * 144);
  EXPECT_LT(result.rms_px, 1e-6);
}

TEST(CalibrateWithMrcal, TooFewViewsAndBadOptionsAreErrors) {
  const Camera camera = TrueCamera();
  const CalibrationBoard board = ParseBoard("chessboard:10x8:0.04");
  const std::vector<BoardObservation> views =
      NoisyViews(camera, board, 2, 0.3, 3);
  MrcalCalibrationOptions options =
      Options("LENSMODEL_OPENCV8", 800.0, 1024, 768);
  try {
    CalibrateWithMrcal(views, board, options);
    ADD_FAILURE() << "calibrated from 2 views";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("2 board views"),
              std::string::npos)
        << error.what();
  }
  options.lens_model = "LENSMODEL_FISHEYE9";
  EXPECT_THROW(options.Check(), Error);
  options.lens_model = "LENSMODEL_OPENCV4";
  options.focal_px = 0.0;
  EXPECT_THROW(options.Check(), Error);
}

TEST(CameraModelFile, MrcalReadsWhatWeWriteToTheLastBit) {
  const fs::path dir = FreshTestDir("uw_mrcal_calibration_test");
  const std::vector<double> intrinsics = {
      851.123456789012,    849.5, 511.25, 383.0625,
      -0.1234567890123e-3, 1e-9,  0.5,    -2.0};
  const fs::path path = dir / "cam.cameramodel";
  Rigid3d cam_from_rig;
  cam_from_rig.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.1, Eigen::Vector3d(1, 2, 3).normalized()));
  cam_from_rig.translation = Eigen::Vector3d(-0.12, 0.003, 0.001);
  WriteFilesAtomically({{path,
                         [&](std::ostream& out) {
                           out << FormatCameraModel("LENSMODEL_OPENCV4",
                                                    intrinsics, 1024, 768,
                                                    cam_from_rig, {"test"});
                         }}},
                       false);
  const MrcalCameraModel model = ReadCameraModel(path.string());
  EXPECT_EQ(model.lens_model, "LENSMODEL_OPENCV4");
  EXPECT_EQ(model.intrinsics, intrinsics);
  EXPECT_EQ(model.image_width, 1024);
  EXPECT_EQ(model.image_height, 768);
  const Eigen::Vector3d r =
      0.1 * Eigen::Vector3d(1, 2, 3).normalized();  // Rodrigues
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(model.rt_cam_ref(i), r(i), 1e-15);
    EXPECT_EQ(model.rt_cam_ref(3 + i), cam_from_rig.translation(i));
  }
  // And mrcal's Python reads it too.
  const ProcessResult python = RunProcess(
      "/usr/bin/python3 -c \"import mrcal,sys; "
      "m=mrcal.cameramodel(sys.argv[1]);"
      " print(m.intrinsics()[0], repr(m.intrinsics()[1][0]))\" " +
          Quoted(path),
      true);
  EXPECT_EQ(python.exit_code, 0) << python.output;
  EXPECT_EQ(python.output, "LENSMODEL_OPENCV4 851.123456789012\n");
  std::ofstream(dir / "bad.cameramodel") << "{ 'lensmodel': 'LENSMODEL_X' }";
  EXPECT_THROW(ReadCameraModel((dir / "bad.cameramodel").string()), Error);
}

}  // namespace
}  // namespace uw
