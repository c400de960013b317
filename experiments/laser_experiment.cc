#include "experiments/laser_experiment.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/error.h"
#include "common/util/random.h"
#include "laserscale/scale_estimators.h"
#include "sim/generate.h"
#include "sim/laser.h"
#include "sim/survey.h"
#include "sim/world.h"

namespace uw {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// A seed for one of many independent draws: SplitMix64 of every index in
// turn, so that draws do not depend on the order work is done in.
uint64_t KeyOf(std::initializer_list<uint64_t> indices) {
  uint64_t key = 0x5EEDull;
  for (const uint64_t index : indices) key = SplitMix64(key ^ index);
  return key;
}

// A unit vector perpendicular to `v`.
Eigen::Vector3d AnyPerpendicular(const Eigen::Vector3d& v) {
  const Eigen::Vector3d axis = std::abs(v.x()) < 0.9 ? Eigen::Vector3d::UnitX()
                                                     : Eigen::Vector3d::UnitY();
  return v.cross(axis).normalized();
}

LaserSetup PerturbedCalibration(const LaserSetup& truth, const ShotNoise& noise,
                                SplitMix64Stream* rng) {
  LaserSetup calibration = truth;
  const double sigma_rad = noise.direction_deg * kDegToRad;
  for (Laser& laser : calibration.lasers) {
    const Eigen::Vector3d d = laser.direction_in_cam.normalized();
    const Eigen::Vector3d e1 = AnyPerpendicular(d);
    const Eigen::Vector3d e2 = d.cross(e1);
    laser.direction_in_cam =
        (d + sigma_rad * (rng->Gaussian() * e1 + rng->Gaussian() * e2))
            .normalized();
    laser.direction_cov =
        IsotropicDirectionCovariance(laser.direction_in_cam, sigma_rad);
    laser.origin_in_cam.x() += noise.origin_m * rng->Gaussian();
    laser.origin_in_cam.y() += noise.origin_m * rng->Gaussian();
    laser.origin_cov = Eigen::Vector3d(noise.origin_m * noise.origin_m,
                                       noise.origin_m * noise.origin_m, 0.0)
                           .asDiagonal();
  }
  return calibration;
}

ErrorStats Stats(const std::vector<double>& errors) {
  ErrorStats stats;
  double sum = 0.0;
  for (const double e : errors) {
    if (std::isnan(e)) {
      ++stats.num_invalid;
      continue;
    }
    ++stats.count;
    sum += e;
    stats.max_abs = std::max(stats.max_abs, std::abs(e));
  }
  if (stats.count == 0) return stats;
  stats.mean = sum / static_cast<double>(stats.count);
  double squares = 0.0;
  for (const double e : errors) {
    if (!std::isnan(e)) squares += (e - stats.mean) * (e - stats.mean);
  }
  stats.std_dev =
      stats.count > 1 ? std::sqrt(squares / (stats.count - 1.0)) : 0.0;
  return stats;
}

bool DavisTustingApplies(const LaserSetup& setup) {
  if (setup.lasers.size() != 4) return false;
  const double min_cos = std::cos(kDavisTustingMaxAxisAngleDeg * kDegToRad);
  for (const Laser& laser : setup.lasers) {
    if (laser.direction_in_cam.normalized().z() < min_cos) return false;
  }
  return true;
}

bool PcmApplies(const LaserSetup& setup) {
  try {
    ScaleItems(ScaleMethod::kPcm, setup);
    return true;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace

void ShotNoise::Check() const {
  for (const double sigma : {feature_px, spot_px, direction_deg, origin_m}) {
    if (!(sigma >= 0.0) || !std::isfinite(sigma)) {
      throw ErrorAt("noise: standard deviations must be finite and >= 0");
    }
  }
}

void ShotOptions::Check() const {
  if (num_features < 10) {
    throw ErrorAt("shot: num_features must be >= 10, got ", num_features);
  }
  if (!(model_scale > 0.0) || !std::isfinite(model_scale)) {
    throw ErrorAt("shot: model_scale must be > 0, got ", model_scale);
  }
  noise.Check();
  localization.Check();
}

Eigen::Vector3d VentFlankTarget(const RayCaster& world_caster) {
  const std::optional<RayCaster::Hit> hit = world_caster.Intersect(
      Eigen::Vector3d(20.0, 3.0, 3.0), -Eigen::Vector3d::UnitX());
  if (!hit) throw ErrorAt("views experiment: the world has no vent flank");
  return hit->point_in_world;
}

TriangleMesh ScaledMesh(const TriangleMesh& mesh, double scale) {
  TriangleMesh scaled = mesh;
  for (Eigen::Vector3d& vertex : scaled.vertices) vertex *= scale;
  return scaled;
}

SyntheticShot MakeSyntheticShot(const RayCaster& world_caster,
                                const Camera& camera,
                                const Rigid3d& cam_from_world,
                                const LaserSetup& truth,
                                const ShotOptions& options, uint64_t seed) {
  options.Check();
  SplitMix64Stream rng(SplitMix64(seed));
  const double k = options.model_scale;
  SyntheticShot shot;
  shot.true_cam_from_world = cam_from_world;
  shot.true_cam_from_world.translation *= k;
  shot.calibration = PerturbedCalibration(truth, options.noise, &rng);

  // Features: surface points seen through uniformly drawn pixels.
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const Eigen::Matrix3d world_from_cam_rotation =
      world_from_cam.RotationMatrix();
  std::vector<Correspondence2D3D> matches;
  const int max_attempts = 20 * options.num_features;
  for (int attempt = 0; attempt < max_attempts &&
                        static_cast<int>(matches.size()) < options.num_features;
       ++attempt) {
    const Eigen::Vector2d pixel(rng.Uniform(0.0, camera.width),
                                rng.Uniform(0.0, camera.height));
    const Eigen::Vector3d ray =
        CameraModelCamFromImg(camera.model_id, camera.params.data(), pixel);
    const std::optional<RayCaster::Hit> hit =
        world_caster.Intersect(world_from_cam.translation,
                               (world_from_cam_rotation * ray).normalized());
    if (!hit) continue;
    const Eigen::Vector3d noise(rng.Gaussian(), rng.Gaussian(), 0.0);
    matches.push_back({camera.ImgFromCam(cam_from_world * hit->point_in_world) +
                           options.noise.feature_px * noise.head<2>(),
                       k * hit->point_in_world});
  }

  // Spots: where the true beams meet the surface, seen by the camera.
  shot.image.camera = camera;
  for (const Laser& laser : truth.lasers) {
    const sim::LaserSpotTruth spot =
        sim::TrueLaserSpot(world_caster, camera, cam_from_world, laser);
    const Eigen::Vector2d noise(rng.Gaussian(), rng.Gaussian());
    if (!spot.visible) {
      shot.image.spots.push_back(std::nullopt);
      continue;
    }
    Spot detected;
    detected.pixel = spot.pixel + options.noise.spot_px * noise;
    detected.covariance = Eigen::Matrix2d::Identity() * options.noise.spot_px *
                          options.noise.spot_px;
    shot.image.spots.push_back(detected);
  }

  LocalizationOptions localization = options.localization;
  localization.seed = seed;
  const Localization located = LocalizeImage(camera, matches, localization);
  if (!located.success) {
    shot.problem = located.problem;
    return shot;
  }
  shot.localized = true;
  for (const int i : located.inliers) shot.image.matches.push_back(matches[i]);
  shot.image.cam_from_world = located.cam_from_world;
  shot.image.feature_sigma_px = located.rms_error_px;
  return shot;
}

void ViewsExperimentOptions::Check() const {
  if (distances_m.empty() || setups.empty() || noise_levels.empty() ||
      methods.empty()) {
    throw ErrorAt(
        "views experiment: distances, set-ups, noise levels and "
        "methods must not be empty");
  }
  for (const double d : distances_m) {
    if (!(d > 0.0)) throw ErrorAt("views experiment: distance ", d, " <= 0");
  }
  for (const ShotNoise& noise : noise_levels) noise.Check();
  if (!(model_scale > 0.0)) {
    throw ErrorAt("views experiment: model_scale must be > 0");
  }
  if (area != "flank" && area != "top" && area != "custom") {
    throw ErrorAt("views experiment: area must be flank, top or custom, got '",
                  area, "'");
  }
  if ((area == "custom") != target.has_value()) {
    throw ErrorAt(
        "views experiment: a target is given with area custom, "
        "and only then");
  }
  if (area == "flank" && world != "vent") {
    throw ErrorAt("views experiment: area flank needs world vent");
  }
  if (trials_per_view < 1) {
    throw ErrorAt("views experiment: trials_per_view must be >= 1");
  }
}

std::vector<ViewsExperimentRow> RunViewsExperiment(
    const ViewsExperimentOptions& options, const ExperimentProgress& progress) {
  options.Check();
  const sim::World world = sim::MakeWorld(sim::WorldKindFromName(options.world),
                                          sim::WorldOptions(), options.seed);
  const RayCaster world_caster(world.mesh);
  std::optional<Eigen::Vector3d> target = options.target;
  if (options.area == "flank") target = VentFlankTarget(world_caster);
  const TriangleMesh model_mesh = ScaledMesh(world.mesh, options.model_scale);
  const RayCaster model_caster(model_mesh);
  const Camera camera = sim::SimConfig::DefaultCamera();

  const int half =
      static_cast<int>(std::round(options.max_angle_deg / options.step_deg));
  const size_t total = options.setups.size() * options.distances_m.size() *
                       options.noise_levels.size();
  size_t done = 0;
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads
                                                : tbb::task_arena::automatic);
  std::vector<ViewsExperimentRow> rows;
  for (size_t s = 0; s < options.setups.size(); ++s) {
    sim::LaserOptions laser_options;
    laser_options.setup = options.setups[s];
    const LaserSetup truth = sim::TrueLaserSetup(laser_options);
    for (size_t d = 0; d < options.distances_m.size(); ++d) {
      sim::SurveyOptions survey;
      survey.views_distance_m = options.distances_m[d];
      survey.views_max_angle_deg = options.max_angle_deg;
      survey.views_step_deg = options.step_deg;
      survey.views_target = target;
      const std::vector<sim::SurveyStation> stations = sim::PlanSurvey(
          sim::SurveyKind::kViews, world, camera, survey, options.seed);
      for (size_t q = 0; q < options.noise_levels.size(); ++q) {
        ShotOptions shot_options;
        shot_options.num_features = options.num_features;
        shot_options.model_scale = options.model_scale;
        shot_options.noise = options.noise_levels[q];
        const size_t num_shots = stations.size() * options.trials_per_view;
        std::vector<SyntheticShot> shots(num_shots);
        arena.execute([&] {
          tbb::parallel_for(size_t{0}, num_shots, [&](size_t i) {
            const size_t view = i / options.trials_per_view;
            const size_t trial = i % options.trials_per_view;
            shots[i] = MakeSyntheticShot(
                world_caster, camera, stations[view].cam_from_world, truth,
                shot_options, KeyOf({options.seed, s, d, q, view, trial}));
          });
        });
        for (const ScaleMethod method : options.methods) {
          if (method == ScaleMethod::kDavisTusting &&
              !DavisTustingApplies(truth))
            continue;
          if (method == ScaleMethod::kPcm && !PcmApplies(truth)) continue;
          ViewsExperimentRow row;
          row.setup = truth.name;
          row.distance_m = options.distances_m[d];
          row.noise = options.noise_levels[q];
          row.method = method;
          row.num_views = stations.size();
          const std::vector<ScaleItem> items = ScaleItems(method, truth);
          std::vector<double> item_errors;
          std::vector<double> image_errors;
          for (size_t i = 0; i < num_shots; ++i) {
            const SyntheticShot& shot = shots[i];
            const size_t view = i / options.trials_per_view;
            const int pass = stations[view].pass;
            const int within = static_cast<int>(view) - pass * (2 * half + 1);
            const double pitch = (pass - half) * options.step_deg;
            const double roll =
                (pass % 2 == 0 ? within - half : half - within) *
                options.step_deg;
            double image_error = std::nan("");
            if (!shot.localized) {
              ++row.num_unlocalized;
              item_errors.insert(item_errors.end(), items.size(), std::nan(""));
            } else {
              SpotPixels spots;
              for (const std::optional<Spot>& spot : shot.image.spots) {
                spots.push_back(spot ? std::optional(spot->pixel)
                                     : std::nullopt);
              }
              const std::vector<ItemScale> scales = EvaluateItems(
                  method, items, shot.calibration.lasers, model_caster, camera,
                  shot.image.cam_from_world, spots);
              double sum = 0.0;
              int count = 0;
              for (const ItemScale& scale : scales) {
                const double error =
                    scale.scale ? *scale.scale * options.model_scale - 1.0
                                : std::nan("");
                item_errors.push_back(error);
                if (scale.scale) {
                  sum += error;
                  ++count;
                }
              }
              if (count > 0) image_error = sum / count;
            }
            image_errors.push_back(image_error);
            row.image_errors.push_back({pitch, roll, image_error});
          }
          row.items = Stats(item_errors);
          row.images = Stats(image_errors);
          rows.push_back(std::move(row));
        }
        if (progress) progress(++done, total);
      }
    }
  }
  return rows;
}

CoverageResult RunCoverageExperiment(
    const TriangleMesh& world_mesh, const Camera& camera,
    const Rigid3d& cam_from_world, const LaserSetup& truth,
    const ShotOptions& shot_options, ScaleMethod method,
    const MonteCarloOptions& monte_carlo, int trials, uint64_t seed) {
  const RayCaster world_caster(world_mesh);
  const RayCaster model_caster(
      ScaledMesh(world_mesh, shot_options.model_scale));
  const double answer = 1.0 / shot_options.model_scale;
  std::vector<double> nominal;
  size_t covered_95 = 0;
  size_t covered_68 = 0;
  double sigma_sum = 0.0;
  for (int trial = 0; trial < trials; ++trial) {
    const SyntheticShot shot =
        MakeSyntheticShot(world_caster, camera, cam_from_world, truth,
                          shot_options, KeyOf({seed, uint64_t(trial)}));
    if (!shot.localized) continue;
    MonteCarloOptions options = monte_carlo;
    options.seed = KeyOf({seed, uint64_t(trial), 1});
    const ImageScaleResult result = EstimateImageScale(
        shot.image, trial, shot.calibration, model_caster, method, options);
    if (!result.nominal || result.monte_carlo.num_samples < 2) continue;
    nominal.push_back(*result.nominal);
    sigma_sum += result.monte_carlo.std_dev;
    const SampleSummary& mc = result.monte_carlo;
    if (mc.p2_5 <= answer && answer <= mc.p97_5) ++covered_95;
    if (mc.p16 <= answer && answer <= mc.p84) ++covered_68;
  }
  CoverageResult result;
  result.num_trials = nominal.size();
  if (nominal.empty()) return result;
  const double n = static_cast<double>(nominal.size());
  result.spread_of_estimates = Summarize(nominal).std_dev;
  result.mean_monte_carlo_sigma = sigma_sum / n;
  result.coverage_95 = covered_95 / n;
  result.coverage_68 = covered_68 / n;
  return result;
}

}  // namespace uw
