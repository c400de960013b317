// poses.json: laser images localized against a model (`laserscale
// localize`), with the inlier correspondences the Monte Carlo re-samples
// (docs/formats.md). Model units and frame; COLMAP pixels and camera.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "colmap_plugins/scene/model.h"
#include "laserscale/localization.h"

namespace uw {

struct LocalizedImage {
  std::string name;
  Camera camera;
  bool success = false;
  std::string problem;  // why not localized
  Rigid3d cam_from_world;
  size_t num_matches = 0;  // 2D-3D correspondences before the PnP
  size_t num_matched_model_images = 0;
  double rms_error_px = 0.0;
  std::vector<Correspondence2D3D> inliers;
};

std::string LaserPosesJsonText(const std::vector<LocalizedImage>& images);
// Rejects unknown keys, wrong types, non-finite numbers and malformed
// cameras with errors naming the file and image.
std::vector<LocalizedImage> ReadLaserPosesJson(
    const std::filesystem::path& path);
std::vector<LocalizedImage> ParseLaserPosesJson(const std::string& text,
                                                const std::string& where);

}  // namespace uw
