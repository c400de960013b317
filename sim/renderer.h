// Underwater image formation for synthetic surveys: a camera with any COLMAP
// model looks at a textured mesh through attenuating, backscattering water,
// lit by a lamp mounted next to it.
//
// Per sample ray through the camera (COLMAP pixel convention: pixel (c, r)
// covers [c, c+1) x [r, r+1)), with the surface point at range d_cam from the
// camera and d_light from the lamp, per colour channel:
//   radiance = albedo * max(0, n.l) * I * cone(angle) / d_light^2
//                     * exp(-c (d_light + d_cam))             (direct light)
//            + B * (1 - exp(-c d_cam))                         (backscatter)
// where n.l is zero in cast shadows and B = backscatter_strength *
// backscatter_rgb is the veil seen where the ray meets nothing. A shiny
// surface (Texture::ShineAt) adds weight (n.h)^exponent to the albedo of
// each light. Laser beams (sim/laser.h) add their light, of one wavelength:
// reflected by the albedo of the channel of the laser's colour's strongest
// component, attenuated by that channel's coefficient over both legs, seen
// in every channel in the proportions of the laser's colour. Samples are
// averaged per pixel and marine snow is composited over them; the sensor
// then applies gain and cos^k vignetting, clips to [0, 1], encodes with the
// sRGB tone curve as cameras do for their JPEG/PNG output (or stays linear),
// adds Gaussian noise, quantises to 8 bits and optionally compresses to JPEG.
//
// Every random draw comes from a counter-based generator keyed by (seed,
// image index, pixel or particle), so an image is byte-identical for any
// number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>
#include <opencv2/core.hpp>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"
#include "sim/laser.h"
#include "sim/texture.h"

namespace uw::sim {

struct WaterOptions {
  // Beam attenuation coefficient c per channel (R, G, B), 1/m. The defaults
  // are a clear coastal / oceanic water (between Jerlov types II and 1C):
  // red is lost within a few metres, green and blue carry.
  Eigen::Vector3d attenuation_per_m{0.45, 0.12, 0.10};
  // Colour of the veil at infinite range, each channel in [0, 1].
  Eigen::Vector3d backscatter_rgb{0.10, 0.45, 0.55};
  // Scale of the veil on the sensor's [0, 1] range (before gain).
  double backscatter_strength = 0.2;

  void Check() const;  // throws uw::Error naming the bad field
};

struct LightOptions {
  // The lamp, in the camera frame (x right, y down, z forward, metres):
  // 0.3 m above the lens, pointing along the optical axis.
  Eigen::Vector3d position_in_cam{0.0, -0.3, 0.0};
  Eigen::Vector3d direction_in_cam{0.0, 0.0, 1.0};  // any length but zero
  // Full intensity up to cone_half_angle_deg - cone_falloff_deg / 2 off the
  // lamp's axis, none beyond cone_half_angle_deg + cone_falloff_deg / 2,
  // smooth in between.
  double cone_half_angle_deg = 50.0;
  double cone_falloff_deg = 20.0;
  // On-axis radiant intensity: a white surface facing the lamp at 1 m in
  // clear water reads `intensity` on the sensor's linear [0, 1] range at
  // gain 1, before vignetting and the tone curve.
  double intensity = 10.0;
  // Exponent k of the cos^k(angle off the optical axis) sensor falloff.
  double vignetting = 2.0;

  void Check() const;
};

struct SensorOptions {
  double noise_sigma = 2.0;  // Gaussian noise, in 8-bit output levels
  double gain = 1.0;         // sensor [0, 1] range per unit of radiance
  int supersampling = 2;     // samples per pixel and axis, 1 to 4
  int jpeg_quality = 0;      // 1 to 100: JPEG round trip; 0: lossless
  // Density of bright particles in front of the camera, per m^3, placed up
  // to marine_snow_range_m ahead; 0 disables marine snow.
  double marine_snow_per_m3 = 0.0;
  double marine_snow_range_m = 4.0;
  bool rgb = true;  // false: one luminance channel
  // Encode with the sRGB tone curve, as a camera's image files are; false
  // keeps levels proportional to radiance (for photometric tests).
  bool srgb = true;

  void Check() const;
};

struct RenderOptions {
  WaterOptions water;
  LightOptions light;
  SensorOptions sensor;

  void Check() const;
};

// JSON with every field; from_json starts from the value it fills, so absent
// keys keep their defaults, and rejects unknown keys (typos) with uw::Error.
void to_json(nlohmann::json& json, const WaterOptions& options);
void from_json(const nlohmann::json& json, WaterOptions& options);
void to_json(nlohmann::json& json, const LightOptions& options);
void from_json(const nlohmann::json& json, LightOptions& options);
void to_json(nlohmann::json& json, const SensorOptions& options);
void from_json(const nlohmann::json& json, SensorOptions& options);
void to_json(nlohmann::json& json, const RenderOptions& options);
void from_json(const nlohmann::json& json, RenderOptions& options);

// What may change from one frame of a camera to the next besides its pose.
struct FrameOptions {
  std::vector<Laser> lasers;  // switched on, in the camera frame
  BeamOptics optics;
  double gain_factor = 1.0;  // multiplies the sensor's gain
};

struct RenderedImage {
  // CV_8UC3 in OpenCV's BGR order, or CV_8UC1 when the sensor is not rgb.
  cv::Mat image;
  // CV_64F range (metres along the ray, from the projection centre) of the
  // ray through each pixel centre; NaN where it meets nothing.
  cv::Mat depth_m;
  // With jpeg_quality > 0: the JPEG file whose decoding is `image`. Write
  // these bytes; encoding `image` again would change it.
  std::vector<uint8_t> jpeg;
};

// The ray through `pixel` (COLMAP convention: (c + 0.5, r + 0.5) is the
// centre of pixel (c, r)) from the projection centre, with a unit direction.
Ray PixelRayInWorld(const Camera& camera, const Rigid3d& cam_from_world,
                    const Eigen::Vector2d& pixel);

// Renders the images of one camera. Construction unprojects every sample of
// the sensor once (costly for distorted models), so a survey keeps one
// Renderer per camera. Keeps references to `caster` and `texture`, which must
// outlive it. Render is thread-safe and parallel (TBB, over rows).
class Renderer {
 public:
  // Throws uw::Error for invalid options or camera.
  Renderer(const RayCaster& caster, const Texture& texture, Camera camera,
           RenderOptions options);

  // `image_index` keys the frame's noise and marine snow: give every frame
  // of a survey its own.
  RenderedImage Render(const Rigid3d& cam_from_world, uint64_t seed,
                       uint64_t image_index,
                       const FrameOptions& frame_options = {}) const;

  const Camera& camera() const { return camera_; }
  const RenderOptions& options() const { return options_; }

 private:
  const RayCaster* caster_;
  const Texture* texture_;
  Camera camera_;
  RenderOptions options_;
  // Unprojected pixel centres, (x, y) of the ray (x, y, 1) in the camera
  // frame, row-major; in double so that depth_m and PixelRayInWorld agree.
  std::vector<Eigen::Vector2d> centre_rays_;
  // The same for the supersampling x supersampling samples of each pixel,
  // pixel-major then row-major within the pixel; empty at supersampling 1.
  // Float is ample: 1e-7 of a normalized coordinate is 1e-4 px.
  std::vector<Eigen::Vector2f> sample_rays_;
  std::vector<float> vignetting_;  // per pixel, from the centre ray
  // Largest |x| and |y| of the centre rays, bounding the view for marine
  // snow.
  Eigen::Vector2d max_abs_centre_ray_ = Eigen::Vector2d::Zero();
};

// How far the camera sees a surface through the water: the range at which
// the light a grey surface (albedo `albedo`, 18 % by default: a grey card)
// on the lamp's axis reflects lifts the image above the veil of the same
// range by 3 noise sigmas (8-bit levels after the tone curve; 1 level
// without noise), on the best channel. Beyond it the surface's texture is
// lost in the noise: nothing can be matched or reconstructed there, so the
// coverage of a reconstruction is measured within it (model_comparer reads
// it from truth/sim.json). The lamp is taken at the lens, facing the
// surface (its 0.3 m default offset moves the range by well under 1 %).
// Throws uw::Error when even 5 cm away the surface is not seen.
double VisibleRange(const RenderOptions& options, double albedo = 0.18);

// One image with a Renderer made for it. A survey should keep a Renderer per
// camera instead: at 1024x768 and supersampling 2 its set-up takes ~0.15 CPU
// s for PINHOLE and ~2 CPU s for distorted models, more than an image.
RenderedImage RenderImage(const RayCaster& caster, const Texture& texture,
                          const Camera& camera, const Rigid3d& cam_from_world,
                          const RenderOptions& options, uint64_t seed,
                          uint64_t image_index,
                          const FrameOptions& frame_options = {});

}  // namespace uw::sim
