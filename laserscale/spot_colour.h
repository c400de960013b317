// What the spot detector needs of a laser's colour: the HSV hue it tests
// pixels with (LSD step 7), and the colour model that tells a laser's spot
// from a bright thing lit by the lamp (a white shell, a highlight): the
// colour the laser's light has after its path through the water, against
// the colour of a candidate's increment over its background in linear
// light.
#pragma once

#include <Eigen/Core>
#include "laserscale/laser_setup.h"
#include "laserscale/spot_detector_options.h"

namespace uw::lsd {

// HSV hue (degrees in [0, 360)) of an RGB triple, hexcone definition; 0
// for a grey.
double HueDeg(double r, double g, double b);

// The angle between two hues, in [0, 180], wrapping at 0/360.
double HueDistanceDeg(double a, double b);

// What the detector needs of a laser's colour, in OpenCV's BGR channel
// order.
struct LaserColour {
  double hue_deg = 0.0;
  bool chromatic = true;  // false: white (saturation < 0.1), no hue test
  int dominant = 2;       // its strongest channel: V on its pixels
  int weakest = 0;        // its weakest: the least disturbed by the spots
  // The unit linear RGB of the laser: of its spots at any range, as the
  // water attenuates its one wavelength alike in every channel.
  Eigen::Vector3d rgb{1.0, 0.0, 0.0};
};

LaserColour ColourOf(const Laser& laser);

// An 8-bit level (0-255, any real value) in linear light: the inverse sRGB
// tone curve with srgb, level / 255 without.
double LinearLevel(double level, bool srgb);

// The colour of a detected spot: its amplitude per channel over its
// background in linear light (RGB order), and the σ of each.
struct SpotRgb {
  Eigen::Vector3d rgb = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();
  // false: a channel had too few pixels to measure (and did not clip).
  bool measured = true;
};

// Whether a spot's colour may be the laser's light of colour `expected`
// (unit, linear RGB: LaserColour::rgb): its part across `expected` is at
// most tan(max_colour_angle_deg) times its part along it plus
// colour_noise_sigmas σ of its noise (in its own direction); the angle
// between them goes to `angle_deg`. A spot darker than its background
// along `expected`, or not measured, is not.
bool IsLaserColour(const SpotRgb& colour, const Eigen::Vector3d& expected,
                   const SpotDetectorOptions& options, double* angle_deg);

}  // namespace uw::lsd
