// The laser images of a survey: where each is taken, its auxiliary image,
// and the ground truth of its spots (truth/laser_images.json,
// docs/uwsim.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"
#include "laserscale/laser_setup.h"
#include "sim/laser.h"
#include "sim/survey.h"

namespace uw::sim {

struct LaserShot {
  std::string name;         // "L" + the survey image's file name
  std::string aux_name;     // name with "_aux" before the extension
  size_t survey_index = 0;  // the survey image it follows
  double time_s = 0.0;
  int dive = 1;
  Rigid3d cam_from_world;
  Rigid3d aux_cam_from_world;
};

// Shots after every options.every_nth_image-th station (stations named with
// their extension), placed as options.placement says; the auxiliary pose
// is drawn from the seed (deterministic).
std::vector<LaserShot> PlanLaserShots(
    const std::vector<SurveyStation>& stations, const LaserOptions& options,
    uint64_t seed);

// The truth of one shot: poses (COLMAP qvec w,x,y,z and tvec), and per
// laser where its axis meets the world and whether and where the camera
// sees it, in the laser image and (lasers "shifted") in the auxiliary one.
nlohmann::json LaserShotTruth(const LaserShot& shot, const LaserSetup& setup,
                              const LaserOptions& options,
                              const RayCaster& caster, const Camera& camera);

}  // namespace uw::sim
