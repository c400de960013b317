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

}  // namespace uw::lsd
