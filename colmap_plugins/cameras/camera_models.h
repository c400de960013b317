// COLMAP's camera models (ids, names, parameter order and maths of COLMAP
// 3.8's src/base/camera_models.h), so that models written by COLMAP project
// here as they did inside COLMAP: to rounding (~1e-13 px), except FOV with
// |omega| < 0.01 where COLMAP's series is wrong (see FOVCameraModel).
// Unprojection iterates further than COLMAP's (see UndistortNewton).
//
// ImgFromCam(u, v, w) projects the point (u, v, w); like COLMAP it assumes
// w > 0 and callers check that. CamFromImg returns the ray scaled to w = 1 and
// is meaningful only where the model is invertible: for the fisheyes, rays
// less than 90 degrees off-axis; for polynomial distortion, radii before the
// distortion folds back. Elsewhere it returns the last Newton iterate, as
// COLMAP does.
//
// Pixel convention (COLMAP's): the upper-left image corner is (0, 0), the
// centre of the upper-left pixel is (0.5, 0.5). The formulas contain no 0.5
// offset; it lives in the principal point, which COLMAP estimates in this
// convention.
//
// Every model is a struct with compile-time constants and templated
// functions, so that Ceres cost functions can be instantiated per model with
// ceres::Jet (see VisitCameraModel). The header does not depend on Ceres:
// maths on T go through unqualified calls (`using std::atan; atan(x)`) that
// find Ceres's Jet overloads by argument-dependent lookup.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/LU>

#include "common/util/error.h"

namespace uw {

// The values are COLMAP's model ids as stored in cameras.bin and databases.
enum class CameraModelId : int {
  kInvalid = -1,
  kSimplePinhole = 0,
  kPinhole = 1,
  kSimpleRadial = 2,
  kRadial = 3,
  kOpenCV = 4,
  kOpenCVFisheye = 5,
  kFullOpenCV = 6,
  kFOV = 7,
  kSimpleRadialFisheye = 8,
  kRadialFisheye = 9,
  kThinPrismFisheye = 10,
};

inline constexpr std::array<CameraModelId, 11> kAllCameraModelIds = {
    CameraModelId::kSimplePinhole,
    CameraModelId::kPinhole,
    CameraModelId::kSimpleRadial,
    CameraModelId::kRadial,
    CameraModelId::kOpenCV,
    CameraModelId::kOpenCVFisheye,
    CameraModelId::kFullOpenCV,
    CameraModelId::kFOV,
    CameraModelId::kSimpleRadialFisheye,
    CameraModelId::kRadialFisheye,
    CameraModelId::kThinPrismFisheye,
};

namespace camera_internal {

// Value of a double or a ceres::Jet. Duck-typed on Jet's `a` member so that
// this header needs no Ceres include.
template <typename T>
double ScalarPart(const T& x) {
  if constexpr (std::is_arithmetic_v<T>) {
    return static_cast<double>(x);
  } else {
    return ScalarPart(x.a);
  }
}

// Below this squared argument the truncated series of atan(x)/x and tan(x)/x
// are exact to double precision (the first dropped term is < 1e-19).
inline constexpr double kSeriesMaxSquaredArgument = 1e-6;

// atan(x) / x as a function of x^2. The quotient is 0/0 at x = 0 (the image
// centre of the fisheye models); the series keeps values and Jet derivatives
// finite there, and taking x^2 avoids sqrt'(0).
template <typename T>
T AtanOverX(const T& x2) {
  using std::atan;
  using std::sqrt;
  if (x2 < T(kSeriesMaxSquaredArgument)) {
    return T(1) - x2 / T(3) + x2 * x2 / T(5);
  }
  const T x = sqrt(x2);
  return atan(x) / x;
}

// tan(x) / x as a function of x^2, for the same reason as AtanOverX.
template <typename T>
T TanOverX(const T& x2) {
  using std::sqrt;
  using std::tan;
  if (x2 < T(kSeriesMaxSquaredArgument)) {
    return T(1) + x2 / T(3) + T(2) * x2 * x2 / T(15);
  }
  const T x = sqrt(x2);
  return tan(x) / x;
}

template <typename Model, typename T>
void ImgFromNormal(const T* params, const T& u, const T& v, T* x, T* y) {
  *x = params[Model::kFocalLengthIdxs.front()] * u +
       params[Model::kPrincipalPointIdxs[0]];
  *y = params[Model::kFocalLengthIdxs.back()] * v +
       params[Model::kPrincipalPointIdxs[1]];
}

template <typename Model, typename T>
void NormalFromImg(const T* params, const T& x, const T& y, T* u, T* v) {
  *u = (x - params[Model::kPrincipalPointIdxs[0]]) /
       params[Model::kFocalLengthIdxs.front()];
  *v = (y - params[Model::kPrincipalPointIdxs[1]]) /
       params[Model::kFocalLengthIdxs.back()];
}

// I + d(Distortion)/d(u, v) by central differences with steps of
// kRelStepSize |x_i|, but at least min_step.
inline constexpr double kRelStepSize = 1e-6;
template <typename Model>
Eigen::Matrix2d DistortedFromUndistortedJacobian(const double* extra_params,
                                                 const Eigen::Vector2d& x,
                                                 double min_step) {
  Eigen::Matrix2d jacobian = Eigen::Matrix2d::Identity();
  for (int i = 0; i < 2; ++i) {
    const double step = std::max(min_step, std::abs(kRelStepSize * x(i)));
    Eigen::Vector2d backward = x;
    Eigen::Vector2d forward = x;
    backward(i) -= step;
    forward(i) += step;
    Eigen::Vector2d d_backward;
    Eigen::Vector2d d_forward;
    Model::Distortion(extra_params, backward(0), backward(1), &d_backward(0),
                      &d_backward(1));
    Model::Distortion(extra_params, forward(0), forward(1), &d_forward(0),
                      &d_forward(1));
    jacobian.col(i) += (d_forward - d_backward) / (2 * step);
  }
  return jacobian;
}

// Solves x + Distortion(x) = (u, v) for x by Newton's method from x = (u, v),
// with COLMAP 3.8's Jacobian and iteration limit, so the iterates are
// COLMAP's. COLMAP stops once a step is below 1e-5 (squared norm 1e-10),
// which leaves errors up to ~1e-10 in normalized units, i.e. up to ~1e-7 px
// after reprojection. Stopping at steps below 1e-10 instead costs about one
// more iteration and brings the round trip to rounding level (~1e-13 px).
template <typename Model>
void UndistortNewton(const double* extra_params, double* u, double* v) {
  constexpr int kNumIterations = 100;
  constexpr double kMaxStepSquaredNorm = 1e-20;
  const Eigen::Vector2d distorted(*u, *v);
  Eigen::Vector2d x = distorted;
  for (int i = 0; i < kNumIterations; ++i) {
    Eigen::Vector2d d;
    Model::Distortion(extra_params, x(0), x(1), &d(0), &d(1));
    const Eigen::Vector2d step =
        DistortedFromUndistortedJacobian<Model>(
            extra_params, x, std::numeric_limits<double>::epsilon())
            .inverse() *
        (x + d - distorted);
    x -= step;
    if (step.squaredNorm() < kMaxStepSquaredNorm) {
      break;
    }
  }
  *u = x(0);
  *v = x(1);
}

// Replaces the distorted normalized coordinates (u, v) by undistorted ones.
// For Jets the Newton iteration runs on the values only; the derivatives then
// follow from the implicit function theorem applied to x + D(x; p) = (u, v):
// dx = J^-1 (d(u, v) - D_p dp). Iterating on Jets instead would leave the
// derivatives a step behind the values when the stopping rule fires.
// T is double or ceres::Jet<double, N>.
template <typename Model, typename T>
void IterativeUndistortion(const T* extra_params, T* u, T* v) {
  if constexpr (std::is_same_v<T, double>) {
    UndistortNewton<Model>(extra_params, u, v);
  } else {
    constexpr std::size_t kNumExtraParams = Model::kExtraParamsIdxs.size();
    std::array<double, kNumExtraParams> extra_values;
    for (std::size_t i = 0; i < kNumExtraParams; ++i) {
      extra_values[i] = ScalarPart(extra_params[i]);
    }
    double u_value = ScalarPart(*u);
    double v_value = ScalarPart(*v);
    UndistortNewton<Model>(extra_values.data(), &u_value, &v_value);
    // COLMAP's minimum step (machine epsilon) turns a Jacobian column into
    // rounding noise where x_i = 0 and the distortion has terms even in x_i
    // (tangential, thin prism). Newton still converges with that; the
    // derivatives would inherit the noise, so here the step is >= 1e-6.
    const Eigen::Matrix2d jacobian_inverse =
        DistortedFromUndistortedJacobian<Model>(
            extra_values.data(), Eigen::Vector2d(u_value, v_value),
            kRelStepSize)
            .inverse();

    // One Newton step in T from the constant solution: the residual's value
    // is ~0, its derivative is D_p dp - d(u, v).
    T du;
    T dv;
    Model::Distortion(extra_params, T(u_value), T(v_value), &du, &dv);
    const T residual_u = T(u_value) + du - *u;
    const T residual_v = T(v_value) + dv - *v;
    *u = T(u_value) - (jacobian_inverse(0, 0) * residual_u +
                       jacobian_inverse(0, 1) * residual_v);
    *v = T(v_value) - (jacobian_inverse(1, 0) * residual_u +
                       jacobian_inverse(1, 1) * residual_v);
  }
}

// Models that distort the normalized image plane (u/w, v/w) additively and
// then apply the focal lengths and principal point:
//   pixel = f * (n + Distortion(n)) + c,  n = (u/w, v/w).
// COLMAP 3.8 treats its OpenCV-style fisheye models this way too, with the
// angle mapping folded into their Distortion.
template <typename Model>
struct DistortedPlaneModel {
  template <typename T>
  static void ImgFromCam(const T* params, T u, T v, T w, T* x, T* y) {
    const T normal_u = u / w;
    const T normal_v = v / w;
    T du;
    T dv;
    Model::Distortion(params + Model::kExtraParamsIdxs[0], normal_u, normal_v,
                      &du, &dv);
    ImgFromNormal<Model>(params, normal_u + du, normal_v + dv, x, y);
  }

  template <typename T>
  static void CamFromImg(const T* params, T x, T y, T* u, T* v, T* w) {
    NormalFromImg<Model>(params, x, y, u, v);
    IterativeUndistortion<Model>(params + Model::kExtraParamsIdxs[0], u, v);
    *w = T(1);
  }
};

// Same as DistortedPlaneModel without distortion.
template <typename Model>
struct UndistortedPlaneModel {
  template <typename T>
  static void ImgFromCam(const T* params, T u, T v, T w, T* x, T* y) {
    ImgFromNormal<Model>(params, u / w, v / w, x, y);
  }

  template <typename T>
  static void CamFromImg(const T* params, T x, T y, T* u, T* v, T* w) {
    NormalFromImg<Model>(params, x, y, u, v);
    *w = T(1);
  }
};

// Equidistant mapping: the point of the normalized plane at radius r = tan
// theta moves along its direction to radius theta.
template <typename T>
void FisheyeFromNormal(const T& u, const T& v, T* uu, T* vv) {
  const T theta_over_r = AtanOverX(u * u + v * v);
  *uu = u * theta_over_r;
  *vv = v * theta_over_r;
}

// Inverse of FisheyeFromNormal, meaningful for theta < pi / 2.
template <typename T>
void NormalFromFisheye(const T& uu, const T& vv, T* u, T* v) {
  const T r_over_theta = TanOverX(uu * uu + vv * vv);
  *u = uu * r_over_theta;
  *v = vv * r_over_theta;
}

// (1 + k1 theta^2 + ... + kn theta^2n) * theta / r - 1 for the normalized
// radius r = |(u, v)|, theta = atan(r): the relative radial displacement of
// COLMAP 3.8's OpenCV-style fisheye models.
template <typename T, std::size_t N>
T FisheyeRadialScaleMinusOne(const T& u, const T& v,
                             const std::array<T, N>& k) {
  const T theta_over_r = AtanOverX(u * u + v * v);
  const T theta2 = (u * u + v * v) * theta_over_r * theta_over_r;
  T polynomial = T(0);
  T theta2_power = T(1);
  for (const T& coefficient : k) {
    theta2_power *= theta2;
    polynomial += coefficient * theta2_power;
  }
  return theta_over_r * (T(1) + polynomial) - T(1);
}

}  // namespace camera_internal

// Parameters: f, cx, cy.
struct SimplePinholeCameraModel
    : camera_internal::UndistortedPlaneModel<SimplePinholeCameraModel> {
  static constexpr CameraModelId kModelId = CameraModelId::kSimplePinhole;
  static constexpr int kNumParams = 3;
  static constexpr const char* kModelName = "SIMPLE_PINHOLE";
  static constexpr const char* kParamsInfo = "f, cx, cy";
  static constexpr std::array<int, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<int, 0> kExtraParamsIdxs = {};
};

// Parameters: fx, fy, cx, cy.
struct PinholeCameraModel
    : camera_internal::UndistortedPlaneModel<PinholeCameraModel> {
  static constexpr CameraModelId kModelId = CameraModelId::kPinhole;
  static constexpr int kNumParams = 4;
  static constexpr const char* kModelName = "PINHOLE";
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy";
  static constexpr std::array<int, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<int, 0> kExtraParamsIdxs = {};
};

// Parameters: f, cx, cy, k. Distortion: n * k r^2.
struct SimpleRadialCameraModel
    : camera_internal::DistortedPlaneModel<SimpleRadialCameraModel> {
  static constexpr CameraModelId kModelId = CameraModelId::kSimpleRadial;
  static constexpr int kNumParams = 4;
  static constexpr const char* kModelName = "SIMPLE_RADIAL";
  static constexpr const char* kParamsInfo = "f, cx, cy, k";
  static constexpr std::array<int, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<int, 1> kExtraParamsIdxs = {3};

  template <typename T>
  static void Distortion(const T* extra_params, T u, T v, T* du, T* dv) {
    const T k = extra_params[0];
    const T radial = k * (u * u + v * v);
    *du = u * radial;
    *dv = v * radial;
  }
};

// Parameters: f, cx, cy, k1, k2. Distortion: n * (k1 r^2 + k2 r^4).
struct RadialCameraModel
    : camera_internal::DistortedPlaneModel<RadialCameraModel> {
  static constexpr CameraModelId kModelId = CameraModelId::kRadial;
  static constexpr int kNumParams = 5;
  static constexpr const char* kModelName = "RADIAL";
  static constexpr const char* kParamsInfo = "f, cx, cy, k1, k2";
  static constexpr std::array<int, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<int, 2> kExtraParamsIdxs = {3, 4};

  template <typename T>
  static void Distortion(const T* extra_params, T u, T v, T* du, T* dv) {
    const T k1 = extra_params[0];
    const T k2 = extra_params[1];
    const T r2 = u * u + v * v;
    const T radial = k1 * r2 + k2 * r2 * r2;
    *du = u * radial;
    *dv = v * radial;
  }
};

// Parameters: fx, fy, cx, cy, k1, k2, p1, p2 (OpenCV's radial-tangential
// model truncated after k2).
struct OpenCVCameraModel
    : camera_internal::DistortedPlaneModel<OpenCVCameraModel> {
  static constexpr CameraModelId kModelId = CameraModelId::kOpenCV;
  static constexpr int kNumParams = 8;
  static constexpr const char* kModelName = "OPENCV";
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy, k1, k2, p1, p2";
  static constexpr std::array<int, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<int, 4> kExtraParamsIdxs = {4, 5, 6, 7};

  template <typename T>
  static void Distortion(const T* extra_params, T u, T v, T* du, T* dv) {
    const T k1 = extra_params[0];
    const T k2 = extra_params[1];
    const T p1 = extra_params[2];
    const T p2 = extra_params[3];
    const T u2 = u * u;
    const T uv = u * v;
    const T v2 = v * v;
    const T r2 = u2 + v2;
    const T radial = k1 * r2 + k2 * r2 * r2;
    *du = u * radial + T(2) * p1 * uv + p2 * (r2 + T(2) * u2);
    *dv = v * radial + T(2) * p2 * uv + p1 * (r2 + T(2) * v2);
  }
};

// Parameters: fx, fy, cx, cy, k1, k2, k3, k4 (OpenCV's equidistant fisheye
// model). The normalized point at r = tan theta is moved to radius
// theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8).
struct OpenCVFisheyeCameraModel
    : camera_internal::DistortedPlaneModel<OpenCVFisheyeCameraModel> {
  static constexpr CameraModelId kModelId = CameraModelId::kOpenCVFisheye;
  static constexpr int kNumParams = 8;
  static constexpr const char* kModelName = "OPENCV_FISHEYE";
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy, k1, k2, k3, k4";
  static constexpr std::array<int, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<int, 4> kExtraParamsIdxs = {4, 5, 6, 7};

  template <typename T>
  static void Distortion(const T* extra_params, T u, T v, T* du, T* dv) {
    const T scale_minus_one = camera_internal::FisheyeRadialScaleMinusOne(
        u, v,
        std::array<T, 4>{extra_params[0], extra_params[1], extra_params[2],
                         extra_params[3]});
    *du = u * scale_minus_one;
    *dv = v * scale_minus_one;
  }
};

// Parameters: fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6 (OpenCV's
// rational radial model with tangential terms).
struct FullOpenCVCameraModel
    : camera_internal::DistortedPlaneModel<FullOpenCVCameraModel> {
  static constexpr CameraModelId kModelId = CameraModelId::kFullOpenCV;
  static constexpr int kNumParams = 12;
  static constexpr const char* kModelName = "FULL_OPENCV";
  static constexpr const char* kParamsInfo =
      "fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6";
  static constexpr std::array<int, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<int, 8> kExtraParamsIdxs = {4, 5, 6,  7,
                                                          8, 9, 10, 11};

  template <typename T>
  static void Distortion(const T* extra_params, T u, T v, T* du, T* dv) {
    const T k1 = extra_params[0];
    const T k2 = extra_params[1];
    const T p1 = extra_params[2];
    const T p2 = extra_params[3];
    const T k3 = extra_params[4];
    const T k4 = extra_params[5];
    const T k5 = extra_params[6];
    const T k6 = extra_params[7];
    const T u2 = u * u;
    const T uv = u * v;
    const T v2 = v * v;
    const T r2 = u2 + v2;
    const T r4 = r2 * r2;
    const T r6 = r4 * r2;
    const T radial = (T(1) + k1 * r2 + k2 * r4 + k3 * r6) /
                     (T(1) + k4 * r2 + k5 * r4 + k6 * r6);
    *du = u * radial + T(2) * p1 * uv + p2 * (r2 + T(2) * u2) - u;
    *dv = v * radial + T(2) * p2 * uv + p1 * (r2 + T(2) * v2) - v;
  }
};

// Parameters: fx, fy, cx, cy, omega (Devernay & Faugeras, "Straight lines
// have to be straight", 2001). The normalized point at radius r moves to
// radius atan(2 r tan(omega / 2)) / omega. Unlike the other distorted models
// the inverse is closed form, so CamFromImg does not iterate.
//
// Distortion returns the displacement, as for every other model here; COLMAP
// 3.8's FOV Distortion returns the distorted point instead.
struct FOVCameraModel {
  static constexpr CameraModelId kModelId = CameraModelId::kFOV;
  static constexpr int kNumParams = 5;
  static constexpr const char* kModelName = "FOV";
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy, omega";
  static constexpr std::array<int, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<int, 1> kExtraParamsIdxs = {4};

  // atan(2 r tan(omega / 2)) / (r omega), written as a product of AtanOverX
  // and TanOverX so that r = 0 and omega = 0 need no special case. COLMAP 3.8
  // switches to Taylor series for omega^2 < 1e-4 or r^2 < 1e-4 instead. Its
  // omega series here is the one of UndistortionFactor (the O(omega^2) terms
  // have the wrong sign), so for |omega| < 0.01 its projection is off by
  // (2/3) omega^2 (r^2 - 1/4) relative (5e-3 px at omega = 0.005, r = 1,
  // f = 400) and disagrees with its own unprojection; its r series is off by
  // up to ~1e-7 px. Both factors here are exact to rounding.
  template <typename T>
  static T DistortionFactor(const T& omega, const T& r2) {
    using camera_internal::AtanOverX;
    using camera_internal::TanOverX;
    const T half_omega2 = omega * omega / T(4);
    const T tan_half_omega_over_half_omega = TanOverX(half_omega2);
    // (2 r tan(omega / 2))^2
    const T z2 = r2 * omega * omega * tan_half_omega_over_half_omega *
                 tan_half_omega_over_half_omega;
    return AtanOverX(z2) * tan_half_omega_over_half_omega;
  }

  // tan(r omega) / (2 r tan(omega / 2)): the inverse of DistortionFactor's
  // radial map, for the distorted radius r.
  template <typename T>
  static T UndistortionFactor(const T& omega, const T& r2) {
    using camera_internal::TanOverX;
    return TanOverX(r2 * omega * omega) / TanOverX(omega * omega / T(4));
  }

  template <typename T>
  static void Distortion(const T* extra_params, T u, T v, T* du, T* dv) {
    const T factor_minus_one =
        DistortionFactor(extra_params[0], u * u + v * v) - T(1);
    *du = u * factor_minus_one;
    *dv = v * factor_minus_one;
  }

  template <typename T>
  static void ImgFromCam(const T* params, T u, T v, T w, T* x, T* y) {
    const T normal_u = u / w;
    const T normal_v = v / w;
    const T factor = DistortionFactor(
        params[kExtraParamsIdxs[0]], normal_u * normal_u + normal_v * normal_v);
    camera_internal::ImgFromNormal<FOVCameraModel>(params, normal_u * factor,
                                                   normal_v * factor, x, y);
  }

  template <typename T>
  static void CamFromImg(const T* params, T x, T y, T* u, T* v, T* w) {
    T distorted_u;
    T distorted_v;
    camera_internal::NormalFromImg<FOVCameraModel>(params, x, y, &distorted_u,
                                                   &distorted_v);
    const T factor = UndistortionFactor(
        params[kExtraParamsIdxs[0]],
        distorted_u * distorted_u + distorted_v * distorted_v);
    *u = distorted_u * factor;
    *v = distorted_v * factor;
    *w = T(1);
  }
};

// Parameters: f, cx, cy, k (OPENCV_FISHEYE with one focal length and k1
// only).
struct SimpleRadialFisheyeCameraModel
    : camera_internal::DistortedPlaneModel<SimpleRadialFisheyeCameraModel> {
  static constexpr CameraModelId kModelId = CameraModelId::kSimpleRadialFisheye;
  static constexpr int kNumParams = 4;
  static constexpr const char* kModelName = "SIMPLE_RADIAL_FISHEYE";
  static constexpr const char* kParamsInfo = "f, cx, cy, k";
  static constexpr std::array<int, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<int, 1> kExtraParamsIdxs = {3};

  template <typename T>
  static void Distortion(const T* extra_params, T u, T v, T* du, T* dv) {
    const T scale_minus_one = camera_internal::FisheyeRadialScaleMinusOne(
        u, v, std::array<T, 1>{extra_params[0]});
    *du = u * scale_minus_one;
    *dv = v * scale_minus_one;
  }
};

// Parameters: f, cx, cy, k1, k2 (OPENCV_FISHEYE with one focal length and
// k1, k2 only).
struct RadialFisheyeCameraModel
    : camera_internal::DistortedPlaneModel<RadialFisheyeCameraModel> {
  static constexpr CameraModelId kModelId = CameraModelId::kRadialFisheye;
  static constexpr int kNumParams = 5;
  static constexpr const char* kModelName = "RADIAL_FISHEYE";
  static constexpr const char* kParamsInfo = "f, cx, cy, k1, k2";
  static constexpr std::array<int, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<int, 2> kExtraParamsIdxs = {3, 4};

  template <typename T>
  static void Distortion(const T* extra_params, T u, T v, T* du, T* dv) {
    const T scale_minus_one = camera_internal::FisheyeRadialScaleMinusOne(
        u, v, std::array<T, 2>{extra_params[0], extra_params[1]});
    *du = u * scale_minus_one;
    *dv = v * scale_minus_one;
  }
};

// Parameters: fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1 (Weng et al.,
// "Camera calibration with distortion models and accuracy evaluation", TPAMI
// 1992). Unlike OPENCV_FISHEYE, the radial, tangential and thin-prism terms
// act on the equidistant plane, i.e. on (u, v) * theta / r, so Distortion
// takes equidistant coordinates.
struct ThinPrismFisheyeCameraModel {
  static constexpr CameraModelId kModelId = CameraModelId::kThinPrismFisheye;
  static constexpr int kNumParams = 12;
  static constexpr const char* kModelName = "THIN_PRISM_FISHEYE";
  static constexpr const char* kParamsInfo =
      "fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1";
  static constexpr std::array<int, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<int, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<int, 8> kExtraParamsIdxs = {4, 5, 6,  7,
                                                          8, 9, 10, 11};

  template <typename T>
  static void Distortion(const T* extra_params, T u, T v, T* du, T* dv) {
    const T k1 = extra_params[0];
    const T k2 = extra_params[1];
    const T p1 = extra_params[2];
    const T p2 = extra_params[3];
    const T k3 = extra_params[4];
    const T k4 = extra_params[5];
    const T sx1 = extra_params[6];
    const T sy1 = extra_params[7];
    const T u2 = u * u;
    const T uv = u * v;
    const T v2 = v * v;
    const T r2 = u2 + v2;
    const T r4 = r2 * r2;
    const T r6 = r4 * r2;
    const T r8 = r6 * r2;
    const T radial = k1 * r2 + k2 * r4 + k3 * r6 + k4 * r8;
    *du = u * radial + T(2) * p1 * uv + p2 * (r2 + T(2) * u2) + sx1 * r2;
    *dv = v * radial + T(2) * p2 * uv + p1 * (r2 + T(2) * v2) + sy1 * r2;
  }

  template <typename T>
  static void ImgFromCam(const T* params, T u, T v, T w, T* x, T* y) {
    T uu;
    T vv;
    camera_internal::FisheyeFromNormal(u / w, v / w, &uu, &vv);
    T du;
    T dv;
    Distortion(params + kExtraParamsIdxs[0], uu, vv, &du, &dv);
    camera_internal::ImgFromNormal<ThinPrismFisheyeCameraModel>(params, uu + du,
                                                                vv + dv, x, y);
  }

  template <typename T>
  static void CamFromImg(const T* params, T x, T y, T* u, T* v, T* w) {
    T uu;
    T vv;
    camera_internal::NormalFromImg<ThinPrismFisheyeCameraModel>(params, x, y,
                                                                &uu, &vv);
    camera_internal::IterativeUndistortion<ThinPrismFisheyeCameraModel>(
        params + kExtraParamsIdxs[0], &uu, &vv);
    camera_internal::NormalFromFisheye(uu, vv, u, v);
    *w = T(1);
  }
};

// Names the model type for a generic lambda in VisitCameraModel.
template <class M>
struct CameraModelTag {
  using type = M;
};

// Calls visitor(CameraModelTag<Model>{}) for the model with this id and
// returns its result; every instantiation must return the same type. This
// is how code instantiates per-model templates (Ceres cost functions) from a
// runtime id. Throws uw::Error for an unknown id.
template <typename Visitor>
decltype(auto) VisitCameraModel(CameraModelId id, Visitor&& visitor) {
  switch (id) {
    case CameraModelId::kSimplePinhole:
      return visitor(CameraModelTag<SimplePinholeCameraModel>{});
    case CameraModelId::kPinhole:
      return visitor(CameraModelTag<PinholeCameraModel>{});
    case CameraModelId::kSimpleRadial:
      return visitor(CameraModelTag<SimpleRadialCameraModel>{});
    case CameraModelId::kRadial:
      return visitor(CameraModelTag<RadialCameraModel>{});
    case CameraModelId::kOpenCV:
      return visitor(CameraModelTag<OpenCVCameraModel>{});
    case CameraModelId::kOpenCVFisheye:
      return visitor(CameraModelTag<OpenCVFisheyeCameraModel>{});
    case CameraModelId::kFullOpenCV:
      return visitor(CameraModelTag<FullOpenCVCameraModel>{});
    case CameraModelId::kFOV:
      return visitor(CameraModelTag<FOVCameraModel>{});
    case CameraModelId::kSimpleRadialFisheye:
      return visitor(CameraModelTag<SimpleRadialFisheyeCameraModel>{});
    case CameraModelId::kRadialFisheye:
      return visitor(CameraModelTag<RadialFisheyeCameraModel>{});
    case CameraModelId::kThinPrismFisheye:
      return visitor(CameraModelTag<ThinPrismFisheyeCameraModel>{});
    case CameraModelId::kInvalid:
      break;
  }
  throw ErrorAt("unknown camera model id ", static_cast<int>(id));
}

bool ExistsCameraModel(CameraModelId id);

// kInvalid if no model has this name (names are COLMAP's, case-sensitive).
CameraModelId CameraModelNameToId(const std::string& name);

// Throws uw::Error for an unknown id.
std::string CameraModelIdToName(CameraModelId id);

// -1 for an unknown id.
int CameraModelNumParams(CameraModelId id);

// "f, cx, cy, k" style parameter order; throws uw::Error for an unknown id.
std::string CameraModelParamsInfo(CameraModelId id);

// Throws uw::Error if the id is unknown or num_params is not the model's
// parameter count.
void CheckCameraModelParams(CameraModelId id, std::size_t num_params);

// Pixel of a point in the camera frame; the point must have z > 0.
Eigen::Vector2d CameraModelImgFromCam(CameraModelId id, const double* params,
                                      const Eigen::Vector3d& point_in_cam);

// Ray through a pixel, scaled to z = 1.
Eigen::Vector3d CameraModelCamFromImg(CameraModelId id, const double* params,
                                      const Eigen::Vector2d& pixel);

// Focal lengths (fx, fy) in pixels; models with one focal length return it
// twice.
Eigen::Vector2d CameraModelFocalLengths(CameraModelId id, const double* params);

// Principal point (cx, cy) in COLMAP's pixel convention.
Eigen::Vector2d CameraModelPrincipalPoint(CameraModelId id,
                                          const double* params);

}  // namespace uw
