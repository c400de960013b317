#include "colmap_plugins/ba/covariance_files.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

#include "colmap_plugins/ba/model_file.h"
#include "common/util/csv.h"
#include "common/util/error.h"
#include "common/util/figure.h"
#include "common/util/file.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'U', 'W', 'C', 'O', 'V', 0, 0, 1};
// chi^2 with 3 degrees of freedom at 95 %.
constexpr double kChi2ThreeDof95 = 7.814727903251178;

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2,
                   values.end());
  return values[values.size() / 2];
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1,
                         static_cast<size_t>(q * values.size()))];
}

double RotationSigmaDeg(const ImageCovariance& image) {
  return std::sqrt(std::max(0.0, image.RotationCovariance().trace())) * 180.0 /
         M_PI;
}

bool Close(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() <= 1e-6 * (1.0 + b.norm());
}

void WriteSidecar(const BundleCovariance& covariance,
                  const Reconstruction& model, std::ostream& out) {
  WriteModelFileHead(kMagic, model, out);
  PutValue<uint8_t>(out, static_cast<uint8_t>(covariance.gauge));
  PutValue<double>(out, covariance.pixel_sigma_px);
  PutValue<uint64_t>(out, covariance.images.size());
  PutValue<uint64_t>(out, covariance.points.size());
  for (const ImageCovariance& image : covariance.images) {
    const Eigen::Vector3d center =
        model.FindImage(image.image_id)->ProjectionCenter();
    PutValue<uint32_t>(out, image.image_id);
    PutValue<uint8_t>(out, image.held ? 1 : 0);
    PutValue<int32_t>(out, image.num_points);
    PutValues(out, center.data(), 3);
    PutValues(out, image.rotation_center.data(), 36);
  }
  for (const PointCovariance& point : covariance.points) {
    const Eigen::Vector3d& xyz = model.FindPoint3D(point.point3D_id)->xyz;
    PutValue<uint64_t>(out, point.point3D_id);
    PutValue<int32_t>(out, point.track_length);
    PutValues(out, xyz.data(), 3);
    PutValues(out, point.xyz.data(), 9);
  }
}

void WriteCamerasCsv(const BundleCovariance& covariance,
                     const Reconstruction& model, std::ostream& out) {
  out << "image_id,name,held,num_points,sigma_x_m,sigma_y_m,sigma_z_m,"
         "sigma_position_m,sigma_rotation_deg\n";
  for (const ImageCovariance& image : covariance.images) {
    const Eigen::Matrix3d center = image.CenterCovariance();
    out << image.image_id << ","
        << CsvField(model.FindImage(image.image_id)->name) << ","
        << (image.held ? 1 : 0) << "," << image.num_points
        << fmt::format(",{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n",
                       std::sqrt(center(0, 0)), std::sqrt(center(1, 1)),
                       std::sqrt(center(2, 2)), std::sqrt(center.trace()),
                       RotationSigmaDeg(image));
  }
}

void WritePointsPly(const BundleCovariance& covariance,
                    const Reconstruction& model, std::ostream& out) {
  out << "ply\nformat ascii 1.0\n"
      << "comment uwmetric covariance_estimator: sigma_m = 1-sigma of the "
         "largest axis, sigma_rms_m = sqrt(trace/3), uncertainty = volume "
         "(m^3) of the 95 % ellipsoid\n"
      << "element vertex " << covariance.points.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property float sigma_m\nproperty float sigma_rms_m\n"
      << "property float uncertainty\nproperty int observations\n"
      << "end_header\n";
  for (const PointCovariance& point : covariance.points) {
    const Eigen::Vector3d& xyz = model.FindPoint3D(point.point3D_id)->xyz;
    out << fmt::format("{:.9g} {:.9g} {:.9g} {:.6g} {:.6g} {:.6g} {}\n",
                       xyz.x(), xyz.y(), xyz.z(), LargestAxisSigma(point.xyz),
                       std::sqrt(point.xyz.trace() / 3.0),
                       EllipsoidVolume95(point.xyz), point.track_length);
  }
}

// Plan view: points in three classes of their largest-axis sigma against
// the median, coverage gaps, cameras on top. Only a model the navigation
// priors hold is in metres; any other is in its own units.
Figure MapFigure(const BundleCovariance& covariance,
                 const Reconstruction& model) {
  const bool metric = covariance.gauge == CovarianceGauge::kPriors;
  const std::string unit = metric ? "m" : "model units";
  std::vector<double> sigmas;
  for (const PointCovariance& point : covariance.points) {
    sigmas.push_back(LargestAxisSigma(point.xyz));
  }
  const double median = Median(sigmas);
  std::vector<double> x[3];
  std::vector<double> y[3];
  for (size_t j = 0; j < covariance.points.size(); ++j) {
    const Eigen::Vector3d& xyz =
        model.FindPoint3D(covariance.points[j].point3D_id)->xyz;
    const int k = sigmas[j] <= median ? 0 : sigmas[j] <= 3.0 * median ? 1 : 2;
    x[k].push_back(xyz.x());
    y[k].push_back(xyz.y());
  }
  Figure figure("Point uncertainty, plan view (\u03c3 of the largest axis)",
                "x (" + unit + ")", "y (" + unit + ")", 9.0, 7.0);
  figure.EqualAspect();
  const std::string labels[3] = {
      metric ? fmt::format("\u2264 median ({:.3g} mm)", 1000.0 * median)
             : fmt::format("\u2264 median ({:.3g} model units)", median),
      "median .. 3\u00d7 median", "> 3\u00d7 median (weak)"};
  const char* const colours[3] = {"#a0a0a0", "#ffa500", "#dc0000"};
  for (int k = 0; k < 3; ++k) {
    if (!x[k].empty()) figure.Points(x[k], y[k], colours[k], labels[k]);
  }
  std::vector<double> gx;
  std::vector<double> gy;
  for (const Eigen::Vector2d& centre : covariance.coverage_gaps.cell_centres) {
    gx.push_back(centre.x());
    gy.push_back(centre.y());
  }
  if (!gx.empty()) {
    figure.Points(gx, gy, "#c800c8", "coverage gap (no points)");
  }
  std::vector<double> sx;
  std::vector<double> sy;
  for (const Eigen::Vector2d& centre :
       covariance.short_baselines.cell_centres) {
    sx.push_back(centre.x());
    sy.push_back(centre.y());
  }
  if (!sx.empty()) {
    figure.Points(sx, sy, "#00c8c8", "short baselines (seen from one place)");
  }
  std::vector<double> cx;
  std::vector<double> cy;
  for (const ImageCovariance& image : covariance.images) {
    const Eigen::Vector3d c =
        model.FindImage(image.image_id)->ProjectionCenter();
    cx.push_back(c.x());
    cy.push_back(c.y());
  }
  figure.Points(cx, cy, "black", "cameras");
  return figure;
}

}  // namespace

double LargestAxisSigma(const Eigen::Matrix3d& covariance) {
  return std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(
                                     covariance, Eigen::EigenvaluesOnly)
                                     .eigenvalues()(2)));
}

double EllipsoidVolume95(const Eigen::Matrix3d& covariance) {
  return 4.0 / 3.0 * M_PI * std::pow(kChi2ThreeDof95, 1.5) *
         std::sqrt(std::max(0.0, covariance.determinant()));
}

nlohmann::json CovarianceSummaryJson(const BundleCovariance& covariance,
                                     const Reconstruction& model) {
  nlohmann::json json;
  json["format"] = "uwmetric-covariance";
  json["version"] = 1;
  json["gauge"] = CovarianceGaugeName(covariance.gauge);
  json["gauge_description"] = covariance.gauge_description;
  json["method"] = CovarianceMethodName(covariance.method);
  json["pixel_sigma_px"] = covariance.pixel_sigma_px;
  json["pixel_sigma_source"] = covariance.pixel_sigma_source;
  json["nav_sigma_scale"] = covariance.nav_sigma_scale;
  json["nav_sigma_source"] = covariance.nav_sigma_source;
  json["num_images"] = covariance.images.size();
  json["num_points"] = covariance.points.size();
  json["num_observations"] = covariance.num_observations;
  json["num_residuals"] = covariance.num_residuals;
  json["num_reduced_coordinates"] = covariance.num_reduced_coordinates;
  json["factor_nonzeros"] = covariance.factor_nonzeros;
  json["reciprocal_condition_scaled"] = covariance.reciprocal_condition;
  json["time_s"] = {{"jacobian", covariance.jacobian_time_s},
                    {"schur", covariance.schur_time_s},
                    {"factor", covariance.factor_time_s},
                    {"inverse", covariance.inverse_time_s},
                    {"total", covariance.total_time_s}};
  json["warnings"] = covariance.warnings;
  const CoverageGaps& gaps = covariance.coverage_gaps;
  json["model_fingerprint"] = fmt::format("{:016x}", ModelFingerprint(model));
  json["cameras"] = nlohmann::json::array();
  for (const CameraCovariance& camera : covariance.cameras) {
    nlohmann::json entry;
    entry["camera_id"] = camera.camera_id;
    entry["param_indices"] = camera.param_indices;
    std::vector<std::vector<double>> rows;
    std::vector<double> sigmas;
    for (int r = 0; r < camera.params.rows(); ++r) {
      rows.emplace_back(camera.params.cols(), 0.0);
      for (int c = 0; c < camera.params.cols(); ++c) {
        rows.back()[c] = camera.params(r, c);
      }
      sigmas.push_back(std::sqrt(camera.params(r, r)));
    }
    entry["covariance"] = rows;
    entry["sigmas"] = sigmas;
    json["cameras"].push_back(entry);
  }
  json["dive_offsets"] = nlohmann::json::array();
  for (const auto& [dive, block] : covariance.dive_offsets) {
    json["dive_offsets"].push_back(
        {{"dive", dive}, {"covariance_m2", ToJson(block)}});
  }
  std::vector<double> positions;
  std::vector<double> rotations;
  for (const ImageCovariance& image : covariance.images) {
    if (image.held) continue;
    positions.push_back(std::sqrt(image.CenterCovariance().trace()));
    rotations.push_back(RotationSigmaDeg(image));
  }
  json["images"] = {{"sigma_position_m",
                     {{"median", Median(positions)},
                      {"p95", Quantile(positions, 0.95)},
                      {"max", Quantile(positions, 1.0)}}},
                    {"sigma_rotation_deg",
                     {{"median", Median(rotations)},
                      {"p95", Quantile(rotations, 0.95)},
                      {"max", Quantile(rotations, 1.0)}}}};
  std::vector<double> sigmas;
  for (const PointCovariance& point : covariance.points) {
    sigmas.push_back(LargestAxisSigma(point.xyz));
  }
  const double median = Median(sigmas);
  json["points"] = {
      {"sigma_largest_axis_m",
       {{"median", median},
        {"p95", Quantile(sigmas, 0.95)},
        {"max", Quantile(sigmas, 1.0)}}},
      {"num_weak", std::count_if(sigmas.begin(), sigmas.end(),
                                 [&](double s) { return s > 3.0 * median; })},
      {"weak_rule", "largest-axis sigma > 3x the median"}};
  nlohmann::json gap_cells = nlohmann::json::array();
  for (const Eigen::Vector2d& centre : gaps.cell_centres) {
    gap_cells.push_back({centre.x(), centre.y()});
  }
  json["points"]["coverage_gaps"] = {
      {"cell_m", gaps.cell_size},
      {"area_m2", gaps.Area()},
      {"cells", gap_cells},
      {"rule",
       "plan-view cells of 4x the points' mean spacing with no point, "
       "surrounded by occupied cells on all four sides"}};
  const ShortBaselines& short_baselines = covariance.short_baselines;
  nlohmann::json short_cells = nlohmann::json::array();
  for (size_t k = 0; k < short_baselines.cell_centres.size(); ++k) {
    short_cells.push_back({short_baselines.cell_centres[k].x(),
                           short_baselines.cell_centres[k].y(),
                           short_baselines.cell_median_angle_deg[k]});
  }
  json["points"]["short_baselines"] = {
      {"cell_m", short_baselines.cell_size},
      {"area_m2", short_baselines.Area()},
      {"cells", short_cells},
      {"rule",
       fmt::format("plan-view cells of {:g}x the points' mean spacing whose "
                   "points' median triangulation angle (widest pair of rays) "
                   "is below {:g} deg, at least {} cells together; cells as "
                   "x, y, median angle (deg)",
                   ShortBaselineOptions().cell_factor,
                   ShortBaselineOptions().min_angle_deg,
                   ShortBaselineOptions().min_cells)}};
  const CovarianceSamples& samples = covariance.samples;
  if (samples.NumSamples() > 0) {
    const double mean = samples.log_scale.mean();
    const double sigma =
        std::sqrt((samples.log_scale.array() - mean).square().sum() /
                  std::max(1, samples.NumSamples() - 1));
    json["samples"] = {
        {"file", "samples.bin"},
        {"count", samples.NumSamples()},
        {"similarity", "removed from each draw (deformation only)"},
        {"log_scale_sigma", sigma},
        {"log_scale_meaning",
         covariance.gauge == CovarianceGauge::kPriors
             ? "the navigation's own scale uncertainty (the priors fix the "
               "datum)"
             : "the gauge's, not a measurement: no priors fix the scale"}};
  }
  return json;
}

CovarianceFiles::CovarianceFiles(const BundleCovariance& covariance,
                                 const Reconstruction& model,
                                 std::filesystem::path folder)
    : covariance_(covariance),
      model_(model),
      folder_(std::move(folder)),
      json_(CovarianceSummaryJson(covariance, model).dump(2)),
      map_(DrawFigures({MapFigure(covariance, model)})) {}

void CovarianceFiles::Write() const {
  fs::create_directories(folder_);
  std::vector<PendingFile> files = {
      {folder_ / "covariance.bin",
       [&](std::ostream& out) { WriteSidecar(covariance_, model_, out); }},
      {folder_ / "covariance.json",
       [&](std::ostream& out) { out << json_ << "\n"; }},
      {folder_ / "cameras.csv",
       [&](std::ostream& out) { WriteCamerasCsv(covariance_, model_, out); }},
      {folder_ / "points.ply",
       [&](std::ostream& out) { WritePointsPly(covariance_, model_, out); }}};
  for (const PendingFile& figure :
       FigureFileSet(map_, {folder_ / "uncertainty_map.png"})) {
    files.push_back(figure);
  }
  if (covariance_.samples.NumSamples() > 0) {
    files.push_back({folder_ / "samples.bin", [&](std::ostream& out) {
                       WriteCovarianceSamples(covariance_.samples, model_, out);
                     }});
  }
  WriteFilesAtomically(files, true);
  // Draws of an earlier run would pass for this one's (same model).
  if (covariance_.samples.NumSamples() == 0) {
    fs::remove(folder_ / "samples.bin");
  }
}

void WriteCovarianceFiles(const BundleCovariance& covariance,
                          const Reconstruction& model,
                          const std::filesystem::path& folder) {
  CovarianceFiles(covariance, model, folder).Write();
}

BundleCovariance ReadCovarianceSidecar(const std::filesystem::path& path,
                                       const Reconstruction& model) {
  std::ifstream in = OpenModelFile(path, kMagic, "covariance sidecar", model);
  BundleCovariance covariance;
  const uint8_t gauge = GetValue<uint8_t>(in, path);
  if (gauge > static_cast<uint8_t>(CovarianceGauge::kFreeNetwork)) {
    throw ErrorAt(path.string(), ": unknown gauge ", int{gauge});
  }
  covariance.gauge = static_cast<CovarianceGauge>(gauge);
  covariance.pixel_sigma_px = GetValue<double>(in, path);
  const uint64_t num_images = GetValue<uint64_t>(in, path);
  const uint64_t num_points = GetValue<uint64_t>(in, path);
  if (num_images != model.Images().size()) {
    throw ErrorAt(path.string(), ": ", num_images, " images, the model has ",
                  model.Images().size());
  }
  for (uint64_t k = 0; k < num_images; ++k) {
    ImageCovariance image;
    image.image_id = GetValue<uint32_t>(in, path);
    image.held = GetValue<uint8_t>(in, path) != 0;
    image.num_points = GetValue<int32_t>(in, path);
    Eigen::Vector3d center;
    GetValues(in, path, center.data(), 3);
    GetValues(in, path, image.rotation_center.data(), 36);
    const Image* model_image = model.FindImage(image.image_id);
    if (model_image == nullptr ||
        !Close(model_image->ProjectionCenter(), center)) {
      throw ErrorAt(path.string(), ": image ", image.image_id,
                    " is not where the covariance was computed (another "
                    "model, or one adjusted since)");
    }
    covariance.images.push_back(image);
  }
  for (uint64_t k = 0; k < num_points; ++k) {
    PointCovariance point;
    point.point3D_id = GetValue<uint64_t>(in, path);
    point.track_length = GetValue<int32_t>(in, path);
    Eigen::Vector3d xyz;
    GetValues(in, path, xyz.data(), 3);
    GetValues(in, path, point.xyz.data(), 9);
    const Point3D* model_point = model.FindPoint3D(point.point3D_id);
    if (model_point == nullptr || !Close(model_point->xyz, xyz)) {
      throw ErrorAt(path.string(), ": point ", point.point3D_id,
                    " is not where the covariance was computed (another "
                    "model, or one adjusted since)");
    }
    covariance.points.push_back(point);
  }
  in.peek();
  if (!in.eof()) throw ErrorAt(path.string(), ": trailing bytes");
  return covariance;
}

}  // namespace uw
