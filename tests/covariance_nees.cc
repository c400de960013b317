#include "tests/covariance_nees.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/ba/covariance_files.h"
#include "colmap_plugins/ba/covariance_samples.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"
#include "common/util/csv.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "sim/observe.h"
#include "tests/support/process.h"
#include "tests/support/uwsim_survey.h"

namespace uw::testing {
namespace {

namespace fs = std::filesystem;

// The model a mapper would give: an image is kept only with 30 points that
// three or more images see (colmap's Mapper.abs_pose_min_num_inliers). The
// scarp's line ends see too little of the wall for that at 120 points per
// image; kept, their baselines would be free, which no mapper's model holds.
constexpr int kMinRegistrationPoints = 30;

// nav.csv of `model`'s images (a log names only images the adjusted model
// has) with the true vehicle positions (truth/nav.csv) plus Gaussian
// noise of `noise_factor` times the sigmas it states: the survey's
// (nav.csv's std_x, std_y, std_z), or `horizontal_sigma_m` (> 0)
// horizontally. With `attitude`, the true roll, pitch and yaw plus noise of
// their stated sigmas too (from a stream of its own: the positions' draws
// stay as they were); the other columns as the survey's.
void WriteNoisyNavigation(const fs::path& sim_dir, const Reconstruction& model,
                          const fs::path& path, unsigned seed, bool attitude,
                          double horizontal_sigma_m, double noise_factor) {
  std::set<std::string> names;
  for (const Image& image : model.Images()) names.insert(image.name);
  const std::vector<std::string> columns = {
      "image_name", "time",  "dive",     "x",         "y",
      "z",          "roll",  "pitch",    "yaw",       "std_x",
      "std_y",      "std_z", "std_roll", "std_pitch", "std_yaw"};
  const CsvTable stated = CsvTable::Read(sim_dir / "nav.csv", columns, columns);
  const CsvTable truth =
      CsvTable::Read(sim_dir / "truth" / "nav.csv", columns, columns);
  ASSERT_EQ(stated.NumRows(), truth.NumRows());
  const auto sigma = [&](size_t row, const std::string& column) {
    return horizontal_sigma_m > 0.0 && (column == "x" || column == "y")
               ? horizontal_sigma_m
               : stated.Double(row, "std_" + column);
  };
  std::mt19937 rng(seed);
  std::mt19937 attitude_rng(seed + 1000000);
  std::normal_distribution<double> normal;
  std::ofstream out(path);
  for (size_t c = 0; c < stated.Header().size(); ++c) {
    out << (c ? "," : "") << stated.Header()[c];
  }
  out << "\n";
  out.precision(17);
  for (size_t row = 0; row < stated.NumRows(); ++row) {
    ASSERT_EQ(stated.Text(row, "image_name"), truth.Text(row, "image_name"));
    // Every row draws its noise, written or not: dropping an image leaves
    // the others' draws as they were.
    std::ostringstream line;
    line.precision(17);
    for (size_t c = 0; c < stated.Header().size(); ++c) {
      const std::string& column = stated.Header()[c];
      line << (c ? "," : "");
      if (column == "x" || column == "y" || column == "z") {
        line << truth.Double(row, column) +
                    noise_factor * sigma(row, column) * normal(rng);
      } else if (horizontal_sigma_m > 0.0 &&
                 (column == "std_x" || column == "std_y")) {
        line << horizontal_sigma_m;
      } else if (attitude &&
                 (column == "roll" || column == "pitch" || column == "yaw")) {
        line << truth.Double(row, column) +
                    stated.Double(row, "std_" + column) * normal(attitude_rng);
      } else {
        line << CsvField(stated.Text(row, column));
      }
    }
    if (names.count(stated.Text(row, "image_name")) != 0) {
      out << line.str() << "\n";
    }
  }
}

Eigen::Vector3d RotationVector(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(rotation);
  return angle_axis.angle() * angle_axis.axis();
}

// The widest angle (deg) between two of the true rays to a point: how well
// its depth is triangulated.
double TriangulationAngleDeg(const Point3D& point,
                             const Reconstruction& truth) {
  std::vector<Eigen::Vector3d> rays;
  for (const TrackElement& element : point.track) {
    rays.push_back(
        (truth.FindImage(element.image_id)->ProjectionCenter() - point.xyz)
            .normalized());
  }
  double widest = 0.0;
  for (size_t a = 0; a < rays.size(); ++a) {
    for (size_t b = a + 1; b < rays.size(); ++b) {
      widest = std::max(widest,
                        std::acos(std::clamp(rays[a].dot(rays[b]), -1.0, 1.0)));
    }
  }
  return widest * 180.0 / M_PI;
}

// One Gauss-Newton step towards the similarity x' = (1 + sigma) x +
// omega x x + tau that takes the truth's datum to the estimate's in the free
// network's metric: least squares over Ceres' tangent of every pose
// (quaternion d, translation t of cam_from_world) and point, with the null
// space's rows as Adjustment::FillSimilarityNullSpace writes them.
Sim3d FreeNetworkDatumStep(const Reconstruction& estimate,
                           const Reconstruction& true_poses,
                           const Reconstruction& true_points) {
  Eigen::Matrix<double, 7, 7> normal = Eigen::Matrix<double, 7, 7>::Zero();
  Eigen::Matrix<double, 7, 1> right = Eigen::Matrix<double, 7, 1>::Zero();
  for (const Image& image : estimate.Images()) {
    const Rigid3d& cam_from_world = image.cam_from_world;
    const Rigid3d& true_cam_from_world =
        true_poses.FindImage(image.image_id)->cam_from_world;
    // cam_from_world = [cos|d|, sin|d| d / |d|] * true cam_from_world.
    const Eigen::AngleAxisd turn(cam_from_world.rotation *
                                 true_cam_from_world.rotation.conjugate());
    Eigen::Matrix<double, 6, 1> error;
    error.head<3>() = 0.5 * turn.angle() * turn.axis();
    error.tail<3>() =
        cam_from_world.translation - true_cam_from_world.translation;
    const Eigen::Matrix3d r = cam_from_world.rotation.toRotationMatrix();
    Eigen::Matrix<double, 6, 7> rows = Eigen::Matrix<double, 6, 7>::Zero();
    rows.block<3, 3>(0, 0) = -0.5 * r;
    rows.block<3, 3>(3, 3) = -r;
    rows.block<3, 1>(3, 6) = cam_from_world.translation;
    normal += rows.transpose() * rows;
    right += rows.transpose() * error;
  }
  for (const Point3D& point : estimate.Points3D()) {
    const Eigen::Matrix<double, 3, 7> rows = SimilarityTangentAt(point.xyz);
    normal += rows.transpose() * rows;
    right += rows.transpose() *
             (point.xyz - true_points.FindPoint3D(point.point3D_id)->xyz);
  }
  const Eigen::Matrix<double, 7, 1> theta = normal.ldlt().solve(right);
  Sim3d datum;
  const Eigen::Vector3d omega = theta.head<3>();
  datum.rotation = omega.norm() > 0.0 ? Eigen::Quaterniond(Eigen::AngleAxisd(
                                            omega.norm(), omega.normalized()))
                                      : Eigen::Quaterniond::Identity();
  datum.translation = theta.segment<3>(3);
  datum.scale = std::exp(theta(6));
  return datum;
}

// Takes the free network's datum out of `estimate`: what is left is the
// error the minimum-norm pseudo-inverse describes. Iterated, not one step:
// the adjuster's gauge drifts during the solve (on the canyon plan by up to
// 0.023 rad and 0.15 m), and one first-order step left a second-order
// datum of 0.026 % in scale, 5e-5 rad and 3.5 mm, as large as the points'
// sigmas: the canyon's free network came out at poses 7.53, points 3.73
// over 400 trials, and at 5.88, 2.99 once iterated.
void RemoveFreeNetworkDatum(const Reconstruction& true_poses,
                            const Reconstruction& true_points,
                            Reconstruction* estimate) {
  constexpr int kMaxSteps = 20;
  // A nanometre, and as small in scale and angle.
  constexpr double kConverged = 1e-9;
  for (int step = 0; step < kMaxSteps; ++step) {
    const Sim3d datum =
        FreeNetworkDatumStep(*estimate, true_poses, true_points);
    TransformReconstruction(datum.Inverse(), estimate);
    if (std::abs(datum.scale - 1.0) < kConverged &&
        Eigen::AngleAxisd(datum.rotation).angle() < kConverged &&
        datum.translation.norm() < kConverged) {
      return;
    }
  }
  ADD_FAILURE() << "the free network's datum did not converge in " << kMaxSteps
                << " Gauss-Newton steps";
}

// The covariance's warnings that its world-frame sigmas are not to be
// trusted (colmap_plugins/ba/track_line.cc).
constexpr char kWeakRotationText[] = "fix the model's rotation only to";
constexpr char kOneLineText[] = "lie nearly on one line";
// NoConvergenceWarning (colmap_plugins/ba/nav_bundle_adjuster.h).
constexpr char kIterationLimitText[] = "stopped at its iteration limit";

// Points' NEES by their triangulation angle: where a mean off 3 comes from.
constexpr double kAngleBinEdgesDeg[] = {5.0, 15.0};

}  // namespace

std::string NeesFigures(const std::string& what, const Nees& nees) {
  std::ostringstream text;
  text << "[ figures ] " << nees.num_trials << " " << what
       << ": mean NEES poses " << nees.pose << " +- "
       << nees.pose_standard_error << " (6), points " << nees.point << " +- "
       << nees.point_standard_error << " (3)";
  if (nees.num_warned > 0) {
    text << "; the covariance warned in " << nees.num_warned << " trials";
  }
  return text.str();
}

Nees MeanNees(const fs::path& sim_dir, const NeesOptions& options) {
  const NeesGauge gauge = options.gauge;
  const bool fused = gauge == NeesGauge::kPriors;
  const fs::path uwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";
  const fs::path dir = FreshTestDir("uw_covariance_nees_" +
                                    sim_dir.parent_path().filename().string() +
                                    "_" + sim_dir.filename().string() +
                                    (fused                       ? "_fused"
                                     : gauge == NeesGauge::kHeld ? "_held"
                                                                 : "_free"));
  const Reconstruction truth = ReadModel(sim_dir / "truth");
  const TriangleMesh mesh = ReadPly(sim_dir / "truth" / "mesh.ply");
  std::vector<double> bin_sums(std::size(kAngleBinEdgesDeg) + 1, 0.0);
  std::vector<size_t> bin_counts(bin_sums.size(), 0);
  const char* trials_override = std::getenv("UW_NEES_TRIALS");
  const int num_trials = trials_override != nullptr ? std::stoi(trials_override)
                                                    : options.num_trials;
  const char* first_override = std::getenv("UW_NEES_FIRST_TRIAL");
  const int first_trial =
      first_override != nullptr ? std::stoi(first_override) : 0;
  std::vector<NeesTrial> trials;
  for (int trial = first_trial; trial < first_trial + num_trials; ++trial) {
    const fs::path trial_dir = dir / std::to_string(trial);
    fs::create_directories(trial_dir / "observed");
    sim::ObserveOptions observe;
    observe.pixel_sigma = 0.5;
    observe.num_points = options.points_observed;
    observe.seed = 1000 + trial;
    observe.min_registration_points = kMinRegistrationPoints;
    // Started at the truth: its points are where the truth has them.
    const Reconstruction observed = sim::ObserveModel(truth, mesh, observe);
    WriteModel(observed, trial_dir / "observed", ModelFormat::kBinary);
    std::string navigation = gauge == NeesGauge::kHeld
                                 ? " --Covariance.gauge held"
                                 : " --Covariance.gauge free_network";
    if (fused) {
      WriteNoisyNavigation(sim_dir, observed, trial_dir / "nav.csv",
                           2000 + trial, options.attitude,
                           options.horizontal_sigma_m,
                           options.navigation_noise_factor);
      navigation = " --nav " + Quoted(trial_dir / "nav.csv") +
                   SurveyMountFlags(sim_dir) +
                   (options.attitude ? " --Nav.use_attitude 1" : "");
    }
    const auto adjusted = RunProcess(
        Quoted(uwcolmap) + " bundle_adjuster --input_path " +
            Quoted(trial_dir / "observed") + " --output_path " +
            Quoted(trial_dir / "ba") + navigation + " --BA.covariance 1",
        true);
    EXPECT_EQ(adjusted.exit_code, 0) << adjusted.output;
    if (adjusted.exit_code != 0) return {};
    Reconstruction model = ReadModel(trial_dir / "ba");
    const BundleCovariance covariance = ReadCovarianceSidecar(
        trial_dir / "ba" / "covariance" / "covariance.bin", model);
    const auto warnings =
        nlohmann::json::parse(ReadFileToString(trial_dir / "ba" / "covariance" /
                                               "covariance.json"))
            .at("warnings")
            .get<std::vector<std::string>>();
    // An adjustment stopped short of its minimum is not what a covariance
    // describes: its NEES would measure the solver.
    const bool stopped =
        std::any_of(warnings.begin(), warnings.end(), [](const auto& text) {
          return text.find(kIterationLimitText) != std::string::npos;
        });
    EXPECT_FALSE(stopped) << "trial " << trial
                          << ": the adjustment stopped at its iteration "
                             "limit; raise it for this plan";
    if (stopped) return {};
    const bool warned =
        std::any_of(warnings.begin(), warnings.end(), [](const auto& text) {
          return text.find(kWeakRotationText) != std::string::npos ||
                 text.find(kOneLineText) != std::string::npos;
        });
    if (gauge == NeesGauge::kFreeNetwork) {
      RemoveFreeNetworkDatum(truth, observed, &model);
    }
    double trial_pose = 0.0;
    double trial_point = 0.0;
    size_t trial_poses = 0;
    for (const ImageCovariance& image : covariance.images) {
      // Held: the first image has no covariance, the second one holds a
      // coordinate (a singular 6x6); neither is a 6-dof estimate.
      if (image.held) continue;
      const Eigen::LDLT<PoseCovariance> ldlt(image.rotation_center);
      if (ldlt.rcond() < 1e-12) continue;
      const Image& estimate = *model.FindImage(image.image_id);
      const Image& true_image = *truth.FindImage(image.image_id);
      Eigen::Matrix<double, 6, 1> error;
      // world_from_cam_estimate = Exp(w) world_from_cam_true.
      error.head<3>() =
          RotationVector((estimate.cam_from_world.rotation.conjugate() *
                          true_image.cam_from_world.rotation)
                             .toRotationMatrix());
      error.tail<3>() =
          estimate.ProjectionCenter() - true_image.ProjectionCenter();
      trial_pose += error.dot(ldlt.solve(error));
      ++trial_poses;
    }
    for (const PointCovariance& point : covariance.points) {
      const Point3D& true_point = *observed.FindPoint3D(point.point3D_id);
      const Eigen::Vector3d error =
          model.FindPoint3D(point.point3D_id)->xyz - true_point.xyz;
      const double nees = error.dot(point.xyz.ldlt().solve(error));
      trial_point += nees;
      const double angle = TriangulationAngleDeg(true_point, truth);
      const size_t bin = std::upper_bound(std::begin(kAngleBinEdgesDeg),
                                          std::end(kAngleBinEdgesDeg), angle) -
                         std::begin(kAngleBinEdgesDeg);
      bin_sums[bin] += nees;
      ++bin_counts[bin];
    }
    trials.push_back({trial_pose, trial_poses, trial_point,
                      covariance.points.size(), warned});
    std::cout << "[ trial " << trial << " ] mean NEES poses "
              << trial_pose / trial_poses << " (" << trial_poses
              << " poses), points " << trial_point / covariance.points.size()
              << " (" << covariance.points.size() << " points)"
              << (warned ? " (warned)" : "")
              << std::endl;  // flushed: a stopped run still shows its trials
    fs::remove_all(trial_dir);
  }
  std::cout << "[ figures ] points' mean NEES by triangulation angle:";
  for (size_t bin = 0; bin < bin_sums.size(); ++bin) {
    std::cout << (bin == 0                     ? " under "
                  : bin + 1 == bin_sums.size() ? ", over "
                                               : ", to ")
              << kAngleBinEdgesDeg[std::min(bin, bin_sums.size() - 2)]
              << " deg " << bin_sums[bin] / std::max<size_t>(1, bin_counts[bin])
              << " (" << bin_counts[bin] << " points)";
  }
  std::cout << "\n";
  return SummariseNees(trials);
}

Nees SummariseNees(const std::vector<NeesTrial>& trials) {
  const auto standard_error = [](const std::vector<double>& values) {
    double mean = 0.0;
    for (const double value : values) mean += value;
    mean /= values.size();
    double squares = 0.0;
    for (const double value : values)
      squares += (value - mean) * (value - mean);
    return std::sqrt(squares / (values.size() - 1) / values.size());
  };
  double pose_sum = 0.0;
  double point_sum = 0.0;
  size_t num_poses = 0;
  size_t num_points = 0;
  std::vector<double> pose_means;
  std::vector<double> point_means;
  Nees nees;
  for (const NeesTrial& trial : trials) {
    pose_sum += trial.pose_sum;
    point_sum += trial.point_sum;
    num_poses += trial.num_poses;
    num_points += trial.num_points;
    pose_means.push_back(trial.pose_sum / trial.num_poses);
    point_means.push_back(trial.point_sum / trial.num_points);
    nees.num_warned += trial.warned;
  }
  nees.pose = pose_sum / num_poses;
  nees.point = point_sum / num_points;
  nees.pose_standard_error = standard_error(pose_means);
  nees.point_standard_error = standard_error(point_means);
  nees.num_trials = static_cast<int>(trials.size());
  nees.trials = trials;
  return nees;
}

void ExpectCalibrated(const Nees& nees) {
  EXPECT_NEAR(nees.pose, 6.0, 0.6);
  EXPECT_NEAR(nees.point, 3.0, 0.3);
}

void ExpectCalibratedOrWarned(const Nees& nees) {
  constexpr size_t kMinTrialsToJudge = 50;
  std::vector<NeesTrial> unwarned;
  std::copy_if(nees.trials.begin(), nees.trials.end(),
               std::back_inserter(unwarned),
               [](const NeesTrial& trial) { return !trial.warned; });
  if (unwarned.size() < kMinTrialsToJudge) {
    std::cout << "[ figures ] " << nees.num_warned << " of " << nees.num_trials
              << " covariances warned; the " << unwarned.size()
              << " others are too few to judge\n";
    return;
  }
  const Nees judged = SummariseNees(unwarned);
  std::cout << NeesFigures("trials whose covariance did not warn", judged)
            << "\n";
  ExpectCalibrated(judged);
}

}  // namespace uw::testing
