#include "colmap_plugins/nav/geographic_positions.h"

#include <gtest/gtest.h>

#include "common/util/error_testing.h"

namespace uw {
namespace {

// Priors of a survey 60 m across at 43.25 N, 5.375 E, written as COLMAP
// stores WGS84 priors: (lat, lon, alt).
std::vector<PosePrior> Wgs84Priors(const LocalEnu& truth,
                                   std::vector<Eigen::Vector3d>* local) {
  std::vector<PosePrior> priors;
  for (uint32_t id = 1; id <= 4; ++id) {
    const Eigen::Vector3d enu(20.0 * id, -10.0 * id, -3.0 - id);
    local->push_back(enu);
    PosePrior prior;
    prior.image_id = id;
    prior.position = truth.ToGeodetic(enu);
    prior.coordinate_system = PosePriorCoordinateSystem::kWGS84;
    prior.position_covariance = Eigen::Matrix3d::Identity() * 1e-12;
    priors.push_back(prior);
  }
  return priors;
}

TEST(WithLocalPositions, PutsWgs84PriorsIntoTheLocalFrame) {
  const LocalEnu truth({43.25, 5.375, 0.0});
  std::vector<Eigen::Vector3d> local;
  const std::vector<PosePrior> priors = Wgs84Priors(truth, &local);
  NavLogFrame frame;
  std::vector<std::string> warnings;
  const std::vector<PosePrior> converted =
      WithLocalPositions(priors, truth.Origin(), "db.db", &frame, &warnings);
  ASSERT_EQ(converted.size(), priors.size());
  for (size_t i = 0; i < converted.size(); ++i) {
    EXPECT_LT((converted[i].position - local[i]).norm(), 1e-6) << i;
    EXPECT_EQ(converted[i].coordinate_system,
              PosePriorCoordinateSystem::kCartesian);
    // deg² or m²: COLMAP does not say, so it is not used.
    EXPECT_FALSE(converted[i].HasPositionCovariance());
  }
  ASSERT_TRUE(frame.origin);
  EXPECT_FALSE(frame.origin_automatic);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("covariances of 4 WGS84 pose priors are not "
                             "used"),
            std::string::npos)
      << warnings[0];

  // Without an origin: the first prior rounded to 0.001 deg, so that the
  // frame is shared with a geographic nav.csv of the same survey.
  NavLogFrame automatic;
  const std::vector<PosePrior> around =
      WithLocalPositions(priors, std::nullopt, "db.db", &automatic, nullptr);
  ASSERT_TRUE(automatic.origin);
  EXPECT_TRUE(automatic.origin_automatic);
  EXPECT_DOUBLE_EQ(automatic.origin->lat_deg, 43.25);
  const LocalEnu used(*automatic.origin);
  EXPECT_LT((used.ToGeodetic(around[2].position) - priors[2].position)
                .cwiseAbs()
                .maxCoeff(),
            1e-9);
}

TEST(WithLocalPositions, LeavesCartesianPriorsAndRefusesAMixture) {
  const LocalEnu truth({43.25, 5.375, 0.0});
  std::vector<Eigen::Vector3d> local;
  std::vector<PosePrior> priors = Wgs84Priors(truth, &local);
  std::vector<PosePrior> cartesian = priors;
  for (size_t i = 0; i < cartesian.size(); ++i) {
    cartesian[i].position = local[i];
    cartesian[i].coordinate_system = PosePriorCoordinateSystem::kCartesian;
  }
  NavLogFrame frame;
  const std::vector<PosePrior> same =
      WithLocalPositions(cartesian, std::nullopt, "db.db", &frame, nullptr);
  EXPECT_EQ(same[1].position, cartesian[1].position);
  EXPECT_TRUE(same[1].HasPositionCovariance());
  EXPECT_FALSE(frame.origin);
  ExpectErrorContaining(
      [&] {
        WithLocalPositions(cartesian, truth.Origin(), "db.db", nullptr,
                           nullptr);
      },
      "db.db: --origin places geographic positions, but none of its pose "
      "priors is WGS84");

  priors[2] = cartesian[2];
  ExpectErrorContaining(
      [&] {
        WithLocalPositions(priors, std::nullopt, "db.db", nullptr, nullptr);
      },
      "db.db: 3 pose priors are WGS84 (latitude, longitude) and 1 are not");
}

// Metres read as degrees: a latitude beyond 90 is named with its image.
TEST(GeographicToLocal, RefusesALatitudeBeyondNinety) {
  ExpectErrorContaining(
      [] {
        GeographicToLocal({{43.2, 5.3, 0.0}, {120.5, 30.0, -2.0}},
                          {"a.png", "b.png"}, std::nullopt, "refs.txt",
                          nullptr);
      },
      "refs.txt: image b.png has latitude 120.5");
}

}  // namespace
}  // namespace uw
