// The doming case of issue 4 (fixtures doming_case and doming_case_full,
// scripts/reconstruct_doming_case.sh): stock colmap, with k1 fixed 0.005
// off the truth, bends a single pass along the scarp into a dome (checked
// against uwsim's true camera centres, independently of uwcolmap), and
// uwcolmap bundle_adjuster with the navigation takes the dome out.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "colmap_plugins/scene/model_io.h"
#include "tests/support/process.h"
#include "tests/support/truth_comparison.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

const fs::path kCaseDir = UW_DOMING_CASE_DIR;
const fs::path kUwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";

// The model's camera centres after a similarity to the true ones, and the
// true ones, in name (acquisition) order.
struct AlignedCentres {
  Eigen::Matrix3Xd model;
  Eigen::Matrix3Xd truth;
};

AlignedCentres AlignToTruth(const Reconstruction& model,
                            const Reconstruction& truth) {
  std::map<std::string, Eigen::Vector3d> true_centres;
  for (const Image& image : truth.Images()) {
    true_centres[image.name] = image.ProjectionCenter();
  }
  std::vector<const Image*> images;
  for (const Image& image : model.Images()) images.push_back(&image);
  std::sort(images.begin(), images.end(),
            [](const Image* a, const Image* b) { return a->name < b->name; });
  AlignedCentres centres{Eigen::Matrix3Xd(3, images.size()),
                         Eigen::Matrix3Xd(3, images.size())};
  for (size_t i = 0; i < images.size(); ++i) {
    centres.model.col(i) = images[i]->ProjectionCenter();
    centres.truth.col(i) = true_centres.at(images[i]->name);
  }
  const Eigen::Matrix4d truth_from_model =
      Eigen::umeyama(centres.model, centres.truth);
  centres.model =
      (truth_from_model.topLeftCorner<3, 3>() * centres.model).colwise() +
      truth_from_model.topRightCorner<3, 1>();
  return centres;
}

// One source, two executables: UW_DOMING_SUITE names the case (CTest needs
// distinct test names).
TEST(UW_DOMING_SUITE, StockColmapBendsTheStripWithAWrongK1) {
  const Reconstruction truth = ReadModel(kCaseDir / "sim" / "truth");
  const Reconstruction model = ReadModel(kCaseDir / "sparse" / "0");
  ASSERT_GE(model.Images().size(), 0.95 * truth.Images().size());
  const AlignedCentres centres = AlignToTruth(model, truth);
  const Eigen::Index n = centres.truth.cols();

  // Track frame of the truth: along the strip, and the wall normal (the
  // cameras look along -normal) made orthogonal to it.
  const Eigen::Vector3d along =
      (centres.truth.col(n - 1) - centres.truth.col(0)).normalized();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (const Image& image : truth.Images()) {
    normal -= image.cam_from_world.RotationMatrix().row(2).transpose();
  }
  normal = (normal - normal.dot(along) * along).normalized();
  const double length =
      (centres.truth.col(n - 1) - centres.truth.col(0)).dot(along);

  // The dome: the normal deviation of the aligned centres as a parabola
  // c0 + c1 x + c2 x^2 along the strip; sagitta = c2 L^2 / 4, ends against
  // middle.
  const Eigen::Vector3d middle = centres.truth.rowwise().mean();
  Eigen::MatrixXd design(n, 3);
  Eigen::VectorXd deviation(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = (centres.truth.col(i) - middle).dot(along);
    design.row(i) << 1.0, x, x * x;
    deviation(i) = (centres.model.col(i) - centres.truth.col(i)).dot(normal);
  }
  const Eigen::Vector3d fit = design.colPivHouseholderQr().solve(deviation);
  const double sagitta = fit(2) * length * length / 4.0;
  const double rmse =
      std::sqrt((centres.model - centres.truth).colwise().squaredNorm().mean());
  const double residual_rms =
      std::sqrt((design * fit - deviation).squaredNorm() / n);
  std::printf(
      "[ figures ] doming case (%s): %zu/%zu images, %.1f m strip; camera "
      "RMSE after similarity %.3f m; camera track sagitta %.3f m (%.2f %% of "
      "the length), %.3f m RMS about the parabola\n",
      kCaseDir.filename().c_str(), model.Images().size(), truth.Images().size(),
      length, rmse, sagitta, 100 * sagitta / length, residual_rms);
  // With the true k1 the same pipeline gives 4 mm (reduced) and 9 mm (full)
  // of RMSE and at most 9 mm of sagitta (docs/uwsim.md, "The doming case");
  // the dome (0.25 m and 1.6 m measured) must stand far above that.
  EXPECT_GT(std::abs(sagitta), 0.004 * length);
  EXPECT_GT(rmse, 0.001 * length);
  // And be a dome: a smooth bend, not scattered cameras.
  EXPECT_LT(residual_rms, 0.25 * std::abs(sagitta));
}

// Acceptance 1 of issue 4. Stock: colmap mapper (k1 fixed wrong) +
// similarity to the navigation (uwcolmap model_aligner, as colmap
// model_aligner would). Ours: uwcolmap bundle_adjuster --Nav.strategy prior
// with uwsim's default navigation noise and otherwise default flags (like
// colmap bundle_adjuster, they refine f and k1). Shape errors after a
// similarity to the truth; absolute ones (bounded by the dive's navigation
// bias, which nothing observes) are printed. For fairness, colmap's own
// bundle_adjuster (self-calibration, no navigation) + the same similarity
// is run too: ours must not be worse than it.
TEST(UW_DOMING_SUITE, NavigationFusedAdjustmentTakesTheDomeOut) {
  const fs::path dir = testing::FreshTestDir(std::string("uw_doming_") +
                                             kCaseDir.filename().string());
  const fs::path sparse = kCaseDir / "sparse" / "0";
  const std::string nav =
      " --nav " + testing::Quoted(kCaseDir / "sim" / "nav.csv") +
      " --mount starboard --lever_arm 0.6,0,-0.3 --boresight 0.3,-0.5,0.8";
  const std::string adjuster = testing::Quoted(kUwcolmap) +
                               " bundle_adjuster --input_path " +
                               testing::Quoted(sparse) + nav +
                               " --Nav.strategy prior --Nav.use_attitude 1";
  for (const char* name : {"colmap_ba", "stock_nav", "self_calibrated_nav",
                           "ours", "ours_fixed_k1"}) {
    fs::create_directories(dir / name);
  }
  testing::RunOrFail(testing::Quoted(kUwcolmap) +
                     " model_aligner --input_path " + testing::Quoted(sparse) +
                     " --output_path " + testing::Quoted(dir / "stock_nav") +
                     nav);
  testing::RunOrFail("colmap bundle_adjuster --input_path " +
                     testing::Quoted(sparse) + " --output_path " +
                     testing::Quoted(dir / "colmap_ba"));
  testing::RunOrFail(testing::Quoted(kUwcolmap) +
                     " model_aligner --input_path " +
                     testing::Quoted(dir / "colmap_ba") + " --output_path " +
                     testing::Quoted(dir / "self_calibrated_nav") + nav);
  testing::RunOrFail(adjuster + " --output_path " +
                     testing::Quoted(dir / "ours"));
  // The user's calibration kept (k1 fixed, as in the mapper): only the
  // navigation can straighten the strip, with Eq. 2's stiffer weights.
  testing::RunOrFail(
      adjuster + " --output_path " + testing::Quoted(dir / "ours_fixed_k1") +
      " --BundleAdjustment.refine_focal_length 0"
      " --BundleAdjustment.refine_extra_params 0 --Nav.weighting thesis");

  std::map<std::string,
           std::pair<testing::TruthDeviation, testing::TruthDeviation>>
      deviations;
  std::printf(
      "[ figures ] %-20s %-10s %14s %14s %12s   per-segment scale 3D / "
      "along the wall\n",
      "model", "alignment", "camera RMSE m", "surface RMS m", "sagitta m");
  for (const char* name :
       {"stock_nav", "self_calibrated_nav", "ours", "ours_fixed_k1"}) {
    for (const char* alignment : {"similarity", "none"}) {
      const testing::TruthDeviation d = testing::CompareWithTruth(
          kUwcolmap, dir / name, kCaseDir / "sim",
          dir / (std::string(name) + "_" + alignment + ".json"), alignment);
      std::string scales;
      for (const nlohmann::json& segment : d.segments) {
        char text[40];
        std::snprintf(text, sizeof(text), " %.4f/%.4f",
                      segment["scale_3d"].get<double>(),
                      segment["scale_along_track"].get<double>());
        scales += text;
      }
      std::printf("[ figures ] %-20s %-10s %14.4f %14.4f %12.4f  %s\n", name,
                  alignment, d.camera_rmse_m, d.surface_rms_m, d.sagitta_m,
                  scales.c_str());
      (std::string(alignment) == "none" ? deviations[name].second
                                        : deviations[name].first) = d;
    }
  }
  const testing::TruthDeviation& stock = deviations["stock_nav"].first;
  const testing::TruthDeviation& self_calibrated =
      deviations["self_calibrated_nav"].first;
  const testing::TruthDeviation& ours = deviations["ours"].first;
  const testing::TruthDeviation& fixed = deviations["ours_fixed_k1"].first;
  std::printf(
      "[ figures ] stock / ours: camera RMSE x%.1f, surface RMS x%.1f, "
      "sagitta x%.1f; with k1 kept fixed x%.1f, x%.1f, x%.1f\n",
      stock.camera_rmse_m / ours.camera_rmse_m,
      stock.surface_rms_m / ours.surface_rms_m,
      std::abs(stock.sagitta_m / ours.sagitta_m),
      stock.camera_rmse_m / fixed.camera_rmse_m,
      stock.surface_rms_m / fixed.surface_rms_m,
      std::abs(stock.sagitta_m / fixed.sagitta_m));
  EXPECT_GT(stock.camera_rmse_m, 5.0 * ours.camera_rmse_m);
  EXPECT_GT(stock.surface_rms_m, 5.0 * ours.surface_rms_m);
  EXPECT_GT(std::abs(stock.sagitta_m), 5.0 * std::abs(ours.sagitta_m));
  EXPECT_LT(ours.camera_rmse_m, 1.25 * self_calibrated.camera_rmse_m);
  EXPECT_LT(ours.surface_rms_m, 1.25 * self_calibrated.surface_rms_m);
  EXPECT_GT(std::abs(stock.sagitta_m), 5.0 * std::abs(fixed.sagitta_m));
}

}  // namespace
}  // namespace uw
