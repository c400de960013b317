#include "colmap_plugins/cameras/camera_models.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>
#include <typeindex>
#include <vector>

#include <ceres/autodiff_cost_function.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace uw {
namespace {

struct TestCamera {
  int width;
  int height;
  std::vector<double> params;
};

// Per model: realistic cameras for 640x480 and 1024x768 images, including
// strong distortion (barrel close to the fold of the polynomial, fisheyes
// seeing ~80 degrees off-axis in the corners) and, for FOV, the small-omega
// range where COLMAP 3.8 switches to series expansions.
template <typename Model>
std::vector<TestCamera> TestCameras();

template <>
std::vector<TestCamera> TestCameras<SimplePinholeCameraModel>() {
  return {{640, 480, {500, 320, 240}}, {1024, 768, {1180.5, 515.2, 380.9}}};
}

template <>
std::vector<TestCamera> TestCameras<PinholeCameraModel>() {
  return {{640, 480, {510, 505, 318.4, 243.1}},
          {1024, 768, {870.2, 880.7, 509.3, 386.2}}};
}

template <>
std::vector<TestCamera> TestCameras<SimpleRadialCameraModel>() {
  return {{640, 480, {500, 320, 240, 0.05}},
          {640, 480, {520, 322.5, 236.5, -0.2}},
          {1024, 768, {800, 512, 384, 0.35}}};
}

template <>
std::vector<TestCamera> TestCameras<RadialCameraModel>() {
  return {{640, 480, {500, 320, 240, -0.25, 0.08}},
          {640, 480, {480, 330, 235, -0.35, 0.12}},
          {1024, 768, {900, 515, 380, 0.2, 0.15}}};
}

template <>
std::vector<TestCamera> TestCameras<OpenCVCameraModel>() {
  return {{640, 480, {500, 505, 322, 238, -0.3, 0.1, 0.002, -0.001}},
          {640, 480, {460, 462, 315, 245, -0.38, 0.16, 0.0015, 0.001}},
          {1024, 768, {800, 805, 512, 384, 0.25, 0.15, -0.003, 0.002}}};
}

template <>
std::vector<TestCamera> TestCameras<OpenCVFisheyeCameraModel>() {
  return {{640, 480, {300, 302, 320, 240, 0.05, -0.01, 0.002, -0.001}},
          {640, 480, {290, 291, 318, 242, -0.02, 0.004, 0, 0}},
          {1024, 768, {420, 420, 512, 384, 0.05, 0.01, 0, 0}}};
}

template <>
std::vector<TestCamera> TestCameras<FullOpenCVCameraModel>() {
  return {
      {640,
       480,
       {500, 505, 322, 238, -0.3, 0.1, 0.002, -0.001, 0.01, 0.05, -0.02, 0.01}},
      {1024,
       768,
       {820, 815, 510, 386, 0.4, -0.1, 0.001, -0.002, 0.05, 0.3, 0.02, 0.01}}};
}

template <>
std::vector<TestCamera> TestCameras<FOVCameraModel>() {
  return {{640, 480, {400, 402, 320, 240, 0.9}},
          {1024, 768, {600, 600, 512, 384, 1.3}},
          {640, 480, {500, 500, 321, 239, 0.005}},
          {640, 480, {500, 500, 321, 239, 0}}};
}

template <>
std::vector<TestCamera> TestCameras<SimpleRadialFisheyeCameraModel>() {
  return {{640, 480, {300, 320, 240, 0.05}},
          {1024, 768, {480, 510, 386, -0.03}}};
}

template <>
std::vector<TestCamera> TestCameras<RadialFisheyeCameraModel>() {
  return {{640, 480, {300, 320, 240, 0.05, -0.01}},
          {1024, 768, {450, 512, 384, 0.08, -0.02}}};
}

template <>
std::vector<TestCamera> TestCameras<ThinPrismFisheyeCameraModel>() {
  return {{640,
           480,
           {300, 302, 320, 240, 0.05, -0.01, 0.001, -0.002, 0.003, -0.001,
            0.0005, -0.0003}},
          {1024,
           768,
           {440, 438, 515, 380, 0.06, -0.02, -0.002, 0.001, 0.004, -0.001,
            0.001, 0.0008}}};
}

// Pixels every `spacing` px across the whole image, borders included.
std::vector<Eigen::Vector2d> PixelGrid(const TestCamera& camera, int spacing) {
  std::vector<double> xs;
  std::vector<double> ys;
  for (int x = 0; x < camera.width; x += spacing) xs.push_back(x);
  for (int y = 0; y < camera.height; y += spacing) ys.push_back(y);
  xs.push_back(camera.width);
  ys.push_back(camera.height);
  std::vector<Eigen::Vector2d> pixels;
  for (const double y : ys) {
    for (const double x : xs) pixels.emplace_back(x, y);
  }
  return pixels;
}

template <typename Model>
Eigen::Vector2d Project(const std::vector<double>& params,
                        const Eigen::Vector3d& point) {
  Eigen::Vector2d pixel;
  Model::ImgFromCam(params.data(), point.x(), point.y(), point.z(), &pixel.x(),
                    &pixel.y());
  return pixel;
}

template <typename Model>
Eigen::Vector3d Unproject(const std::vector<double>& params,
                          const Eigen::Vector2d& pixel) {
  Eigen::Vector3d ray;
  Model::CamFromImg(params.data(), pixel.x(), pixel.y(), &ray.x(), &ray.y(),
                    &ray.z());
  return ray;
}

double AngleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Half-angle of the field of view: the largest angle to the optical axis of
// a ray through the image border.
template <typename Model>
double MaxAngleInImage(const TestCamera& camera) {
  double max_angle = 0;
  for (const Eigen::Vector2d& pixel : PixelGrid(camera, 16)) {
    if (pixel.x() > 0 && pixel.x() < camera.width && pixel.y() > 0 &&
        pixel.y() < camera.height) {
      continue;
    }
    max_angle =
        std::max(max_angle, AngleBetween(Unproject<Model>(camera.params, pixel),
                                         Eigen::Vector3d::UnitZ()));
  }
  return max_angle;
}

// Central differences of f (R^n -> R^m) at x with steps of 1e-6 |x_i|, but
// at least 1e-6 * typical_magnitude, so that rounding (relative 1e-16 / step)
// and truncation (step^2) errors both stay below ~1e-9 relative.
template <typename Function>
Eigen::MatrixXd NumericJacobian(const Function& f, const Eigen::VectorXd& x,
                                int num_outputs, double typical_magnitude) {
  Eigen::MatrixXd jacobian(num_outputs, x.size());
  for (int i = 0; i < x.size(); ++i) {
    const double step = 1e-6 * std::max(std::abs(x(i)), typical_magnitude);
    Eigen::VectorXd forward = x;
    Eigen::VectorXd backward = x;
    forward(i) += step;
    backward(i) -= step;
    jacobian.col(i) = (f(forward) - f(backward)) / (2 * step);
  }
  return jacobian;
}

// Largest |a - b| relative to max(|a|, floor), entry by entry; the floor
// keeps entries that are zero or negligible (dy/dcx, any derivative at the
// principal point) from turning rounding noise into huge ratios.
double MaxRelativeMismatch(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                           double floor) {
  double max_mismatch = 0;
  for (int r = 0; r < a.rows(); ++r) {
    for (int c = 0; c < a.cols(); ++c) {
      const double mismatch =
          std::abs(a(r, c) - b(r, c)) / std::max(std::abs(a(r, c)), floor);
      // NaN must fail rather than be skipped by std::max.
      if (!(mismatch <= max_mismatch)) max_mismatch = mismatch;
    }
  }
  return max_mismatch;
}

template <typename Model>
struct ProjectionFunctor {
  template <typename T>
  bool operator()(const T* params, const T* point_in_cam, T* pixel) const {
    Model::ImgFromCam(params, point_in_cam[0], point_in_cam[1], point_in_cam[2],
                      &pixel[0], &pixel[1]);
    return true;
  }
};

template <typename Model>
struct UnprojectionFunctor {
  template <typename T>
  bool operator()(const T* params, const T* pixel, T* normalized) const {
    T w;
    Model::CamFromImg(params, pixel[0], pixel[1], &normalized[0],
                      &normalized[1], &w);
    return true;
  }
};

// Evaluates a Ceres autodiff cost function with parameter blocks
// (params, second) and returns its value and the Jacobians w.r.t. both.
template <typename Functor, int kNumParams, int kSecondSize>
void AutodiffJacobians(const std::vector<double>& params,
                       const Eigen::Matrix<double, kSecondSize, 1>& second,
                       Eigen::Vector2d* value, Eigen::MatrixXd* jacobian_params,
                       Eigen::MatrixXd* jacobian_second) {
  ceres::AutoDiffCostFunction<Functor, 2, kNumParams, kSecondSize> cost(
      new Functor);
  const double* blocks[] = {params.data(), second.data()};
  Eigen::Matrix<double, 2, kNumParams, Eigen::RowMajor> d_params;
  Eigen::Matrix<double, 2, kSecondSize, Eigen::RowMajor> d_second;
  double* jacobians[] = {d_params.data(), d_second.data()};
  ASSERT_TRUE(cost.Evaluate(blocks, value->data(), jacobians));
  *jacobian_params = d_params;
  *jacobian_second = d_second;
}

// For RecordProperty: the measured maxima are far below std::to_string's
// six decimals.
std::string Scientific(double value) {
  std::ostringstream text;
  text << std::scientific << std::setprecision(2) << value;
  return text.str();
}

template <typename Model>
class CameraModelTest : public ::testing::Test {};

using AllCameraModels = ::testing::Types<
    SimplePinholeCameraModel, PinholeCameraModel, SimpleRadialCameraModel,
    RadialCameraModel, OpenCVCameraModel, OpenCVFisheyeCameraModel,
    FullOpenCVCameraModel, FOVCameraModel, SimpleRadialFisheyeCameraModel,
    RadialFisheyeCameraModel, ThinPrismFisheyeCameraModel>;

struct ModelNameGenerator {
  template <typename Model>
  static std::string GetName(int) {
    return Model::kModelName;
  }
};

TYPED_TEST_SUITE(CameraModelTest, AllCameraModels, ModelNameGenerator);

TYPED_TEST(CameraModelTest, ProjectionOfUnprojectionIsIdentityOverWholeImage) {
  using Model = TypeParam;
  double max_error = 0;
  for (const TestCamera& camera : TestCameras<Model>()) {
    for (const Eigen::Vector2d& pixel : PixelGrid(camera, 16)) {
      const Eigen::Vector3d ray = Unproject<Model>(camera.params, pixel);
      ASSERT_EQ(ray.z(), 1);
      // A depth other than 1 checks that ImgFromCam divides by w.
      const Eigen::Vector2d reprojected =
          Project<Model>(camera.params, 3.7 * ray);
      const double error = (reprojected - pixel).norm();
      EXPECT_LT(error, 1e-9) << "pixel " << pixel.transpose() << " params "
                             << Eigen::Map<const Eigen::VectorXd>(
                                    camera.params.data(), camera.params.size())
                                    .transpose();
      max_error = std::max(max_error, error);

      // The runtime dispatch must run the same code.
      EXPECT_EQ(
          CameraModelCamFromImg(Model::kModelId, camera.params.data(), pixel),
          ray);
      EXPECT_EQ(CameraModelImgFromCam(Model::kModelId, camera.params.data(),
                                      3.7 * ray),
                reprojected);
    }
  }
  this->RecordProperty("max_round_trip_error_px", Scientific(max_error));
}

TYPED_TEST(CameraModelTest, UnprojectionOfProjectionRecoversDirection) {
  using Model = TypeParam;
  std::mt19937 rng(42);
  double max_angle_error = 0;
  for (const TestCamera& camera : TestCameras<Model>()) {
    const double max_angle = MaxAngleInImage<Model>(camera);
    std::uniform_real_distribution<double> cos_angle(std::cos(max_angle), 1);
    std::uniform_real_distribution<double> azimuth(-M_PI, M_PI);
    std::uniform_real_distribution<double> depth(0.3, 30);
    int num_in_image = 0;
    for (int i = 0; i < 2000; ++i) {
      const double c = cos_angle(rng);
      const double s = std::sqrt(1 - c * c);
      const double phi = azimuth(rng);
      const Eigen::Vector3d point =
          depth(rng) * Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), c);
      const Eigen::Vector2d pixel = Project<Model>(camera.params, point);
      if (pixel.x() < 0 || pixel.x() > camera.width || pixel.y() < 0 ||
          pixel.y() > camera.height) {
        continue;
      }
      ++num_in_image;
      const double angle_error =
          AngleBetween(Unproject<Model>(camera.params, pixel), point);
      EXPECT_LT(angle_error, 1e-12) << "point " << point.transpose();
      max_angle_error = std::max(max_angle_error, angle_error);
    }
    EXPECT_GT(num_in_image, 1000);
  }
  this->RecordProperty("max_angle_error_rad", Scientific(max_angle_error));
}

// Points on the optical axis (where the fisheye models have 0/0 terms), at
// the image corners and in between.
template <typename Model>
std::vector<Eigen::Vector3d> JacobianTestPoints(const TestCamera& camera) {
  std::vector<Eigen::Vector3d> points = {Eigen::Vector3d(0, 0, 2.5)};
  for (const Eigen::Vector2d& pixel : PixelGrid(camera, camera.width / 4)) {
    points.push_back(2.5 * Unproject<Model>(camera.params, pixel));
  }
  return points;
}

TYPED_TEST(CameraModelTest, AutodiffJacobiansMatchNumericDifferences) {
  using Model = TypeParam;
  constexpr int kNumParams = Model::kNumParams;
  double max_mismatch = 0;
  for (const TestCamera& camera : TestCameras<Model>()) {
    const Eigen::Map<const Eigen::VectorXd> params(camera.params.data(),
                                                   kNumParams);
    for (const Eigen::Vector3d& point : JacobianTestPoints<Model>(camera)) {
      Eigen::Vector2d pixel;
      Eigen::MatrixXd d_params;
      Eigen::MatrixXd d_point;
      AutodiffJacobians<ProjectionFunctor<Model>, kNumParams, 3>(
          camera.params, point, &pixel, &d_params, &d_point);
      // Jets must not change the value beyond rounding.
      EXPECT_LT((pixel - Project<Model>(camera.params, point)).norm(), 1e-9);

      const Eigen::MatrixXd numeric_d_params = NumericJacobian(
          [&](const Eigen::VectorXd& p) {
            return Project<Model>({p.data(), p.data() + p.size()}, point);
          },
          params, 2, 1.0);
      const Eigen::MatrixXd numeric_d_point = NumericJacobian(
          [&](const Eigen::VectorXd& x) {
            return Project<Model>(camera.params, x);
          },
          point, 2, 1.0);
      // Derivatives of pixels below 1 px per unit do not matter at 1e-6.
      const double mismatch =
          std::max(MaxRelativeMismatch(d_params, numeric_d_params, 1.0),
                   MaxRelativeMismatch(d_point, numeric_d_point, 1.0));
      EXPECT_LT(mismatch, 1e-6) << "point " << point.transpose() << "\n"
                                << d_params << "\nvs\n"
                                << numeric_d_params << "\n"
                                << d_point << "\nvs\n"
                                << numeric_d_point;
      max_mismatch = std::max(max_mismatch, mismatch);
    }
  }
  this->RecordProperty("max_relative_mismatch", Scientific(max_mismatch));
}

TYPED_TEST(CameraModelTest, UnprojectionAutodiffMatchesNumericDifferences) {
  using Model = TypeParam;
  constexpr int kNumParams = Model::kNumParams;
  double max_mismatch = 0;
  for (const TestCamera& camera : TestCameras<Model>()) {
    const Eigen::Map<const Eigen::VectorXd> params(camera.params.data(),
                                                   kNumParams);
    const double focal = camera.params[Model::kFocalLengthIdxs[0]];
    for (const Eigen::Vector2d& pixel : PixelGrid(camera, camera.width / 4)) {
      Eigen::Vector2d value;
      Eigen::MatrixXd d_params;
      Eigen::MatrixXd d_pixel;
      AutodiffJacobians<UnprojectionFunctor<Model>, kNumParams, 2>(
          camera.params, pixel, &value, &d_params, &d_pixel);

      const auto normalized = [](const Eigen::Vector3d& ray) {
        return Eigen::Vector2d(ray.head<2>());
      };
      // Jets must not change the value beyond rounding.
      EXPECT_LT(
          (value - normalized(Unproject<Model>(camera.params, pixel))).norm(),
          1e-12);
      const Eigen::MatrixXd numeric_d_params = NumericJacobian(
          [&](const Eigen::VectorXd& p) {
            return normalized(
                Unproject<Model>({p.data(), p.data() + p.size()}, pixel));
          },
          params, 2, 1.0);
      // Pixels vary on the scale of the image, not of one pixel.
      const Eigen::MatrixXd numeric_d_pixel = NumericJacobian(
          [&](const Eigen::VectorXd& x) {
            return normalized(Unproject<Model>(camera.params, x));
          },
          pixel, 2, camera.width);
      // Normalized coordinates are pixels divided by the focal length, so
      // the floor scales like the 1 px per unit of the projection test.
      const double mismatch =
          std::max(MaxRelativeMismatch(d_params, numeric_d_params, 1.0 / focal),
                   MaxRelativeMismatch(d_pixel, numeric_d_pixel, 1.0 / focal));
      EXPECT_LT(mismatch, 1e-6) << "pixel " << pixel.transpose() << "\n"
                                << d_params << "\nvs\n"
                                << numeric_d_params << "\n"
                                << d_pixel << "\nvs\n"
                                << numeric_d_pixel;
      max_mismatch = std::max(max_mismatch, mismatch);
    }
  }
  this->RecordProperty("max_relative_mismatch", Scientific(max_mismatch));
}

TYPED_TEST(CameraModelTest, PrincipalPointIsOpticalAxis) {
  using Model = TypeParam;
  for (const TestCamera& camera : TestCameras<Model>()) {
    const Eigen::Vector2d principal_point(
        camera.params[Model::kPrincipalPointIdxs[0]],
        camera.params[Model::kPrincipalPointIdxs[1]]);
    EXPECT_EQ(Project<Model>(camera.params, Eigen::Vector3d(0, 0, 4)),
              principal_point);
    EXPECT_EQ(Unproject<Model>(camera.params, principal_point),
              Eigen::Vector3d(0, 0, 1));
  }
}

TYPED_TEST(CameraModelTest, NameIdAndParameterCountRoundTrip) {
  using Model = TypeParam;
  EXPECT_TRUE(ExistsCameraModel(Model::kModelId));
  EXPECT_EQ(CameraModelNameToId(Model::kModelName), Model::kModelId);
  EXPECT_EQ(CameraModelIdToName(Model::kModelId), Model::kModelName);
  EXPECT_EQ(CameraModelNameToId(CameraModelIdToName(Model::kModelId)),
            Model::kModelId);
  EXPECT_EQ(CameraModelNumParams(Model::kModelId), Model::kNumParams);
  EXPECT_EQ(CameraModelParamsInfo(Model::kModelId), Model::kParamsInfo);
  EXPECT_NO_THROW(CheckCameraModelParams(Model::kModelId, Model::kNumParams));
}

// The info string names one parameter per index, focal lengths (f, fx, fy)
// first, then the principal point (cx, cy), then the extra parameters, each
// group at the indices the model declares.
TYPED_TEST(CameraModelTest, ParameterIndicesMatchParamsInfo) {
  using Model = TypeParam;
  std::vector<std::string> names;
  std::string info = Model::kParamsInfo;
  for (std::size_t start = 0;;) {
    const std::size_t comma = info.find(", ", start);
    names.push_back(info.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 2;
  }
  ASSERT_EQ(static_cast<int>(names.size()), Model::kNumParams);

  std::vector<int> all_idxs;
  for (const int idx : Model::kFocalLengthIdxs) {
    EXPECT_EQ(names.at(idx)[0], 'f') << names.at(idx);
    all_idxs.push_back(idx);
  }
  EXPECT_EQ(names.at(Model::kPrincipalPointIdxs[0]), "cx");
  EXPECT_EQ(names.at(Model::kPrincipalPointIdxs[1]), "cy");
  all_idxs.push_back(Model::kPrincipalPointIdxs[0]);
  all_idxs.push_back(Model::kPrincipalPointIdxs[1]);
  for (const int idx : Model::kExtraParamsIdxs) {
    EXPECT_NE(names.at(idx)[0], 'f') << names.at(idx);
    EXPECT_NE(names.at(idx)[0], 'c') << names.at(idx);
    all_idxs.push_back(idx);
  }
  std::vector<int> expected(Model::kNumParams);
  for (int i = 0; i < Model::kNumParams; ++i) expected[i] = i;
  EXPECT_EQ(all_idxs, expected);
}

TYPED_TEST(CameraModelTest, WrongParameterCountNamesModelAndCounts) {
  using Model = TypeParam;
  for (const std::size_t wrong :
       {std::size_t{0}, std::size_t{2}, std::size_t(Model::kNumParams + 1)}) {
    try {
      CheckCameraModelParams(Model::kModelId, wrong);
      ADD_FAILURE() << "no error for " << wrong << " parameters";
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_NE(
          message.find(std::string("camera model ") + Model::kModelName + " "),
          std::string::npos)
          << message;
      EXPECT_NE(message.find("expects " + std::to_string(Model::kNumParams) +
                             " parameters"),
                std::string::npos)
          << message;
      EXPECT_NE(message.find("got " + std::to_string(wrong)), std::string::npos)
          << message;
    }
  }
}

// COLMAP 3.8's table: these ids and counts are what cameras.bin and
// databases written by COLMAP contain.
TEST(CameraModels, IdsNamesAndCountsAreColmaps) {
  struct Row {
    int id;
    const char* name;
    int num_params;
  };
  const Row colmap_models[] = {
      {0, "SIMPLE_PINHOLE", 3},
      {1, "PINHOLE", 4},
      {2, "SIMPLE_RADIAL", 4},
      {3, "RADIAL", 5},
      {4, "OPENCV", 8},
      {5, "OPENCV_FISHEYE", 8},
      {6, "FULL_OPENCV", 12},
      {7, "FOV", 5},
      {8, "SIMPLE_RADIAL_FISHEYE", 4},
      {9, "RADIAL_FISHEYE", 5},
      {10, "THIN_PRISM_FISHEYE", 12},
  };
  ASSERT_EQ(kAllCameraModelIds.size(), std::size(colmap_models));
  for (const Row& row : colmap_models) {
    const auto id = static_cast<CameraModelId>(row.id);
    EXPECT_EQ(CameraModelNameToId(row.name), id);
    EXPECT_EQ(CameraModelIdToName(id), row.name);
    EXPECT_EQ(CameraModelNumParams(id), row.num_params);
  }
}

TEST(CameraModels, UnknownNamesAndIdsAreRejected) {
  for (const char* name : {"", "FOO", "opencv", "OPENCV ", "SIMPLE_RADIAL_"}) {
    EXPECT_EQ(CameraModelNameToId(name), CameraModelId::kInvalid) << name;
  }
  for (const int raw_id : {-1, 11, 12, 1000, -7}) {
    const auto id = static_cast<CameraModelId>(raw_id);
    EXPECT_FALSE(ExistsCameraModel(id)) << raw_id;
    EXPECT_EQ(CameraModelNumParams(id), -1) << raw_id;
    EXPECT_THROW(CameraModelIdToName(id), Error) << raw_id;
    EXPECT_THROW(CameraModelParamsInfo(id), Error) << raw_id;
    EXPECT_THROW(CheckCameraModelParams(id, 4), Error) << raw_id;
    EXPECT_THROW(VisitCameraModel(id, [](auto) { return 0; }), Error) << raw_id;
  }
}

TEST(CameraModels, VisitDispatchesTheModelOfEachId) {
  const std::pair<CameraModelId, std::type_index> expected[] = {
      {CameraModelId::kSimplePinhole, typeid(SimplePinholeCameraModel)},
      {CameraModelId::kPinhole, typeid(PinholeCameraModel)},
      {CameraModelId::kSimpleRadial, typeid(SimpleRadialCameraModel)},
      {CameraModelId::kRadial, typeid(RadialCameraModel)},
      {CameraModelId::kOpenCV, typeid(OpenCVCameraModel)},
      {CameraModelId::kOpenCVFisheye, typeid(OpenCVFisheyeCameraModel)},
      {CameraModelId::kFullOpenCV, typeid(FullOpenCVCameraModel)},
      {CameraModelId::kFOV, typeid(FOVCameraModel)},
      {CameraModelId::kSimpleRadialFisheye,
       typeid(SimpleRadialFisheyeCameraModel)},
      {CameraModelId::kRadialFisheye, typeid(RadialFisheyeCameraModel)},
      {CameraModelId::kThinPrismFisheye, typeid(ThinPrismFisheyeCameraModel)},
  };
  ASSERT_EQ(kAllCameraModelIds.size(), std::size(expected));
  for (const auto& [id, type] : expected) {
    EXPECT_EQ(VisitCameraModel(id,
                               [](auto tag) {
                                 using Model = typename decltype(tag)::type;
                                 return std::type_index(typeid(Model));
                               }),
              type);
    EXPECT_EQ(VisitCameraModel(id,
                               [](auto tag) {
                                 using Model = typename decltype(tag)::type;
                                 return Model::kModelId;
                               }),
              id);
  }
}

// Expected pixels below are written out from COLMAP's documented formulas,
// independently of the code under test, so that a wrong formula, parameter
// order or missing perspective division fails.
constexpr double kKnownValueTolerance = 1e-9;

Eigen::Vector2d ProjectWithId(CameraModelId id,
                              const std::vector<double>& params,
                              const Eigen::Vector3d& point) {
  CheckCameraModelParams(id, params.size());
  return CameraModelImgFromCam(id, params.data(), point);
}

TEST(CameraModelKnownValues, Pinholes) {
  // (0.4, -0.2, 2): u = 0.2, v = -0.1.
  const Eigen::Vector3d point(0.4, -0.2, 2);
  EXPECT_LT(
      (ProjectWithId(CameraModelId::kSimplePinhole, {500, 320, 240}, point) -
       Eigen::Vector2d(420, 190))
          .norm(),
      kKnownValueTolerance);
  EXPECT_LT(
      (ProjectWithId(CameraModelId::kPinhole, {500, 600, 320, 240}, point) -
       Eigen::Vector2d(420, 180))
          .norm(),
      kKnownValueTolerance);
}

TEST(CameraModelKnownValues, SimpleRadialAndRadial) {
  // u = 0.2, v = -0.1, r^2 = 0.05.
  const Eigen::Vector3d point(0.4, -0.2, 2);
  // 1 + k r^2 = 1.005.
  EXPECT_LT((ProjectWithId(CameraModelId::kSimpleRadial, {500, 320, 240, 0.1},
                           point) -
             Eigen::Vector2d(320 + 500 * 0.2 * 1.005, 240 - 500 * 0.1 * 1.005))
                .norm(),
            kKnownValueTolerance);
  // 1 + k1 r^2 + k2 r^4 = 1 + 0.005 - 0.000125 = 1.004875.
  EXPECT_LT((ProjectWithId(CameraModelId::kRadial, {500, 320, 240, 0.1, -0.05},
                           point) -
             Eigen::Vector2d(420.4875, 189.75625))
                .norm(),
            kKnownValueTolerance);
}

TEST(CameraModelKnownValues, OpenCVAndFullOpenCV) {
  const Eigen::Vector3d point(0.4, -0.2, 2);
  // u = 0.2, v = -0.1, r^2 = 0.05, radial 1.004875,
  // tangential du = 2 p1 u v + p2 (r^2 + 2 u^2) = -0.00004 - 0.00026,
  //            dv = 2 p2 u v + p1 (r^2 + 2 v^2) = 0.00008 + 0.00007.
  EXPECT_LT(
      (ProjectWithId(CameraModelId::kOpenCV,
                     {500, 510, 320, 240, 0.1, -0.05, 0.001, -0.002}, point) -
       Eigen::Vector2d(320 + 500 * (0.200975 - 0.0003),
                       240 + 510 * (-0.1004875 + 0.00015)))
          .norm(),
      kKnownValueTolerance);
  // Rational radial (1 + k1 r^2 + k2 r^4 + k3 r^6) / (1 + k4 r^2 + ...)
  // with k3 = 0.2, k4 = 0.3, k5 = -0.1, k6 = 0.4:
  const double r2 = 0.05;
  const double radial = (1 + 0.1 * r2 - 0.05 * r2 * r2 + 0.2 * r2 * r2 * r2) /
                        (1 + 0.3 * r2 - 0.1 * r2 * r2 + 0.4 * r2 * r2 * r2);
  EXPECT_LT((ProjectWithId(CameraModelId::kFullOpenCV,
                           {500, 510, 320, 240, 0.1, -0.05, 0.001, -0.002, 0.2,
                            0.3, -0.1, 0.4},
                           point) -
             Eigen::Vector2d(320 + 500 * (0.2 * radial - 0.0003),
                             240 + 510 * (-0.1 * radial + 0.00015)))
                .norm(),
            kKnownValueTolerance);
}

TEST(CameraModelKnownValues, FisheyesFollowTheAngleFromTheAxis) {
  // (1, 0, 1) and (1, 1, sqrt 2) are 45 degrees off-axis: theta = pi / 4.
  const double theta = M_PI / 4;
  const double t2 = theta * theta;
  const Eigen::Vector3d on_x(1, 0, 1);
  const Eigen::Vector3d diagonal(1, 1, std::sqrt(2.0));
  const double diagonal_unit = std::sqrt(0.5);

  const double opencv_thetad =
      theta * (1 + 0.1 * t2 - 0.02 * t2 * t2 + 0.003 * t2 * t2 * t2 -
               0.0004 * t2 * t2 * t2 * t2);
  const std::vector<double> opencv_params = {300, 310,   320,   240,
                                             0.1, -0.02, 0.003, -0.0004};
  EXPECT_LT((ProjectWithId(CameraModelId::kOpenCVFisheye, opencv_params, on_x) -
             Eigen::Vector2d(320 + 300 * opencv_thetad, 240))
                .norm(),
            kKnownValueTolerance);
  EXPECT_LT(
      (ProjectWithId(CameraModelId::kOpenCVFisheye, opencv_params, diagonal) -
       Eigen::Vector2d(320 + 300 * opencv_thetad * diagonal_unit,
                       240 + 310 * opencv_thetad * diagonal_unit))
          .norm(),
      kKnownValueTolerance);

  EXPECT_LT(
      (ProjectWithId(CameraModelId::kSimpleRadialFisheye, {300, 320, 240, 0.1},
                     diagonal) -
       Eigen::Vector2d(320 + 300 * theta * (1 + 0.1 * t2) * diagonal_unit,
                       240 + 300 * theta * (1 + 0.1 * t2) * diagonal_unit))
          .norm(),
      kKnownValueTolerance);
  EXPECT_LT((ProjectWithId(CameraModelId::kRadialFisheye,
                           {300, 320, 240, 0.1, -0.02}, on_x) -
             Eigen::Vector2d(
                 320 + 300 * theta * (1 + 0.1 * t2 - 0.02 * t2 * t2), 240))
                .norm(),
            kKnownValueTolerance);

  // Thin prism: the polynomial acts on the equidistant point (theta, 0):
  // du = theta radial + p2 (3 theta^2) + sx1 theta^2,
  // dv = p1 theta^2 + sy1 theta^2.
  const std::vector<double> thin_prism_params = {
      300,   310,    320,   240,     0.1,    -0.02,
      0.001, -0.002, 0.003, -0.0004, 0.0005, -0.0007};
  const double radial = 0.1 * t2 - 0.02 * t2 * t2 + 0.003 * t2 * t2 * t2 -
                        0.0004 * t2 * t2 * t2 * t2;
  const double du = theta * radial - 0.002 * 3 * t2 + 0.0005 * t2;
  const double dv = 0.001 * t2 - 0.0007 * t2;
  EXPECT_LT((ProjectWithId(CameraModelId::kThinPrismFisheye, thin_prism_params,
                           2 * on_x) -
             Eigen::Vector2d(320 + 300 * (theta + du), 240 + 310 * dv))
                .norm(),
            kKnownValueTolerance);
}

// FOV maps radius r to atan(2 r tan(omega / 2)) / omega. For |omega| < 0.01
// COLMAP 3.8 uses a series whose O(omega^2) error is omega^2 (r^2 - 1/4) / 2
// relative, ~3e-3 px here at omega = 0.005 (it vanishes at r = 1/2).
TEST(CameraModelKnownValues, FOVIncludingSmallOmega) {
  const Eigen::Vector3d point(1.2, 1.6, 2);  // u = 0.6, v = 0.8, r = 1.
  for (const double omega : {0.9, 0.2, 0.0101, 0.005, 1e-4}) {
    const double factor = std::atan(2 * std::tan(omega / 2)) / omega;
    EXPECT_LT(
        (ProjectWithId(CameraModelId::kFOV, {400, 410, 320, 240, omega},
                       point) -
         Eigen::Vector2d(320 + 400 * 0.6 * factor, 240 + 410 * 0.8 * factor))
            .norm(),
        kKnownValueTolerance)
        << "omega " << omega;
  }
  // omega = 0 is the pinhole limit.
  EXPECT_LT(
      (ProjectWithId(CameraModelId::kFOV, {400, 410, 320, 240, 0}, point) -
       Eigen::Vector2d(320 + 400 * 0.6, 240 + 410 * 0.8))
          .norm(),
      kKnownValueTolerance);
}

}  // namespace
}  // namespace uw
