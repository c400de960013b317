// What the spot detector needs of a laser's colour, and the HSV hue it
// tests pixels with (LSD step 7).
#pragma once

#include "laserscale/laser_setup.h"

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
};

LaserColour ColourOf(const Laser& laser);

}  // namespace uw::lsd
