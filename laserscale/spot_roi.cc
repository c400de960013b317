#include "laserscale/spot_roi.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "laserscale/beam_image.h"

namespace uw::lsd {

Eigen::Vector2d AuxView(const Roi& roi, const Eigen::Vector2d& p) {
  const Eigen::Vector3d h =
      roi.aux_view_from_roi * Eigen::Vector3d(p.x() - 0.5, p.y() - 0.5, 1.0);
  return h.head<2>() / h.z() + Eigen::Vector2d(0.5, 0.5);
}

std::vector<Roi> PredictRois(const cv::Mat& image, const Camera& camera,
                             const LaserSetup& setup,
                             const SpotDetectorOptions& options) {
  std::vector<Roi> rois(setup.lasers.size());
  std::vector<std::vector<Eigen::Vector2d>> beams;
  for (const Laser& laser : setup.lasers) {
    beams.push_back(BeamImage(camera, laser, options));
  }
  const cv::Rect image_rect(0, 0, image.cols, image.rows);
  for (size_t l = 0; l < setup.lasers.size(); ++l) {
    Roi& roi = rois[l];
    roi.laser = l;
    roi.colour = ColourOf(setup.lasers[l]);
    const std::vector<Eigen::Vector2d>& beam = beams[l];
    cv::Rect rect;
    if (!beam.empty()) {
      Eigen::Vector2d low = beam[0];
      Eigen::Vector2d high = beam[0];
      for (const Eigen::Vector2d& p : beam) {
        low = low.cwiseMin(p);
        high = high.cwiseMax(p);
      }
      const double margin = options.roi_margin_px;
      const auto clamp = [](double v) {
        return static_cast<int>(std::clamp(v, -1e9, 1e9));
      };
      const int x0 = clamp(std::floor(low.x() - margin));
      const int y0 = clamp(std::floor(low.y() - margin));
      const int x1 = clamp(std::ceil(high.x() + margin));
      const int y1 = clamp(std::ceil(high.y() + margin));
      rect = cv::Rect(x0, y0, x1 - x0, y1 - y0) & image_rect;
    }
    if (rect.area() == 0) {
      roi.problem = fmt::format(
          "outside the image (the beam between {:g} and {:g} m depth does "
          "not project into it)",
          options.min_range_m, options.max_range_m);
      continue;
    }
    roi.rect = rect;
    for (const std::vector<Eigen::Vector2d>& image_beam : beams) {
      roi.beams.emplace_back();
      for (const Eigen::Vector2d& p : image_beam) {
        roi.beams.back().push_back(p - Eigen::Vector2d(rect.x, rect.y));
      }
    }
    image(rect).convertTo(roi.main, CV_32FC3);
    roi.valid = cv::Mat(rect.size(), CV_8U, cv::Scalar(255));
  }
  return rois;
}

Roi Crop(const Roi& roi, const cv::Rect& window) {
  Roi out;
  out.rect = window + roi.rect.tl();
  out.laser = roi.laser;
  out.colour = roi.colour;
  const Eigen::Vector2d shift(window.x, window.y);
  const auto shifted =
      [&](const std::vector<std::vector<Eigen::Vector2d>>& in) {
        std::vector<std::vector<Eigen::Vector2d>> lines;
        for (const std::vector<Eigen::Vector2d>& line : in) {
          lines.emplace_back();
          for (const Eigen::Vector2d& p : line)
            lines.back().push_back(p - shift);
        }
        return lines;
      };
  out.beams = shifted(roi.beams);
  out.aux_beams = shifted(roi.aux_beams);
  out.main = roi.main(window);
  if (!roi.aux.empty()) out.aux = roi.aux(window);
  out.valid = roi.valid(window);
  for (int c = 0; c < 3; ++c) {
    out.clipped_main[c] = roi.clipped_main[c](window);
    if (!roi.aux.empty()) out.clipped_aux[c] = roi.clipped_aux[c](window);
  }
  out.background = roi.background;
  out.channel = roi.channel;
  for (const auto& [from, to] :
       {std::pair(&roi.print, &out.print),
        std::pair(&roi.nominal_spot, &out.nominal_spot),
        std::pair(&roi.nominal_print, &out.nominal_print)}) {
    *to = *from;
    if (*to) (*to)->mean -= shift;
  }
  if (roi.print) out.print_window = roi.print_window(window);
  return out;
}

}  // namespace uw::lsd
