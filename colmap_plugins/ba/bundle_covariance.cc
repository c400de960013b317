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

void BundleCovarianceOptions::Check() const {
  if (!(std::isfinite(pixel_sigma_px) && pixel_sigma_px >= 0.0)) {
    throw ErrorAt("the pixel sigma (", pixel_sigma_px,
                  " px) must be >= 0 (0: estimated)");
  }
  if (num_samples < 0) {
    throw ErrorAt("the number of samples (", num_samples, ") must be >= 0");
  }
}

}  // namespace uw
