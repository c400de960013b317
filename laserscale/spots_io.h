// spots.json: the laser spots detected in a set of images
// (docs/laserscale_detector.md):
//   {"format": "uwmetric-laser-spots", "version": 1, "images": [
//     {"name": "L00002.png", "setup": "C", "spots": [
//       {"laser": "L1", "detected": true, "stable": true,
//        "detection_rate": 0.97, "pixel": [x, y],
//        "covariance": [[a, b], [b, c]], "problem": ""}]}]}
// Pixels in COLMAP's convention, covariances in px^2. The Monte Carlo
// iterations of a spot are not stored.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "laserscale/spot_detector.h"

namespace uw {

struct ImageSpots {
  std::string name;   // image file name, as in the COLMAP model
  std::string setup;  // laser set-up name in lasers.json
  std::vector<DetectedSpot> spots;
};

// Throws uw::Error naming the image and laser if a number is not finite or
// a covariance not symmetric positive semi-definite.
std::string SpotsJsonText(const std::vector<ImageSpots>& images);

// Reads spots.json; rejects unknown keys, wrong types, non-finite numbers,
// non-PSD covariances, repeated image or laser names and stable spots that
// were not detected, with errors naming the file, image and laser.
std::vector<ImageSpots> ReadSpotsJson(const std::filesystem::path& path);
std::vector<ImageSpots> ParseSpotsJson(const std::string& text,
                                       const std::string& where);

}  // namespace uw
