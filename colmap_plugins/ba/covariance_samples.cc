#include "colmap_plugins/ba/covariance_samples.h"

#include <cmath>
#include <fstream>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "colmap_plugins/ba/model_file.h"
#include "common/util/error.h"

namespace uw {
namespace {

constexpr char kMagic[8] = {'U', 'W', 'S', 'M', 'P', 0, 0, 1};

}  // namespace

int CovarianceSamples::CameraRow(camera_t camera_id) const {
  const auto it = camera_rows_.find(camera_id);
  return it == camera_rows_.end() ? -1 : it->second;
}

int CovarianceSamples::PointRow(point3D_t point3D_id) const {
  const auto it = point_rows_.find(point3D_id);
  return it == point_rows_.end() ? -1 : it->second;
}

void CovarianceSamples::Index() {
  camera_rows_.clear();
  point_rows_.clear();
  int row = 0;
  for (size_t c = 0; c < camera_ids.size(); ++c) {
    if (!camera_param_indices[c].empty()) camera_rows_[camera_ids[c]] = row;
    row += static_cast<int>(camera_param_indices[c].size());
  }
  for (size_t j = 0; j < point3D_ids.size(); ++j) {
    point_rows_[point3D_ids[j]] = 3 * static_cast<int>(j);
  }
}

Eigen::Matrix<double, 3, 7> SimilarityTangentAt(const Eigen::Vector3d& x) {
  Eigen::Matrix<double, 3, 7> a;
  a << 0.0, x.z(), -x.y(), 1.0, 0.0, 0.0, x.x(),  //
      -x.z(), 0.0, x.x(), 0.0, 1.0, 0.0, x.y(),   //
      x.y(), -x.x(), 0.0, 0.0, 0.0, 1.0, x.z();
  return a;
}

void SeparateSimilarity(const Reconstruction& model,
                        CovarianceSamples* samples) {
  const int num_points = static_cast<int>(samples->point3D_ids.size());
  if (num_points < 3) {
    throw ErrorAt("the draws hold ", num_points,
                  " points; a similarity needs at least 3");
  }
  // About the centroid, so that survey coordinates far from the origin
  // (UTM) cost no precision.
  Eigen::Matrix3Xd nominal(3, num_points);
  for (int j = 0; j < num_points; ++j) {
    const Point3D* point = model.FindPoint3D(samples->point3D_ids[j]);
    if (point == nullptr) {
      throw ErrorAt("point ", samples->point3D_ids[j],
                    " of the draws is not in the model");
    }
    nominal.col(j) = point->xyz;
  }
  const Eigen::Vector3d centroid = nominal.rowwise().mean();
  nominal.colwise() -= centroid;
  // The draws are tangent (first-order) errors, so the similarity is too:
  // delta = A(p) theta (SimilarityTangentAt). An exact similarity fit
  // (Umeyama) would leave its own second-order terms, |omega|^2 |p| / 2, as
  // a spurious deformation: with navigation priors as the datum, omega is
  // ~1e-2 rad and that is as large as the deformation itself.
  const int m = static_cast<int>(samples->point_deltas.cols());
  Eigen::Matrix<double, 7, 7> normal = Eigen::Matrix<double, 7, 7>::Zero();
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(7, m);
  for (int j = 0; j < num_points; ++j) {
    const Eigen::Matrix<double, 3, 7> a = SimilarityTangentAt(nominal.col(j));
    normal.noalias() += a.transpose() * a;
    rhs.noalias() += a.transpose() *
                     samples->point_deltas.middleRows<3>(3 * j).cast<double>();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 7, 7>> eigen(
      normal);
  if (!(eigen.eigenvalues()(0) > 1e-12 * eigen.eigenvalues()(6))) {
    throw ErrorAt("the draws' points are collinear: no similarity fits them");
  }
  const Eigen::MatrixXd theta = normal.ldlt().solve(rhs);
  samples->log_scale = theta.row(6).transpose();
  for (int j = 0; j < num_points; ++j) {
    samples->point_deltas.middleRows<3>(3 * j) -=
        (SimilarityTangentAt(nominal.col(j)) * theta).cast<float>();
  }
  for (size_t i = 0; i < samples->image_ids.size(); ++i) {
    const Image* image = model.FindImage(samples->image_ids[i]);
    if (image == nullptr) {
      throw ErrorAt("image ", samples->image_ids[i],
                    " of the draws is not in the model");
    }
    // world_from_cam' = Exp(omega) Exp(w) world_from_cam: w' = w + omega.
    samples->image_deltas.middleRows<3>(6 * i) -=
        theta.topRows<3>().cast<float>();
    samples->image_deltas.middleRows<3>(6 * i + 3) -=
        (SimilarityTangentAt(image->ProjectionCenter() - centroid) * theta)
            .cast<float>();
  }
}

void WriteCovarianceSamples(const CovarianceSamples& samples,
                            const Reconstruction& model, std::ostream& out) {
  WriteModelFileHead(kMagic, model, out);
  PutValue<uint64_t>(out, samples.camera_ids.size());
  PutValue<uint64_t>(out, samples.image_ids.size());
  PutValue<uint64_t>(out, samples.point3D_ids.size());
  PutValue<uint64_t>(out, samples.NumSamples());
  for (size_t c = 0; c < samples.camera_ids.size(); ++c) {
    PutValue<uint32_t>(out, samples.camera_ids[c]);
    PutValue<uint32_t>(out, samples.camera_param_indices[c].size());
    for (const int index : samples.camera_param_indices[c]) {
      PutValue<uint32_t>(out, index);
    }
  }
  for (const image_t id : samples.image_ids) PutValue<uint32_t>(out, id);
  for (const point3D_t id : samples.point3D_ids) PutValue<uint64_t>(out, id);
  for (int s = 0; s < samples.NumSamples(); ++s) {
    PutValue<double>(out, samples.log_scale(s));
    // Columns of column-major matrices: contiguous.
    PutValues(out, samples.camera_deltas.col(s).data(),
              samples.camera_deltas.rows());
    PutValues(out, samples.image_deltas.col(s).data(),
              samples.image_deltas.rows());
    PutValues(out, samples.point_deltas.col(s).data(),
              samples.point_deltas.rows());
  }
}

CovarianceSamples ReadCovarianceSamples(const std::filesystem::path& path,
                                        const Reconstruction& model) {
  std::ifstream in = OpenModelFile(path, kMagic, "samples file", model);
  const uint64_t num_cameras = GetValue<uint64_t>(in, path);
  const uint64_t num_images = GetValue<uint64_t>(in, path);
  const uint64_t num_points = GetValue<uint64_t>(in, path);
  const uint64_t num_samples = GetValue<uint64_t>(in, path);
  if (num_cameras > model.Cameras().size() ||
      num_images > model.Images().size() ||
      num_points > model.Points3D().size()) {
    throw ErrorAt(path.string(), ": more cameras, images or points than the ",
                  "model has");
  }
  CovarianceSamples samples;
  int num_camera_rows = 0;
  for (uint64_t c = 0; c < num_cameras; ++c) {
    samples.camera_ids.push_back(GetValue<uint32_t>(in, path));
    const uint32_t count = GetValue<uint32_t>(in, path);
    const Camera* camera = model.FindCamera(samples.camera_ids.back());
    if (camera == nullptr || count > camera->params.size()) {
      throw ErrorAt(path.string(), ": camera ", samples.camera_ids.back(),
                    " is not the model's");
    }
    samples.camera_param_indices.emplace_back();
    for (uint32_t k = 0; k < count; ++k) {
      const uint32_t index = GetValue<uint32_t>(in, path);
      if (index >= camera->params.size()) {
        throw ErrorAt(path.string(), ": camera ", camera->camera_id,
                      " has no parameter ", index);
      }
      samples.camera_param_indices.back().push_back(static_cast<int>(index));
    }
    num_camera_rows += static_cast<int>(count);
  }
  for (uint64_t i = 0; i < num_images; ++i) {
    samples.image_ids.push_back(GetValue<uint32_t>(in, path));
    if (model.FindImage(samples.image_ids.back()) == nullptr) {
      throw ErrorAt(path.string(), ": image ", samples.image_ids.back(),
                    " is not in the model");
    }
  }
  for (uint64_t j = 0; j < num_points; ++j) {
    samples.point3D_ids.push_back(GetValue<uint64_t>(in, path));
    if (model.FindPoint3D(samples.point3D_ids.back()) == nullptr) {
      throw ErrorAt(path.string(), ": point ", samples.point3D_ids.back(),
                    " is not in the model");
    }
  }
  // Bounded by the file's size before anything that large is allocated.
  const auto here = in.tellg();
  in.seekg(0, std::ios::end);
  const uint64_t remaining = static_cast<uint64_t>(in.tellg() - here);
  in.seekg(here);
  const uint64_t per_sample =
      8 * (1 + num_camera_rows) + 4 * (6 * num_images + 3 * num_points);
  if (remaining != per_sample * num_samples) {
    throw ErrorAt(path.string(), ": ", remaining, " bytes of draws, expected ",
                  per_sample * num_samples, " for ", num_samples, " draws");
  }
  const int m = static_cast<int>(num_samples);
  samples.log_scale.resize(m);
  samples.camera_deltas.resize(num_camera_rows, m);
  samples.image_deltas.resize(6 * num_images, m);
  samples.point_deltas.resize(3 * num_points, m);
  for (int s = 0; s < m; ++s) {
    samples.log_scale(s) = GetValue<double>(in, path);
    GetValues(in, path, samples.camera_deltas.col(s).data(),
              samples.camera_deltas.rows());
    GetValues(in, path, samples.image_deltas.col(s).data(),
              samples.image_deltas.rows());
    GetValues(in, path, samples.point_deltas.col(s).data(),
              samples.point_deltas.rows());
  }
  samples.Index();
  return samples;
}

}  // namespace uw
