// Figures of a camera track against a reference track and of a deviation
// field along it, as the doming analysis defines them
// (shared/spec/doming_feasibility.md; ch4 spec §7.5–7.6):
//  - the along-track axis: principal direction of the reference centres;
//  - per-segment scale: Σ reference / Σ reconstructed consecutive
//    camera-centre distances in N segments, in 3D and along the track only;
//  - the tilt of the viewing direction per segment;
//  - a deviation field (e.g. of 3D points from the true surface) binned
//    along the track with a quadratic "dome" fit and its sagitta;
//  - ratios of camera distances between two models (λ sensitivity).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace uw {

// x = direction · (p − origin); origin is the middle of the reference
// centres' range along the direction, so x runs over [−length/2, length/2].
struct TrackAxis {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit
  double length = 0.0;
  // RMS spread of the centres along the direction and along the second
  // principal axis (across a straight pass: its few-cm scatter).
  double rms_along = 0.0;
  double rms_across = 0.0;

  double AlongTrack(const Eigen::Vector3d& point) const {
    return direction.dot(point - origin);
  }
};

// From centres in acquisition order: the principal direction, pointing
// from the first centre to the last. Throws uw::Error for fewer than 2
// centres or centres that all coincide.
TrackAxis TrackAxisFromCentres(const std::vector<Eigen::Vector3d>& centres);

// Across / along below this: centres like a single survey pass (the true
// centres of the breakwater's and canyon's plans: 0.012-0.018; the scarp's
// two stacked lines: 0.019; the seafloor's and vent's lawnmowers:
// 0.67-0.77). A similarity to positions of such centres fixes the rotation
// about the line only through their small scatter off it.
constexpr double kMinAcrossAlongSpread = 0.1;

// "N camera centres lie nearly on one line (RMS a m across it, b m along,
// axis [x, y, z]): positions alone fix ... not affected" when at least 3
// centres do (rms_across below kMinAcrossAlongSpread x rms_along), for the
// warnings of the adjuster and of the alignment; none otherwise.
std::optional<std::string> DescribeOneLineTrack(
    const std::vector<Eigen::Vector3d>& centres);

struct SegmentScale {
  double begin = 0.0;  // along-track interval, m
  double end = 0.0;
  size_t num_steps = 0;   // consecutive pairs whose midpoint falls here
  size_t num_images = 0;  // images whose reference centre falls here
  // Σ |Δ reference| / Σ |Δ track|: > 1 when the track is too short there.
  double scale_3d = 0.0;
  // The same with the steps projected on the along-track axis: a bent
  // (domed) track shows 1/cos of its local tilt.
  double scale_along_track = 0.0;
  // Mean signed angle (deg) from the reference viewing direction to the
  // track's, about axis × (mean reference viewing direction): how much the
  // cameras turn along a dome. 0 when no viewing directions are given.
  double view_tilt_deg = 0.0;
};

// `track` and `reference`: centres of the same images in the same order
// (acquisition order) and frame. view directions: unit camera z axes in
// that frame, one per image, or both empty. Segments split the reference
// range along `axis` into equal lengths; a segment without steps has scale
// 0. Throws uw::Error on sizes that differ or num_segments < 1.
std::vector<SegmentScale> PerSegmentScale(
    const std::vector<Eigen::Vector3d>& track,
    const std::vector<Eigen::Vector3d>& reference,
    const std::vector<Eigen::Vector3d>& track_views,
    const std::vector<Eigen::Vector3d>& reference_views, const TrackAxis& axis,
    int num_segments);

struct DeviationBin {
  double begin = 0.0;  // along-track interval, m
  double end = 0.0;
  size_t count = 0;
  double median_m = 0.0;  // 0 when empty
};

// Bins `values` by their along-track coordinate over [begin, end) (values
// outside are left out) into num_bins equal bins.
std::vector<DeviationBin> BinAlongTrack(const std::vector<double>& along_track,
                                        const std::vector<double>& values,
                                        double begin, double end, int num_bins);

struct DomeFit {
  bool valid = false;  // at least 3 bins with min_count values
  size_t num_bins_used = 0;
  // d(x) = c0 + c1 x + c2 x², x along track from the track's middle.
  std::array<double, 3> coefficients = {0.0, 0.0, 0.0};
  // c2 L² / 4: the fitted deviation at the ends relative to the middle.
  // Negative when the middle stands out towards the cameras (a dome seen
  // from them, with deviations positive towards the cameras).
  double sagitta_m = 0.0;
  double sagitta_percent = 0.0;  // of the track length L
};

// Least-squares quadratic through the bin medians (at bin centres) of the
// bins holding at least min_count values.
DomeFit FitDome(const std::vector<DeviationBin>& bins, double track_length,
                size_t min_count);

// Spec §7.5: r_ij = |a_i − a_j| / |b_i − b_j| over pairs of images whose
// reference distance is at least min_distance_fraction of the largest (short
// baselines only measure noise). With more than max_images images, an
// evenly spaced subset is used.
struct DistanceRatios {
  size_t num_pairs = 0;
  double median_ratio = 0.0;
  double max_abs_deviation = 0.0;  // max |r − 1|
  double p95_abs_deviation = 0.0;
};
DistanceRatios CameraDistanceRatios(const std::vector<Eigen::Vector3d>& a,
                                    const std::vector<Eigen::Vector3d>& b,
                                    double min_distance_fraction = 0.1,
                                    size_t max_images = 2000);

// Quantile q in [0, 1] of values, linear between order statistics (the
// median of an even count is the mean of the middle two); 0 for none.
double Quantile(std::vector<double> values, double q);

}  // namespace uw
