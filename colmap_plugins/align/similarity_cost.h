// The cost of a similarity fit onto covariance-weighted targets, shared by
// EstimateSimilarity (similarity.h) and EstimateSimilarityWithOffsets
// (similarity_with_offsets.h), which adds an offset to the targets.
#pragma once

#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace uw {

// Residual of one point pair, whitened by the target's covariance:
// L^-1 (scale * R * src + t − dst − offset), with Σ = L L^T. Frames: src
// in a, dst, offset and the residual's metres in b (both centred by the
// callers, so large coordinates keep their digits). A fit without offsets
// holds a zero offset block constant.
struct WhitenedPointResidual {
  WhitenedPointResidual(const Eigen::Vector3d& src, const Eigen::Vector3d& dst,
                        const Eigen::Matrix3d& sqrt_information)
      : src_(src), dst_(dst), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* log_scale,
                  const T* offset, T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> b_from_a_rotation(rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> b_from_a_translation(
        translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> dst_offset(offset);
    const Eigen::Matrix<T, 3, 1> error =
        ceres::exp(log_scale[0]) * (b_from_a_rotation * src_.cast<T>()) +
        b_from_a_translation - dst_.cast<T>() - dst_offset;
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residuals);
    whitened = sqrt_information_.cast<T>() * error;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& src,
                                     const Eigen::Vector3d& dst,
                                     const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<WhitenedPointResidual, 3, 4, 3, 1,
                                           3>(
        new WhitenedPointResidual(src, dst, sqrt_information));
  }

 private:
  const Eigen::Vector3d src_;
  const Eigen::Vector3d dst_;
  const Eigen::Matrix3d sqrt_information_;
};

// Small dense problems solved to the last digits, silently, on one thread
// (the callers' results must not depend on the thread count).
inline ceres::Solver::Options SimilaritySolverOptions(int max_iterations) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = 1e-12;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  return options;
}

inline Eigen::Vector3d Mean(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& point : points) sum += point;
  return sum / static_cast<double>(points.size());
}

}  // namespace uw
