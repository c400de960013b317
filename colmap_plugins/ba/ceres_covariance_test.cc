#include "colmap_plugins/ba/ceres_covariance.h"

#include <algorithm>
#include <iostream>

#include <gtest/gtest.h>

#include "colmap_plugins/ba/test_covariance_problem.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

using test::Gauge;
using test::SmallProblem;

// Worst relative difference of the marginal blocks, Ceres against ours.
double WorstDifference(const SchurCovariance& ours,
                       const SchurCovariance& theirs) {
  EXPECT_EQ(ours.reduced.size(), theirs.reduced.size());
  EXPECT_EQ(ours.points.size(), theirs.points.size());
  double worst = 0.0;
  for (size_t a = 0; a < theirs.reduced.size(); ++a) {
    if (theirs.reduced[a].size() == 0) continue;  // held: no coordinates
    EXPECT_EQ(ours.reduced[a].rows(), theirs.reduced[a].rows());
    worst = std::max(worst, (ours.reduced[a] - theirs.reduced[a]).norm() /
                                theirs.reduced[a].norm());
  }
  for (size_t j = 0; j < theirs.points.size(); ++j) {
    worst = std::max(worst, (ours.points[j] - theirs.points[j]).norm() /
                                theirs.points[j].norm());
  }
  return worst;
}

// Both of Ceres' algorithms give what the Schur route gives, held cameras
// and priors as the gauge, with a robust loss.
TEST(CeresCovariance, EqualsTheSchurRoute) {
  for (const CeresCovarianceAlgorithm algorithm :
       {CeresCovarianceAlgorithm::kDenseSvd,
        CeresCovarianceAlgorithm::kSparseQr}) {
    for (const Gauge gauge : {Gauge::kHeld, Gauge::kPriors}) {
      SmallProblem problem(gauge, true);
      const SchurCovariance ours = ComputeSchurCovariance(
          &problem.problem(), problem.reduced(), problem.points(), {});
      CeresCovarianceOptions options;
      options.algorithm = algorithm;
      const SchurCovariance theirs = ComputeCeresCovariance(
          &problem.problem(), problem.reduced(), problem.points(), options);
      const double worst = WorstDifference(ours, theirs);
      std::cout << "[ figures ] "
                << (algorithm == CeresCovarianceAlgorithm::kDenseSvd
                        ? "DENSE_SVD"
                        : "SPARSE_QR")
                << (gauge == Gauge::kHeld ? ", held" : ", priors")
                << ": worst block relative difference " << worst << "\n";
      // The priors-only datum is ill-conditioned (schur_covariance_test.cc,
      // IllConditionedProblemsLoseAt1e8To1e7): both engines lose ~1e-8
      // there; held cameras are exact.
      EXPECT_LT(worst, gauge == Gauge::kHeld ? 1e-9 : 1e-7);
      EXPECT_EQ(theirs.num_reduced_coordinates, ours.num_reduced_coordinates);
    }
  }
}

TEST(CeresCovariance, RefusesAFreeGauge) {
  SmallProblem problem(Gauge::kFree, false);
  ExpectErrorContaining(
      [&] {
        ComputeCeresCovariance(&problem.problem(), problem.reduced(),
                               problem.points(), {});
      },
      "rank deficient");
}

TEST(CeresCovariance, ChecksItsOptions) {
  CeresCovarianceOptions options;
  options.num_threads = 0;
  ExpectErrorContaining([&] { options.Check(); }, "num_threads");
}

}  // namespace
}  // namespace uw
