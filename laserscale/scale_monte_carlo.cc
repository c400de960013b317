#include "laserscale/scale_monte_carlo.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <Eigen/Eigenvalues>

#include "common/util/error.h"
#include "common/util/random.h"

namespace uw {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A factor F with F F^T = covariance (positive semi-definite), so that
// F z with z standard normal has that covariance.
template <int N>
Eigen::Matrix<double, N, N> CovarianceFactor(
    const Eigen::Matrix<double, N, N>& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eigen(
      covariance);
  return eigen.eigenvectors() *
         eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

Eigen::Vector3d StandardNormal3(SplitMix64Stream* rng) {
  const Eigen::Vector2d xy = rng->GaussianPair();
  return {xy.x(), xy.y(), rng->Gaussian()};
}

// Mean of the valid entries, NaN when there is none.
double MeanOfValid(const double* values, size_t n) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (std::isnan(values[i])) continue;
    sum += values[i];
    ++count;
  }
  return count == 0 ? kNaN : sum / static_cast<double>(count);
}

double Percentile(const std::vector<double>& sorted, double p) {
  const double position = p * static_cast<double>(sorted.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(position));
  const size_t above = std::min(below + 1, sorted.size() - 1);
  const double fraction = position - static_cast<double>(below);
  return sorted[below] + fraction * (sorted[above] - sorted[below]);
}

std::string Acceptance(const LaserImage& image,
                       const std::vector<ItemResult>& items,
                       const MonteCarloOptions& options) {
  // Lasers that give a scale: detected, and their ray meets the surface.
  std::vector<bool> measuring(image.spots.size(), false);
  for (const ItemResult& item : items) {
    if (!item.nominal.scale) continue;
    for (const int laser : item.item.lasers) measuring[laser] = true;
  }
  const int num_detected = static_cast<int>(
      std::count_if(image.spots.begin(), image.spots.end(),
                    [](const std::optional<Spot>& spot) { return spot; }));
  const int num_measuring =
      static_cast<int>(std::count(measuring.begin(), measuring.end(), true));
  if (num_measuring < options.min_lasers) {
    std::ostringstream message;
    message << num_measuring << " laser(s) give a scale (" << num_detected
            << " detected), fewer than the " << options.min_lasers
            << " required";
    return message.str();
  }
  std::vector<double> scales;
  for (const ItemResult& item : items) {
    if (item.nominal.scale) scales.push_back(*item.nominal.scale);
  }
  std::sort(scales.begin(), scales.end());
  const double median = Percentile(scales, 0.5);
  // Items disagree when one lies further from the median than its own
  // Monte Carlo spread allows (spots, calibration); without any spread
  // (noise-free inputs) any disagreement beyond rounding counts.
  for (const ItemResult& item : items) {
    if (!item.nominal.scale) continue;
    const double deviation = std::abs(*item.nominal.scale - median);
    const double allowed = std::max(
        options.max_item_sigmas * item.monte_carlo.std_dev, 1e-9 * median);
    if (deviation > allowed) {
      std::ostringstream message;
      message << "the items' scales disagree: " << item.item.name << " is "
              << 100.0 * deviation / median << " % from their median, "
              << (item.monte_carlo.std_dev > 0.0
                      ? deviation / item.monte_carlo.std_dev
                      : INFINITY)
              << " of its sigmas (max " << options.max_item_sigmas
              << "); a calibration error?";
      return message.str();
    }
  }
  return "";
}

}  // namespace

std::string ScaleSourceName(ScaleSource source) {
  switch (source) {
    case ScaleSource::kFeatures:
      return "features";
    case ScaleSource::kSpots:
      return "spots";
    case ScaleSource::kCalibration:
      return "calibration";
    case ScaleSource::kModel:
      return "model";
  }
  return "?";
}

bool MonteCarloOptions::Samples(ScaleSource source) const {
  switch (source) {
    case ScaleSource::kFeatures:
      return sample_features;
    case ScaleSource::kSpots:
      return sample_spots;
    case ScaleSource::kCalibration:
      return sample_calibration;
    case ScaleSource::kModel:
      return sample_model;
  }
  return false;
}

MonteCarloOptions MonteCarloOptions::Only(ScaleSource source) const {
  MonteCarloOptions only = *this;
  only.sample_features = source == ScaleSource::kFeatures;
  only.sample_spots = source == ScaleSource::kSpots;
  only.sample_calibration = source == ScaleSource::kCalibration;
  only.sample_model = source == ScaleSource::kModel;
  return only;
}

void MonteCarloOptions::Check() const {
  if (num_iterations < 1) {
    throw ErrorAt("Monte Carlo: num_iterations must be >= 1, got ",
                  num_iterations);
  }
  if (max_refine_iterations < 1) {
    throw ErrorAt("Monte Carlo: max_refine_iterations must be >= 1");
  }
  if (convergence_every < 1) {
    throw ErrorAt("Monte Carlo: convergence_every must be >= 1");
  }
  if (min_lasers < 1) throw ErrorAt("Monte Carlo: min_lasers must be >= 1");
  if (!(max_item_sigmas > 0.0)) {
    throw ErrorAt("Monte Carlo: max_item_sigmas must be > 0, got ",
                  max_item_sigmas);
  }
}

SampleSummary Summarize(std::vector<double> samples) {
  samples.erase(std::remove_if(samples.begin(), samples.end(),
                               [](double x) { return !std::isfinite(x); }),
                samples.end());
  SampleSummary summary;
  summary.num_samples = samples.size();
  if (samples.empty()) return summary;
  double sum = 0.0;
  for (const double x : samples) sum += x;
  summary.mean = sum / static_cast<double>(samples.size());
  double squares = 0.0;
  for (const double x : samples) {
    squares += (x - summary.mean) * (x - summary.mean);
  }
  summary.std_dev =
      samples.size() > 1
          ? std::sqrt(squares / static_cast<double>(samples.size() - 1))
          : 0.0;
  std::sort(samples.begin(), samples.end());
  summary.p2_5 = Percentile(samples, 0.025);
  summary.p16 = Percentile(samples, 0.16);
  summary.p50 = Percentile(samples, 0.5);
  summary.p84 = Percentile(samples, 0.84);
  summary.p97_5 = Percentile(samples, 0.975);
  return summary;
}

ImageScaleResult EstimateImageScale(const LaserImage& image, int image_index,
                                    const LaserSetup& setup,
                                    const RayCaster& caster, ScaleMethod method,
                                    const MonteCarloOptions& options) {
  options.Check();
  const std::vector<Laser>& lasers = setup.lasers;
  if (image.spots.size() != lasers.size()) {
    throw ErrorAt("image ", image.name, ": ", image.spots.size(),
                  " spot entries for the ", lasers.size(), " lasers of set-up ",
                  setup.name);
  }
  ImageScaleResult result;
  result.image = image.name;
  result.method = method;
  const std::vector<ScaleItem> items = ScaleItems(method, setup);
  const size_t num_items = items.size();

  SpotPixels nominal_spots(lasers.size());
  for (size_t l = 0; l < lasers.size(); ++l) {
    if (image.spots[l]) nominal_spots[l] = image.spots[l]->pixel;
  }
  const std::vector<ItemScale> nominal =
      EvaluateItems(method, items, lasers, caster, image.camera,
                    image.cam_from_world, nominal_spots);
  std::vector<double> nominal_values(num_items, kNaN);
  for (size_t k = 0; k < num_items; ++k) {
    if (nominal[k].scale) nominal_values[k] = *nominal[k].scale;
  }
  const double nominal_image = MeanOfValid(nominal_values.data(), num_items);
  if (!std::isnan(nominal_image)) result.nominal = nominal_image;

  // Factors of every sampled covariance, computed once.
  std::vector<Eigen::Matrix3d> direction_factors;
  std::vector<Eigen::Matrix3d> origin_factors;
  for (const Laser& laser : lasers) {
    direction_factors.push_back(CovarianceFactor<3>(laser.direction_cov));
    origin_factors.push_back(CovarianceFactor<3>(laser.origin_cov));
  }
  std::vector<Eigen::Matrix2d> spot_factors(lasers.size(),
                                            Eigen::Matrix2d::Zero());
  for (size_t l = 0; l < lasers.size(); ++l) {
    if (image.spots[l]) {
      spot_factors[l] = CovarianceFactor<2>(image.spots[l]->covariance);
    }
  }

  const int num_iterations = options.num_iterations;
  std::vector<double> item_samples(
      static_cast<size_t>(num_iterations) * num_items, kNaN);
  std::vector<std::string> problems(static_cast<size_t>(num_iterations) *
                                    num_items);
  const uint64_t image_key =
      SplitMix64(SplitMix64(options.seed) ^
                 SplitMix64(static_cast<uint64_t>(image_index)));
  const uint64_t calibration_key =
      SplitMix64(SplitMix64(options.seed) ^ 0xCA1Bull);
  const bool sample_features =
      options.sample_features && image.feature_sigma_px > 0.0;
  std::optional<LinearizedPose> linearized;
  if (sample_features && !options.exact_relocalization) {
    linearized.emplace(image.camera, image.matches, image.cam_from_world);
  }

  // Per draw of the model: its camera, and the pose refined to convergence
  // on the drawn points (nonlinear in the model, which moves a pose by far
  // more than the features do).
  const ImageModelDraws& model = image.model;
  const int num_draws = options.sample_model ? model.NumDraws() : 0;
  if (num_draws > 0 &&
      model.point_deltas.rows() !=
          3 * static_cast<Eigen::Index>(image.matches.size())) {
    throw ErrorAt("image ", image.name, ": model draws for ",
                  model.point_deltas.rows() / 3, " matches, the image has ",
                  image.matches.size());
  }
  result.num_model_draws = num_draws;
  if (num_draws > 0) result.model_note = model.note;
  const auto drawn_matches = [&](int m,
                                 std::vector<Correspondence2D3D>* matches) {
    for (size_t j = 0; j < matches->size(); ++j) {
      (*matches)[j].point_in_world =
          image.matches[j].point_in_world +
          model.point_deltas.block<3, 1>(3 * static_cast<Eigen::Index>(j), m)
              .cast<double>();
    }
  };
  std::vector<Camera> draw_cameras(num_draws, image.camera);
  std::vector<Rigid3d> draw_poses(num_draws, image.cam_from_world);
  std::vector<char> draw_localized(num_draws, 1);
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads
                                                : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(0, num_draws, [&](int m) {
      for (size_t p = 0; p < model.param_indices.size(); ++p) {
        draw_cameras[m].params[model.param_indices[p]] +=
            model.camera_deltas(static_cast<Eigen::Index>(p), m);
      }
      std::vector<Correspondence2D3D> matches = image.matches;
      drawn_matches(m, &matches);
      draw_localized[m] = RefinePose(
          draw_cameras[m], matches, {},
          std::max(options.max_refine_iterations, 50), &draw_poses[m]);
    });
  });

  const auto run = [&](const tbb::blocked_range<int>& range) {
    std::vector<Correspondence2D3D> perturbed = image.matches;
    Eigen::VectorXd offsets(2 * image.matches.size());
    std::vector<Laser> sampled_lasers = lasers;
    SpotPixels spots(lasers.size());
    for (int n = range.begin(); n != range.end(); ++n) {
      SplitMix64Stream rng(SplitMix64(image_key + static_cast<uint64_t>(n)));
      SplitMix64Stream calibration_rng(
          SplitMix64(calibration_key + static_cast<uint64_t>(n)));
      const int m = num_draws > 0 ? n % num_draws : -1;
      const Camera& camera = m >= 0 ? draw_cameras[m] : image.camera;
      Rigid3d cam_from_world = m >= 0 ? draw_poses[m] : image.cam_from_world;
      bool localized = m < 0 || draw_localized[m];
      if (sample_features && localized) {
        for (size_t j = 0; j < perturbed.size(); ++j) {
          offsets.segment<2>(2 * j) =
              image.feature_sigma_px * rng.GaussianPair();
        }
        if (linearized) {
          cam_from_world =
              m >= 0 ? linearized->PerturbedFrom(cam_from_world, offsets)
                     : linearized->Perturbed(offsets);
        } else {
          if (m >= 0) drawn_matches(m, &perturbed);
          for (size_t j = 0; j < perturbed.size(); ++j) {
            perturbed[j].pixel =
                image.matches[j].pixel + offsets.segment<2>(2 * j);
          }
          localized =
              RefinePose(camera, perturbed, {}, options.max_refine_iterations,
                         &cam_from_world);
        }
      }
      if (m >= 0) {
        // The mesh is the nominal model's: a surface moved by the draw is
        // met by the camera moved the opposite way.
        cam_from_world.translation +=
            cam_from_world.rotation *
            model.surface_shifts.col(m).cast<double>();
      }
      for (size_t l = 0; l < lasers.size(); ++l) {
        spots[l] = nominal_spots[l];
        if (spots[l] && options.sample_spots) {
          *spots[l] += spot_factors[l] * rng.GaussianPair();
        }
        if (options.sample_calibration) {
          sampled_lasers[l].direction_in_cam =
              (lasers[l].direction_in_cam +
               direction_factors[l] * StandardNormal3(&calibration_rng))
                  .normalized();
          sampled_lasers[l].origin_in_cam =
              lasers[l].origin_in_cam +
              origin_factors[l] * StandardNormal3(&calibration_rng);
        }
      }
      const size_t offset = static_cast<size_t>(n) * num_items;
      if (!localized) {
        for (size_t k = 0; k < num_items; ++k) {
          problems[offset + k] = "the re-localization failed";
        }
        continue;
      }
      const std::vector<ItemScale> scales = EvaluateItems(
          method, items, sampled_lasers, caster, camera, cam_from_world, spots);
      for (size_t k = 0; k < num_items; ++k) {
        if (scales[k].scale) {
          item_samples[offset + k] = *scales[k].scale;
        } else {
          problems[offset + k] = scales[k].problem;
        }
      }
    }
  };
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, num_iterations, 16), run);
  });

  for (size_t k = 0; k < num_items; ++k) {
    ItemResult item;
    item.item = items[k];
    item.nominal = nominal[k];
    for (int n = 0; n < num_iterations; ++n) {
      const size_t index = static_cast<size_t>(n) * num_items + k;
      if (std::isnan(item_samples[index])) {
        if (item.num_invalid++ == 0) item.first_problem = problems[index];
      } else {
        item.samples.push_back(item_samples[index]);
      }
    }
    item.monte_carlo = Summarize(item.samples);
    result.items.push_back(std::move(item));
  }
  double sum = 0.0;
  double squares = 0.0;
  for (int n = 0; n < num_iterations; ++n) {
    const double scale = MeanOfValid(
        item_samples.data() + static_cast<size_t>(n) * num_items, num_items);
    result.per_iteration.push_back(scale);
    if (!std::isnan(scale)) {
      result.samples.push_back(scale);
      sum += scale;
      squares += scale * scale;
    }
    if ((n + 1) % options.convergence_every == 0 && !result.samples.empty()) {
      const double count = static_cast<double>(result.samples.size());
      const double mean = sum / count;
      const double variance =
          count > 1
              ? std::max(0.0, (squares - count * mean * mean) / (count - 1.0))
              : 0.0;
      result.convergence.push_back({n + 1, mean, std::sqrt(variance)});
    }
  }
  result.monte_carlo = Summarize(result.samples);
  if (num_draws > 0) {
    MonteCarloOptions without_model = options;
    without_model.sample_model = false;
    result.rejection = EstimateImageScale(image, image_index, setup, caster,
                                          method, without_model)
                           .rejection;
  } else {
    result.rejection = Acceptance(image, result.items, options);
  }
  result.accepted = result.rejection.empty();
  return result;
}

}  // namespace uw
