#include "colmap_plugins/ba/difference_noise.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "common/util/error.h"

namespace uw {

std::optional<DifferenceNoise> EstimateDifferenceNoise(
    std::vector<TimedResidual> residuals, int lag, int min_differences) {
  if (lag < 1) throw ErrorAt("the lag of a difference must be >= 1, not ", lag);
  for (const TimedResidual& r : residuals) {
    if (Eigen::LLT<Eigen::Matrix3d>(r.covariance).info() != Eigen::Success) {
      throw ErrorAt(
          "a navigation prior's covariance is not positive "
          "definite (dive ",
          r.dive, ", time ", r.time_s, ")");
    }
  }
  std::stable_sort(residuals.begin(), residuals.end(),
                   [](const TimedResidual& a, const TimedResidual& b) {
                     return a.dive != b.dive ? a.dive < b.dive
                                             : a.time_s < b.time_s;
                   });
  // One sample per dive and time: the images of a rig share it.
  residuals.erase(
      std::unique(residuals.begin(), residuals.end(),
                  [](const TimedResidual& a, const TimedResidual& b) {
                    return a.dive == b.dive && a.time_s == b.time_s;
                  }),
      residuals.end());
  double sum = 0.0;
  int count = 0;
  const size_t k = static_cast<size_t>(lag);
  for (size_t i = k; i + k < residuals.size(); ++i) {
    const TimedResidual& before = residuals[i - k];
    const TimedResidual& here = residuals[i];
    const TimedResidual& after = residuals[i + k];
    if (before.dive != here.dive || after.dive != here.dive) continue;
    const double a =
        (after.time_s - here.time_s) / (after.time_s - before.time_s);
    const double b = 1.0 - a;
    const Eigen::Vector3d difference =
        a * before.residual + b * after.residual - here.residual;
    const Eigen::Matrix3d covariance =
        a * a * before.covariance + b * b * after.covariance + here.covariance;
    const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
    sum += difference.dot(llt.solve(difference));
    ++count;
  }
  if (count < min_differences) return std::nullopt;
  return DifferenceNoise{std::sqrt(sum / (3.0 * count)), count};
}

}  // namespace uw
