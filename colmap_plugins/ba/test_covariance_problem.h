// A small survey as a Ceres problem, solved, with its variables listed as
// ComputeSchurCovariance takes them: the covariance engines' unit tests
// (schur_covariance_test.cc, ceres_covariance_test.cc) compare on it.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_plugins/ba/nav_prior.h"
#include "colmap_plugins/ba/reprojection_error.h"
#include "colmap_plugins/ba/schur_covariance.h"
#include "colmap_plugins/ba/test_scene.h"
#include "colmap_plugins/cameras/camera_models.h"

namespace uw::test {

enum class Gauge { kPriors, kHeld, kFree };

// A small survey as a Ceres problem: poses (quaternion manifold), one
// SIMPLE_RADIAL camera (principal point constant), points, and with kPriors
// whitened position priors.
class SmallProblem {
 public:
  SmallProblem(Gauge gauge, bool huber, bool refine_intrinsics = false,
               unsigned seed = 3, int num_points = 160)
      : refine_intrinsics_(refine_intrinsics) {
    TestSceneOptions options;
    options.num_lines = 2;
    options.images_per_line = 5;
    options.num_points = num_points;
    options.seed = seed;
    scene_ = MakeTestScene(options);
    Reconstruction& model = scene_.observed;
    Perturb(0.002, 0.0005, seed + 1, &model);
    params_ = model.Cameras()[0].params;
    for (const Image& image : model.Images()) {
      const Eigen::Quaterniond& q = image.cam_from_world.rotation;
      poses_.push_back({q.w(), q.x(), q.y(), q.z(),
                        image.cam_from_world.translation.x(),
                        image.cam_from_world.translation.y(),
                        image.cam_from_world.translation.z()});
    }
    for (const Point3D& point : model.Points3D()) {
      point_ids_.push_back(point.point3D_id);
      points_[point.point3D_id] = point.xyz;
    }
    for (size_t i = 0; i < model.Images().size(); ++i) {
      for (const Point2D& point2D : model.Images()[i].points2D) {
        if (!point2D.HasPoint3D()) continue;
        problem_.AddResidualBlock(
            ReprojectionErrorCostFunctor<SimpleRadialCameraModel>::Create(
                point2D.xy, 1.0 / 0.5),
            huber ? new ceres::HuberLoss(1.0) : nullptr, Rotation(i),
            Translation(i), points_.at(point2D.point3D_id).data(),
            params_.data());
      }
    }
    if (gauge == Gauge::kPriors) {
      for (const ImagePosePrior& prior : scene_.priors) {
        const size_t i = prior.image_id - 1;
        problem_.AddResidualBlock(
            PositionPriorCostFunctor::Create(
                prior.position_in_world,
                SqrtInformation(prior.position_covariance)),
            nullptr, Rotation(i), Translation(i), offset_.data());
      }
      problem_.SetParameterBlockConstant(offset_.data());
    }
    for (size_t i = 0; i < poses_.size(); ++i) {
      problem_.SetManifold(Rotation(i), new ceres::QuaternionManifold);
    }
    if (refine_intrinsics) {
      problem_.SetManifold(params_.data(),
                           new ceres::SubsetManifold(4, {1, 2}));
    } else {
      problem_.SetParameterBlockConstant(params_.data());
    }
    if (gauge == Gauge::kHeld) {
      problem_.SetParameterBlockConstant(Rotation(0));
      problem_.SetParameterBlockConstant(Translation(0));
      problem_.SetManifold(Translation(1), new ceres::SubsetManifold(3, {0}));
    }
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_SCHUR;
    solver.function_tolerance = 1e-14;
    solver.gradient_tolerance = 1e-14;
    solver.parameter_tolerance = 1e-14;
    solver.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem_, &summary);
    for (size_t i = 0; i < poses_.size(); ++i) {
      reduced_.push_back(
          {{Rotation(i), Translation(i)}, "image " + std::to_string(i + 1)});
    }
    reduced_.push_back({{params_.data()}, "camera 1"});
    for (const point3D_t id : point_ids_) {
      points_list_.push_back(
          {points_.at(id).data(), "point " + std::to_string(id)});
    }
  }

  double* Rotation(size_t i) { return poses_[i].data(); }
  double* Translation(size_t i) { return poses_[i].data() + 4; }
  ceres::Problem& problem() { return problem_; }
  const std::vector<ReducedVariable>& reduced() const { return reduced_; }
  const std::vector<EliminatedPoint>& points() const { return points_list_; }

  // The whole information matrix J^T J in the engine's column order.
  Eigen::MatrixXd DenseInformation() {
    ceres::Problem::EvaluateOptions evaluate;
    for (const ReducedVariable& variable : reduced_) {
      for (double* block : variable.blocks) {
        if (!problem_.IsParameterBlockConstant(block)) {
          evaluate.parameter_blocks.push_back(block);
        }
      }
    }
    for (const EliminatedPoint& point : points_list_) {
      evaluate.parameter_blocks.push_back(point.block);
    }
    ceres::CRSMatrix crs;
    problem_.Evaluate(evaluate, nullptr, nullptr, nullptr, &crs);
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
    for (int r = 0; r < crs.num_rows; ++r) {
      for (int e = crs.rows[r]; e < crs.rows[r + 1]; ++e) {
        j(r, crs.cols[e]) = crs.values[e];
      }
    }
    return j.transpose() * j;
  }

  // Rows per variable of the similarity null space (free problem only).
  void FillNullSpace(SchurCovarianceOptions* options) {
    for (size_t i = 0; i < poses_.size(); ++i) {
      const Eigen::Matrix3d r = Eigen::Quaterniond(poses_[i][0], poses_[i][1],
                                                   poses_[i][2], poses_[i][3])
                                    .toRotationMatrix();
      Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(6, 7);
      rows.block<3, 3>(0, 0) = -0.5 * r;  // Ceres' tangent: half the angle
      rows.block<3, 3>(3, 3) = -r;
      rows.block<3, 1>(3, 6) =
          Eigen::Map<const Eigen::Vector3d>(Translation(i));
      options->null_space_reduced.push_back(rows);
    }
    options->null_space_reduced.push_back(
        Eigen::MatrixXd::Zero(refine_intrinsics_ ? 2 : 0, 7));
    for (const point3D_t id : point_ids_) {
      const Eigen::Vector3d& x = points_.at(id);
      Eigen::MatrixXd rows(3, 7);
      rows << 0, x.z(), -x.y(), 1, 0, 0, x.x(), -x.z(), 0, x.x(), 0, 1, 0,
          x.y(), x.y(), -x.x(), 0, 0, 0, 1, x.z();
      options->null_space_points.push_back(rows);
    }
  }

  // The engine's result laid out as the dense matrix (marginal blocks and
  // co-visible cross blocks only), and the mask of what it covers.
  void Scatter(const SchurCovariance& covariance, Eigen::MatrixXd* dense,
               Eigen::MatrixXd* mask) const {
    std::vector<int> offsets;
    int offset = 0;
    for (const Eigen::MatrixXd& block : covariance.reduced) {
      offsets.push_back(offset);
      offset += static_cast<int>(block.rows());
    }
    const int n = offset + 3 * static_cast<int>(covariance.points.size());
    *dense = Eigen::MatrixXd::Zero(n, n);
    *mask = Eigen::MatrixXd::Zero(n, n);
    for (size_t a = 0; a < covariance.reduced.size(); ++a) {
      const int d = static_cast<int>(covariance.reduced[a].rows());
      dense->block(offsets[a], offsets[a], d, d) = covariance.reduced[a];
      mask->block(offsets[a], offsets[a], d, d).setOnes();
    }
    for (const auto& [pair, block] : covariance.cross) {
      dense->block(offsets[pair.first], offsets[pair.second], block.rows(),
                   block.cols()) = block;
      mask->block(offsets[pair.first], offsets[pair.second], block.rows(),
                  block.cols())
          .setOnes();
    }
    for (size_t j = 0; j < covariance.points.size(); ++j) {
      const int row = offset + 3 * static_cast<int>(j);
      dense->block<3, 3>(row, row) = covariance.points[j];
      mask->block<3, 3>(row, row).setOnes();
    }
  }

 private:
  bool refine_intrinsics_ = false;
  TestScene scene_;
  std::vector<std::array<double, 7>> poses_;
  std::vector<double> params_;
  std::map<point3D_t, Eigen::Vector3d> points_;
  std::vector<point3D_t> point_ids_;
  std::array<double, 3> offset_{0.0, 0.0, 0.0};
  ceres::Problem problem_;
  std::vector<ReducedVariable> reduced_;
  std::vector<EliminatedPoint> points_list_;
};

}  // namespace uw::test
