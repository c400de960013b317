#include "colmap_plugins/ba/nav_prior.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "common/util/error.h"

namespace uw {

Eigen::Matrix3d SqrtInformation(const Eigen::Matrix3d& covariance) {
  if (!covariance.allFinite() ||
      (covariance - covariance.transpose()).cwiseAbs().maxCoeff() >
          1e-9 * covariance.cwiseAbs().maxCoeff()) {
    throw ErrorAt("covariance is not finite and symmetric");
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(covariance.inverse());
  if (llt.info() != Eigen::Success ||
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance)
              .eigenvalues()
              .minCoeff() <= 0.0) {
    throw ErrorAt("covariance is not positive definite");
  }
  // information = L L^T = S^T S with S = L^T (upper triangular).
  return llt.matrixL().transpose();
}

}  // namespace uw
