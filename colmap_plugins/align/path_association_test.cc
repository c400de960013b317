#include "colmap_plugins/align/path_association.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/util/error.h"

namespace uw {
namespace {

// A vehicle path at 1 m/s that weaves and changes depth, so that its shape
// pins the cameras along it.
Eigen::Vector3d PathAt(double time_s) {
  return {time_s, 3.0 * std::sin(time_s / 10.0),
          -20.0 + 0.8 * std::cos(time_s / 7.0)};
}

Sim3d TrueMapFromModel() {
  Sim3d b_from_a;
  b_from_a.scale = 0.42;
  b_from_a.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.9, Eigen::Vector3d(0.2, 0.3, 1.0).normalized()));
  b_from_a.translation = Eigen::Vector3d(350.0, -120.0, 4.0);
  return b_from_a;
}

// Navigation at 10 Hz over 0..100 s; cameras every 1.7 s from 0.53 s: no
// camera time is a navigation time.
struct Scenario {
  TimedPath nav;
  std::vector<double> camera_times_s;
  std::vector<Eigen::Vector3d> centres_in_model;
};

Scenario MakeScenario() {
  Scenario scenario;
  for (int i = 0; i <= 1000; ++i) {
    scenario.nav.times_s.push_back(0.1 * i);
    scenario.nav.positions.push_back(PathAt(0.1 * i));
  }
  const Sim3d model_from_map = TrueMapFromModel().Inverse();
  for (double time = 0.53; time < 99.0; time += 1.7) {
    scenario.camera_times_s.push_back(time);
    scenario.centres_in_model.push_back(model_from_map * PathAt(time));
  }
  return scenario;
}

double MaxCentreError(const Sim3d& estimate, const Scenario& scenario) {
  double max_error = 0.0;
  for (size_t k = 0; k < scenario.centres_in_model.size(); ++k) {
    max_error = std::max(max_error, (estimate * scenario.centres_in_model[k] -
                                     PathAt(scenario.camera_times_s[k]))
                                        .norm());
  }
  return max_error;
}

TEST(AlignToPathByClosestPoints,
     RecoversTheSimilarityFromUnsynchronisedCameras) {
  const Scenario scenario = MakeScenario();
  PathAssociationOptions options;
  options.similarity.robust = false;
  // Image order only, then camera times known to 0.4 s (a clock offset).
  std::vector<double> offset_times = scenario.camera_times_s;
  for (double& time : offset_times) time += 0.4;
  const std::vector<const std::vector<double>*> initial_times = {nullptr,
                                                                 &offset_times};
  for (const std::vector<double>* times : initial_times) {
    const PathAssociationResult result = AlignToPathByClosestPoints(
        scenario.centres_in_model, times, scenario.nav, options);
    const double max_error =
        MaxCentreError(result.similarity.b_from_a, scenario);
    double max_time_error = 0.0;
    for (size_t k = 0; k < scenario.camera_times_s.size(); ++k) {
      max_time_error = std::max(
          max_time_error,
          std::abs(result.associated_times_s[k] - scenario.camera_times_s[k]));
    }
    std::cout << "[ figures ] closest-point association ("
              << (times == nullptr ? "image order" : "times +0.4 s")
              << "): " << result.iterations << " iterations, converged "
              << result.converged << ", scale error "
              << result.similarity.b_from_a.scale / TrueMapFromModel().scale - 1
              << ", max camera centre error " << max_error
              << " m, max time error " << max_time_error << " s, RMS "
              << result.similarity.rms_m << " m\n";
    EXPECT_TRUE(result.converged);
    // The polyline's chords stay within ~5e-5 m of the smooth path.
    EXPECT_LT(max_error, 1e-3);
    EXPECT_LT(max_time_error, 1e-3);
    EXPECT_NEAR(result.similarity.b_from_a.scale, TrueMapFromModel().scale,
                1e-5);
  }
}

TEST(AlignToPathByClosestPoints, NeverJoinsDives) {
  // Two parallel passes as two dives: the gap between them is no path.
  TimedPath path;
  for (int dive = 1; dive <= 2; ++dive) {
    for (int i = 0; i <= 10; ++i) {
      path.times_s.push_back(100.0 * dive + i);
      path.positions.emplace_back(i, 5.0 * dive, 0.1 * i * i);
      path.dives.push_back(dive);
    }
  }
  // A camera halfway between the end of dive 1 and the start of dive 2.
  const std::vector<Eigen::Vector3d> centres = {
      {0, 5, 0}, {10, 5, 10}, {5, 5, 2.5}, {5, 7.5, 0}, {0, 10, 0}};
  PathAssociationOptions options;
  options.similarity.robust = false;
  options.max_iterations = 1;
  const PathAssociationResult result =
      AlignToPathByClosestPoints(centres, nullptr, path, options);
  for (const Eigen::Vector3d& point : result.associated_positions) {
    EXPECT_TRUE(std::abs(point.y() - 5.0) < 1e-9 ||
                std::abs(point.y() - 10.0) < 1e-9)
        << point.transpose();
  }
}

TEST(AlignToPathByClosestPoints, RejectsBadPaths) {
  TimedPath path;
  path.times_s = {0.0, 1.0, 1.0};
  path.positions = {{0, 0, 0}, {1, 0, 0}, {2, 1, 0}};
  const std::vector<Eigen::Vector3d> centres = {
      {0, 0, 0}, {1, 0, 0}, {2, 1, 0}};
  EXPECT_THROW(AlignToPathByClosestPoints(centres, nullptr, path, {}), Error);
  path.times_s = {0.0};
  path.positions = {{0, 0, 0}};
  EXPECT_THROW(AlignToPathByClosestPoints(centres, nullptr, path, {}), Error);
}

}  // namespace
}  // namespace uw
