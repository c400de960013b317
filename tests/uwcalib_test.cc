// uwcalib detect + calibrate on OpenCV's real chessboard images, checked
// with mrcal's own reader; lasers-from-mission on a synthetic mission in
// models of two scales; bad input refused with nothing written.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "calib/calibration_testing.h"
#include "calib/corners_vnl.h"
#include "calib/mission_scene_testing.h"
#include "calib/mrcal_calibration.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "laserscale/spots_io.h"
#include "sim/laser.h"
#include "tests/support/process.h"
#include "tests/support/svg_ticks.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kUwcalib = fs::path(UW_BIN_DIR) / "uwcalib";
const fs::path kImages =
    fs::path(UW_REALDATA_DIR) / "opencv_chessboard_stereo_640x480";

TEST(Uwcalib, DetectAndCalibrateTheLeftCamera) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  {
    std::ofstream list(dir / "left.txt");
    for (const char* n : {"01", "02", "03", "04", "05", "06", "07", "08", "09",
                          "11", "12", "13", "14"}) {
      list << "left" << n << ".jpg\n";
    }
  }
  const auto detect = RunProcess(
      kUwcalib.string() + " detect --board chessboard:9x6:0.025 --images " +
          Quoted(kImages) + " --image_list_path " + Quoted(dir / "left.txt") +
          " --out " + Quoted(dir / "corners.vnl"),
      true);
  ASSERT_EQ(detect.exit_code, 0) << detect.output;
  EXPECT_NE(detect.output.find("board found in 13 of 13 images"),
            std::string::npos)
      << detect.output;
  const CornersVnl corners = ReadCornersVnl((dir / "corners.vnl").string(), 54);
  EXPECT_EQ(corners.observations.size(), 13u);

  const auto calibrate = RunProcess(
      kUwcalib.string() + " calibrate --board chessboard:9x6:0.025 --corners " +
          Quoted(dir / "corners.vnl") +
          " --lens_model LENSMODEL_OPENCV5 --focal 530 --imagersize 640,480 "
          "--out " +
          Quoted(dir / "cal"),
      true);
  ASSERT_EQ(calibrate.exit_code, 0) << calibrate.output;
  const MrcalCameraModel model =
      ReadCameraModel((dir / "cal" / "camera-0.cameramodel").string());
  EXPECT_EQ(model.lens_model, "LENSMODEL_OPENCV5");
  EXPECT_NEAR(model.intrinsics[0], 533.1, 1.0);  // OpenCV: 531.9
  const nlohmann::json report =
      nlohmann::json::parse(std::ifstream(dir / "cal" / "calibration.json"));
  EXPECT_EQ(report["cameras"][0]["images"].size(), 13u);
  EXPECT_EQ(report["lens_model"], "LENSMODEL_OPENCV5");
  for (const char* plot : {"residuals", "residuals_per_image"}) {
    const fs::path png = dir / "cal" / (std::string(plot) + ".png");
    EXPECT_FALSE(cv::imread(png.string()).empty()) << plot;
    const std::string svg =
        ReadFileToString(fs::path(png).replace_extension(".svg"));
    EXPECT_EQ(TickProblem(SvgTickLabels(svg, 'y')), "") << plot;
    if (std::string(plot) == "residuals") {
      EXPECT_EQ(TickProblem(SvgTickLabels(svg, 'x')), "");
    } else {  // the images by name
      const std::vector<std::string> names = SvgTickLabels(svg, 'x');
      ASSERT_EQ(names.size(), 13u);
      EXPECT_EQ(names[0],
                report["cameras"][0]["images"][0]["image"].get<std::string>());
    }
  }

  // The camera into a COLMAP model that stock colmap reads: its text has
  // the camera, cx and cy moved by +0.5 to COLMAP's pixel centres.
  const auto exported =
      RunProcess(kUwcalib.string() + " export --cameramodel " +
                     Quoted(dir / "cal" / "camera-0.cameramodel") +
                     " --to colmap --output_type BIN --output_path " +
                     Quoted(dir / "colmap_bin"),
                 true);
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_NE(exported.output.find("1 FULL_OPENCV 640 480 "), std::string::npos)
      << exported.output;
  fs::create_directories(dir / "colmap_txt");
  const auto converted = RunProcess(
      "colmap model_converter --input_path " + Quoted(dir / "colmap_bin") +
          " --output_path " + Quoted(dir / "colmap_txt") + " --output_type TXT",
      true);
  ASSERT_EQ(converted.exit_code, 0) << converted.output;
  std::ifstream cameras(dir / "colmap_txt" / "cameras.txt");
  std::string line;
  while (std::getline(cameras, line) && line[0] == '#') {
  }
  std::istringstream fields(line);
  std::string id, name;
  int width = 0, height = 0;
  std::vector<double> params(12);
  fields >> id >> name >> width >> height;
  for (double& param : params) fields >> param;
  EXPECT_EQ(name, "FULL_OPENCV");
  EXPECT_NEAR(params[2], model.intrinsics[2] + 0.5, 1e-9);
  EXPECT_NEAR(params[3], model.intrinsics[3] + 0.5, 1e-9);
  EXPECT_NEAR(params[8], model.intrinsics[8], 1e-12);  // k3
  EXPECT_EQ(params[9], 0.0);                           // OPENCV5: no k4

  const auto yaml =
      RunProcess(kUwcalib.string() + " export --cameramodel " +
                     Quoted(dir / "cal" / "camera-0.cameramodel") +
                     " --to opencv-yaml --out " + Quoted(dir / "camera.yaml"),
                 true);
  ASSERT_EQ(yaml.exit_code, 0) << yaml.output;
  EXPECT_TRUE(fs::exists(dir / "camera.yaml"));
}

// Both cameras of the stereo pair from one corners.vnl, split by globs and
// paired by the numbers in their names: the baseline as the library's
// (CalibrateRigWithMrcal.*: 3.3267 squares, within 0.02 % of OpenCV's
// stereoCalibrate), here in metres for 25 mm squares.
TEST(Uwcalib, CalibratesTheStereoPair) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  auto result = RunProcess(
      kUwcalib.string() + " detect --board chessboard:9x6:0.025 --images " +
          Quoted(kImages) + " --out " + Quoted(dir / "corners.vnl"),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("board found in 26 of 26 images"),
            std::string::npos)
      << result.output;
  result = RunProcess(
      kUwcalib.string() + " calibrate --board chessboard:9x6:0.025 --corners " +
          Quoted(dir / "corners.vnl") +
          " --cameras 'left*.jpg,right*.jpg' --lens_model LENSMODEL_OPENCV5"
          " --focal 530 --imagersize 640,480 --out " +
          Quoted(dir / "stereo"),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const MrcalCameraModel left =
      ReadCameraModel((dir / "stereo" / "camera-0.cameramodel").string());
  const MrcalCameraModel right =
      ReadCameraModel((dir / "stereo" / "camera-1.cameramodel").string());
  EXPECT_EQ(left.rt_cam_ref.norm(), 0.0);
  EXPECT_NEAR(right.rt_cam_ref.tail<3>().norm(), 3.3267 * 0.025, 0.0005);
}

// Kalibr AprilGrids into corners.vnl (Kalibr's corner order, '-' for the
// corners of missing tags), which calibrate reads (two frames of two
// cameras are too few, and it says so).
TEST(Uwcalib, DetectsAprilGridsIntoCornersVnl) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  std::ofstream(dir / "grids.txt") << "EuRoC.png\nTUM_VI.png\n";
  const fs::path images = fs::path(UW_REALDATA_DIR) / "aprilgrid_samples" /
                          "powei-lin_aprilgrid-rs_tests";
  auto result = RunProcess(
      kUwcalib.string() + " detect --board aprilgrid:6x6:0.088:0.3 --images " +
          Quoted(images) + " --image_list_path " + Quoted(dir / "grids.txt") +
          " --out " + Quoted(dir / "corners.vnl"),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const CornersVnl corners =
      ReadCornersVnl((dir / "corners.vnl").string(), 144);
  ASSERT_EQ(corners.observations.size(), 2u);
  EXPECT_GE(corners.observations[0].NumFoundCorners(), 140);
  result = RunProcess(
      kUwcalib.string() +
          " calibrate --board aprilgrid:6x6:0.088:0.3 --corners " +
          Quoted(dir / "corners.vnl") +
          " --focal 460 --imagersize 752,480 --out " + Quoted(dir / "cal"),
      true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("2 board views are too few"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "cal"));
}

// pyCamSet's three cameras x 22 views of a 20x20 ChArUco board (4 mm
// squares): detected, and calibrated as a rig in one solve. pyCamSet's own
// test asks a mean reprojection error under 1.8 px of its calibration; its
// initial focal lengths (2828-2861 px) are the reference for ours.
TEST(Uwcalib, CalibratesTheThreeCameraCharucoRig) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  const fs::path data = fs::path(UW_REALDATA_DIR) / "charuco_pycamset_3cam";
  // One folder, names "<camera>-cal<frame>.jpg": the frame is the last
  // number of a name, the camera its glob.
  fs::create_directories(dir / "images");
  for (const char* camera : {"1", "2", "3"}) {
    for (const auto& entry : fs::directory_iterator(data / camera)) {
      fs::create_symlink(entry.path(), dir / "images" /
                                           (std::string(camera) + "-" +
                                            entry.path().filename().string()));
    }
  }
  const std::string board = "charuco:20x20:0.004:0.0032:DICT_4X4_1000";
  auto result = RunProcess(kUwcalib.string() + " detect --board " + board +
                               " --images " + Quoted(dir / "images") +
                               " --out " + Quoted(dir / "corners.vnl"),
                           true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  // Three views are out of focus: no marker can be read in them.
  EXPECT_NE(result.output.find("board found in 63 of 66 images"),
            std::string::npos)
      << result.output;
  result = RunProcess(
      kUwcalib.string() + " calibrate --board " + board + " --corners " +
          Quoted(dir / "corners.vnl") +
          " --cameras '1-*,2-*,3-*' --lens_model LENSMODEL_OPENCV5 --focal "
          "2840 --imagersize 1280,1024 --out " +
          Quoted(dir / "cal"),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json report =
      nlohmann::json::parse(ReadFileToString(dir / "cal" / "calibration.json"));
  const double rms = report["rms_px"].get<double>();
  const double reference_fx[3] = {2840.4, 2828.2, 2860.7};  // pyCamSet's
  for (int c = 0; c < 3; ++c) {
    const MrcalCameraModel model = ReadCameraModel(
        (dir / "cal" / ("camera-" + std::to_string(c) + ".cameramodel"))
            .string());
    const double baseline = model.rt_cam_ref.tail<3>().norm();
    std::printf(
        "[ figures ] ChArUco rig camera %d: fx %.1f fy %.1f (pyCamSet's "
        "initial fx %.1f), baseline to camera 0 %.4f m\n",
        c, model.intrinsics[0], model.intrinsics[1], reference_fx[c], baseline);
    EXPECT_NEAR(model.intrinsics[0] / reference_fx[c], 1.0, 0.015) << c;
    if (c > 0) {
      EXPECT_GT(baseline, 0.02) << c;
      EXPECT_LT(baseline, 0.06) << c;
    }
  }
  // Per coordinate; the mean 2D error is at most sqrt(2) times it.
  std::printf("[ figures ] ChArUco rig: RMS %.3f px per coordinate\n", rms);
  EXPECT_LT(std::sqrt(2.0) * rms, 1.8);
}

// Acceptance (issue 6, 5) from images: set-up C's four lasers on a board
// at 10 distances (rendered), the camera from its .cameramodel: directions
// within 0.05 deg, origins within 1 mm.
TEST(Uwcalib, LasersFromBoardImages) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  const Camera camera = testing_calibration::TrueCamera();
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const std::vector<testing_calibration::LaserBoardView> views =
      testing_calibration::RenderLaserBoardViews(camera, truth, 10, 8);
  fs::create_directories(dir / "boards");
  for (size_t v = 0; v < views.size(); ++v) {
    ASSERT_TRUE(cv::imwrite(
        (dir / "boards" / ("board" + std::to_string(v) + ".png")).string(),
        views[v].bgr));
  }
  // mrcal's LENSMODEL_OPENCV4 is COLMAP's OPENCV, its pixel centres 0.5 up.
  std::vector<double> intrinsics = camera.params;
  intrinsics[2] -= 0.5;
  intrinsics[3] -= 0.5;
  std::ofstream(dir / "camera.cameramodel")
      << FormatCameraModel("LENSMODEL_OPENCV4", intrinsics, camera.width,
                           camera.height, Rigid3d(), {});
  const auto result = RunProcess(
      kUwcalib.string() + " lasers --images " + Quoted(dir / "boards") +
          " --board chessboard:9x7:0.08 --cameramodel " +
          Quoted(dir / "camera.cameramodel") + " --num_lasers 4 --out " +
          Quoted(dir / "lasers.json"),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::vector<LaserSetup> setups = ReadLasersJson(dir / "lasers.json");
  ASSERT_EQ(setups.size(), 1u);
  ASSERT_EQ(setups[0].lasers.size(), 4u);
  for (const Laser& fitted : setups[0].lasers) {
    const Laser* nearest = &truth.lasers[0];
    for (const Laser& laser : truth.lasers) {
      if ((laser.origin_in_cam - fitted.origin_in_cam).norm() <
          (nearest->origin_in_cam - fitted.origin_in_cam).norm()) {
        nearest = &laser;
      }
    }
    const double angle_deg = testing_mission::AngleDeg(
        fitted.direction_in_cam, nearest->direction_in_cam);
    const double origin_mm =
        1000.0 * (fitted.origin_in_cam - nearest->origin_in_cam).norm();
    std::printf(
        "[ figures ] uwcalib lasers %s: direction %.4f deg, origin %.3f mm "
        "from the truth\n",
        fitted.name.c_str(), angle_deg, origin_mm);
    EXPECT_LT(angle_deg, 0.05) << fitted.name;
    EXPECT_LT(origin_mm, 1.0) << fitted.name;
  }
  // Too few images with the board: refused, nothing written.
  fs::remove(dir / "lasers.json");
  std::ofstream(dir / "two.txt") << "board0.png\nboard1.png\n";
  const auto refused = RunProcess(
      kUwcalib.string() + " lasers --images " + Quoted(dir / "boards") +
          " --image_list_path " + Quoted(dir / "two.txt") +
          " --board chessboard:9x7:0.08 --cameramodel " +
          Quoted(dir / "camera.cameramodel") + " --num_lasers 4 --out " +
          Quoted(dir / "lasers.json"),
      true);
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("the board was found in 2 of 2 images"),
            std::string::npos)
      << refused.output;
  EXPECT_FALSE(fs::exists(dir / "lasers.json"));
}

TEST(Uwcalib, BadInputIsRefusedAndNothingIsWritten) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  // Images without the board (the board asked for is not the one shown).
  auto result = RunProcess(
      kUwcalib.string() + " detect --board chessboard:7x7:0.025 --images " +
          Quoted(kImages) + " --out " + Quoted(dir / "corners.vnl"),
      true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("no image shows the whole board"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "corners.vnl"));

  // A malformed corners file.
  std::ofstream(dir / "bad.vnl") << "# filename x y level\na.jpg 1 2 0\n";
  result = RunProcess(
      kUwcalib.string() + " calibrate --board chessboard:9x6:0.025 --corners " +
          Quoted(dir / "bad.vnl") + " --focal 530 --imagersize 640,480 --out " +
          Quoted(dir / "cal"),
      true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("bad.vnl:2: image a.jpg has 1 rows"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "cal"));

  // Too few views for the lens model: two boards.
  std::ofstream two(dir / "two.vnl");
  for (const char* image : {"a.jpg", "b.jpg"}) {
    for (int j = 0; j < 6; ++j) {
      for (int i = 0; i < 9; ++i) {
        two << image << " " << 100 + 20 * i + j << " " << 100 + 20 * j
            << " 0\n";
      }
    }
  }
  two.close();
  result = RunProcess(
      kUwcalib.string() + " calibrate --board chessboard:9x6:0.025 --corners " +
          Quoted(dir / "two.vnl") + " --focal 530 --imagersize 640,480 --out " +
          Quoted(dir / "cal"),
      true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("2 board views"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "cal"));
}

// The files `uwcalib lasers-from-mission` reads, for a synthetic mission
// in a model of scale k: the model (its points are the poses' inliers), its
// mesh, poses.json, spots.json and origins.json (a-priori directions 0.4
// deg off), and dives.csv (first half dive 1).
void WriteMission(const testing_mission::Mission& mission,
                  const LaserSetup& origins, double k, const fs::path& dir) {
  const TriangleMesh floor = testing_mission::Floor(k);
  const RayCaster caster(floor);
  const std::vector<LocalizedImage> poses =
      testing_mission::Localized(caster, mission, k);
  Reconstruction model;
  Camera camera = testing_mission::SurveyCamera();
  camera.camera_id = 1;
  model.AddCamera(camera);
  for (const LocalizedImage& image : poses) {
    for (const Correspondence2D3D& inlier : image.inliers) {
      Point3D point;
      point.point3D_id = model.Points3D().size() + 1;
      point.xyz = inlier.point_in_world;
      model.AddPoint3D(point);
    }
  }
  fs::create_directories(dir / "sparse");
  WriteModel(model, dir / "sparse", ModelFormat::kBinary);
  WritePly(floor, dir / "mesh.ply", "test floor; metres");
  std::ofstream(dir / "poses.json") << LaserPosesJsonText(poses);
  std::map<std::string, ImageSpots> by_image;
  for (const auto& laser_spots : mission.spots) {
    for (size_t s = 0; s < laser_spots.size(); ++s) {
      const MissionSpot& m = laser_spots[s];
      ImageSpots& image = by_image[m.image];
      image.name = m.image;
      image.setup = origins.name;
      DetectedSpot spot;
      spot.laser = origins.lasers[&laser_spots - mission.spots.data()].name;
      spot.detected = true;
      spot.stable = true;
      spot.detection_rate = 1.0;
      spot.pixel = m.pixel;
      spot.covariance = m.covariance_px;
      image.spots.push_back(spot);
    }
  }
  std::vector<ImageSpots> spots;
  for (const auto& [name, image] : by_image) spots.push_back(image);
  std::ofstream(dir / "spots.json") << SpotsJsonText(spots);
  std::ofstream(dir / "origins.json") << LasersJsonText({origins});
  std::ofstream dives(dir / "dives.csv");
  dives << "image_name,dive\n";
  for (size_t i = 0; i < mission.cam_from_world.size(); ++i) {
    dives << "L" << i << ".png,"
          << (2 * i < mission.cam_from_world.size() ? 1 : 2) << "\n";
  }
}

std::string LasersFromMission(const fs::path& dir, const fs::path& poses,
                              const fs::path& mesh) {
  return kUwcalib.string() + " lasers-from-mission --input_path " +
         Quoted(dir / "sparse") + " --mesh " + Quoted(mesh) + " --spots " +
         Quoted(dir / "spots.json") + " --poses " + Quoted(poses) +
         " --origins " + Quoted(dir / "origins.json") + " --image_dives " +
         Quoted(dir / "dives.csv") + " --out " + Quoted(dir / "lasers.json") +
         " --report_path " + Quoted(dir / "report.json");
}

// Acceptance (issue 6, 5): from mission data, the directions of models of
// scale 0.237 and 1.0 agree within their sigma; poses or a mesh of another
// model are refused, nothing written.
TEST(Uwcalib, LasersFromMissionInModelsOfTwoScales) {
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  LaserSetup origins = truth;
  for (Laser& laser : origins.lasers) {
    laser.direction_in_cam =
        (Eigen::AngleAxisd(0.4 * M_PI / 180, Eigen::Vector3d::UnitY()) *
         laser.direction_in_cam)
            .normalized();
  }
  const RayCaster metric(testing_mission::Floor(1.0));
  const testing_mission::Mission mission =
      testing_mission::MakeMission(metric, truth, 40, 0.3, 17);
  const fs::path root = FreshTestDir("uw_uwcalib_test");
  std::map<double, std::vector<LaserSetup>> results;
  for (const double k : {1.0, 0.237}) {
    const fs::path dir = root / ("k" + std::to_string(k));
    WriteMission(mission, origins, k, dir);
    const auto run = RunProcess(
        LasersFromMission(dir, dir / "poses.json", dir / "mesh.ply"), true);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("dive 2:"), std::string::npos) << run.output;
    results[k] = ReadLasersJson(dir / "lasers.json");
    const nlohmann::json report =
        nlohmann::json::parse(ReadFileToString(dir / "report.json"));
    EXPECT_EQ(report["setups"][0]["lasers"][0]["monte_carlo_iterations"], 1000);
  }
  for (size_t l = 0; l < truth.lasers.size(); ++l) {
    const Laser& one = results[1.0][0].lasers[l];
    const Laser& other = results[0.237][0].lasers[l];
    const double sigma = std::sqrt(
        std::min(one.direction_cov.trace(), other.direction_cov.trace()));
    // Radians, as the covariances' sigma.
    const double between = testing_mission::AngleDeg(one.direction_in_cam,
                                                     other.direction_in_cam) *
                           M_PI / 180.0;
    const double error =
        testing_mission::AngleDeg(one.direction_in_cam,
                                  truth.lasers[l].direction_in_cam) *
        M_PI / 180.0;
    std::printf(
        "[ figures ] lasers-from-mission %s: scale 1 vs 0.237 %.2e "
        "rad (sigma %.2e rad); %.4f deg from the truth\n",
        one.name.c_str(), between, sigma, error * 180 / M_PI);
    EXPECT_LT(between, sigma) << one.name;
    EXPECT_LT(error, 3 * sigma) << one.name;
    EXPECT_EQ(one.origin_in_cam, origins.lasers[l].origin_in_cam);
  }

  // Poses localized against the other model; then the other model's mesh.
  const fs::path dir = root / ("k" + std::to_string(1.0));
  const fs::path other = root / ("k" + std::to_string(0.237));
  fs::remove(dir / "lasers.json");
  auto run = RunProcess(
      LasersFromMission(dir, other / "poses.json", dir / "mesh.ply"), true);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("localized against another model"),
            std::string::npos)
      << run.output;
  run = RunProcess(
      LasersFromMission(dir, dir / "poses.json", other / "mesh.ply"), true);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("it is not the surface of their model"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(fs::exists(dir / "lasers.json"));
  EXPECT_FALSE(fs::exists(dir / "report.json.tmp"));
}

}  // namespace
}  // namespace uw
