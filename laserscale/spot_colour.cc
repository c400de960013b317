#include "laserscale/spot_colour.h"

#include <algorithm>
#include <cmath>

namespace uw::lsd {

double HueDeg(double r, double g, double b) {
  const double max = std::max({r, g, b});
  const double chroma = max - std::min({r, g, b});
  if (chroma <= 0.0) return 0.0;
  if (max == r) return 60.0 * std::fmod((g - b) / chroma + 6.0, 6.0);
  if (max == g) return 60.0 * ((b - r) / chroma + 2.0);
  return 60.0 * ((r - g) / chroma + 4.0);
}

double HueDistanceDeg(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}

LaserColour ColourOf(const Laser& laser) {
  const Eigen::Vector3d& rgb = laser.colour;
  LaserColour colour;
  colour.rgb = rgb.normalized();
  colour.hue_deg = HueDeg(rgb(0), rgb(1), rgb(2));
  colour.chromatic = rgb.maxCoeff() > 0.0 &&
                     (rgb.maxCoeff() - rgb.minCoeff()) / rgb.maxCoeff() >= 0.1;
  int max_rgb = 0;
  int min_rgb = 0;
  rgb.maxCoeff(&max_rgb);
  rgb.minCoeff(&min_rgb);
  colour.dominant = 2 - max_rgb;
  colour.weakest = 2 - min_rgb;
  return colour;
}

double LinearLevel(double level, bool srgb) {
  const double v = level / 255.0;
  if (!srgb) return v;
  // The sRGB curve, continued as an odd function below 0 (a low-passed
  // noisy level can dip under it).
  const double a = std::abs(v);
  const double linear =
      a <= 0.04045 ? a / 12.92 : std::pow((a + 0.055) / 1.055, 2.4);
  return v < 0.0 ? -linear : linear;
}

bool IsLaserColour(const SpotRgb& colour, const Eigen::Vector3d& expected,
                   const SpotDetectorOptions& options, double* angle_deg) {
  const Eigen::Vector3d& rgb = colour.rgb;
  const double along = rgb.dot(expected);
  const double across = (rgb - along * expected).norm();
  *angle_deg = std::atan2(across, along) * 180.0 / M_PI;
  if (options.max_colour_angle_deg >= 180.0) return true;
  if (!colour.measured || !(along > 0.0)) return false;
  // The noise of the part across `expected`, in its direction.
  const Eigen::Vector3d direction =
      across > 0.0 ? Eigen::Vector3d((rgb - along * expected) / across)
                   : Eigen::Vector3d::Zero();
  const double noise = direction.cwiseProduct(colour.sigma).norm();
  return across <=
         std::tan(options.max_colour_angle_deg * M_PI / 180.0) * along +
             options.colour_noise_sigmas * noise;
}

}  // namespace uw::lsd
