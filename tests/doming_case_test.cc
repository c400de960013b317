// The doming case of issue 4 (fixtures doming_case and doming_case_full,
// scripts/reconstruct_doming_case.sh): stock colmap, with k1 fixed 0.005
// off the truth, bends a single pass along the scarp into a dome. Checked
// against uwsim's true camera centres, independently of uwcolmap.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <map>

#include "colmap_plugins/scene/model_io.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

const fs::path kCaseDir = UW_DOMING_CASE_DIR;

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

}  // namespace
}  // namespace uw
