// What the survey report reads, besides the model: the files that
// bundle_adjuster, laserscale estimate, model_comparer, dense_mesher and
// the scripts wrote (docs/formats.md). Each reader keeps only what the
// report shows and throws uw::Error naming the file (and key or line) when
// the file is not what it should be.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "common/util/csv.h"

namespace uw {

// The report's inputs; every path but the model and the output folder may
// be empty (its section is then left out, with a note saying which flag
// would add it).
struct SurveyReportInputs {
  std::filesystem::path model_path;          // COLMAP model (BIN or TXT)
  std::filesystem::path ba_report_path;      // bundle_adjuster's ba_report.json
  std::filesystem::path nav_path;            // nav.csv
  std::filesystem::path laser_report_dir;    // laserscale estimate --out
  std::filesystem::path compare_table_path;  // compare_with_colmap table.csv
  std::filesystem::path dense_comparison_path;  // model_comparer compare.json
  std::filesystem::path mesh_path;              // dense mesh, model frame
  std::filesystem::path timings_path;           // timings.csv (stage,seconds)
  std::filesystem::path truth_dir;              // uwsim output folder
  std::filesystem::path covariance_dir;         // covariance_estimator's output

  // Throws uw::Error naming the flag and the path of the first input that
  // does not exist (a folder for the model, laser report and truth, else a
  // file).
  void Check() const;
};

// ba_report.json (format "uwmetric-ba-report").
struct BaReportSummary {
  struct Residual {
    std::string name;
    int dive = 1;
    Eigen::Vector3d error_m = Eigen::Vector3d::Zero();  // centre - prior, m
    double error_norm_m = 0.0;
    std::optional<double> mahalanobis;
  };
  struct DiveOffset {
    int dive = 1;
    int num_images = 0;
    Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();
    std::optional<Eigen::Vector3d> sigma_m;  // absent for the reference dive
  };
  double weight_px_per_m = 0.0;  // λ
  std::string weighting;
  std::string strategy;
  std::optional<double> nav_sigma_m;
  std::optional<double> prior_residual_rms_m;
  std::vector<Residual> residuals;
  std::vector<DiveOffset> dive_offsets;
  std::vector<std::string> warnings;  // the adjuster's (e.g. one pass)
};
BaReportSummary ReadBaReport(const std::filesystem::path& path);

// laserscale estimate's output folder: scale.json, items.csv, segments.csv,
// the plots and overlays.
struct LaserReportSummary {
  std::filesystem::path dir;
  std::string method;
  std::optional<double> scale;  // null without an accepted image
  double sigma = 0.0;
  double ci95_low = 0.0;
  double ci95_high = 0.0;
  double birge_ratio = 0.0;
  int num_images = 0;
  int num_accepted = 0;
  int num_iterations = 0;
  std::optional<CsvTable> items;     // items.csv
  std::optional<CsvTable> segments;  // segments.csv
  // Paths (absent ones left out) of scales.png, histogram.png,
  // convergence.png; the overlays (overlays/*.png|jpg), sorted.
  std::vector<std::filesystem::path> plots;
  std::vector<std::filesystem::path> overlays;
  // The model's covariance draws the Monte Carlo used (0: the model taken
  // as exact), each source's share of the variance, and the z-score
  // against the navigation's scale (a fused model only).
  int model_draws = 0;
  std::string model_gauge;
  std::vector<std::pair<std::string, double>> variance_shares;
  std::optional<double> navigation_z;
  bool navigation_consistent = true;
};
LaserReportSummary ReadLaserReport(const std::filesystem::path& dir);

// covariance_estimator's (or bundle_adjuster --BA.covariance 1's) folder:
// covariance.json (format "uwmetric-covariance"), cameras.csv and
// uncertainty_map.png.
struct CovarianceSummary {
  struct Quantiles {
    double median = 0.0, p95 = 0.0, max = 0.0;
  };
  std::filesystem::path dir;
  std::string gauge;
  std::string gauge_description;
  double pixel_sigma_px = 0.0;
  std::string pixel_sigma_source;
  // The factor on the navigation's stated sigmas (docs/covariance.md).
  double nav_sigma_scale = 1.0;
  std::string nav_sigma_source;
  int num_images = 0;
  int num_points = 0;
  Quantiles centre_sigma_m;
  Quantiles rotation_sigma_deg;
  std::optional<Quantiles> point_sigma_m;  // without point marginals: none
  int num_weak_points = 0;
  std::vector<std::string> warnings;
  int num_samples = 0;
  double log_scale_sigma = 0.0;
  std::string log_scale_meaning;
  CsvTable cameras;                          // cameras.csv
  std::optional<std::filesystem::path> map;  // uncertainty_map.png
};
CovarianceSummary ReadCovarianceSummary(const std::filesystem::path& dir);

// model_comparer's compare.json (format "uwmetric-model-comparison") with
// a dense_surface block.
struct DenseComparisonSummary {
  double reference_from_model_scale = 0.0;
  double camera_scene_distance = 0.0;
  double median_distance = 0.0;
  double p90_distance = 0.0;
  double rms_distance = 0.0;
  double mean_signed_distance = 0.0;
  double observed_area = 0.0;
  double covered_area = 0.0;
  double coverage = 0.0;
  double coverage_tolerance = 0.0;
  size_t num_samples = 0;
};
DenseComparisonSummary ReadDenseComparison(const std::filesystem::path& path);

// timings.csv: "stage,seconds" rows; a stage named "total" is the total.
struct StageTime {
  std::string stage;
  double seconds = 0.0;
};
std::vector<StageTime> ReadTimings(const std::filesystem::path& path);

}  // namespace uw
