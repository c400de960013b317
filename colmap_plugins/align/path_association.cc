#include "colmap_plugins/align/path_association.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "common/util/error.h"
#include "common/util/time_text.h"

namespace uw {
namespace {

// A point of the path: on the segment from sample `first` to `second`
// (equal for a dive of one sample) at fraction `t`.
struct PathPoint {
  size_t first = 0;
  size_t second = 0;
  double t = 0.0;
};

class Polyline {
 public:
  explicit Polyline(const TimedPath& path) : path_(path) {
    const size_t n = path.positions.size();
    for (size_t i = 0; i < n; ++i) {
      const bool dive_continues =
          i + 1 < n &&
          (path.dives.empty() || path.dives[i] == path.dives[i + 1]);
      const bool dive_starts =
          i == 0 || !(path.dives.empty() || path.dives[i] == path.dives[i - 1]);
      if (dive_continues) {
        segments_.push_back({i, i + 1});
      } else if (dive_starts) {
        segments_.push_back({i, i});  // a dive of one sample
      }
    }
    double arc_length = 0.0;
    for (const auto& [first, second] : segments_) {
      arc_start_.push_back(arc_length);
      arc_length += (path.positions[second] - path.positions[first]).norm();
    }
    arc_length_ = arc_length;
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3d& position : path.positions) box.extend(position);
    extent_ = box.diagonal().norm();
  }

  double ArcLength() const { return arc_length_; }
  double Extent() const { return extent_; }

  Eigen::Vector3d Position(const PathPoint& point) const {
    return (1.0 - point.t) * path_.positions[point.first] +
           point.t * path_.positions[point.second];
  }
  double Time(const PathPoint& point) const {
    return (1.0 - point.t) * path_.times_s[point.first] +
           point.t * path_.times_s[point.second];
  }
  Eigen::Matrix3d Covariance(const PathPoint& point) const {
    return (1.0 - point.t) * path_.covariances[point.first] +
           point.t * path_.covariances[point.second];
  }

  PathPoint Closest(const Eigen::Vector3d& position) const {
    PathPoint best;
    double best_distance = std::numeric_limits<double>::infinity();
    for (const auto& [first, second] : segments_) {
      const Eigen::Vector3d& p = path_.positions[first];
      const Eigen::Vector3d direction = path_.positions[second] - p;
      const double squared_length = direction.squaredNorm();
      const double t =
          squared_length > 0.0
              ? std::clamp((position - p).dot(direction) / squared_length, 0.0,
                           1.0)
              : 0.0;
      const double distance = (p + t * direction - position).squaredNorm();
      if (distance < best_distance) {
        best_distance = distance;
        best = {first, second, t};
      }
    }
    return best;
  }

  // The point at `time`: on the segment that spans it, else the sample
  // nearest in time.
  PathPoint AtTime(double time) const {
    PathPoint nearest;
    double nearest_gap = std::numeric_limits<double>::infinity();
    for (const auto& [first, second] : segments_) {
      const double t0 = path_.times_s[first];
      const double t1 = path_.times_s[second];
      if (first != second && t0 <= time && time <= t1) {
        return {first, second, (time - t0) / (t1 - t0)};
      }
      for (const size_t sample : {first, second}) {
        const double gap = std::abs(path_.times_s[sample] - time);
        if (gap < nearest_gap) {
          nearest_gap = gap;
          nearest = {sample, sample, 0.0};
        }
      }
    }
    return nearest;
  }

  // The point at arc length `s` from the start (dive gaps count as 0).
  PathPoint AtArcLength(double s) const {
    for (size_t k = 0; k < segments_.size(); ++k) {
      const auto& [first, second] = segments_[k];
      const double length =
          (path_.positions[second] - path_.positions[first]).norm();
      if (s <= arc_start_[k] + length || k + 1 == segments_.size()) {
        const double t =
            length > 0.0 ? std::clamp((s - arc_start_[k]) / length, 0.0, 1.0)
                         : 0.0;
        return {first, second, t};
      }
    }
    return {};
  }

 private:
  const TimedPath& path_;
  std::vector<std::pair<size_t, size_t>> segments_;
  std::vector<double> arc_start_;
  double arc_length_ = 0.0;
  double extent_ = 0.0;
};

std::vector<PathPoint> InitialAssociation(
    const std::vector<Eigen::Vector3d>& centres,
    const std::vector<double>* centre_times_s, const Polyline& polyline) {
  std::vector<PathPoint> points;
  if (centre_times_s != nullptr) {
    for (const double time : *centre_times_s) {
      points.push_back(polyline.AtTime(time));
    }
    return points;
  }
  std::vector<double> camera_arc = {0.0};
  for (size_t k = 1; k < centres.size(); ++k) {
    camera_arc.push_back(camera_arc.back() +
                         (centres[k] - centres[k - 1]).norm());
  }
  for (size_t k = 0; k < centres.size(); ++k) {
    const double fraction =
        camera_arc.back() > 0.0
            ? camera_arc[k] / camera_arc.back()
            : static_cast<double>(k) / std::max<size_t>(1, centres.size() - 1);
    points.push_back(polyline.AtArcLength(fraction * polyline.ArcLength()));
  }
  return points;
}

}  // namespace

void TimedPath::Check() const {
  const size_t n = positions.size();
  if (times_s.size() != n ||
      (!covariances.empty() && covariances.size() != n) ||
      (!dives.empty() && dives.size() != n)) {
    throw ErrorAt("path: ", n, " positions, ", times_s.size(), " times, ",
                  covariances.size(), " covariances, ", dives.size(),
                  " dives: expected one of each per sample");
  }
  for (size_t i = 0; i < n; ++i) {
    if (!positions[i].allFinite() || !std::isfinite(times_s[i])) {
      throw ErrorAt("path: sample ", i, " is not finite");
    }
    const bool same_dive = dives.empty() || (i > 0 && dives[i] == dives[i - 1]);
    if (i > 0 && same_dive && !(times_s[i] > times_s[i - 1])) {
      throw ErrorAt("path: sample ", i, " at ", TimeText(times_s[i]),
                    " s does not come after the previous one (",
                    TimeText(times_s[i - 1]), " s) of its dive");
    }
  }
}

void PathAssociationOptions::Check() const {
  similarity.Check();
  if (max_iterations < 1) {
    throw ErrorAt("PathAssociationOptions: max_iterations must be >= 1, got ",
                  max_iterations);
  }
  if (!(tolerance > 0.0)) {
    throw ErrorAt("PathAssociationOptions: tolerance must be > 0, got ",
                  tolerance);
  }
}

PathAssociationResult AlignToPathByClosestPoints(
    const std::vector<Eigen::Vector3d>& centres_in_a,
    const std::vector<double>* centre_times_s, const TimedPath& path_in_b,
    const PathAssociationOptions& options) {
  options.Check();
  path_in_b.Check();
  if (path_in_b.positions.size() < 2) {
    throw ErrorAt("path: ", path_in_b.positions.size(),
                  " samples; closest-point association needs a path of at "
                  "least 2");
  }
  if (centre_times_s != nullptr &&
      centre_times_s->size() != centres_in_a.size()) {
    throw ErrorAt("path association: ", centres_in_a.size(), " centres, ",
                  centre_times_s->size(), " times");
  }
  const Polyline polyline(path_in_b);
  const bool has_covariances = !path_in_b.covariances.empty();

  std::vector<PathPoint> association =
      InitialAssociation(centres_in_a, centre_times_s, polyline);
  PathAssociationResult result;
  const auto estimate = [&] {
    std::vector<Eigen::Vector3d> positions;
    std::vector<Eigen::Matrix3d> covariances;
    for (const PathPoint& point : association) {
      positions.push_back(polyline.Position(point));
      if (has_covariances) covariances.push_back(polyline.Covariance(point));
    }
    return EstimateSimilarity(centres_in_a, positions,
                              has_covariances ? &covariances : nullptr,
                              options.similarity);
  };
  for (result.iterations = 1; result.iterations <= options.max_iterations;
       ++result.iterations) {
    const Sim3d b_from_a = estimate().b_from_a;
    double max_move = 0.0;
    for (size_t k = 0; k < centres_in_a.size(); ++k) {
      const PathPoint next = polyline.Closest(b_from_a * centres_in_a[k]);
      max_move = std::max(
          max_move,
          (polyline.Position(next) - polyline.Position(association[k])).norm());
      association[k] = next;
    }
    if (max_move <= options.tolerance * polyline.Extent()) {
      result.converged = true;
      break;
    }
  }
  result.iterations = std::min(result.iterations, options.max_iterations);
  result.similarity = estimate();
  for (const PathPoint& point : association) {
    result.associated_positions.push_back(polyline.Position(point));
    result.associated_times_s.push_back(polyline.Time(point));
  }
  return result;
}

}  // namespace uw
