#include "laserscale/spot_detector.h"

#include <cmath>
#include <optional>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/error.h"
#include "laserscale/beam_image.h"
#include "laserscale/roi_detection.h"
#include "laserscale/spot_monte_carlo.h"
#include "laserscale/spot_roi.h"
#include "laserscale/spot_segmentation.h"

namespace uw {
namespace {

using lsd::Detection;
using lsd::GaussianSpot;
using lsd::Roi;
using lsd::RoiRun;

void CheckImages(const cv::Mat& image, const cv::Mat* aux, const Camera& camera,
                 const char* what) {
  if (image.empty()) throw ErrorAt(what, ": empty image");
  if (image.type() != CV_8UC3) {
    throw ErrorAt(what, ": expected an 8-bit BGR image (CV_8UC3), got ",
                  image.channels(), " channel(s) of depth ", image.depth());
  }
  CheckCameraModelParams(camera.model_id, camera.params.size());
  if (static_cast<uint64_t>(image.cols) != camera.width ||
      static_cast<uint64_t>(image.rows) != camera.height) {
    throw ErrorAt(what, ": the image is ", image.cols, "x", image.rows,
                  ", its camera ", camera.width, "x", camera.height);
  }
  if (aux != nullptr && !aux->empty()) {
    if (aux->type() != CV_8UC3) {
      throw ErrorAt(what,
                    ": expected an 8-bit BGR auxiliary image (CV_8UC3), got ",
                    aux->channels(), " channel(s) of depth ", aux->depth());
    }
    if (aux->size() != image.size()) {
      throw ErrorAt(what, ": the auxiliary image is ", aux->cols, "x",
                    aux->rows, ", the image ", image.cols, "x", image.rows);
    }
  }
}

std::string Percent(double rate) {
  return fmt::format("{:.0f} %", 100.0 * rate);
}

}  // namespace

std::vector<DetectedSpot> DetectSpots(const cv::Mat& image, const cv::Mat& aux,
                                      const Camera& camera,
                                      const LaserSetup& setup,
                                      const SpotDetectorOptions& options,
                                      uint64_t seed) {
  CheckImages(image, &aux, camera, "DetectSpots");
  options.Check();
  setup.Check();
  std::vector<Roi> rois = lsd::PredictRois(image, camera, setup, options);
  const size_t num_lasers = rois.size();
  const int iterations = options.monte_carlo_iterations;
  const double centre_scale = 2.0 *
                              std::log(1.0 / (1.0 - options.top_fraction)) /
                              (-2.0 * std::log(1.0 - options.confidence));
  const auto to_detection = [&](const Roi& roi, const GaussianSpot& spot) {
    Detection detection;
    detection.centre = spot.mean + Eigen::Vector2d(roi.rect.x, roi.rect.y);
    detection.centre_cov = centre_scale * spot.covariance;
    return detection;
  };

  std::vector<std::optional<RoiRun>> nominal(num_lasers);
  std::vector<Roi> windows(num_lasers);
  std::vector<std::optional<GaussianSpot>> runs(num_lasers * iterations);
  double noise_sigma = options.noise_sigma;
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads
                                                : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(size_t{0}, num_lasers, [&](size_t l) {
      if (!rois[l].problem.empty()) return;
      nominal[l] = lsd::PrepareRoi(image, aux, options, &rois[l]);
      if (!nominal[l]) return;
      // The iterations' window: the nominal fit and its rivals, with room
      // for the low-pass and the fit margin.
      const int grow =
          options.fit_margin_px +
          static_cast<int>(std::ceil(4.0 * options.lowpass_sigma_px)) + 2;
      const cv::Rect extent = nominal[l]->extent;
      windows[l] = lsd::Crop(
          rois[l], cv::Rect(extent.x - grow, extent.y - grow,
                            extent.width + 2 * grow, extent.height + 2 * grow) &
                       cv::Rect(cv::Point(0, 0), rois[l].rect.size()));
    });
    if (noise_sigma < 0.0) {
      noise_sigma = lsd::NoiseFromDifference(rois, options);
      if (noise_sigma < 0.0) noise_sigma = lsd::NoiseFromImage(rois);
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, runs.size(), 4),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i != range.end(); ++i) {
                          const size_t l = i / iterations;
                          const int n = static_cast<int>(i % iterations);
                          if (!nominal[l]) continue;
                          const Roi& window = windows[l];
                          const std::optional<RoiRun> run = lsd::DetectInRoi(
                              window,
                              lsd::WithNoise(window.main, noise_sigma,
                                             lsd::IterationKey(seed, l, n)),
                              1, window.background, noise_sigma, window.channel,
                              options);
                          if (run) runs[i] = run->spot;
                        }
                      });
  });

  std::vector<DetectedSpot> spots(num_lasers);
  for (size_t l = 0; l < num_lasers; ++l) {
    DetectedSpot& spot = spots[l];
    const Roi& roi = rois[l];
    spot.laser = setup.lasers[l].name;
    if (!roi.problem.empty()) {
      spot.problem = roi.problem;
      continue;
    }
    std::vector<Detection> detections;
    for (int n = 0; n < iterations; ++n) {
      const std::optional<GaussianSpot>& run = runs[l * iterations + n];
      if (!run) continue;
      detections.push_back(to_detection(windows[l], *run));
      spot.iterations.emplace_back(detections.back().centre,
                                   detections.back().centre_cov);
    }
    spot.detected = nominal[l].has_value();
    if (iterations == 0) {
      spot.detection_rate = spot.detected ? 1.0 : 0.0;
      if (spot.detected) {
        detections.push_back(to_detection(roi, nominal[l]->spot));
      }
    } else {
      spot.detection_rate = static_cast<double>(detections.size()) / iterations;
    }
    if (!detections.empty()) {
      lsd::Merge(detections, &spot);
    } else if (spot.detected) {
      const Detection only = to_detection(roi, nominal[l]->spot);
      spot.pixel = only.centre;
      spot.covariance = only.centre_cov;
    }
    spot.stable =
        spot.detected && spot.detection_rate >= options.min_detection_rate;
    if (!spot.detected) {
      spot.problem = "not detected";
      if (!roi.colour_note.empty())
        spot.problem += " (" + roi.colour_note + ")";
    } else if (!spot.stable) {
      spot.problem = "unstable: detected in " + Percent(spot.detection_rate) +
                     " of iterations";
    }
    if (!roi.texture_note.empty()) {
      if (spot.stable && roi.aux_mismatch && options.require_texture_removal) {
        spot.stable = false;
        spot.problem = "not used: " + roi.texture_note;
      } else if (!spot.stable || roi.aux_mismatch) {
        // Kept with --require_texture_removal 0: the note still goes with it.
        spot.problem += (spot.problem.empty() ? "" : " ") + std::string("(") +
                        roi.texture_note + ")";
      }
    }
  }
  return spots;
}

std::vector<DetectedSpot> DetectBrightestPixel(
    const cv::Mat& image, const Camera& camera, const LaserSetup& setup,
    const SpotDetectorOptions& options) {
  CheckImages(image, nullptr, camera, "DetectBrightestPixel");
  options.Check();
  setup.Check();
  const std::vector<Roi> rois = lsd::PredictRois(image, camera, setup, options);
  std::vector<DetectedSpot> spots(rois.size());
  for (size_t l = 0; l < rois.size(); ++l) {
    const Roi& roi = rois[l];
    DetectedSpot& spot = spots[l];
    spot.laser = setup.lasers[l].name;
    if (!roi.problem.empty()) {
      spot.problem = roi.problem;
      continue;
    }
    const cv::Mat mask = [&] {
      SpotDetectorOptions no_opening = options;
      no_opening.opening_radius_px = 0;
      return lsd::ColourMask(roi.main, roi.valid, roi.colour, 0.0, no_opening);
    }();
    // 8-bit levels tie often (a saturated spot is a plateau): the centre of
    // the brightest pixels.
    double brightest = -1.0;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    for (int r = 0; r < roi.main.rows; ++r) {
      for (int c = 0; c < roi.main.cols; ++c) {
        const Eigen::Vector2d centre(c + 0.5, r + 0.5);
        const double value = roi.main.at<cv::Vec3f>(r, c)[roi.colour.dominant];
        if (value < brightest || !mask.at<uint8_t>(r, c) ||
            !lsd::OnOwnBeam(centre, roi.beams, roi.laser,
                            options.roi_margin_px)) {
          continue;
        }
        if (value > brightest) {
          brightest = value;
          sum.setZero();
          count = 0;
        }
        if (value == brightest) {
          sum += centre;
          ++count;
        }
      }
    }
    if (count == 0) {
      spot.problem = "not detected";
      continue;
    }
    spot.detected = true;
    spot.stable = true;
    spot.detection_rate = 1.0;
    spot.pixel = sum / count + Eigen::Vector2d(roi.rect.x, roi.rect.y);
    spot.covariance = Eigen::Matrix2d::Identity() / 12.0;
  }
  return spots;
}

}  // namespace uw
