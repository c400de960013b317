// The files of `uwcolmap covariance_estimator` (and bundle_adjuster
// --BA.covariance 1), docs/formats.md "Covariance":
//   covariance.bin   binary sidecar: every image's 6x6 and point's 3x3,
//                    with the model's fingerprint;
//   covariance.json  what was computed (gauge, pixel sigma, sizes, times,
//                    warnings), the intrinsics' and dive offsets' blocks,
//                    summaries of the image and point sigmas;
//   cameras.csv      per image: sigma of the centre per world axis and in
//                    all (m), of the rotation (deg);
//   points.ply       the model's points with their uncertainty measures as
//                    vertex properties;
//   uncertainty_map.png, .svg  plan view of the points coloured by sigma,
//                    in metres when the navigation priors fix the gauge,
//                    else in model units.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "colmap_plugins/ba/bundle_covariance.h"
#include "colmap_plugins/scene/model.h"
#include "common/util/figure.h"

namespace uw {

// Radius (m) of the 95 % sphere of the largest axis: sqrt(chi2_3(0.95)
// lambda_max); the volume of the 95 % ellipsoid, (4/3) pi chi2^(3/2)
// sqrt(det) (m^3); the RMS sigma sqrt(trace / 3) (m).
double LargestAxisSigma(const Eigen::Matrix3d& covariance);
double EllipsoidVolume95(const Eigen::Matrix3d& covariance);

nlohmann::json CovarianceSummaryJson(const BundleCovariance& covariance,
                                     const Reconstruction& model);

// The files above for `folder`, prepared: the map is drawn on
// construction, so that a plotting failure (no matplotlib) comes before a
// command writes anything. Write() writes them together or not at all.
// `covariance` and `model` must outlive it.
class CovarianceFiles {
 public:
  CovarianceFiles(const BundleCovariance& covariance,
                  const Reconstruction& model, std::filesystem::path folder);
  void Write() const;

 private:
  const BundleCovariance& covariance_;
  const Reconstruction& model_;
  std::filesystem::path folder_;
  std::string json_;
  std::vector<FigureFiles> map_;
};

// Prepares and writes them.
void WriteCovarianceFiles(const BundleCovariance& covariance,
                          const Reconstruction& model,
                          const std::filesystem::path& folder);

// Reads covariance.bin back for `model`; throws uw::Error naming the file
// when it is not one, or when it belongs to another model (other images,
// points or camera centres).
BundleCovariance ReadCovarianceSidecar(const std::filesystem::path& path,
                                       const Reconstruction& model);

}  // namespace uw
