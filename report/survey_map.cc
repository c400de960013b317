#include "report/survey_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <fmt/format.h>
#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "common/util/error.h"
#include "common/util/nice_ticks.h"

namespace uw {
namespace {
// ---------------------------------------------------------------------------
// Drawing. Lengths are given for a 1600 px wide figure and scaled with it.

const cv::HersheyFonts kFont = cv::FONT_HERSHEY_SIMPLEX;
const cv::Vec3b kPaper(255, 255, 255);
const cv::Vec3b kNoMesh(238, 238, 238);
const cv::Scalar kInk(0, 0, 0);
const cv::Scalar kGreyInk(90, 90, 90);
// Standard deviation of the blur applied to the height map before shading.
constexpr double kReliefSmoothingPx = 1.0;
// Sub-pixel drawing: OpenCV coordinates in 1/16 px.
constexpr int kShift = 4;

// Sun from the north-west, 45 deg up: the cartographic convention, so that
// relief does not look inverted.
const Eigen::Vector3d kSunInWorld =
    Eigen::Vector3d(-0.5, 0.5, std::sqrt(0.5)).normalized();

cv::Point SubPixel(const Eigen::Vector2d& pixel) {
  return cv::Point(static_cast<int>(std::lround(pixel.x() * (1 << kShift))),
                   static_cast<int>(std::lround(pixel.y() * (1 << kShift))));
}

cv::Scalar ToScalar(const cv::Vec3b& color) {
  return cv::Scalar(color[0], color[1], color[2]);
}

// A light bathymetric ramp (deep blue, teal, pale green, sand; RGB stops),
// light enough that the overlays stand out.
cv::Vec3d HeightRamp(double t) {
  static const std::array<cv::Vec3d, 5> kStops = {
      cv::Vec3d(50, 82, 140), cv::Vec3d(58, 130, 175), cv::Vec3d(105, 178, 170),
      cv::Vec3d(178, 210, 158), cv::Vec3d(242, 228, 182)};
  t = std::clamp(t, 0.0, 1.0) * (kStops.size() - 1);
  const size_t i = std::min(static_cast<size_t>(t), kStops.size() - 2);
  const cv::Vec3d rgb = kStops[i] + (t - i) * (kStops[i + 1] - kStops[i]);
  return cv::Vec3d(rgb[2], rgb[1], rgb[0]);
}

// Hillshade intensity, 1 on flat ground so that flat ground shows the colour
// bar's colours.
double ShadeFactor(double shade) {
  return (0.25 + 0.75 * shade) / (0.25 + 0.75 * kSunInWorld.z());
}

// The largest 1, 2 or 5 × 10^k not above `raw`.
double NiceLengthBelow(double raw) {
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double mantissa : {5.0, 2.0}) {
    if (mantissa * power <= raw * (1.0 + 1e-9)) return mantissa * power;
  }
  return power;
}

class Figure {
 public:
  Figure(cv::Mat* image, double unit) : image_(*image), unit_(unit) {}

  int Px(double length) const {
    return std::max(1, static_cast<int>(std::lround(length * unit_)));
  }
  double FontScale(double size) const { return size * unit_; }
  int FontThickness() const { return Px(1.6); }
  double Unit() const { return unit_; }

  cv::Size TextSize(const std::string& text, double size) const {
    int baseline = 0;
    return cv::getTextSize(text, kFont, FontScale(size), FontThickness(),
                           &baseline);
  }

  // Text whose cap height is centred on y; `align` -1 left, 0 centre,
  // 1 right of x. Returns the x just past the text.
  int Text(const std::string& text, int x, int y, double size, int align,
           const cv::Scalar& color = kInk) {
    const cv::Size text_size = TextSize(text, size);
    const int left = x - (align + 1) * text_size.width / 2;
    cv::putText(image_, text, cv::Point(left, y + text_size.height / 2), kFont,
                FontScale(size), color, FontThickness(), cv::LINE_AA);
    return left + text_size.width;
  }

  // Text reading bottom to top, centred on (x, y).
  void VerticalText(const std::string& text, int x, int y, double size) {
    const cv::Size text_size = TextSize(text, size);
    const int along = text_size.width + Px(8);
    const int across = 2 * text_size.height + Px(8);
    const cv::Rect box =
        cv::Rect(x - across / 2, y - along / 2, across, along) &
        cv::Rect(0, 0, image_.cols, image_.rows);
    cv::Mat patch;
    cv::rotate(image_(box), patch, cv::ROTATE_90_CLOCKWISE);
    Figure(&patch, unit_).Text(text, patch.cols / 2, patch.rows / 2, size, 0);
    cv::Mat upright;
    cv::rotate(patch, upright, cv::ROTATE_90_COUNTERCLOCKWISE);
    upright.copyTo(image_(box));
  }

  void Line(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
            const cv::Scalar& color, double width) {
    // Anti-aliased lines thinner than 2 px never show their colour whole.
    cv::line(image_, SubPixel(from), SubPixel(to), color,
             std::max(2, Px(width)), cv::LINE_AA, kShift);
  }

  // A filled dot with a dark rim.
  void Dot(const Eigen::Vector2d& centre, double radius,
           const cv::Scalar& color) {
    cv::circle(image_, SubPixel(centre), Px(radius + 1.5) << kShift, kInk,
               cv::FILLED, cv::LINE_AA, kShift);
    cv::circle(image_, SubPixel(centre), Px(radius) << kShift, color,
               cv::FILLED, cv::LINE_AA, kShift);
  }

 private:
  cv::Mat& image_;
  double unit_;
};

// The mesh's highest surface under each pixel centre of the map (NaN where
// there is none): triangles projected onto the xy plane, heights
// interpolated, the maximum kept, so that overhangs show their top.
cv::Mat1f HeightMap(const TriangleMesh& mesh, const SurveyMap& map) {
  cv::Mat1f height(map.map_area.height, map.map_area.width,
                   std::numeric_limits<float>::quiet_NaN());
  const double scale = map.pixels_per_metre;
  // Map pixel (i, j) has its centre at (i + 0.5, j + 0.5) in these units.
  const auto local = [&](const Eigen::Vector3d& vertex) {
    return Eigen::Vector2d((vertex.x() - map.top_left_in_world.x()) * scale,
                           (map.top_left_in_world.y() - vertex.y()) * scale);
  };
  const auto edge = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       const Eigen::Vector2d& p) {
    const Eigen::Vector2d ab = b - a;
    const Eigen::Vector2d ap = p - a;
    return ab.x() * ap.y() - ab.y() * ap.x();
  };
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    const std::array<Eigen::Vector3d, 3> vertex = {mesh.vertices[triangle[0]],
                                                   mesh.vertices[triangle[1]],
                                                   mesh.vertices[triangle[2]]};
    const std::array<Eigen::Vector2d, 3> p = {
        local(vertex[0]), local(vertex[1]), local(vertex[2])};
    const double area = edge(p[0], p[1], p[2]);
    if (std::abs(area) < 1e-12) continue;  // seen edge-on from above
    const Eigen::Vector2d low = p[0].cwiseMin(p[1]).cwiseMin(p[2]);
    const Eigen::Vector2d high = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
    const int i0 = std::max(0, static_cast<int>(std::ceil(low.x() - 0.5)));
    const int j0 = std::max(0, static_cast<int>(std::ceil(low.y() - 0.5)));
    const int i1 =
        std::min(height.cols - 1, static_cast<int>(std::floor(high.x() - 0.5)));
    const int j1 =
        std::min(height.rows - 1, static_cast<int>(std::floor(high.y() - 0.5)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const Eigen::Vector2d centre(i + 0.5, j + 0.5);
        const double w0 = edge(p[1], p[2], centre) / area;
        const double w1 = edge(p[2], p[0], centre) / area;
        const double w2 = 1.0 - w0 - w1;
        // A little slack so that pixel centres on shared edges are kept.
        if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9) continue;
        const float z = static_cast<float>(
            w0 * vertex[0].z() + w1 * vertex[1].z() + w2 * vertex[2].z());
        float& stored = height(j, i);
        if (std::isnan(stored) || z > stored) stored = z;
      }
    }
  }
  return height;
}

// The height map blurred by a Gaussian of `sigma_px`, ignoring the pixels
// without height (they stay NaN).
cv::Mat1f SmoothHeights(const cv::Mat1f& height, double sigma_px) {
  const cv::Mat has_height = height == height;  // false for NaN
  cv::Mat1f weight;
  has_height.convertTo(weight, CV_32F, 1.0 / 255.0);
  cv::Mat1f filled = height.clone();
  filled.setTo(0.0f, ~has_height);
  cv::GaussianBlur(filled, filled, cv::Size(), sigma_px);
  cv::GaussianBlur(weight, weight, cv::Size(), sigma_px);
  cv::Mat1f smooth = filled / weight;
  smooth.setTo(std::numeric_limits<float>::quiet_NaN(), ~has_height);
  return smooth;
}

// Colour-ramped hillshade of the height map, into the map area.
void DrawRelief(const cv::Mat1f& height, double pixels_per_metre, double z_low,
                double z_high, cv::Mat3b map_pixels) {
  const auto valid = [&](int j, int i) {
    return i >= 0 && j >= 0 && i < height.cols && j < height.rows &&
           !std::isnan(height(j, i));
  };
  // dz per pixel step along (di, dj), central where both neighbours exist.
  const auto slope = [&](int j, int i, int di, int dj) {
    const bool before = valid(j - dj, i - di);
    const bool after = valid(j + dj, i + di);
    if (before && after) {
      return 0.5 * (height(j + dj, i + di) - height(j - dj, i - di));
    }
    if (after) {
      return static_cast<double>(height(j + dj, i + di) - height(j, i));
    }
    if (before) {
      return static_cast<double>(height(j, i) - height(j - dj, i - di));
    }
    return 0.0;
  };
  const double z_range = std::max(z_high - z_low, 1e-6);
  for (int j = 0; j < height.rows; ++j) {
    for (int i = 0; i < height.cols; ++i) {
      if (!valid(j, i)) {
        map_pixels(j, i) = kNoMesh;
        continue;
      }
      // Rows grow southwards, so the northward slope is minus the row slope.
      const double dz_dx = slope(j, i, 1, 0) * pixels_per_metre;
      const double dz_dy = -slope(j, i, 0, 1) * pixels_per_metre;
      const Eigen::Vector3d normal =
          Eigen::Vector3d(-dz_dx, -dz_dy, 1.0).normalized();
      const double shade = std::max(0.0, normal.dot(kSunInWorld));
      const cv::Vec3d color =
          HeightRamp((height(j, i) - z_low) / z_range) * ShadeFactor(shade);
      map_pixels(j, i) = cv::Vec3b(cv::saturate_cast<uchar>(color[0]),
                                   cv::saturate_cast<uchar>(color[1]),
                                   cv::saturate_cast<uchar>(color[2]));
    }
  }
}

// Consecutive points of the same dive, as separate polylines: the vehicle
// was not surveying between dives.
std::vector<std::vector<const SurveyMapPoint*>> DiveRuns(
    const std::vector<SurveyMapPoint>& points) {
  std::vector<std::vector<const SurveyMapPoint*>> runs;
  for (const SurveyMapPoint& point : points) {
    if (runs.empty() || runs.back().back()->dive != point.dive) {
      runs.emplace_back();
    }
    runs.back().push_back(&point);
  }
  return runs;
}

void DrawAxes(const SurveyMap& map, MapFrame frame, Figure* figure) {
  const cv::Rect& area = map.map_area;
  cv::rectangle(map.image, area.tl() - cv::Point(1, 1), area.br(), kInk,
                figure->Px(1.5));
  const double scale = map.pixels_per_metre;
  const double x0 = map.top_left_in_world.x();
  const double x1 = x0 + area.width / scale;
  const double y1 = map.top_left_in_world.y();
  const double y0 = y1 - area.height / scale;
  const int tick = figure->Px(9);
  const int label_gap = figure->Px(12);
  // Ticks about 150 px apart and at least two on an axis (a step of at
  // most a fifth of the extent).
  const double x_step = NiceStep(
      (x1 - x0) / std::max(5.0, area.width / (150.0 * figure->Unit())));
  for (double k = std::ceil(x0 / x_step); k * x_step <= x1; ++k) {
    const double x = k * x_step;
    const int column = static_cast<int>(
        std::lround(map.PixelFromWorld(Eigen::Vector2d(x, y0)).x()));
    const int bottom = area.y + area.height;
    cv::line(map.image, {column, bottom}, {column, bottom + tick}, kInk,
             figure->Px(1.5));
    figure->Text(TickLabel(x, x_step), column,
                 bottom + tick + label_gap + figure->Px(2), 0.7, 0);
  }
  const bool metric = frame == MapFrame::kEastNorthUpMetres;
  figure->Text(metric ? "x east (m)" : "x (model units)",
               area.x + area.width / 2, area.y + area.height + figure->Px(72),
               0.8, 0);
  const double y_step = NiceStep(
      (y1 - y0) / std::max(5.0, area.height / (110.0 * figure->Unit())));
  for (double k = std::ceil(y0 / y_step); k * y_step <= y1; ++k) {
    const double y = k * y_step;
    const int row = static_cast<int>(
        std::lround(map.PixelFromWorld(Eigen::Vector2d(x0, y)).y()));
    cv::line(map.image, {area.x - 1, row}, {area.x - 1 - tick, row}, kInk,
             figure->Px(1.5));
    figure->Text(TickLabel(y, y_step), area.x - tick - label_gap, row, 0.7, 1);
  }
  figure->VerticalText(metric ? "y north (m)" : "y (model units)",
                       area.x - figure->Px(100), area.y + area.height / 2, 0.8);
}

struct NavigationError {
  size_t count = 0;
  double rms_m = 0.0;
  double max_m = 0.0;
};

// Horizontal distance between nav.csv and truth/nav.csv per image.
NavigationError HorizontalNavigationError(const SurveyMapData& data) {
  std::unordered_map<std::string, const SurveyMapPoint*> truth;
  for (const SurveyMapPoint& point : data.true_track) {
    truth.emplace(point.image_name, &point);
  }
  NavigationError error;
  double sum_squares = 0.0;
  for (const SurveyMapPoint& point : data.navigation) {
    const auto found = truth.find(point.image_name);
    if (found == truth.end()) continue;
    const double distance = (point.position_in_world.head<2>() -
                             found->second->position_in_world.head<2>())
                                .norm();
    sum_squares += distance * distance;
    error.max_m = std::max(error.max_m, distance);
    ++error.count;
  }
  if (error.count > 0) error.rms_m = std::sqrt(sum_squares / error.count);
  return error;
}

// Below the map: legend (left), height colour bar (middle), scale bar and
// north arrow (right).
void DrawLegend(const SurveyMapData& data, const SurveyMap& map, int top,
                double z_low, double z_high, MapFrame frame, Figure* figure) {
  const int width = map.image.cols;
  const int row_height = figure->Px(34);
  const int left = map.map_area.x;
  const double dot_radius = 6.0;
  const int text_x = left + figure->Px(62);
  int row = top + row_height / 2;

  std::vector<int> dives;
  for (const SurveyMapPoint& camera : data.cameras) {
    dives.push_back(camera.dive);
  }
  std::sort(dives.begin(), dives.end());
  dives.erase(std::unique(dives.begin(), dives.end()), dives.end());
  const int column_b = static_cast<int>(0.50 * width);
  const Eigen::Vector2d symbol(left + figure->Px(23), row);
  if (dives.size() == 1) {
    figure->Dot(symbol, dot_radius, ToScalar(DiveColor(dives[0])));
    figure->Text(data.cameras_label + ", dive " + std::to_string(dives[0]),
                 text_x, row, 0.65, -1);
  } else {
    int x = figure->Text(data.cameras_label + ":", left, row, 0.65, -1);
    for (const int dive : dives) {
      const std::string label = "dive " + std::to_string(dive);
      const int needed = figure->Px(40) + figure->TextSize(label, 0.65).width;
      if (x + needed > column_b - figure->Px(20)) {
        figure->Text("...", x + figure->Px(10), row, 0.65, -1);
        break;
      }
      figure->Dot(Eigen::Vector2d(x + figure->Px(22), row), dot_radius,
                  ToScalar(DiveColor(dive)));
      x = figure->Text(label, x + figure->Px(36), row, 0.65, -1);
    }
  }
  row += row_height;
  if (!data.true_track.empty()) {
    figure->Line(Eigen::Vector2d(left + figure->Px(2), row),
                 Eigen::Vector2d(left + figure->Px(44), row),
                 ToScalar(TrueTrackColor()), 3.0);
    figure->Text(data.true_track_label, text_x, row, 0.65, -1);
    row += row_height;
  }
  if (!data.navigation.empty()) {
    figure->Line(Eigen::Vector2d(left + figure->Px(2), row),
                 Eigen::Vector2d(left + figure->Px(44), row),
                 ToScalar(NavigationTrackColor()), 2.0);
    cv::circle(map.image, {left + figure->Px(23), row}, figure->Px(4),
               ToScalar(NavigationTrackColor()), cv::FILLED, cv::LINE_AA);
    figure->Text(data.navigation_label, text_x, row, 0.65, -1);
    row += row_height;
  }
  const NavigationError error = HorizontalNavigationError(data);
  if (error.count > 0) {
    figure->Text(fmt::format("{} images; navigation error (horizontal): RMS "
                             "{:.2f} m, max {:.2f} m",
                             data.cameras.size(), error.rms_m, error.max_m),
                 left, row, 0.55, -1, kGreyInk);
  }

  // Height colour bar.
  const int bar_width = static_cast<int>(0.22 * width);
  const int bar_height = figure->Px(20);
  const int bar_top = top + row_height;
  const bool metric = frame == MapFrame::kEastNorthUpMetres;
  figure->Text(metric ? "height z (m, up)" : "height (model units, up)",
               column_b + bar_width / 2, top + row_height / 2, 0.65, 0);
  for (int i = 0; i < bar_width; ++i) {
    const cv::Vec3d color = HeightRamp((i + 0.5) / bar_width);
    cv::line(map.image, {column_b + i, bar_top},
             {column_b + i, bar_top + bar_height - 1},
             cv::Scalar(color[0], color[1], color[2]));
  }
  cv::rectangle(map.image, {column_b - 1, bar_top - 1},
                {column_b + bar_width, bar_top + bar_height}, kInk,
                figure->Px(1));
  const double z_step = NiceStep(std::max(z_high - z_low, 1e-3) / 50.0);
  for (int k = 0; k <= 2; ++k) {
    const int x = column_b + k * (bar_width - 1) / 2;
    const double z = z_low + k * (z_high - z_low) / 2.0;
    cv::line(map.image, {x, bar_top + bar_height},
             {x, bar_top + bar_height + figure->Px(6)}, kInk, figure->Px(1.5));
    figure->Text(TickLabel(z, z_step), x, bar_top + bar_height + figure->Px(22),
                 0.6, 0);
  }

  // North arrow at the right edge (the map is drawn north up; a model in
  // its own frame has no north), and left of it a scale bar of a round
  // length near 1/8 of the figure, in halves.
  const int arrow_x = width - figure->Px(60);
  if (metric) {
    const int arrow_bottom = bar_top + figure->Px(44);
    const int arrow_top = top + figure->Px(26);
    cv::arrowedLine(map.image, {arrow_x, arrow_bottom}, {arrow_x, arrow_top},
                    kInk, figure->Px(3), cv::LINE_AA, 0, 0.3);
    figure->Text("N", arrow_x, top + figure->Px(8), 0.8, 0);
  }
  const double length_m = NiceLengthBelow(0.125 * width / map.pixels_per_metre);
  const int length_px =
      static_cast<int>(std::lround(length_m * map.pixels_per_metre));
  const int scale_left = arrow_x - figure->Px(90) - length_px;
  const int scale_top = bar_top;
  const int bar_thickness = figure->Px(10);
  cv::rectangle(map.image, {scale_left, scale_top},
                {scale_left + length_px / 2, scale_top + bar_thickness}, kInk,
                cv::FILLED);
  cv::rectangle(map.image, {scale_left, scale_top},
                {scale_left + length_px, scale_top + bar_thickness}, kInk,
                figure->Px(1.5));
  figure->Text("0", scale_left, scale_top + figure->Px(32), 0.6, 0);
  figure->Text(TickLabel(length_m, length_m) + (metric ? " m" : " units"),
               scale_left + length_px, scale_top + figure->Px(32), 0.6, 0);
  figure->Text("scale", scale_left + length_px / 2, top + row_height / 2, 0.65,
               0);
}

}  // namespace

void SurveyMapOptions::Check() const {
  if (width_px < 800 || width_px > 8000) {
    throw ErrorAt("survey map width must be in [800, 8000] px, got ", width_px);
  }
}

Eigen::Vector2d SurveyMap::PixelFromWorld(
    const Eigen::Vector2d& xy_in_world) const {
  return Eigen::Vector2d(
      map_area.x - 0.5 +
          (xy_in_world.x() - top_left_in_world.x()) * pixels_per_metre,
      map_area.y - 0.5 +
          (top_left_in_world.y() - xy_in_world.y()) * pixels_per_metre);
}

cv::Vec3b DiveColor(int dive) {
  // Okabe & Ito's colour-blind safe palette (BGR), orange first.
  static const std::array<cv::Vec3b, 7> kPalette = {
      cv::Vec3b(0, 159, 230),  cv::Vec3b(233, 180, 86),
      cv::Vec3b(66, 228, 240), cv::Vec3b(167, 121, 204),
      cv::Vec3b(115, 158, 0),  cv::Vec3b(178, 114, 0),
      cv::Vec3b(0, 94, 213)};
  return kPalette[static_cast<size_t>(std::max(dive, 1) - 1) % kPalette.size()];
}

cv::Vec3b TrueTrackColor() { return cv::Vec3b(0, 0, 0); }

cv::Vec3b NavigationTrackColor() { return cv::Vec3b(200, 0, 230); }

SurveyMap DrawSurveyMap(const SurveyMapData& data,
                        const SurveyMapOptions& options) {
  options.Check();
  if (data.mesh.triangles.empty()) throw ErrorAt("the mesh has no triangles");
  if (data.cameras.empty()) throw ErrorAt("the survey has no cameras");

  Eigen::AlignedBox2d extent;
  for (const Eigen::Vector3i& triangle : data.mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      extent.extend(data.mesh.vertices[triangle[k]].head<2>());
    }
  }
  for (const auto* points :
       {&data.cameras, &data.true_track, &data.navigation}) {
    for (const SurveyMapPoint& point : *points) {
      extent.extend(point.position_in_world.head<2>());
    }
  }
  const double margin = 0.03 * std::max(extent.sizes().maxCoeff(), 1.0);
  extent.min().array() -= margin;
  extent.max().array() += margin;

  const double unit = options.width_px / 1600.0;
  const auto px = [unit](double length) {
    return static_cast<int>(std::lround(length * unit));
  };
  const int left = px(140);
  const int right = px(50);
  const int top = options.title.empty() ? px(30) : px(80);
  const int axes_height = px(100);
  const int legend_height = px(150);
  const double max_map_width = options.width_px - left - right;
  const double max_map_height = 1.5 * options.width_px;
  const Eigen::Vector2d size = extent.sizes();
  const double pixels_per_metre =
      std::min(max_map_width / size.x(), max_map_height / size.y());

  SurveyMap map;
  map.pixels_per_metre = pixels_per_metre;
  map.top_left_in_world = Eigen::Vector2d(extent.min().x(), extent.max().y());
  const int map_width =
      static_cast<int>(std::ceil(size.x() * pixels_per_metre - 1e-6));
  const int map_height =
      static_cast<int>(std::ceil(size.y() * pixels_per_metre - 1e-6));
  map.map_area =
      cv::Rect(left + static_cast<int>(max_map_width - map_width) / 2, top,
               map_width, map_height);
  map.image = cv::Mat(top + map_height + axes_height + legend_height,
                      options.width_px, CV_8UC3, ToScalar(kPaper));
  Figure figure(&map.image, unit);

  const cv::Mat1f height = HeightMap(data.mesh, map);
  double z_low = 0.0;
  double z_high = 0.0;
  const cv::Mat has_height = height == height;  // false for NaN
  cv::minMaxIdx(height, &z_low, &z_high, nullptr, nullptr, has_height);
  // The mesh's facets, a pixel or two wide at a figure's scale, would
  // otherwise shade as pixel noise.
  DrawRelief(SmoothHeights(height, kReliefSmoothingPx), pixels_per_metre, z_low,
             z_high, map.image(map.map_area));

  const auto pixel = [&map](const SurveyMapPoint* point) {
    return map.PixelFromWorld(point->position_in_world.head<2>());
  };
  for (const auto& run : DiveRuns(data.true_track)) {
    for (size_t i = 1; i < run.size(); ++i) {
      figure.Line(pixel(run[i - 1]), pixel(run[i]), ToScalar(TrueTrackColor()),
                  3.0);
    }
  }
  const cv::Scalar navigation_color = ToScalar(NavigationTrackColor());
  for (const auto& run : DiveRuns(data.navigation)) {
    for (size_t i = 1; i < run.size(); ++i) {
      figure.Line(pixel(run[i - 1]), pixel(run[i]), navigation_color, 2.0);
    }
    for (const SurveyMapPoint* point : run) {
      cv::circle(map.image, SubPixel(pixel(point)), figure.Px(4) << kShift,
                 navigation_color, cv::FILLED, cv::LINE_AA, kShift);
    }
  }
  for (const SurveyMapPoint& camera : data.cameras) {
    figure.Dot(pixel(&camera), 6.0, ToScalar(DiveColor(camera.dive)));
  }

  if (!options.title.empty()) {
    figure.Text(options.title, options.width_px / 2, top / 2, 0.9, 0);
  }
  DrawAxes(map, options.frame, &figure);
  DrawLegend(data, map, map.map_area.y + map_height + axes_height, z_low,
             z_high, options.frame, &figure);
  return map;
}

}  // namespace uw
