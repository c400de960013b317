#include "colmap_plugins/nav/camera_prior.h"

#include <cmath>
#include <functional>
#include <iostream>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "colmap_plugins/nav/attitude.h"
#include "common/util/error.h"

namespace uw {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

Eigen::Vector3d Log(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(rotation);
  return angle_axis.angle() * angle_axis.axis();
}

Eigen::Matrix3d Exp(const Eigen::Vector3d& w) {
  return w.norm() > 0.0
             ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()
             : Eigen::Matrix3d::Identity();
}

// A vehicle moving at constant velocity and turning at a constant rate
// about a fixed world axis: linear interpolation and slerp between any two
// of its samples are exact.
struct Motion {
  Eigen::Vector3d position0{10.0, -4.0, -30.0};
  Eigen::Vector3d velocity{0.4, 0.3, -0.05};
  Eigen::Matrix3d rotation0 = WorldFromVehicleRotation({0.05, -0.1, 0.7});
  Eigen::Vector3d angular_velocity{0.02, -0.01, 0.15};  // rad/s, world

  Eigen::Vector3d Position(double t) const { return position0 + t * velocity; }
  Eigen::Matrix3d WorldFromVehicle(double t) const {
    return Exp(t * angular_velocity) * rotation0;
  }
  NavRecord Row(const std::string& name, double t, int dive = 1,
                int line = 0) const {
    NavRecord row;
    row.image_name = name;
    row.time_s = t;
    row.dive = dive;
    row.position = Position(t);
    row.rpy_rad = RollPitchYawFromRotation(WorldFromVehicle(t));
    row.position_sigma = Eigen::Vector3d(0.5, 0.6, 0.02);
    row.rpy_sigma_rad = Eigen::Vector3d(0.05, 0.05, 0.2) * kDegToRad;
    row.line = line;
    return row;
  }
};

// world_from_cam of a camera on `motion`'s vehicle at time t.
Rigid3d WorldFromCam(const Motion& motion, double t,
                     const Rigid3d& vehicle_from_cam) {
  Rigid3d world_from_cam;
  world_from_cam.rotation = Eigen::Quaterniond(
      motion.WorldFromVehicle(t) * vehicle_from_cam.RotationMatrix());
  world_from_cam.translation =
      motion.Position(t) +
      motion.WorldFromVehicle(t) * vehicle_from_cam.translation;
  return world_from_cam;
}

// Distance of a prior from a true world_from_cam: centre (m) + angle (rad).
double PoseError(const CameraPrior& prior, const Rigid3d& world_from_cam) {
  return (prior.position - world_from_cam.translation).norm() +
         prior.cam_from_world_rotation->angularDistance(
             world_from_cam.rotation.conjugate());
}

NavToCameraOptions SomeCamera() {
  NavToCameraOptions options;
  options.mount = CameraMount::kStarboard;
  options.lever_arm_m = Eigen::Vector3d(0.6, -0.2, -0.3);
  options.boresight_deg = Eigen::Vector3d(0.3, -0.5, 0.8);
  return options;
}

std::string ErrorOf(const std::function<void()>& run) {
  try {
    run();
  } catch (const Error& error) {
    return error.what();
  }
  return "no error";
}

// Worked by hand: bow north (yaw 90 deg), camera looking down with its
// image top to the bow and 1 m ahead of, 0.5 m below the vehicle origin.
TEST(CameraPrior, ARowPlacesTheCameraThroughMountAndLeverArm) {
  NavRecord row;
  row.image_name = "a.png";
  row.position = Eigen::Vector3d(10, 20, -5);
  row.rpy_rad = Eigen::Vector3d(0, 0, M_PI / 2);
  NavToCameraOptions options;
  options.lever_arm_m = Eigen::Vector3d(1, 0, -0.5);
  const std::vector<CameraPrior> priors =
      CameraPriorsFromNavigation({row}, nullptr, options);
  ASSERT_EQ(priors.size(), 1u);
  EXPECT_EQ(priors[0].image_name, "a.png");
  EXPECT_EQ(priors[0].sampling, NavSampling::kExact);
  EXPECT_LT((priors[0].position - Eigen::Vector3d(10, 21, -5.5)).norm(), 1e-14);
  Eigen::Matrix3d world_from_cam;  // columns: east, south, down
  world_from_cam << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  EXPECT_LT((priors[0].cam_from_world_rotation->toRotationMatrix() -
             world_from_cam.transpose())
                .norm(),
            1e-15);
  // Zero sigmas, zero covariances.
  EXPECT_EQ(priors[0].position_covariance, Eigen::Matrix3d::Zero());
  EXPECT_EQ(priors[0].rotation_covariance, Eigen::Matrix3d::Zero());
}

TEST(CameraPrior, ImageTimesAreInterpolatedAndExtrapolatedOneIntervalAtMost) {
  const Motion motion;
  const std::vector<NavRecord> nav = {
      motion.Row("", 0.0, 1, 2), motion.Row("", 1.0, 1, 3),
      motion.Row("", 2.5, 1, 4), motion.Row("", 3.0, 1, 5)};
  const NavToCameraOptions options = SomeCamera();
  const Rigid3d vehicle_from_cam = VehicleFromCam(options);
  const std::vector<ImageTime> times = {
      {"exact.png", 2.5, 0, 2},   {"between.png", 1.7, 0, 3},
      {"before.png", -0.9, 0, 4}, {"after.png", 3.5, 0, 5},
      {"first.png", 0.0, 0, 6},   {"last.png", 3.0, 0, 7}};
  const std::vector<CameraPrior> priors =
      CameraPriorsFromNavigation(nav, &times, options);
  ASSERT_EQ(priors.size(), times.size());
  double worst = 0.0;
  for (size_t i = 0; i < times.size(); ++i) {
    EXPECT_EQ(priors[i].image_name, times[i].image_name);
    EXPECT_EQ(priors[i].time_s, times[i].time_s);
    EXPECT_EQ(priors[i].dive, 1);
    worst = std::max(worst,
                     PoseError(priors[i], WorldFromCam(motion, times[i].time_s,
                                                       vehicle_from_cam)));
  }
  std::cout << "[ figures ] interpolated/extrapolated prior vs true motion: "
            << worst << " (m + rad)\n";
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(priors[0].sampling, NavSampling::kExact);
  EXPECT_EQ(priors[1].sampling, NavSampling::kInterpolated);
  EXPECT_EQ(priors[2].sampling, NavSampling::kExtrapolated);
  EXPECT_EQ(priors[3].sampling, NavSampling::kExtrapolated);
  EXPECT_EQ(priors[5].sampling, NavSampling::kExact);

  // Beyond one interval (1 s at the start, 0.5 s at the end): refused.
  const std::vector<ImageTime> late = {{"late.png", 3.6, 0, 9}};
  EXPECT_EQ(ErrorOf([&] { CameraPriorsFromNavigation(nav, &late, options); }),
            "image_times.csv:9: image 'late.png' at navigation time 3.6 s "
            "lies outside the navigation of every dive, even allowing one "
            "sampling interval beyond each end; dive 1: 0 to 3 s, nav.csv "
            "lines 2 to 5");
  const std::vector<ImageTime> early = {{"early.png", -1.1, 1, 4}};
  EXPECT_EQ(
      ErrorOf([&] {
        CameraPriorsFromNavigation(nav, &early, options, nullptr,
                                   {"log.csv", "times.csv"});
      }),
      "times.csv:4: image 'early.png' at navigation time -1.1 s lies outside "
      "the navigation of dive 1 (0 to 3 s, log.csv lines 2 to 5): "
      "extrapolation reaches one sampling interval beyond each end at most");
}

// A log on Unix time, and an image 58 days off it (a camera clock never
// set): the message gives both times in full and as dates, so the offset
// shows; 1.72841e+09 would hide it and the fraction.
TEST(CameraPrior, UnixTimesAreNamedInFullAndAsDates) {
  const Motion motion;
  const double start = 1728410000.25;
  const std::vector<NavRecord> nav = {motion.Row("", start, 1, 2),
                                      motion.Row("", start + 1.0, 1, 3)};
  const std::vector<ImageTime> off = {{"off.png", start - 5011200.0, 0, 4}};
  EXPECT_EQ(
      ErrorOf([&] { CameraPriorsFromNavigation(nav, &off, SomeCamera()); }),
      "image_times.csv:4: image 'off.png' at navigation time 1723398800.25 "
      "(2024-08-11T17:53:20.25Z) s lies outside the navigation of every dive, "
      "even allowing one sampling interval beyond each end; dive 1: "
      "1728410000.25 (2024-10-08T17:53:20.25Z) to 1728410001.25 "
      "(2024-10-08T17:53:21.25Z) s, nav.csv lines 2 to 3");
}

// Every image of a survey 58 days and 3 hours off the log (a camera clock
// never set): one error for the clock, with the offset that fixes it, not
// one for the first image.
TEST(CameraPrior, AClockOffForMostImagesIsNamedWithItsOffset) {
  const Motion motion;
  const double start = 1728410000.25;
  std::vector<NavRecord> nav;
  for (int k = 0; k < 7; ++k) {
    nav.push_back(motion.Row("", start + 600.0 * k, 1, k + 2));
  }
  std::vector<ImageTime> times;
  for (int k = 0; k < 5; ++k) {
    times.push_back(
        {std::to_string(k) + ".png", start - 5022000.0 + 900.0 * k, 0, k + 2});
  }
  // One image within the log does not change the verdict.
  times.push_back({"5.png", start + 100.0, 0, 7});
  NavToCameraOptions options = SomeCamera();
  options.time_offset_s = 2.5;
  EXPECT_EQ(
      ErrorOf([&] { CameraPriorsFromNavigation(nav, &times, options); }),
      "image_times.csv: 5 of its 6 images lie outside the navigation (the "
      "images from 1723388002.75 (2024-08-11T14:53:22.75Z) to "
      "1728410102.75 (2024-10-08T17:55:02.75Z) s on the navigation's clock, "
      "with --time_offset 2.5; nav.csv from 1728410000.25 "
      "(2024-10-08T17:53:20.25Z) to 1728413600.25 (2024-10-08T18:53:20.25Z) "
      "s). Is the camera clock off by about 58 d 2 h 59 min 57.5 s? "
      "--time_offset 5022000 puts the median of those 5 at the navigation's "
      "median time");
  // Applied, the offset places every image inside the log.
  options.time_offset_s = 5022000.0;
  times.pop_back();
  EXPECT_EQ(CameraPriorsFromNavigation(nav, &times, options).size(), 5u);
}

// Yaw from 179 to -179 deg turns 2 deg through 180, not 358 back.
TEST(CameraPrior, AttitudeTakesTheShorterArc) {
  NavRecord a;
  a.rpy_rad = Eigen::Vector3d(0.0, 0.0, 179.0 * kDegToRad);
  NavRecord b = a;
  b.time_s = 1.0;
  b.rpy_rad.z() = -179.0 * kDegToRad;
  const std::vector<ImageTime> times = {{"mid", 0.5, 0, 1}};
  const CameraPrior prior =
      CameraPriorsFromNavigation({a, b}, &times, NavToCameraOptions())[0];
  const Eigen::Matrix3d world_from_vehicle =
      prior.cam_from_world_rotation->conjugate().toRotationMatrix() *
      NominalVehicleFromCamRotation(CameraMount::kDown).transpose();
  EXPECT_NEAR(std::abs(RollPitchYawFromRotation(world_from_vehicle).z()), M_PI,
              1e-12);
}

TEST(CameraPrior, SigmasAreInterpolatedButNotExtrapolated) {
  const Motion motion;
  std::vector<NavRecord> nav = {motion.Row("a", 0.0), motion.Row("b", 2.0)};
  nav[1].position_sigma *= 3.0;
  nav[1].rpy_sigma_rad *= 2.0;
  const std::vector<ImageTime> times = {{"mid", 0.5, 0, 1},
                                        {"past", 2.5, 0, 2}};
  NavToCameraOptions options;  // no lever arm: position sigma alone
  const std::vector<CameraPrior> priors =
      CameraPriorsFromNavigation(nav, &times, options);
  const Eigen::Vector3d mid_sigma = nav[0].position_sigma * 1.5;
  EXPECT_LT(
      (priors[0].position_covariance.diagonal().cwiseSqrt() - mid_sigma).norm(),
      1e-12);
  const Eigen::Vector3d mid_rpy_sigma = nav[0].rpy_sigma_rad * 1.25;
  EXPECT_LT((priors[0].rotation_covariance -
             WorldRotationCovariance(
                 RollPitchYawFromRotation(motion.WorldFromVehicle(0.5)),
                 mid_rpy_sigma))
                .norm(),
            1e-15);
  EXPECT_LT((priors[1].position_covariance.diagonal().cwiseSqrt() -
             nav[1].position_sigma)
                .norm(),
            1e-12);
}

TEST(CameraPrior, ByNameEachRowIsItsImageAndTheTimeOffsetMovesAlongTheLog) {
  const Motion motion;
  const std::vector<NavRecord> nav = {motion.Row("a.png", 0.0, 1, 2),
                                      motion.Row("b.png", 1.0, 1, 3),
                                      motion.Row("c.png", 2.0, 1, 4)};
  NavToCameraOptions options = SomeCamera();
  const Rigid3d vehicle_from_cam = VehicleFromCam(options);
  std::vector<CameraPrior> priors =
      CameraPriorsFromNavigation(nav, nullptr, options);
  ASSERT_EQ(priors.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(priors[i].image_name, nav[i].image_name);
    EXPECT_EQ(priors[i].sampling, NavSampling::kExact);
    EXPECT_LT(PoseError(priors[i],
                        WorldFromCam(motion, nav[i].time_s, vehicle_from_cam)),
              1e-12);
  }
  // Images taken 0.25 s after their rows' times.
  options.time_offset_s = 0.25;
  priors = CameraPriorsFromNavigation(nav, nullptr, options);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(priors[i].time_s, nav[i].time_s + 0.25);
    EXPECT_LT(PoseError(priors[i], WorldFromCam(motion, nav[i].time_s + 0.25,
                                                vehicle_from_cam)),
              1e-12);
  }
  EXPECT_EQ(priors[2].sampling, NavSampling::kExtrapolated);
  // A log without image names needs the images' times.
  std::vector<NavRecord> unnamed = nav;
  for (NavRecord& row : unnamed) row.image_name.clear();
  EXPECT_EQ(
      ErrorOf([&] { CameraPriorsFromNavigation(unnamed, nullptr, options); }),
      "nav.csv:2: the navigation has no image names; give the images' times "
      "(image_times.csv)");
}

TEST(CameraPrior, ImagesFallInTheDiveWhoseSpanHoldsThem) {
  const Motion motion;
  const std::vector<NavRecord> nav = {
      motion.Row("", 0.0, 1, 2),   motion.Row("", 1.0, 1, 3),
      motion.Row("", 100.0, 2, 4), motion.Row("", 102.0, 2, 5),
      motion.Row("", 1.5, 3, 6),   motion.Row("", 4.0, 3, 7),
      motion.Row("", 50.0, 4, 8)};
  const NavToCameraOptions options;
  const auto run = [&](const ImageTime& image) {
    const std::vector<ImageTime> times = {image};
    return CameraPriorsFromNavigation(nav, &times, options);
  };
  EXPECT_EQ(run({"x", 101.0, 0, 1})[0].dive, 2);
  EXPECT_EQ(run({"x", 3.5, 0, 1})[0].dive, 3);
  EXPECT_EQ(run({"x", 50.0, 0, 1})[0].dive, 4);
  // Dives 1 and 3 overlap at 1.6 s (dive 1 extrapolated by its 1 s).
  EXPECT_EQ(ErrorOf([&] {
              run({"x", 1.6, 0, 9});
            }),
            "image_times.csv:9: image 'x' at navigation time 1.6 s lies in "
            "the navigation of several dives; dive 1: 0 to 1 s, nav.csv lines "
            "2 to 3; dive 2: 100 to 102 s, nav.csv lines 4 to 5; dive 3: 1.5 "
            "to 4 s, nav.csv lines 6 to 7; dive 4: 50 to 50 s, nav.csv lines "
            "8 to 8; give image_times.csv a dive column");
  EXPECT_EQ(run({"x", 1.6, 3, 9})[0].dive, 3);
  EXPECT_EQ(ErrorOf([&] {
              run({"x", 1.6, 5, 9});
            }),
            "image_times.csv:9: image 'x' is of dive 5, which nav.csv has no "
            "rows for");
  // A single row places images at its own time only.
  EXPECT_EQ(ErrorOf([&] {
              run({"x", 50.5, 4, 9});
            }),
            "image_times.csv:9: image 'x' at navigation time 50.5 s lies "
            "outside the navigation of dive 4 (50 to 50 s, nav.csv lines 8 to "
            "8): a single row gives a prior only at its own time");
  EXPECT_NE(ErrorOf([&] {
              run({"x", 60.0, 0, 9});
            }).find("lies outside the navigation of every dive"),
            std::string::npos);
  // Hand-made records must keep time order too.
  std::vector<NavRecord> backwards = {motion.Row("", 2.0, 1, 2),
                                      motion.Row("", 1.0, 1, 3)};
  EXPECT_EQ(ErrorOf([&] {
              const std::vector<ImageTime> times = {{"x", 1.5, 0, 1}};
              CameraPriorsFromNavigation(backwards, &times, options);
            }),
            "nav.csv:3: time 1 s is not after the previous row of dive 1 "
            "(line 2)");
}

RigConfig TwoCameraRig() {
  RigConfig rig;
  rig.cameras.resize(2);
  rig.cameras[0].camera_id = 1;
  rig.cameras[0].image_prefix = "cam1/";
  rig.cameras[1].camera_id = 2;
  rig.cameras[1].image_prefix = "cam2/";
  rig.cameras[1].cam_from_rig.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()));
  rig.cameras[1].cam_from_rig.translation = Eigen::Vector3d(-0.4, 0.05, 0.1);
  rig.cameras[1].time_offset_s = 0.04;
  return rig;
}

// Camera 2 at its own time is camera 1's pose at that time followed by
// cam2_from_rig (rig frame = camera 1).
TEST(CameraPrior, RigCamerasSitAtTheirRelativePoseAtTheirOwnTimes) {
  const Motion motion;
  const RigConfig rig = TwoCameraRig();
  const std::vector<NavRecord> nav = {motion.Row("cam1/0.png", 0.0),
                                      motion.Row("cam1/1.png", 1.0)};
  const NavToCameraOptions options = SomeCamera();
  const std::vector<ImageTime> times = {{"cam1/0.png", 0.0, 0, 2},
                                        {"cam2/0.png", 0.04, 0, 3},
                                        {"cam2/1.png", 1.04, 0, 4}};
  const std::vector<CameraPrior> priors =
      CameraPriorsFromNavigation(nav, &times, options, &rig);
  ASSERT_EQ(priors.size(), 3u);
  const Rigid3d vehicle_from_cam1 = VehicleFromCam(options);
  for (size_t i = 1; i < 3; ++i) {
    const Rigid3d cam1_from_world =
        WorldFromCam(motion, times[i].time_s, vehicle_from_cam1).Inverse();
    const Rigid3d& cam2_from_rig = rig.cameras[1].cam_from_rig;
    Rigid3d cam2_from_world;
    cam2_from_world.rotation =
        cam2_from_rig.rotation * cam1_from_world.rotation;
    cam2_from_world.translation = cam2_from_rig * cam1_from_world.translation;
    EXPECT_LT(PoseError(priors[i], cam2_from_world.Inverse()), 1e-12);
  }
  EXPECT_EQ(priors[2].sampling, NavSampling::kExtrapolated);
  const std::vector<ImageTime> stray = {{"cam3/0.png", 0.0, 0, 7}};
  EXPECT_EQ(
      ErrorOf([&] { CameraPriorsFromNavigation(nav, &stray, options, &rig); }),
      "image_times.csv:7: image 'cam3/0.png' belongs to no camera of the rig "
      "(image prefixes 'cam1/', 'cam2/')");
}

TEST(CameraPrior, RigImageTimesFollowTheReferenceRowsByTheRigsDelays) {
  const Motion motion;
  const RigConfig rig = TwoCameraRig();
  const std::vector<NavRecord> nav = {motion.Row("cam1/0.png", 0.0, 1, 2),
                                      motion.Row("cam1/1.png", 1.0, 2, 3)};
  const std::vector<ImageTime> times = RigImageTimes(
      nav, rig,
      {"cam1/0.png", "cam2/1.png", "cam2/0.png", "cam2/9.png", "other.png"});
  ASSERT_EQ(times.size(), 3u);
  EXPECT_EQ(times[0].image_name, "cam1/0.png");
  EXPECT_EQ(times[0].time_s, 0.0);
  EXPECT_EQ(times[1].image_name, "cam2/1.png");
  EXPECT_EQ(times[1].time_s, 1.04);
  EXPECT_EQ(times[1].dive, 2);
  EXPECT_EQ(times[1].line, 3);
  EXPECT_EQ(times[2].time_s, 0.04);
}

// The covariances against the scatter of camera poses computed from
// navigation perturbed by its sigmas.
TEST(CameraPrior, CovariancesMatchMonteCarlo) {
  const Motion motion;
  NavRecord row = motion.Row("cam2/a.png", 0.0);
  row.position_sigma = Eigen::Vector3d(0.01, 0.02, 0.005);
  row.rpy_sigma_rad = Eigen::Vector3d(1.0, 0.5, 2.0) * kDegToRad;
  // A long lever arm so that attitude errors move the camera as much as
  // position errors do.
  NavToCameraOptions options = SomeCamera();
  options.lever_arm_m = Eigen::Vector3d(0.8, -0.5, 0.3);
  const RigConfig rig = TwoCameraRig();
  const CameraPrior prior =
      CameraPriorsFromNavigation({row}, nullptr, options, &rig)[0];
  const Eigen::Matrix3d prior_world_from_cam =
      prior.cam_from_world_rotation->conjugate().toRotationMatrix();

  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto gaussian = [&](const Eigen::Vector3d& sigma) {
    return Eigen::Vector3d(sigma.x() * normal(rng), sigma.y() * normal(rng),
                           sigma.z() * normal(rng));
  };
  Eigen::Matrix3d position_sum = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d rotation_sum = Eigen::Matrix3d::Zero();
  const int draws = 40000;
  for (int i = 0; i < draws; ++i) {
    NavRecord noisy = row;
    noisy.position += gaussian(row.position_sigma);
    noisy.rpy_rad += gaussian(row.rpy_sigma_rad);
    noisy.position_sigma.setZero();
    noisy.rpy_sigma_rad.setZero();
    const CameraPrior sample =
        CameraPriorsFromNavigation({noisy}, nullptr, options, &rig)[0];
    const Eigen::Vector3d dp = sample.position - prior.position;
    const Eigen::Vector3d w =
        Log(sample.cam_from_world_rotation->conjugate().toRotationMatrix() *
            prior_world_from_cam.transpose());
    position_sum += dp * dp.transpose();
    rotation_sum += w * w.transpose();
  }
  const double position_error =
      (position_sum / draws - prior.position_covariance).norm() /
      prior.position_covariance.norm();
  const double rotation_error =
      (rotation_sum / draws - prior.rotation_covariance).norm() /
      prior.rotation_covariance.norm();
  std::cout << "[ figures ] rig camera prior covariances vs Monte Carlo "
               "(40000 draws, relative Frobenius): position "
            << position_error << ", rotation " << rotation_error << "\n";
  EXPECT_LT(position_error, 0.03);
  EXPECT_LT(rotation_error, 0.03);
  // The lever arm's share is not small here: without it the position
  // covariance would be far off.
  EXPECT_GT((prior.position_covariance -
             Eigen::Matrix3d(row.position_sigma.cwiseAbs2().asDiagonal()))
                    .norm() /
                prior.position_covariance.norm(),
            0.2);
}

// A USBL log: positions only. The lever arm's horizontal part (0.6, -0.2)
// turns with a yaw nobody logged: the camera is placed at the arm's
// vertical part, the circle's radius² / 2 added along each horizontal axis,
// and the tilt of roll and pitch (5 deg each, unlogged) on top: the
// vertical 0.3 m swings by 0.3 * 5 deg sideways, the horizontal 0.63 m by
// 0.63 * 5 deg up and down. No rotation or gravity is claimed.
TEST(CameraPrior, APositionOnlyLogSpreadsTheLeverArmOverItsCircle) {
  const Motion motion;
  NavRecord row = motion.Row("a.png", 0.0);
  row.has_roll_pitch = false;
  row.has_yaw = false;
  row.rpy_rad.setZero();
  row.rpy_sigma_rad.setZero();
  const CameraPrior prior =
      CameraPriorsFromNavigation({row}, nullptr, SomeCamera())[0];
  EXPECT_EQ(prior.position, row.position + Eigen::Vector3d(0, 0, -0.3));
  const double tilt2 = std::pow(5.0 * kDegToRad, 2);
  const Eigen::Matrix3d expected =
      Eigen::Vector3d(0.25 + 0.2 + 0.09 * tilt2, 0.36 + 0.2 + 0.09 * tilt2,
                      0.0004 + 0.4 * tilt2)
          .asDiagonal();
  EXPECT_LT((prior.position_covariance - expected).norm(), 1e-15);
  EXPECT_FALSE(prior.cam_from_world_rotation.has_value());
  EXPECT_FALSE(prior.gravity_in_cam.has_value());
}

// Roll and pitch without heading: the camera's gravity direction is known
// (it needs no yaw), its rotation is not.
TEST(CameraPrior, RollAndPitchWithoutHeadingGiveGravityOnly) {
  const Motion motion;
  const NavRecord full = motion.Row("a.png", 0.0);
  NavRecord row = full;
  row.has_yaw = false;
  row.rpy_rad.z() = 0.0;
  const NavToCameraOptions options = SomeCamera();
  const CameraPrior with_yaw =
      CameraPriorsFromNavigation({full}, nullptr, options)[0];
  const CameraPrior prior =
      CameraPriorsFromNavigation({row}, nullptr, options)[0];
  ASSERT_TRUE(prior.gravity_in_cam.has_value());
  EXPECT_LT((*prior.gravity_in_cam -
             *with_yaw.cam_from_world_rotation * -Eigen::Vector3d::UnitZ())
                .norm(),
            1e-14);
  EXPECT_FALSE(prior.cam_from_world_rotation.has_value());
  // Centred on the arm's height under the logged roll and pitch.
  const Eigen::Vector3d arm =
      WorldFromVehicleRotation(row.rpy_rad) * options.lever_arm_m;
  EXPECT_LT(
      (prior.position - row.position - Eigen::Vector3d(0, 0, arm.z())).norm(),
      1e-14);
}

// Heading without roll and pitch: roll and pitch taken as 0 with their
// unlogged sigma (5 deg), carried through a long lever arm; the position
// covariance against the scatter of camera centres over draws of the
// attitude the vehicle may have had.
TEST(CameraPrior, HeadingWithoutRollAndPitchMatchesMonteCarlo) {
  const Motion motion;
  NavRecord row = motion.Row("a.png", 0.0);
  row.has_roll_pitch = false;
  row.rpy_rad.head<2>().setZero();
  row.rpy_sigma_rad = Eigen::Vector3d(0.0, 0.0, 2.0 * kDegToRad);
  row.position_sigma = Eigen::Vector3d(0.01, 0.02, 0.005);
  NavToCameraOptions options = SomeCamera();
  options.lever_arm_m = Eigen::Vector3d(0.8, -0.5, 0.3);
  const CameraPrior prior =
      CameraPriorsFromNavigation({row}, nullptr, options)[0];
  EXPECT_FALSE(prior.cam_from_world_rotation.has_value());
  EXPECT_FALSE(prior.gravity_in_cam.has_value());
  EXPECT_LT((prior.position - row.position -
             WorldFromVehicleRotation(row.rpy_rad) * options.lever_arm_m)
                .norm(),
            1e-14);

  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Vector3d rpy_sigma(5.0 * kDegToRad, 5.0 * kDegToRad,
                                  2.0 * kDegToRad);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  const int draws = 40000;
  for (int i = 0; i < draws; ++i) {
    Eigen::Vector3d rpy = row.rpy_rad;
    Eigen::Vector3d position = row.position;
    for (int k = 0; k < 3; ++k) {
      rpy(k) += rpy_sigma(k) * normal(rng);
      position(k) += row.position_sigma(k) * normal(rng);
    }
    const Eigen::Vector3d dp =
        position + WorldFromVehicleRotation(rpy) * options.lever_arm_m -
        prior.position;
    sum += dp * dp.transpose();
  }
  const double error = (sum / draws - prior.position_covariance).norm() /
                       prior.position_covariance.norm();
  std::cout << "[ figures ] heading-only prior position covariance vs Monte "
               "Carlo (40000 draws, relative Frobenius): "
            << error << "\n";
  EXPECT_LT(error, 0.03);
  // Without the unlogged roll and pitch it would be far off.
  options.unlogged_roll_pitch_sigma_deg = 1e-6;
  EXPECT_GT((CameraPriorsFromNavigation({row}, nullptr, options)[0]
                 .position_covariance -
             prior.position_covariance)
                    .norm() /
                prior.position_covariance.norm(),
            0.5);
}

}  // namespace
}  // namespace uw
