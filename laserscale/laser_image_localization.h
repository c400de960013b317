// `laserscale localize`'s method: laser images, added to the model's COLMAP
// database, localized one by one against the model through their verified
// matches (model_matches.h, localization.h), as poses.json records.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/model.h"
#include "laserscale/laser_poses_io.h"
#include "laserscale/localization.h"
#include "laserscale/model_matches.h"

namespace uw {

// The non-empty lines of an image list, trailing spaces and CRs removed.
// Throws uw::Error naming the file when it cannot be read or is empty.
std::vector<std::string> ReadLaserImageList(const std::string& path);

// The database's images that the model has not registered, in database
// order; throws uw::Error naming `database_path` when there are none.
std::vector<std::string> UnregisteredImageNames(
    const Database& database, const Reconstruction& model,
    const std::string& database_path);

// Called after each image with its index, the number of images, its
// result and whether its camera is the model's (else the database's).
using LocalizedImageCallback =
    std::function<void(size_t index, size_t count, const LocalizedImage& result,
                       bool camera_from_model)>;

// One record per name, in order; a failed localization keeps its problem.
std::vector<LocalizedImage> LocalizeLaserImages(
    const DatabaseModelMatches& matcher, const std::vector<std::string>& names,
    const LocalizationOptions& options,
    const LocalizedImageCallback& done = nullptr);

}  // namespace uw
