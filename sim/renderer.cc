#include "sim/renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/util/error.h"
#include "common/util/json_fields.h"
#include "common/util/random.h"

namespace uw::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

// Marine snow: particles nearer than this are out of focus and would cover
// much of the image; sizes and reflectances of typical flocs.
constexpr double kSnowMinRange = 0.2;
constexpr double kSnowMinRadius = 0.5e-3;
constexpr double kSnowMaxRadius = 2.5e-3;
constexpr double kSnowMinAlbedo = 0.4;
constexpr double kSnowMaxAlbedo = 1.0;
// Bounds the snow volume of fisheye views (|x / z| grows without bound
// towards 90 degrees off-axis); 4 is 76 degrees.
constexpr double kSnowMaxTan = 4.0;
// A particle smaller than a pixel is still blurred over about one pixel by
// the optics.
constexpr double kSnowMinSigmaPx = 0.5;

// Rec. 709 luminance of linear RGB, for monochrome sensors.
const Eigen::Vector3d kLuminance(0.2126, 0.7152, 0.0722);

// ---------------------------------------------------------------------------
// Counter-based random numbers: every draw is a hash of (seed, image index,
// stream, item, draw number), so no state is shared between pixels or
// threads and the order of evaluation cannot change a result.

enum class Stream : uint64_t { kNoise = 1, kSnowCount = 2, kSnowParticle = 3 };

class CounterRng {
 public:
  CounterRng(uint64_t seed, uint64_t image_index, Stream stream, uint64_t item)
      : key_(SplitMix64(SplitMix64(SplitMix64(SplitMix64(seed) ^ image_index) ^
                                   static_cast<uint64_t>(stream)) ^
                        item)) {}

  uint64_t Next() { return SplitMix64(key_ + kSplitMix64Gamma * counter_++); }

  // Uniform in (0, 1): never 0, so that log() stays finite.
  double Uniform() {
    return (static_cast<double>(Next() >> 11) + 0.5) * 0x1.0p-53;
  }

  // Two independent standard normals by Box-Muller from one 64-bit draw.
  Eigen::Vector2d GaussianPair() {
    const uint64_t bits = Next();
    const double u1 = (static_cast<double>(bits >> 32) + 0.5) * 0x1.0p-32;
    const double u2 =
        (static_cast<double>(bits & 0xFFFFFFFFull) + 0.5) * 0x1.0p-32;
    const double radius = std::sqrt(-2.0 * std::log(u1));
    return {radius * std::cos(2.0 * kPi * u2),
            radius * std::sin(2.0 * kPi * u2)};
  }

 private:
  uint64_t key_;
  uint64_t counter_ = 0;
};

// ---------------------------------------------------------------------------
// Light transport.

// Per channel; several times faster than Eigen's array exp on 3-vectors.
Eigen::Vector3d Exp(const Eigen::Vector3d& x) {
  return {std::exp(x.x()), std::exp(x.y()), std::exp(x.z())};
}

// The lamp of one frame, in the world frame.
struct SpotLight {
  Eigen::Vector3d position_in_world;
  Eigen::Vector3d axis_in_world;  // unit
  double inner_angle;             // radians: full intensity up to here
  double outer_angle;             // radians: nothing beyond
  double cos_inner;
  double cos_outer;
  double intensity;

  // Fraction of the on-axis intensity emitted along the unit direction
  // `from_light`.
  double Cone(const Eigen::Vector3d& from_light) const {
    const double cos_angle = from_light.dot(axis_in_world);
    if (cos_angle >= cos_inner) return 1.0;
    if (cos_angle <= cos_outer) return 0.0;
    const double s =
        (std::acos(cos_angle) - inner_angle) / (outer_angle - inner_angle);
    return 1.0 - s * s * (3.0 - 2.0 * s);  // smoothstep down to 0
  }
};

// Everything one frame's samples share. Light reaches a point from each
// emitter (the lamp, laser beams) through ForEachIncidence, so surfaces and
// particles see every emitter alike.
class FrameShader {
 public:
  FrameShader(const RayCaster& caster, const Texture& texture,
              const RenderOptions& options,
              const Eigen::Matrix3d& world_from_cam_rotation,
              const Eigen::Vector3d& camera_in_world,
              const Rigid3d& cam_from_world, const FrameOptions& frame_options)
      : texture_(texture),
        shiny_(texture.HasShine()),
        attenuation_(options.water.attenuation_per_m),
        veil_(options.water.backscatter_strength *
              options.water.backscatter_rgb),
        surface_epsilon_(caster.SurfaceEpsilon()) {
    const LightOptions& light = options.light;
    SpotLight spot;
    spot.position_in_world =
        world_from_cam_rotation * light.position_in_cam + camera_in_world;
    spot.axis_in_world =
        world_from_cam_rotation * light.direction_in_cam.normalized();
    spot.inner_angle = std::max(
        0.0,
        (light.cone_half_angle_deg - 0.5 * light.cone_falloff_deg) * kDegToRad);
    spot.outer_angle = std::min(
        kPi,
        (light.cone_half_angle_deg + 0.5 * light.cone_falloff_deg) * kDegToRad);
    spot.cos_inner = std::cos(spot.inner_angle);
    spot.cos_outer = std::cos(spot.outer_angle);
    spot.intensity = light.intensity;
    spots_.push_back(spot);
    for (const Laser& laser : frame_options.lasers) {
      beams_.emplace_back(laser, frame_options.optics, cam_from_world);
    }
  }

  const Eigen::Vector3d& Veil() const { return veil_; }
  bool HasShine() const { return shiny_; }
  Shine ShineAt(const Eigen::Vector3d& point) const {
    return texture_.ShineAt(point);
  }

  Eigen::Vector3d Transmission(double distance) const {
    return Exp(-attenuation_ * distance);
  }

  // Calls add(light, channel, shadow_ray, shadow_length) for each emitter
  // that lights `point` unless something lies along the shadow ray: the
  // light that a unit albedo at the point sends to the camera,
  // camera_distance_m away, through the water: the irradiance (on the
  // surface with its unit normal on the camera's side; without, on a
  // particle facing the emitter) with the water's attenuation on both legs.
  // The lamp's broadband light is reflected by the albedo of each channel
  // and attenuated by each channel's coefficient (channel -1). A laser's
  // light is one wavelength, that of its colour's strongest channel
  // (`channel`): the surface reflects it by that channel's albedo and the
  // water attenuates it by that channel's coefficient, and the sensor sees
  // it in every channel in the proportions of the laser's colour.
  template <typename Add>
  void ForEachIncidence(const Eigen::Vector3d& point,
                        const Eigen::Vector3d* surface_normal,
                        double camera_distance_m, Add&& add) const {
    for (const SpotLight& spot : spots_) {
      const Eigen::Vector3d to_light = spot.position_in_world - point;
      const double distance = to_light.norm();
      Ray shadow_ray;
      shadow_ray.direction = to_light / distance;
      const double cos_incidence =
          surface_normal == nullptr ? 1.0
                                    : surface_normal->dot(shadow_ray.direction);
      if (cos_incidence <= 0.0) continue;
      const double cone = spot.Cone(-shadow_ray.direction);
      if (cone == 0.0) continue;
      // A shadow ray leaving a surface starts off it, lest it hit the
      // triangle it starts on.
      const double offset = surface_normal == nullptr ? 0.0 : surface_epsilon_;
      shadow_ray.origin =
          surface_normal == nullptr
              ? point
              : Eigen::Vector3d(point + offset * *surface_normal);
      add((spot.intensity * cone * cos_incidence / (distance * distance)) *
              Transmission(distance + camera_distance_m),
          -1, shadow_ray, distance - offset);
    }
    for (const LaserBeam& beam : beams_) {
      double along = 0.0;
      const double irradiance = beam.Irradiance(point, &along);
      if (irradiance == 0.0) continue;
      // The beam's light travels along its axis (its divergence is
      // milliradians), so it reaches the point unless something lies
      // between the point and the laser's plane along that axis.
      Ray shadow_ray;
      shadow_ray.direction = -beam.direction_in_world;
      const double cos_incidence =
          surface_normal == nullptr ? 1.0
                                    : surface_normal->dot(shadow_ray.direction);
      if (cos_incidence <= 0.0) continue;
      const double offset = surface_normal == nullptr ? 0.0 : surface_epsilon_;
      shadow_ray.origin =
          surface_normal == nullptr
              ? point
              : Eigen::Vector3d(point + offset * *surface_normal);
      const int channel = beam.dominant_channel;
      add((irradiance * cos_incidence *
           std::exp(-attenuation_(channel) * (along + camera_distance_m))) *
              beam.colour,
          channel, shadow_ray, std::max(0.0, along - offset));
    }
  }

  // What a surface hit by a camera ray sends to the camera, split as
  // radiance = veil_part + albedo * (the light of ForEachIncidence);
  // `normal` is set to the hit's shading normal on the camera's side.
  void SurfaceTerms(const Eigen::Vector3d& direction, const RayCaster::Hit& hit,
                    Eigen::Vector3d* normal, Eigen::Vector3d* veil_part,
                    Eigen::Vector3d* albedo) const {
    // The side the camera sees is lit and shaded, so an open mesh seen from
    // behind still looks like a surface rather than a hole.
    *normal = hit.normal_in_world.dot(direction) < 0.0
                  ? hit.shading_normal_in_world
                  : Eigen::Vector3d(-hit.shading_normal_in_world);
    *veil_part = veil_.cwiseProduct(Eigen::Vector3d::Ones() -
                                    Transmission(hit.distance));
    *albedo =
        texture_.Albedo(hit.point_in_world, hit.normal_in_world).cast<double>();
  }

 private:
  const Texture& texture_;
  bool shiny_;
  Eigen::Vector3d attenuation_;
  Eigen::Vector3d veil_;
  double surface_epsilon_;
  std::vector<SpotLight> spots_;
  std::vector<LaserBeam> beams_;
};

// What the samples of one frame share with the row that renders them.
struct FrameRays {
  int width;
  int supersampling;
  const std::vector<Eigen::Vector2d>* centre_rays;
  const std::vector<Eigen::Vector2f>* sample_rays;
  Eigen::Matrix3d world_from_cam_rotation;
  Eigen::Vector3d camera_in_world;
};

// Renders one image row at a time; its buffers are reused across rows.
// Rays go to Embree a row at a time, in pixel order, so that neighbouring
// rays are traced together in packets.
class RowRenderer {
 public:
  RowRenderer(const RayCaster& caster, const FrameShader& shader,
              const FrameRays& frame)
      : caster_(caster), shader_(shader), frame_(frame) {}

  // Writes the pixel-centre ranges (NaN for no hit) and the mean radiance
  // of each pixel's samples.
  void Render(int row, double* depth_row, Eigen::Vector3d* radiance_row) {
    const int width = frame_.width;
    const int ss = frame_.supersampling;
    const int samples_per_pixel = ss * ss;
    // For odd supersampling the middle sample is the pixel centre, whose ray
    // also gives the depth; for even, the centre ray is cast for depth only,
    // ahead of the pixel's samples.
    const bool odd = ss % 2 == 1;
    const int centre_sample = (ss / 2) * ss + ss / 2;
    const int rays_per_pixel = samples_per_pixel + (odd ? 0 : 1);
    const int first_sample = odd ? 0 : 1;
    const int centre_ray = odd ? centre_sample : 0;

    rays_.resize(static_cast<size_t>(width) * rays_per_pixel);
    for (int col = 0; col < width; ++col) {
      const size_t pixel = static_cast<size_t>(row) * width + col;
      Ray* pixel_rays = &rays_[static_cast<size_t>(col) * rays_per_pixel];
      const Eigen::Vector2d& centre = (*frame_.centre_rays)[pixel];
      for (int k = 0; k < rays_per_pixel; ++k) {
        pixel_rays[k].origin = frame_.camera_in_world;
      }
      pixel_rays[centre_ray].direction =
          frame_.world_from_cam_rotation *
          Eigen::Vector3d(centre.x(), centre.y(), 1.0).normalized();
      for (int k = 0; ss > 1 && k < samples_per_pixel; ++k) {
        if (odd && k == centre_sample) continue;
        const Eigen::Vector2f& sample =
            (*frame_.sample_rays)[pixel * samples_per_pixel + k];
        pixel_rays[first_sample + k].direction =
            frame_.world_from_cam_rotation *
            Eigen::Vector3d(sample.x(), sample.y(), 1.0).normalized();
      }
    }
    caster_.IntersectMany(rays_, &hits_);

    const size_t num_samples = static_cast<size_t>(width) * samples_per_pixel;
    veil_parts_.resize(num_samples);
    radiances_.resize(num_samples);
    shadow_rays_.clear();
    shadow_lengths_.clear();
    shadow_radiances_.clear();
    shadow_samples_.clear();
    const bool shiny = shader_.HasShine();
    for (int col = 0; col < width; ++col) {
      const size_t first_ray = static_cast<size_t>(col) * rays_per_pixel;
      const std::optional<RayCaster::Hit>& centre_hit =
          hits_[first_ray + centre_ray];
      depth_row[col] = centre_hit ? centre_hit->distance
                                  : std::numeric_limits<double>::quiet_NaN();
      for (int k = 0; k < samples_per_pixel; ++k) {
        const size_t ray = first_ray + first_sample + k;
        const size_t sample = static_cast<size_t>(col) * samples_per_pixel + k;
        const std::optional<RayCaster::Hit>& hit = hits_[ray];
        if (!hit) {
          veil_parts_[sample] = shader_.Veil();
          continue;
        }
        Eigen::Vector3d normal;
        Eigen::Vector3d albedo;
        shader_.SurfaceTerms(rays_[ray].direction, *hit, &normal,
                             &veil_parts_[sample], &albedo);
        // A shiny surface adds its lobe per light: weight (n.h)^exponent.
        const Shine shine =
            shiny ? shader_.ShineAt(hit->point_in_world) : Shine{};
        const Eigen::Vector3d to_camera = -rays_[ray].direction;
        shader_.ForEachIncidence(
            hit->point_in_world, &normal, hit->distance,
            [&](const Eigen::Vector3d& light, int channel,
                const Ray& shadow_ray, double shadow_length) {
              double lobe = 0.0;
              if (shine.weight > 0.0f) {
                const double cos_half = std::max(
                    0.0, normal.dot(
                             (shadow_ray.direction + to_camera).normalized()));
                lobe = shine.weight * std::pow(cos_half, shine.exponent);
              }
              const Eigen::Vector3d reflected =
                  channel < 0
                      ? Eigen::Vector3d(albedo.array() + lobe)
                      : Eigen::Vector3d::Constant(albedo(channel) + lobe);
              shadow_rays_.push_back(shadow_ray);
              shadow_lengths_.push_back(shadow_length);
              shadow_radiances_.push_back(reflected.cwiseProduct(light));
              shadow_samples_.push_back(sample);
            });
      }
    }
    caster_.OccludedMany(shadow_rays_, shadow_lengths_, &occluded_);

    radiances_ = veil_parts_;
    for (size_t i = 0; i < shadow_rays_.size(); ++i) {
      if (!occluded_[i]) radiances_[shadow_samples_[i]] += shadow_radiances_[i];
    }
    for (int col = 0; col < width; ++col) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int k = 0; k < samples_per_pixel; ++k) {
        sum += radiances_[static_cast<size_t>(col) * samples_per_pixel + k];
      }
      radiance_row[col] = sum / samples_per_pixel;
    }
  }

 private:
  const RayCaster& caster_;
  const FrameShader& shader_;
  const FrameRays& frame_;
  std::vector<Ray> rays_;
  std::vector<std::optional<RayCaster::Hit>> hits_;
  std::vector<Eigen::Vector3d> veil_parts_;
  std::vector<Eigen::Vector3d> radiances_;
  std::vector<Ray> shadow_rays_;
  std::vector<double> shadow_lengths_;
  // What each shadow ray's light adds to its sample's radiance if it is
  // not occluded.
  std::vector<Eigen::Vector3d> shadow_radiances_;
  std::vector<size_t> shadow_samples_;
  std::vector<bool> occluded_;
};

// One marine snow particle as the camera sees it.
struct SnowFlake {
  double range;  // from the projection centre, metres
  Eigen::Vector2d pixel;
  double sigma_px;
  double peak_alpha;
  Eigen::Vector3d radiance;
};

// The marine snow of one frame, far to near: particles uniform in a box in
// front of the camera that contains the view out to marine_snow_range_m,
// those outside the image dropped.
std::vector<SnowFlake> MakeMarineSnow(const Camera& camera,
                                      const SensorOptions& sensor,
                                      const Eigen::Vector2d& max_abs_ray,
                                      const RayCaster& caster,
                                      const FrameShader& shader,
                                      const FrameRays& frame, uint64_t seed,
                                      uint64_t image_index) {
  const double range = sensor.marine_snow_range_m;
  const Eigen::Vector2d half_width = range * max_abs_ray.cwiseMin(kSnowMaxTan);
  const double volume =
      4.0 * half_width.x() * half_width.y() * (range - kSnowMinRange);
  CounterRng count_rng(seed, image_index, Stream::kSnowCount, 0);
  // Rounded up or down at random so that the mean count is exact.
  const auto count = static_cast<uint64_t>(
      std::floor(sensor.marine_snow_per_m3 * volume + count_rng.Uniform()));
  std::vector<SnowFlake> flakes;
  for (uint64_t i = 0; i < count; ++i) {
    CounterRng rng(seed, image_index, Stream::kSnowParticle, i);
    const Eigen::Vector3d point_in_cam(
        (2.0 * rng.Uniform() - 1.0) * half_width.x(),
        (2.0 * rng.Uniform() - 1.0) * half_width.y(),
        kSnowMinRange + rng.Uniform() * (range - kSnowMinRange));
    const double radius =
        kSnowMinRadius + rng.Uniform() * (kSnowMaxRadius - kSnowMinRadius);
    const double albedo =
        kSnowMinAlbedo + rng.Uniform() * (kSnowMaxAlbedo - kSnowMinAlbedo);
    SnowFlake flake;
    flake.pixel = camera.ImgFromCam(point_in_cam);
    const double radius_px =
        (camera.ImgFromCam(point_in_cam + Eigen::Vector3d(radius, 0, 0)) -
         flake.pixel)
            .norm();
    flake.sigma_px = std::max(0.5 * radius_px, kSnowMinSigmaPx);
    const double reach = 3.0 * flake.sigma_px;
    if (!(flake.pixel.x() > -reach &&
          flake.pixel.x() < static_cast<double>(camera.width) + reach &&
          flake.pixel.y() > -reach &&
          flake.pixel.y() < static_cast<double>(camera.height) + reach)) {
      continue;
    }
    flake.range = point_in_cam.norm();
    // A Gaussian spot with the disc's area (pi radius_px^2) as its
    // integral, opaque where that exceeds one.
    flake.peak_alpha =
        radius_px * radius_px / (2.0 * flake.sigma_px * flake.sigma_px);
    const Eigen::Vector3d point_in_world =
        frame.world_from_cam_rotation * point_in_cam + frame.camera_in_world;
    // A grey particle: every channel's albedo is the same.
    Eigen::Vector3d light = Eigen::Vector3d::Zero();
    shader.ForEachIncidence(
        point_in_world, nullptr, flake.range,
        [&](const Eigen::Vector3d& incident, int /*channel*/,
            const Ray& shadow_ray, double shadow_length) {
          if (!caster.Occluded(shadow_ray.origin, shadow_ray.direction,
                               shadow_length)) {
            light += incident;
          }
        });
    flake.radiance = albedo * light;
    flakes.push_back(flake);
  }
  // Far to near, so that nearer flakes cover farther ones.
  std::stable_sort(
      flakes.begin(), flakes.end(),
      [](const SnowFlake& a, const SnowFlake& b) { return a.range > b.range; });
  return flakes;
}

// Composites the flakes, in order, over the radiance of the pixels where no
// surface lies in front of them.
void AddMarineSnow(const std::vector<SnowFlake>& flakes, const cv::Mat& depth_m,
                   std::vector<Eigen::Vector3d>* radiance) {
  const int width = depth_m.cols;
  const int height = depth_m.rows;
  for (const SnowFlake& flake : flakes) {
    const double reach = 3.0 * flake.sigma_px;
    const int col_begin =
        std::max(0, static_cast<int>(std::floor(flake.pixel.x() - reach)));
    const int col_end =
        std::min(width, static_cast<int>(std::ceil(flake.pixel.x() + reach)));
    const int row_begin =
        std::max(0, static_cast<int>(std::floor(flake.pixel.y() - reach)));
    const int row_end =
        std::min(height, static_cast<int>(std::ceil(flake.pixel.y() + reach)));
    for (int row = row_begin; row < row_end; ++row) {
      for (int col = col_begin; col < col_end; ++col) {
        // NaN (nothing hit) compares false: the flake is in front.
        if (depth_m.at<double>(row, col) < flake.range) continue;
        const Eigen::Vector2d offset =
            Eigen::Vector2d(col + 0.5, row + 0.5) - flake.pixel;
        const double alpha = std::min(
            1.0, flake.peak_alpha *
                     std::exp(-offset.squaredNorm() /
                              (2.0 * flake.sigma_px * flake.sigma_px)));
        Eigen::Vector3d& value =
            (*radiance)[static_cast<size_t>(row) * width + col];
        value = (1.0 - alpha) * value + alpha * flake.radiance;
      }
    }
  }
}

// Sensor value in [0, 1] (clipped) to 8-bit output levels, linearly or by
// the sRGB transfer function (IEC 61966-2-1). The sRGB curve is tabulated and
// interpolated: pow() for every channel of every pixel would cost a tenth of
// the rendering, and the table is off by < 0.01 level.
class ToneCurve {
 public:
  explicit ToneCurve(bool srgb) : srgb_(srgb) {}

  double Levels(double value) const {
    const double clipped = std::clamp(value, 0.0, 1.0);
    if (!srgb_) return 255.0 * clipped;
    static const std::vector<double> table = [] {
      std::vector<double> levels(kTableSize + 1);
      for (int i = 0; i <= kTableSize; ++i) {
        const double x = static_cast<double>(i) / kTableSize;
        levels[i] =
            255.0 * (x <= 0.0031308 ? 12.92 * x
                                    : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055);
      }
      return levels;
    }();
    const double position = clipped * kTableSize;
    const int index = std::min(static_cast<int>(position), kTableSize - 1);
    const double fraction = position - index;
    return (1.0 - fraction) * table[index] + fraction * table[index + 1];
  }

 private:
  static constexpr int kTableSize = 4096;
  bool srgb_;
};

// Levels above the veil that a grey surface at `range` adds, best channel.
double SurfaceContrastLevels(const RenderOptions& options, double albedo,
                             double range) {
  const ToneCurve encode(options.sensor.srgb);
  const Eigen::Vector3d transmission =
      Exp(-range * options.water.attenuation_per_m);
  const Eigen::Vector3d veil = options.water.backscatter_strength *
                               options.water.backscatter_rgb.cwiseProduct(
                                   Eigen::Vector3d::Ones() - transmission);
  // Lamp to surface and back: twice the range through the water.
  const Eigen::Vector3d reflected = albedo * options.light.intensity /
                                    (range * range) *
                                    transmission.cwiseProduct(transmission);
  double best = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double gain = options.sensor.gain;
    best = std::max(best, encode.Levels(gain * (veil(c) + reflected(c))) -
                              encode.Levels(gain * veil(c)));
  }
  return best;
}

uint8_t Quantise(double level) {
  return static_cast<uint8_t>(std::clamp(std::floor(level + 0.5), 0.0, 255.0));
}

// ---------------------------------------------------------------------------
// Options.

void CheckFiniteNonNegative(const char* name, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    throw ErrorAt(name, " must be finite and >= 0, got ", value);
  }
}

void CheckFiniteNonNegative(const char* name, const Eigen::Vector3d& value) {
  if (!(value.allFinite() && value.minCoeff() >= 0.0)) {
    throw ErrorAt(name, " must be finite and >= 0, got [", value.transpose(),
                  "]");
  }
}

}  // namespace

void WaterOptions::Check() const {
  CheckFiniteNonNegative("WaterOptions.attenuation_per_m", attenuation_per_m);
  CheckFiniteNonNegative("WaterOptions.backscatter_rgb", backscatter_rgb);
  if (backscatter_rgb.maxCoeff() > 1.0) {
    throw ErrorAt("WaterOptions.backscatter_rgb must lie in [0, 1], got [",
                  backscatter_rgb.transpose(), "]");
  }
  CheckFiniteNonNegative("WaterOptions.backscatter_strength",
                         backscatter_strength);
}

void LightOptions::Check() const {
  if (!position_in_cam.allFinite()) {
    throw ErrorAt("LightOptions.position_in_cam must be finite, got [",
                  position_in_cam.transpose(), "]");
  }
  if (!(direction_in_cam.allFinite() && direction_in_cam.norm() > 0.0)) {
    throw ErrorAt(
        "LightOptions.direction_in_cam must be finite and non-zero, got [",
        direction_in_cam.transpose(), "]");
  }
  if (!(cone_half_angle_deg > 0.0 && cone_half_angle_deg <= 180.0)) {
    throw ErrorAt("LightOptions.cone_half_angle_deg must lie in (0, 180], got ",
                  cone_half_angle_deg);
  }
  if (!(cone_falloff_deg >= 0.0 && cone_falloff_deg <= 180.0)) {
    throw ErrorAt("LightOptions.cone_falloff_deg must lie in [0, 180], got ",
                  cone_falloff_deg);
  }
  CheckFiniteNonNegative("LightOptions.intensity", intensity);
  CheckFiniteNonNegative("LightOptions.vignetting", vignetting);
}

void SensorOptions::Check() const {
  CheckFiniteNonNegative("SensorOptions.noise_sigma", noise_sigma);
  CheckFiniteNonNegative("SensorOptions.gain", gain);
  if (supersampling < 1 || supersampling > 4) {
    throw ErrorAt("SensorOptions.supersampling must lie in [1, 4], got ",
                  supersampling);
  }
  if (jpeg_quality < 0 || jpeg_quality > 100) {
    throw ErrorAt("SensorOptions.jpeg_quality must lie in [0, 100], got ",
                  jpeg_quality);
  }
  CheckFiniteNonNegative("SensorOptions.marine_snow_per_m3",
                         marine_snow_per_m3);
  if (!(std::isfinite(marine_snow_range_m) &&
        marine_snow_range_m > kSnowMinRange)) {
    throw ErrorAt("SensorOptions.marine_snow_range_m must be finite and > ",
                  kSnowMinRange, ", got ", marine_snow_range_m);
  }
}

void RenderOptions::Check() const {
  water.Check();
  light.Check();
  sensor.Check();
}

void to_json(nlohmann::json& json, const WaterOptions& options) {
  json = {{"attenuation_per_m", ToJson(options.attenuation_per_m)},
          {"backscatter_rgb", ToJson(options.backscatter_rgb)},
          {"backscatter_strength", options.backscatter_strength}};
}

void from_json(const nlohmann::json& json, WaterOptions& options) {
  JsonFields fields(json, "water");
  fields.Read("attenuation_per_m", &options.attenuation_per_m);
  fields.Read("backscatter_rgb", &options.backscatter_rgb);
  fields.Read("backscatter_strength", &options.backscatter_strength);
  fields.RejectUnknown();
}

void to_json(nlohmann::json& json, const LightOptions& options) {
  json = {{"position_in_cam", ToJson(options.position_in_cam)},
          {"direction_in_cam", ToJson(options.direction_in_cam)},
          {"cone_half_angle_deg", options.cone_half_angle_deg},
          {"cone_falloff_deg", options.cone_falloff_deg},
          {"intensity", options.intensity},
          {"vignetting", options.vignetting}};
}

void from_json(const nlohmann::json& json, LightOptions& options) {
  JsonFields fields(json, "light");
  fields.Read("position_in_cam", &options.position_in_cam);
  fields.Read("direction_in_cam", &options.direction_in_cam);
  fields.Read("cone_half_angle_deg", &options.cone_half_angle_deg);
  fields.Read("cone_falloff_deg", &options.cone_falloff_deg);
  fields.Read("intensity", &options.intensity);
  fields.Read("vignetting", &options.vignetting);
  fields.RejectUnknown();
}

void to_json(nlohmann::json& json, const SensorOptions& options) {
  json = {{"noise_sigma", options.noise_sigma},
          {"gain", options.gain},
          {"supersampling", options.supersampling},
          {"jpeg_quality", options.jpeg_quality},
          {"marine_snow_per_m3", options.marine_snow_per_m3},
          {"marine_snow_range_m", options.marine_snow_range_m},
          {"rgb", options.rgb},
          {"srgb", options.srgb}};
}

void from_json(const nlohmann::json& json, SensorOptions& options) {
  JsonFields fields(json, "sensor");
  fields.Read("noise_sigma", &options.noise_sigma);
  fields.Read("gain", &options.gain);
  fields.Read("supersampling", &options.supersampling);
  fields.Read("jpeg_quality", &options.jpeg_quality);
  fields.Read("marine_snow_per_m3", &options.marine_snow_per_m3);
  fields.Read("marine_snow_range_m", &options.marine_snow_range_m);
  fields.Read("rgb", &options.rgb);
  fields.Read("srgb", &options.srgb);
  fields.RejectUnknown();
}

void to_json(nlohmann::json& json, const RenderOptions& options) {
  json = {{"water", options.water},
          {"light", options.light},
          {"sensor", options.sensor}};
}

void from_json(const nlohmann::json& json, RenderOptions& options) {
  JsonFields fields(json, "render");
  fields.Read("water", &options.water);
  fields.Read("light", &options.light);
  fields.Read("sensor", &options.sensor);
  fields.RejectUnknown();
}

Ray PixelRayInWorld(const Camera& camera, const Rigid3d& cam_from_world,
                    const Eigen::Vector2d& pixel) {
  CheckCameraModelParams(camera.model_id, camera.params.size());
  const Eigen::Matrix3d world_from_cam_rotation =
      cam_from_world.RotationMatrix().transpose();
  const Eigen::Vector3d in_cam =
      CameraModelCamFromImg(camera.model_id, camera.params.data(), pixel);
  Ray ray;
  ray.origin = -(world_from_cam_rotation * cam_from_world.translation);
  ray.direction = world_from_cam_rotation * in_cam.normalized();
  return ray;
}

Renderer::Renderer(const RayCaster& caster, const Texture& texture,
                   Camera camera, RenderOptions options)
    : caster_(&caster),
      texture_(&texture),
      camera_(std::move(camera)),
      options_(std::move(options)) {
  options_.Check();
  CheckCameraModelParams(camera_.model_id, camera_.params.size());
  constexpr uint64_t kMaxSide = 1 << 16;
  if (camera_.width == 0 || camera_.height == 0 || camera_.width > kMaxSide ||
      camera_.height > kMaxSide) {
    throw ErrorAt("Renderer: camera ", camera_.camera_id, " has size ",
                  camera_.width, "x", camera_.height, ", expected 1 to ",
                  kMaxSide, " pixels a side");
  }
  const int width = static_cast<int>(camera_.width);
  const int height = static_cast<int>(camera_.height);
  const int ss = options_.sensor.supersampling;
  const size_t num_pixels = static_cast<size_t>(width) * height;
  centre_rays_.resize(num_pixels);
  vignetting_.resize(num_pixels);
  if (ss > 1) {
    sample_rays_.resize(num_pixels * ss * ss);
  }
  const CameraModelId model_id = camera_.model_id;
  const double* params = camera_.params.data();
  const double vignetting_exponent = options_.light.vignetting;
  tbb::parallel_for(
      tbb::blocked_range<int>(0, height),
      [&](const tbb::blocked_range<int>& rows) {
        for (int row = rows.begin(); row < rows.end(); ++row) {
          for (int col = 0; col < width; ++col) {
            const size_t pixel = static_cast<size_t>(row) * width + col;
            const Eigen::Vector3d centre = CameraModelCamFromImg(
                model_id, params, Eigen::Vector2d(col + 0.5, row + 0.5));
            centre_rays_[pixel] = centre.head<2>();
            // cos of the angle off the optical axis of the ray (x, y, 1).
            const double cos_off_axis = 1.0 / centre.norm();
            vignetting_[pixel] =
                static_cast<float>(std::pow(cos_off_axis, vignetting_exponent));
            for (int j = 0; ss > 1 && j < ss; ++j) {
              for (int i = 0; i < ss; ++i) {
                const Eigen::Vector2d position(col + (i + 0.5) / ss,
                                               row + (j + 0.5) / ss);
                sample_rays_[pixel * ss * ss + j * ss + i] =
                    CameraModelCamFromImg(model_id, params, position)
                        .head<2>()
                        .cast<float>();
              }
            }
          }
        }
      });
  for (const Eigen::Vector2d& ray : centre_rays_) {
    max_abs_centre_ray_ = max_abs_centre_ray_.cwiseMax(ray.cwiseAbs());
  }
}

RenderedImage Renderer::Render(const Rigid3d& cam_from_world, uint64_t seed,
                               uint64_t image_index,
                               const FrameOptions& frame_options) const {
  frame_options.optics.Check();
  if (!(frame_options.gain_factor > 0.0 &&
        std::isfinite(frame_options.gain_factor))) {
    throw ErrorAt("Renderer: frame gain_factor = ", frame_options.gain_factor,
                  ", expected finite and > 0");
  }
  const int width = static_cast<int>(camera_.width);
  const int height = static_cast<int>(camera_.height);
  FrameRays frame;
  frame.width = width;
  frame.supersampling = options_.sensor.supersampling;
  frame.centre_rays = &centre_rays_;
  frame.sample_rays = &sample_rays_;
  frame.world_from_cam_rotation = cam_from_world.RotationMatrix().transpose();
  frame.camera_in_world =
      -(frame.world_from_cam_rotation * cam_from_world.translation);
  const FrameShader shader(*caster_, *texture_, options_,
                           frame.world_from_cam_rotation, frame.camera_in_world,
                           cam_from_world, frame_options);

  RenderedImage rendered;
  rendered.depth_m.create(height, width, CV_64F);
  std::vector<Eigen::Vector3d> radiance(static_cast<size_t>(width) * height);
  tbb::parallel_for(tbb::blocked_range<int>(0, height),
                    [&](const tbb::blocked_range<int>& rows) {
                      RowRenderer row_renderer(*caster_, shader, frame);
                      for (int row = rows.begin(); row < rows.end(); ++row) {
                        row_renderer.Render(
                            row, rendered.depth_m.ptr<double>(row),
                            &radiance[static_cast<size_t>(row) * width]);
                      }
                    });

  const SensorOptions& sensor = options_.sensor;
  if (sensor.marine_snow_per_m3 > 0.0) {
    AddMarineSnow(MakeMarineSnow(camera_, sensor, max_abs_centre_ray_, *caster_,
                                 shader, frame, seed, image_index),
                  rendered.depth_m, &radiance);
  }

  const ToneCurve encode(sensor.srgb);
  const double gain = sensor.gain * frame_options.gain_factor;
  rendered.image.create(height, width, sensor.rgb ? CV_8UC3 : CV_8UC1);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, height),
      [&](const tbb::blocked_range<int>& rows) {
        for (int row = rows.begin(); row < rows.end(); ++row) {
          uint8_t* out = rendered.image.ptr<uint8_t>(row);
          for (int col = 0; col < width; ++col) {
            const size_t pixel = static_cast<size_t>(row) * width + col;
            const Eigen::Vector3d linear =
                (gain * vignetting_[pixel]) * radiance[pixel];
            Eigen::Vector3d noise = Eigen::Vector3d::Zero();
            if (sensor.noise_sigma > 0.0) {
              CounterRng rng(seed, image_index, Stream::kNoise, pixel);
              const Eigen::Vector2d first = rng.GaussianPair();
              noise = sensor.noise_sigma *
                      Eigen::Vector3d(first.x(), first.y(),
                                      sensor.rgb ? rng.GaussianPair().x() : 0);
            }
            if (sensor.rgb) {
              // OpenCV stores B, G, R.
              for (int c = 0; c < 3; ++c) {
                out[3 * col + c] =
                    Quantise(encode.Levels(linear(2 - c)) + noise(2 - c));
              }
            } else {
              out[col] =
                  Quantise(encode.Levels(kLuminance.dot(linear)) + noise.x());
            }
          }
        }
      });

  if (sensor.jpeg_quality > 0) {
    if (!cv::imencode(".jpg", rendered.image, rendered.jpeg,
                      {cv::IMWRITE_JPEG_QUALITY, sensor.jpeg_quality})) {
      throw ErrorAt("Renderer: OpenCV could not encode image ", image_index,
                    " as JPEG");
    }
    rendered.image = cv::imdecode(rendered.jpeg, cv::IMREAD_UNCHANGED);
    if (rendered.image.empty()) {
      throw ErrorAt("Renderer: OpenCV could not decode the JPEG of image ",
                    image_index);
    }
  }
  return rendered;
}

RenderedImage RenderImage(const RayCaster& caster, const Texture& texture,
                          const Camera& camera, const Rigid3d& cam_from_world,
                          const RenderOptions& options, uint64_t seed,
                          uint64_t image_index,
                          const FrameOptions& frame_options) {
  return Renderer(caster, texture, camera, options)
      .Render(cam_from_world, seed, image_index, frame_options);
}

double VisibleRange(const RenderOptions& options, double albedo) {
  options.Check();
  if (!(albedo > 0.0 && albedo <= 1.0)) {
    throw ErrorAt("visible range: albedo = ", albedo, " must be in (0, 1]");
  }
  const double threshold = std::max(1.0, 3.0 * options.sensor.noise_sigma);
  // The contrast falls with range (less light, more veil, a concave tone
  // curve): bisect where it crosses the threshold.
  double near = 0.05;
  double far = 10000.0;
  if (SurfaceContrastLevels(options, albedo, near) < threshold) {
    throw ErrorAt("visible range: a surface 5 cm from the lamp is not seen (",
                  SurfaceContrastLevels(options, albedo, near),
                  " levels above the veil, ", threshold, " needed)");
  }
  if (SurfaceContrastLevels(options, albedo, far) >= threshold) return far;
  for (int k = 0; k < 100 && far - near > 1e-6 * far; ++k) {
    const double middle = 0.5 * (near + far);
    (SurfaceContrastLevels(options, albedo, middle) >= threshold ? near : far) =
        middle;
  }
  return 0.5 * (near + far);
}

}  // namespace uw::sim
