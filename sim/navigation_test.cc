#include "sim/navigation.h"

#include <gtest/gtest.h>

#include <sstream>

#include "common/util/error.h"

namespace uw::sim {
namespace {

// Stations on a straight line at 1 m/s and constant depth, two dives.
std::vector<SurveyStation> LineStations(size_t count) {
  std::vector<SurveyStation> stations;
  for (size_t i = 0; i < count; ++i) {
    SurveyStation station;
    station.image_name = std::to_string(i) + ".png";
    station.time_s = static_cast<double>(i);
    station.dive = i < count / 2 ? 1 : 2;
    station.vehicle_position = Eigen::Vector3d(static_cast<double>(i), 0, 2.0);
    stations.push_back(station);
  }
  return stations;
}

TEST(Navigation, WhiteNoiseBiasAndDepthHaveTheConfiguredSizes) {
  NavigationOptions options;
  options.site_depth_m = 502.0;  // vehicle depth 500 m
  options.drift_fraction_of_speed = 0.0;
  const auto stations = LineStations(4000);
  std::vector<Eigen::Vector3d> biases;
  const auto records = NoisyNavigation(stations, options, 11, &biases);
  ASSERT_EQ(biases.size(), 2u);
  EXPECT_EQ(biases[0].z(), 0.0);
  for (int dive = 1; dive <= 2; ++dive) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d sum_squares = Eigen::Vector3d::Zero();
    size_t n = 0;
    for (size_t i = 0; i < records.size(); ++i) {
      if (records[i].dive != dive) continue;
      const Eigen::Vector3d error =
          records[i].position - stations[i].vehicle_position - biases[dive - 1];
      sum += error;
      sum_squares += error.cwiseProduct(error);
      ++n;
    }
    const Eigen::Vector3d sigma = (sum_squares / n).cwiseSqrt();
    EXPECT_NEAR(sigma.x(), 5.0, 0.3);  // 1 % of 500 m
    EXPECT_NEAR(sigma.y(), 5.0, 0.3);
    EXPECT_NEAR(sigma.z(), 0.02, 0.002);
    EXPECT_LT((sum / n).head<2>().norm(), 0.5);  // the bias is all removed
  }
  EXPECT_NEAR(records[0].position_sigma.x(), 5.0, 1e-12);
}

TEST(Navigation, DriftIsSmoothAndGrowsWithTime) {
  NavigationOptions options;
  options.usbl_sigma_fraction_of_depth = 0.0;
  options.dive_bias_fraction_of_depth = 0.0;
  options.depth_sigma_m = 0.0;
  options.drift_fraction_of_speed = 0.05;
  auto stations = LineStations(2000);
  for (auto& station : stations) station.dive = 1;
  const auto records = NoisyNavigation(stations, options, 5, nullptr);
  double max_step = 0.0;
  for (size_t i = 1; i < records.size(); ++i) {
    const Eigen::Vector3d error_now =
        records[i].position - stations[i].vehicle_position;
    const Eigen::Vector3d error_before =
        records[i - 1].position - stations[i - 1].vehicle_position;
    max_step = std::max(max_step, (error_now - error_before).norm());
  }
  const double final_error =
      (records.back().position - stations.back().vehicle_position).norm();
  // One second at 5 % of 1 m/s moves the error by at most a few cm, while
  // over 2000 s it wanders by metres.
  EXPECT_LT(max_step, 0.25);
  EXPECT_GT(final_error, 1.0);
  EXPECT_EQ(records.back().position.z(), stations.back().vehicle_position.z());
}

TEST(Navigation, SeededAndWrittenAsCsv) {
  const auto stations = LineStations(10);
  NavigationOptions options;
  const auto a = NoisyNavigation(stations, options, 1, nullptr);
  const auto b = NoisyNavigation(stations, options, 1, nullptr);
  const auto c = NoisyNavigation(stations, options, 2, nullptr);
  EXPECT_EQ(a[3].position, b[3].position);
  EXPECT_NE(a[3].position, c[3].position);
  const std::string csv = NavigationCsv(a, options.site_depth_m);
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line[0], '#');
  std::getline(lines, line);
  EXPECT_EQ(line,
            "image_name,time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,"
            "std_roll,std_pitch,std_yaw");
  std::getline(lines, line);
  std::istringstream fields(line);
  std::string name, time, dive, x;
  std::getline(fields, name, ',');
  std::getline(fields, time, ',');
  std::getline(fields, dive, ',');
  std::getline(fields, x, ',');
  EXPECT_EQ(name, "0.png");
  EXPECT_EQ(std::stod(x), a[0].position.x());
  size_t rows = 0;
  while (std::getline(lines, line)) ++rows;
  EXPECT_EQ(rows, 9u);
}

TEST(Navigation, ExplicitDiveBiasesReplaceTheDrawnOnes) {
  const auto stations = LineStations(20);
  NavigationOptions options;
  std::vector<Eigen::Vector3d> drawn;
  const auto random = NoisyNavigation(stations, options, 3, &drawn);
  options.dive_biases_m = {{2.0, -1.0, 0.0}, {-0.5, 2.5, 0.1}};
  std::vector<Eigen::Vector3d> given;
  const auto explicit_biases = NoisyNavigation(stations, options, 3, &given);
  ASSERT_EQ(given.size(), 2u);
  EXPECT_EQ(given[1], Eigen::Vector3d(-0.5, 2.5, 0.1));
  // Only the bias changes: the white noise and drift are the seed's.
  for (size_t i = 0; i < stations.size(); ++i) {
    const int dive = stations[i].dive - 1;
    EXPECT_LT((explicit_biases[i].position - given[dive] -
               (random[i].position - drawn[dive]))
                  .norm(),
              1e-12);
  }
  options.dive_biases_m.pop_back();
  EXPECT_THROW(NoisyNavigation(stations, options, 3, nullptr), Error);
  EXPECT_THROW(options.CheckNumDives(2), Error);
  EXPECT_NO_THROW(options.CheckNumDives(1));
}

TEST(Navigation, DiveBiasesAreReadAndWrittenOnlyWhenSet) {
  const nlohmann::json defaults = NavigationOptions();
  EXPECT_FALSE(defaults.contains("dive_biases_m"));
  const nlohmann::json json = {{"dive_biases_m", {{2, 0, 0}, {0, -3, 0}}}};
  NavigationOptions read;
  json.get_to(read);
  ASSERT_EQ(read.dive_biases_m.size(), 2u);
  EXPECT_EQ(read.dive_biases_m[1], Eigen::Vector3d(0, -3, 0));
  const nlohmann::json written = read;
  EXPECT_EQ(written.at("dive_biases_m"), json.at("dive_biases_m"));
  NavigationOptions bad;
  EXPECT_THROW(nlohmann::json({{"dive_biases_m", {{1, 2}}}}).get_to(bad),
               Error);
  bad.dive_biases_m = {{1, NAN, 0}};
  EXPECT_THROW(bad.Check(), Error);
}

TEST(Navigation, OptionsAreChecked) {
  NavigationOptions options;
  options.depth_sigma_m = -1.0;
  EXPECT_THROW(options.Check(), Error);
  nlohmann::json json = NavigationOptions();
  json["speed"] = 3;
  NavigationOptions read;
  EXPECT_THROW(json.get_to(read), Error);
}

}  // namespace
}  // namespace uw::sim
