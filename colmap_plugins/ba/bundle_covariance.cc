#include "colmap_plugins/ba/bundle_covariance.h"

#include <cmath>

#include "common/util/error.h"

namespace uw {

std::string CovarianceGaugeName(CovarianceGauge gauge) {
  switch (gauge) {
    case CovarianceGauge::kPriors:
      return "priors";
    case CovarianceGauge::kHeld:
      return "held";
    case CovarianceGauge::kFreeNetwork:
      return "free_network";
  }
  return "?";
}

CovarianceGauge CovarianceGaugeFromName(const std::string& name) {
  if (name == "priors") return CovarianceGauge::kPriors;
  if (name == "held") return CovarianceGauge::kHeld;
  if (name == "free_network") return CovarianceGauge::kFreeNetwork;
  throw ErrorAt("unknown covariance gauge '", name,
                "' (priors, held or free_network)");
}

std::string CovarianceMethodName(CovarianceMethod method) {
  switch (method) {
    case CovarianceMethod::kSchur:
      return "schur";
    case CovarianceMethod::kCeresSparseQr:
      return "ceres_sparse_qr";
  }
  return "?";
}

CovarianceMethod CovarianceMethodFromName(const std::string& name) {
  if (name == "schur") return CovarianceMethod::kSchur;
  if (name == "ceres_sparse_qr") return CovarianceMethod::kCeresSparseQr;
  throw ErrorAt("unknown covariance method '", name,
                "' (schur or ceres_sparse_qr)");
}

void BundleCovarianceOptions::Check() const {
  if (!(std::isfinite(pixel_sigma_px) && pixel_sigma_px >= 0.0)) {
    throw ErrorAt("the pixel sigma (", pixel_sigma_px,
                  " px) must be >= 0 (0: estimated)");
  }
  if (!(std::isfinite(nav_weight_px_per_m) && nav_weight_px_per_m >= 0.0)) {
    throw ErrorAt("the navigation weight (", nav_weight_px_per_m,
                  " px/m) must be >= 0 (0: the priors' sigmas as stated)");
  }
  if (num_samples < 0) {
    throw ErrorAt("the number of samples (", num_samples, ") must be >= 0");
  }
  if (method == CovarianceMethod::kCeresSparseQr) {
    // ceres::Covariance takes no null-space basis and gives no joint draws;
    // the co-visible blocks would be requested pair by pair.
    if (gauge == CovarianceGauge::kFreeNetwork) {
      throw ErrorAt(
          "the covariance method ceres_sparse_qr cannot give the "
          "free network (use schur)");
    }
    if (covisible_cross || num_samples > 0) {
      throw ErrorAt(
          "the covariance method ceres_sparse_qr gives marginals "
          "only: no co-visible blocks or samples (use schur)");
    }
  }
}

}  // namespace uw
