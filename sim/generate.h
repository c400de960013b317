// uwsim generate: a world, a survey over it, the rendered images, the
// navigation log and the ground truth, all from one configuration and seed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>

#include <nlohmann/json.hpp>

#include "sim/sim_config.h"

namespace uw::sim {

struct GenerateSummary {
  size_t num_images = 0;        // survey images of every camera
  size_t num_laser_images = 0;  // each with its auxiliary image
  size_t num_triangles = 0;
  std::vector<Eigen::Vector3d> dive_biases;
};

// Writes into `out` (which must be empty or absent):
//   images/NNNNN.png        the survey images (with a rig:
//                           images/camK/NNNNN.png, camera K)
//   image_times.csv         when each image was taken
//   rig.json                with a rig: its calibration (with errors)
//   laser_images/LNNNNN.png, LNNNNN_aux.png   laser images, auxiliaries
//   laser_image_times.csv   when each laser image was taken
//   nav.csv                 navigation with errors
//   lasers.json             the laser set-up as calibrated (with errors)
//   truth/cameras.txt, images.txt, points3D.txt   true poses (COLMAP text)
//   truth/ref_images.txt    true camera centres (colmap model_aligner)
//   truth/nav.csv           true navigation
//   truth/lasers.json       the true laser set-up
//   truth/rig.json          with a rig: the true relative poses
//   truth/laser_images.json poses and true spots of the laser images
//   truth/mesh.ply          the world's mesh
//   truth/sim.json          the configuration, seed and dive biases
// `progress(done, total)` is called after each image (laser and auxiliary
// images included).
//
// With `render_images` false, images/ and laser_images/ are not written and
// everything else is as a rendered run writes it, but for truth/sim.json's
// "rendered": false: the plan and its truth in seconds, for what needs no
// pixels (uwsim observe's synthetic tracks, the covariance's Monte Carlo).
GenerateSummary Generate(
    const SimConfig& config, const std::filesystem::path& out,
    const std::function<void(size_t, size_t)>& progress = nullptr,
    bool render_images = true);

}  // namespace uw::sim
