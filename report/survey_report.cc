#include "report/survey_report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "colmap_plugins/align/mesh_comparison.h"
#include "colmap_plugins/align/mesh_distance.h"
#include "colmap_plugins/align/mesh_frame.h"
#include "colmap_plugins/align/model_comparison.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/scene/camera_up.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"
#include "common/util/csv.h"
#include "common/util/error.h"
#include "common/util/figure.h"
#include "common/util/file.h"
#include "common/util/html.h"
#include "common/util/json_fields.h"
#include "common/util/median.h"
#include "report/survey_map.h"

namespace uw {
namespace fs = std::filesystem;
namespace {

using Json = nlohmann::json;

// 95 % quantile of a χ distribution with 3 degrees of freedom (√7.8147):
// the Mahalanobis distance a 3D prior residual stays below 95 % of the time
// when the stated covariance is right.
constexpr double kMahalanobis95 = 2.795483;

std::string Fixed(double value, int decimals) {
  return fmt::format("{:.{}f}", value, decimals);
}

std::string Signed(double value, int decimals) {
  return (value >= 0.0 ? "+" : "") + Fixed(value, decimals);
}

std::string Note(const std::string& text) {
  return "<p class=\"note\">" + HtmlEscape(text) + "</p>\n";
}

// An image with its caption; a figure drawn with matplotlib links its SVG
// (for print) from its PNG.
std::string HtmlFigure(const std::string& src, const std::string& alt,
                       const std::string& caption, bool has_svg = false) {
  std::string img =
      "<img src=\"" + HtmlEscape(src) + "\" alt=\"" + HtmlEscape(alt) + "\">";
  if (has_svg) {
    img = "<a href=\"" +
          HtmlEscape(fs::path(src).replace_extension(".svg").string()) + "\">" +
          img + "</a>";
  }
  return "<figure>" + img + "<figcaption>" + caption +
         "</figcaption></figure>\n";
}

double MeshArea(const TriangleMesh& mesh) {
  double area = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    area += 0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]])
                      .cross(mesh.vertices[t[2]] - mesh.vertices[t[0]])
                      .norm();
  }
  return area;
}

// The folder's files, collected and written in one atomic set.
class ReportFiles {
 public:
  explicit ReportFiles(fs::path dir) : dir_(std::move(dir)) {}

  void Add(const std::string& relative, std::string bytes) {
    names_.push_back(relative);
    contents_.push_back(std::move(bytes));
  }
  void Png(const std::string& relative, const cv::Mat& image) {
    Add(relative, Encode(".png", image, relative));
  }
  void Jpeg(const std::string& relative, const cv::Mat& image) {
    Add(relative, Encode(".jpg", image, relative));
  }
  void Copy(const fs::path& source, const std::string& relative) {
    Add(relative, ReadFileToString(source));
  }
  // Copies a figure's PNG and, when it has one beside it, its SVG; returns
  // whether it had.
  bool CopyFigure(const fs::path& png, const std::string& relative) {
    Copy(png, relative);
    const fs::path svg = fs::path(png).replace_extension(".svg");
    if (!fs::is_regular_file(svg)) return false;
    Copy(svg, fs::path(relative).replace_extension(".svg").string());
    return true;
  }
  // A figure to draw as `relative` (PNG) and its SVG by DrawFigures: one
  // run of matplotlib for all of them.
  void AddFigure(const std::string& relative, Figure figure) {
    figure_names_.push_back(relative);
    figures_.push_back(std::move(figure));
  }
  void DrawFigures() {
    const std::vector<FigureFiles> drawn = uw::DrawFigures(figures_);
    for (size_t i = 0; i < drawn.size(); ++i) {
      Add(figure_names_[i], drawn[i].png);
      Add(fs::path(figure_names_[i]).replace_extension(".svg").string(),
          drawn[i].svg);
    }
    figures_.clear();
    figure_names_.clear();
  }
  void Replace(const std::string& relative, std::string bytes) {
    const auto at = std::find(names_.begin(), names_.end(), relative);
    contents_.at(static_cast<size_t>(at - names_.begin())) = std::move(bytes);
  }
  const std::vector<std::string>& Names() const { return names_; }

  void Write() const {
    std::vector<PendingFile> files;
    for (size_t i = 0; i < names_.size(); ++i) {
      const std::string* bytes = &contents_[i];
      files.push_back({dir_ / names_[i], [bytes](std::ostream& out) {
                         out.write(bytes->data(),
                                   static_cast<std::streamsize>(bytes->size()));
                       }});
    }
    WriteFilesAtomically(files, true);
  }

 private:
  std::string Encode(const std::string& extension, const cv::Mat& image,
                     const std::string& relative) const {
    std::vector<uchar> bytes;
    if (!cv::imencode(extension, image, bytes)) {
      throw ErrorAt((dir_ / relative).string(), ": cannot encode the image");
    }
    return std::string(bytes.begin(), bytes.end());
  }

  fs::path dir_;
  std::vector<std::string> names_;
  std::vector<std::string> contents_;
  std::vector<std::string> figure_names_;
  std::vector<Figure> figures_;
};

// What the truth says about the model (a uwsim output folder).
struct TruthFigures {
  double scale = 1.0;  // of the similarity true_from_model
  double camera_rmse_m = 0.0;
  size_t num_common_images = 0;
  Sim3d true_from_model;
  std::vector<NavRecord> track;  // truth/nav.csv
  fs::path mesh_path;            // truth/mesh.ply
};

TruthFigures ReadTruth(const fs::path& truth_dir, const Reconstruction& model) {
  const fs::path truth_model_dir = truth_dir / "truth";
  if (!fs::is_directory(truth_model_dir)) {
    throw ErrorAt("--truth_dir ", truth_dir.string(),
                  ": no truth/ folder (expected an output folder of uwsim "
                  "generate)");
  }
  const Reconstruction truth = ReadModel(truth_model_dir);
  const ModelComparison comparison =
      CompareModels(model, truth, nullptr, ModelComparisonOptions());
  TruthFigures figures;
  figures.true_from_model = comparison.alignment.b_from_a;
  figures.scale = comparison.alignment.b_from_a.scale;
  figures.camera_rmse_m = comparison.camera_rmse_m;
  figures.num_common_images = comparison.cameras.size();
  if (fs::is_regular_file(truth_model_dir / "nav.csv")) {
    figures.track = ReadNavigationCsv(truth_model_dir / "nav.csv");
  }
  figures.mesh_path = truth_model_dir / "mesh.ply";
  return figures;
}

std::string LaserItemsTable(const CsvTable& items) {
  // Per laser / pair over the images: how many images gave it a scale, the
  // mean and spread of those, and the median of the per-image intervals.
  struct Item {
    std::vector<double> nominal, low, high;
  };
  std::map<std::string, Item> by_item;
  for (size_t row = 0; row < items.NumRows(); ++row) {
    Item& item = by_item[items.Text(row, "item")];
    const std::optional<double> nominal = items.Number(row, "nominal");
    if (!nominal) continue;
    item.nominal.push_back(*nominal);
    if (const auto low = items.Number(row, "p2_5")) item.low.push_back(*low);
    if (const auto high = items.Number(row, "p97_5")) {
      item.high.push_back(*high);
    }
  }
  std::vector<std::vector<std::string>> rows;
  for (const auto& [name, item] : by_item) {
    const size_t n = item.nominal.size();
    double mean = 0.0, squares = 0.0;
    for (const double v : item.nominal) mean += v;
    mean = n > 0 ? mean / n : std::nan("");
    for (const double v : item.nominal) squares += (v - mean) * (v - mean);
    const std::string spread =
        n > 1 ? Fixed(std::sqrt(squares / (n - 1)), 5) : "";
    const std::string interval = item.low.empty()
                                     ? ""
                                     : "[" + Fixed(Median(item.low), 5) + ", " +
                                           Fixed(Median(item.high), 5) + "]";
    rows.push_back({name, std::to_string(n), n > 0 ? Fixed(mean, 5) : "",
                    spread, interval});
  }
  return HtmlTable(
      {"laser / pair", "images with a scale", "mean scale",
       "std. dev. across images", "median per-image 95 % interval"},
      rows);
}

std::string SegmentsTable(const CsvTable& segments) {
  std::vector<std::vector<std::string>> rows;
  for (size_t row = 0; row < segments.NumRows(); ++row) {
    const auto number = [&](const char* column, int decimals) {
      const std::optional<double> value = segments.Number(row, column);
      return value ? Fixed(*value, decimals) : std::string();
    };
    rows.push_back(
        {segments.Text(row, "segment"),
         "(" + number("x", 2) + ", " + number("y", 2) + ", " + number("z", 2) +
             ")",
         segments.Text(row, "num_images"), number("scale", 5),
         number("sigma", 5),
         "[" + number("ci95_low", 5) + ", " + number("ci95_high", 5) + "]",
         number("birge_ratio", 2)});
  }
  return HtmlTable({"segment", "centre (model frame)", "images", "scale s",
                    "sigma", "95 % interval", "Birge ratio"},
                   rows);
}

}  // namespace

void SurveyReportOptions::Check() const {
  if (map_width_px < 800 || map_width_px > 8000) {
    throw ErrorAt(
        "SurveyReportOptions.map_width_px must be in [800, 8000], "
        "got ",
        map_width_px);
  }
  if (thumbnail_width_px < 32 || thumbnail_width_px > 2000) {
    throw ErrorAt(
        "SurveyReportOptions.thumbnail_width_px must be in "
        "[32, 2000], got ",
        thumbnail_width_px);
  }
  if (max_histogram_vertices < 1) {
    throw ErrorAt(
        "SurveyReportOptions.max_histogram_vertices must be >= 1, "
        "got ",
        max_histogram_vertices);
  }
}

SurveyReportResult WriteSurveyReport(const SurveyReportInputs& inputs,
                                     const SurveyReportOptions& options,
                                     const fs::path& output_dir) {
  inputs.Check();
  options.Check();
  ReportFiles files(output_dir);
  SurveyReportResult result;
  Json report = {{"format", "uwmetric-survey-report"}, {"version", 1}};
  report["inputs"] = {
      {"model", inputs.model_path.string()},
      {"ba_report", inputs.ba_report_path.string()},
      {"nav", inputs.nav_path.string()},
      {"laser_report", inputs.laser_report_dir.string()},
      {"compare_table", inputs.compare_table_path.string()},
      {"dense_comparison", inputs.dense_comparison_path.string()},
      {"mesh", inputs.mesh_path.string()},
      {"timings", inputs.timings_path.string()},
      {"truth_dir", inputs.truth_dir.string()},
      {"covariance", inputs.covariance_dir.string()}};
  const auto omit = [&](const std::string& text) {
    result.omitted.push_back(text);
    return Note(text);
  };

  // ---------------------------------------------------------------- inputs
  const Reconstruction model = ReadModel(inputs.model_path);
  std::vector<NavRecord> navigation;
  if (!inputs.nav_path.empty()) {
    navigation = ReadNavigationCsv(inputs.nav_path);
  }
  std::optional<BaReportSummary> ba;
  if (!inputs.ba_report_path.empty()) ba = ReadBaReport(inputs.ba_report_path);
  std::optional<LaserReportSummary> laser;
  if (!inputs.laser_report_dir.empty()) {
    laser = ReadLaserReport(inputs.laser_report_dir);
  }
  std::optional<DenseComparisonSummary> dense;
  if (!inputs.dense_comparison_path.empty()) {
    dense = ReadDenseComparison(inputs.dense_comparison_path);
  }
  std::optional<CsvTable> compare_table;
  if (!inputs.compare_table_path.empty()) {
    compare_table = CsvTable::Read(inputs.compare_table_path);
  }
  std::vector<StageTime> timings;
  if (!inputs.timings_path.empty()) timings = ReadTimings(inputs.timings_path);
  std::optional<TriangleMesh> mesh;
  if (!inputs.mesh_path.empty()) {
    mesh = ReadMesh(inputs.mesh_path);
    RequireMeshInModelFrame(CheckMeshFrame(model, RayCaster(*mesh)),
                            inputs.mesh_path.string(),
                            inputs.model_path.string());
  }
  std::optional<TruthFigures> truth;
  if (!inputs.truth_dir.empty()) truth = ReadTruth(inputs.truth_dir, model);
  std::optional<CovarianceSummary> covariance;
  if (!inputs.covariance_dir.empty()) {
    covariance = ReadCovarianceSummary(inputs.covariance_dir);
  }

  // Only the navigation-fused adjustment (--ba_report, or a covariance in
  // the priors' gauge) puts a model in the navigation's east-north-up
  // metres. Any other model (stock colmap) is in its own frame and units,
  // often upside down.
  const bool metric =
      ba.has_value() || (covariance && covariance->gauge == "priors");

  std::unordered_map<std::string, int> dive_of_image;
  for (const NavRecord& record : navigation) {
    dive_of_image.emplace(record.image_name, record.dive);
  }
  std::vector<const Image*> images;
  for (const Image& image : model.Images()) images.push_back(&image);
  std::sort(images.begin(), images.end(),
            [](const Image* a, const Image* b) { return a->name < b->name; });

  // ------------------------------------------------------------ survey map
  std::string map_html = "<h2 id=\"map\">Survey map</h2>\n";
  if (mesh && !mesh->triangles.empty() && !images.empty()) {
    // A model in its own frame is drawn from above along the up its
    // cameras give, labelled in model units, and without the tracks, which
    // lie in another frame.
    std::optional<CameraUp> up;
    Eigen::Matrix3d view_from_model = Eigen::Matrix3d::Identity();
    if (!metric) {
      up = UpFromCameras(model);
      if (up) view_from_model = ViewFromModel(up->up_in_model);
    }
    SurveyMapData data;
    data.mesh = *mesh;
    for (Eigen::Vector3d& vertex : data.mesh.vertices) {
      vertex = view_from_model * vertex;
    }
    for (const Image* image : images) {
      const auto dive = dive_of_image.find(image->name);
      data.cameras.push_back({image->name,
                              dive == dive_of_image.end() ? 1 : dive->second,
                              view_from_model * image->ProjectionCenter()});
    }
    if (metric) {
      for (const NavRecord& record : navigation) {
        data.navigation.push_back(
            {record.image_name, record.dive, record.position});
      }
      if (truth) {
        for (const NavRecord& record : truth->track) {
          data.true_track.push_back(
              {record.image_name, record.dive, record.position});
        }
      }
    }
    std::string frame_text =
        "Model frame: the navigation's (x east, y north, metres), as the "
        "navigation-fused adjustment gives it.";
    if (!metric) {
      frame_text =
          "Model frame: the model's own, in its units (not metres, no "
          "north: neither --ba_report nor a covariance in the priors' "
          "gauge says it was fused with the navigation), " +
          (up ? "seen from above along the up its cameras give (" + up->method +
                    ")"
              : std::string("seen along its own z: its cameras give no up")) +
          "; the navigation and true tracks lie in another frame and are "
          "not drawn.";
    }
    report["map_frame"] = metric ? "east-north-up metres" : "model units";
    data.cameras_label = "model camera centres";
    data.true_track_label = "true vehicle track (truth/nav.csv)";
    data.navigation_label = "navigation (nav.csv)";
    SurveyMapOptions map_options;
    map_options.width_px = options.map_width_px;
    map_options.frame =
        metric ? MapFrame::kEastNorthUpMetres : MapFrame::kModelUnits;
    map_options.title = metric
                            ? "Dense mesh from above, navigation and cameras"
                            : "Dense mesh from above and cameras (model units)";
    files.Png("survey_map.png", DrawSurveyMap(data, map_options).image);
    map_html += HtmlFigure(
        "survey_map.png", "survey map",
        "The dense mesh seen from above (hillshade, coloured by height), the "
        "model's camera centres coloured by dive" +
            std::string(navigation.empty() || !metric
                            ? ""
                            : ", the navigation track (nav.csv) with its "
                              "errors") +
            (truth && metric ? " and the true vehicle track" : "") + ". " +
            frame_text);
  } else {
    map_html += omit(
        "No survey map: it needs the dense mesh (--mesh) and a model with "
        "registered images.");
  }

  // ----------------------------------------------------------------- scale
  std::string scale_html =
      "<h2 id=\"scale\">Scale from the laser images</h2>\n";
  std::string overlays_html =
      "<h2 id=\"overlays\">Laser spots on the images</h2>\n";
  if (laser) {
    Json scale_json = {{"method", laser->method},
                       {"num_images", laser->num_images},
                       {"num_accepted", laser->num_accepted},
                       {"num_iterations", laser->num_iterations}};
    if (laser->scale) {
      const double s = *laser->scale;
      scale_json["scale"] = s;
      scale_json["sigma"] = laser->sigma;
      scale_json["ci95"] = {laser->ci95_low, laser->ci95_high};
      scale_json["birge_ratio"] = laser->birge_ratio;
      scale_html += "<p><b>s = " + Fixed(s, 5) + "</b>, 95 % interval [" +
                    Fixed(laser->ci95_low, 5) + ", " +
                    Fixed(laser->ci95_high, 5) + "] (&plusmn;" +
                    Fixed(50.0 * (laser->ci95_high - laser->ci95_low) / s, 2) +
                    " %), &sigma; = " + Fixed(laser->sigma, 5) +
                    ", Birge ratio " + Fixed(laser->birge_ratio, 2) + "; " +
                    std::to_string(laser->num_accepted) + " of " +
                    std::to_string(laser->num_images) +
                    " laser images accepted, method " +
                    HtmlEscape(laser->method) + ", " +
                    std::to_string(laser->num_iterations) +
                    " Monte Carlo iterations. Multiply the model by s to get "
                    "metres.</p>\n";
      if (laser->birge_ratio > 1.0) {
        scale_html +=
            "<p class=\"bad\">The laser images disagree more than their "
            "uncertainties allow (Birge ratio above 1); the interval was "
            "widened by it. Look at the segments: the scale may vary along "
            "the model.</p>\n";
      }
      scale_json["model_draws"] = laser->model_draws;
      if (laser->model_draws > 0) {
        scale_html += "<p>The interval holds the model's own error: " +
                      std::to_string(laser->model_draws) +
                      " draws of its covariance (gauge " +
                      HtmlEscape(laser->model_gauge) +
                      ") re-sampled its intrinsics, points and surface.</p>\n";
      } else {
        scale_html +=
            "<p class=\"bad\">The laser scale took the model as exact "
            "(laserscale estimate without --covariance): the model's own "
            "error is not in the interval.</p>\n";
      }
      if (!laser->variance_shares.empty()) {
        std::string shares;
        Json shares_json = Json::object();
        for (const auto& [source, share] : laser->variance_shares) {
          shares += (shares.empty() ? "" : ", ") + HtmlEscape(source) + " " +
                    Fixed(100.0 * share, 0) + " %";
          shares_json[source] = share;
        }
        scale_json["variance_shares"] = shares_json;
        scale_html += "<p>Share of the variance, each source alone: " + shares +
                      ".</p>\n";
      }
      if (laser->navigation_z) {
        scale_json["navigation_z"] = *laser->navigation_z;
        scale_html +=
            std::string(laser->navigation_consistent ? "<p>"
                                                     : "<p class=\"bad\">") +
            "Against the navigation's own scale of this fused model: z = " +
            Signed(*laser->navigation_z, 2) +
            (laser->navigation_consistent
                 ? " (consistent)."
                 : ": beyond 3 &sigma;, the laser scale and the navigation "
                   "disagree; one of them is wrong.") +
            "</p>\n";
      }
    } else {
      scale_html +=
          "<p class=\"bad\">No laser image was accepted: the model has no "
          "scale from the lasers (see items.csv and images.csv).</p>\n";
    }
    report["scale"] = scale_json;
    if (laser->items) {
      files.Copy(laser->items->Path(), "laser/items.csv");
      scale_html += "<h3>Per laser / pair</h3>\n" +
                    LaserItemsTable(*laser->items) +
                    "<p>Every image's figures: <a href=\"laser/items.csv\">"
                    "laser/items.csv</a>.</p>\n";
    }
    if (laser->segments) {
      files.Copy(laser->segments->Path(), "laser/segments.csv");
      scale_html += "<h3>Per segment along the survey</h3>\n" +
                    SegmentsTable(*laser->segments) +
                    "<p><a href=\"laser/segments.csv\">laser/segments.csv"
                    "</a></p>\n";
    }
    for (const char* name : {"images.csv", "scale.json"}) {
      if (fs::is_regular_file(laser->dir / name)) {
        files.Copy(laser->dir / name, std::string("laser/") + name);
      }
    }
    const std::map<std::string, std::string> captions = {
        {"scales.png",
         "Scale per laser image: nominal value (dot), its 95 % Monte Carlo "
         "interval (bar) and each laser / pair; the horizontal lines are the "
         "model's scale and its 95 % interval."},
        {"histogram.png",
         "Monte Carlo distribution of the model's scale: the spread the "
         "uncertainties of the spots, the features and the calibration "
         "give; the vertical lines are s and its 95 % interval."},
        {"convergence.png",
         "Running mean &plusmn; &sigma; over the Monte Carlo iterations: flat "
         "lines mean enough iterations."}};
    for (const fs::path& plot : laser->plots) {
      const std::string name = plot.filename().string();
      const bool has_svg = files.CopyFigure(plot, "laser/" + name);
      scale_html +=
          HtmlFigure("laser/" + name, name, captions.at(name), has_svg);
    }
    if (laser->overlays.empty()) {
      overlays_html += omit(
          "No spot overlays in the laser report (laserscale estimate "
          "--overlays).");
    } else {
      overlays_html +=
          "<p>Each laser image with its detected spots and their 68 / 95 % "
          "ellipses; click a thumbnail for the full image.</p>\n"
          "<div class=\"thumbs\">\n";
      for (const fs::path& overlay : laser->overlays) {
        const std::string name = overlay.filename().string();
        const cv::Mat image = cv::imread(overlay.string(), cv::IMREAD_COLOR);
        if (image.empty()) {
          throw ErrorAt(overlay.string(), ": cannot decode the image");
        }
        const int width = std::min(options.thumbnail_width_px, image.cols);
        const int height = std::max(
            1, static_cast<int>(std::lround(static_cast<double>(image.rows) *
                                            width / image.cols)));
        cv::Mat thumbnail;
        cv::resize(image, thumbnail, cv::Size(width, height), 0, 0,
                   cv::INTER_AREA);
        const std::string full = "overlays/" + name;
        const std::string thumb =
            "overlays/thumbs/" + overlay.stem().string() + ".jpg";
        files.Copy(overlay, full);
        files.Jpeg(thumb, thumbnail);
        overlays_html += "<a href=\"" + HtmlEscape(full) + "\"><img src=\"" +
                         HtmlEscape(thumb) + "\" alt=\"" + HtmlEscape(name) +
                         "\" title=\"" + HtmlEscape(name) + "\"></a>\n";
      }
      overlays_html += "</div>\n";
    }
  } else {
    scale_html += omit(
        "No scale section: give laserscale estimate's output folder with "
        "--laser_report.");
    overlays_html += omit("No spot overlays: no --laser_report.");
  }

  // ------------------------------------------------------------ navigation
  std::string nav_html = "<h2 id=\"navigation\">Navigation fusion</h2>\n";
  if (ba) {
    Json nav_json = {{"weight_px_per_m", ba->weight_px_per_m},
                     {"weighting", ba->weighting},
                     {"strategy", ba->strategy},
                     {"num_priors", ba->residuals.size()}};
    if (ba->prior_residual_rms_m) {
      nav_json["prior_residual_rms_m"] = *ba->prior_residual_rms_m;
    }
    nav_json["warnings"] = ba->warnings;
    nav_html +=
        "<p>Navigation weight &lambda; = " + Fixed(ba->weight_px_per_m, 4) +
        " px/m (" + HtmlEscape(ba->weighting) + " weighting" +
        (ba->strategy.empty() ? "" : ", strategy " + HtmlEscape(ba->strategy)) +
        ")" +
        (ba->nav_sigma_m ? ", stated navigation &sigma; " +
                               Fixed(*ba->nav_sigma_m, 3) + " m"
                         : std::string()) +
        (ba->prior_residual_rms_m
             ? "; RMS of the prior residuals " +
                   Fixed(*ba->prior_residual_rms_m, 3) + " m"
             : std::string()) +
        ".</p>\n";
    for (const std::string& warning : ba->warnings) {
      nav_html += "<p class=\"bad\">" + HtmlEscape(warning) + "</p>\n";
    }
    if (ba->residuals.empty()) {
      nav_html += omit(
          "ba_report.json has no prior residuals (a BA without "
          "navigation priors).");
    } else {
      std::vector<double> x, norm, x_mahalanobis, mahalanobis;
      std::vector<std::string> names;
      std::vector<std::vector<std::string>> rows;
      std::string csv =
          "image,dive,error_x_m,error_y_m,error_z_m,"
          "error_norm_m,mahalanobis\n";
      for (size_t i = 0; i < ba->residuals.size(); ++i) {
        const BaReportSummary::Residual& r = ba->residuals[i];
        x.push_back(static_cast<double>(i));
        names.push_back(r.name);
        norm.push_back(r.error_norm_m);
        if (r.mahalanobis) {
          x_mahalanobis.push_back(static_cast<double>(i));
          mahalanobis.push_back(*r.mahalanobis);
        }
        const std::string m = r.mahalanobis ? Fixed(*r.mahalanobis, 3) : "";
        rows.push_back({std::to_string(i), r.name, std::to_string(r.dive),
                        Signed(r.error_m.x(), 3), Signed(r.error_m.y(), 3),
                        Signed(r.error_m.z(), 3), Fixed(r.error_norm_m, 3), m});
        csv += CsvField(r.name) + "," + std::to_string(r.dive) + "," +
               Fixed(r.error_m.x(), 6) + "," + Fixed(r.error_m.y(), 6) + "," +
               Fixed(r.error_m.z(), 6) + "," + Fixed(r.error_norm_m, 6) + "," +
               (r.mahalanobis ? Fixed(*r.mahalanobis, 6) : "") + "\n";
      }
      files.Add("prior_residuals.csv", csv);
      Figure norm_plot("Camera centre \u2212 navigation prior, per image",
                       "image", "|e| (m)", 10.0, 4.8);
      norm_plot.ItemAxis(names);
      norm_plot.Bars(x, norm, 0.7, Figure::Colour(0), "|e| per image");
      if (ba->prior_residual_rms_m) {
        norm_plot.HorizontalLine(*ba->prior_residual_rms_m, Figure::Colour(3),
                                 "RMS");
      }
      files.AddFigure("prior_residuals.png", norm_plot);
      nav_html += HtmlFigure(
          "prior_residuals.png", "prior residuals",
          "Distance between each camera centre of the fused model and its "
          "navigation prior (plus its dive's offset). It is the navigation's "
          "error as the images see it: large bars are fixes the images "
          "overruled.",
          true);
      if (!mahalanobis.empty()) {
        Figure m_plot(
            "Prior residual in units of the navigation's stated "
            "uncertainty",
            "image", "Mahalanobis distance", 10.0, 4.8);
        m_plot.ItemAxis(names);
        m_plot.Bars(x_mahalanobis, mahalanobis, 0.7, Figure::Colour(2),
                    "Mahalanobis distance");
        m_plot.HorizontalLine(kMahalanobis95, Figure::Colour(3),
                              "95 % of a correct covariance");
        files.AddFigure("prior_mahalanobis.png", m_plot);
        size_t above = 0;
        for (const double m : mahalanobis) above += m > kMahalanobis95;
        nav_json["num_mahalanobis_above_95"] = above;
        nav_html += HtmlFigure(
            "prior_mahalanobis.png", "prior Mahalanobis distances",
            "The same residuals divided by the navigation's stated covariance "
            "(nav.csv's std columns). With a right covariance, 95 % of the "
            "images stay below the line (" +
                std::to_string(above) + " of " +
                std::to_string(mahalanobis.size()) +
                " are above it here); many more above means the navigation is "
                "worse than it says.",
            true);
      }
      nav_html += "<details><summary>Per image (" +
                  std::to_string(rows.size()) +
                  " images; <a href=\"prior_residuals.csv\">"
                  "prior_residuals.csv</a>)</summary>\n" +
                  HtmlTable({"#", "image", "dive", "e_x (m)", "e_y (m)",
                             "e_z (m)", "|e| (m)", "Mahalanobis"},
                            rows) +
                  "</details>\n";
    }
    std::vector<std::vector<std::string>> offset_rows;
    Json offsets = Json::array();
    for (const BaReportSummary::DiveOffset& offset : ba->dive_offsets) {
      const auto vector = [](const Eigen::Vector3d& v) {
        return "(" + Signed(v.x(), 3) + ", " + Signed(v.y(), 3) + ", " +
               Signed(v.z(), 3) + ")";
      };
      offset_rows.push_back(
          {std::to_string(offset.dive), std::to_string(offset.num_images),
           vector(offset.offset_m),
           offset.sigma_m ? vector(*offset.sigma_m) : "reference"});
      offsets.push_back(
          {{"dive", offset.dive}, {"offset_m", ToJson(offset.offset_m)}});
    }
    nav_json["dive_offsets"] = offsets;
    if (!offset_rows.empty()) {
      nav_html +=
          "<h3>Dive offsets</h3>\n<p>Added to each dive's navigation "
          "(world frame, m); the reference dive's is 0.</p>\n" +
          HtmlTable({"dive", "images", "offset (m)", "1-sigma (m)"},
                    offset_rows);
    }
    files.Copy(inputs.ba_report_path, "ba_report.json");
    report["navigation"] = nav_json;
  } else {
    nav_html += omit(
        "No navigation fusion section: give bundle_adjuster's ba_report.json "
        "with --ba_report.");
  }

  // ----------------------------------------------------------- uncertainty
  std::string uncertainty_html =
      "<h2 id=\"uncertainty\">Uncertainty of the model</h2>\n";
  if (covariance) {
    const CovarianceSummary& c = *covariance;
    Json uncertainty = {
        {"gauge", c.gauge},
        {"pixel_sigma_px", c.pixel_sigma_px},
        {"nav_sigma_scale", c.nav_sigma_scale},
        {"num_images", c.num_images},
        {"num_points", c.num_points},
        {"centre_sigma_m_median", c.centre_sigma_m.median},
        {"centre_sigma_m_max", c.centre_sigma_m.max},
        {"rotation_sigma_deg_median", c.rotation_sigma_deg.median},
        {"warnings", c.warnings}};
    uncertainty_html +=
        "<p>Covariance of the bundle adjustment (uwcolmap "
        "covariance_estimator; docs/covariance.md), gauge <b>" +
        HtmlEscape(c.gauge) + "</b>" +
        (c.gauge_description.empty()
             ? std::string()
             : " (" + HtmlEscape(c.gauge_description) + ")") +
        ": the sigmas are relative to what the gauge holds fixed" +
        (c.gauge == "priors" ? ", here the navigation, so they are absolute"
                             : "") +
        ". Pixel noise " + Fixed(c.pixel_sigma_px, 3) + " px (" +
        HtmlEscape(c.pixel_sigma_source) + ")" +
        (c.gauge == "priors" ? "; navigation sigmas as stated &times; " +
                                   Fixed(c.nav_sigma_scale, 3) + " (" +
                                   HtmlEscape(c.nav_sigma_source) + ")"
                             : std::string()) +
        ".</p>\n";
    // A model no navigation scaled has sigmas in its own units.
    const std::string unit = metric ? "m" : "model units";
    std::vector<std::vector<std::string>> rows = {
        {"camera centre (" + unit + ")", Fixed(c.centre_sigma_m.median, 4),
         Fixed(c.centre_sigma_m.p95, 4), Fixed(c.centre_sigma_m.max, 4)},
        {"camera rotation (deg)", Fixed(c.rotation_sigma_deg.median, 3),
         Fixed(c.rotation_sigma_deg.p95, 3),
         Fixed(c.rotation_sigma_deg.max, 3)}};
    if (c.point_sigma_m) {
      rows.push_back({"point, largest axis (" + unit + ")",
                      Fixed(c.point_sigma_m->median, 4),
                      Fixed(c.point_sigma_m->p95, 4),
                      Fixed(c.point_sigma_m->max, 4)});
      uncertainty["point_sigma_m_median"] = c.point_sigma_m->median;
      uncertainty["num_weak_points"] = c.num_weak_points;
    }
    uncertainty_html +=
        HtmlTable({"1-sigma of", "median", "95 %", "max"}, rows) + "<p>" +
        std::to_string(c.num_images) + " images, " +
        std::to_string(c.num_points) + " points" +
        (c.point_sigma_m ? ", " + std::to_string(c.num_weak_points) +
                               " weak points (largest-axis sigma above 3x "
                               "the median)"
                         : std::string()) +
        ".</p>\n";
    for (const std::string& warning : c.warnings) {
      // The adjuster's own (a single pass) are shown with the navigation.
      if (ba && std::find(ba->warnings.begin(), ba->warnings.end(), warning) !=
                    ba->warnings.end()) {
        continue;
      }
      uncertainty_html += "<p class=\"bad\">" + HtmlEscape(warning) + "</p>\n";
    }
    if (c.num_samples > 0) {
      uncertainty["num_samples"] = c.num_samples;
      uncertainty["log_scale_sigma"] = c.log_scale_sigma;
      uncertainty_html +=
          "<p>" + std::to_string(c.num_samples) +
          " joint draws of the model's error (samples.bin) for the laser "
          "scale's Monte Carlo; their scale spreads by " +
          Fixed(100.0 * c.log_scale_sigma, 2) + " % (" +
          HtmlEscape(c.log_scale_meaning) + ").</p>\n";
    }
    // The least certain images first: where the model is weakest.
    std::vector<size_t> order(c.cameras.NumRows());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return c.cameras.Double(a, "sigma_position_m") >
             c.cameras.Double(b, "sigma_position_m");
    });
    std::vector<std::vector<std::string>> worst;
    for (size_t k = 0; k < std::min<size_t>(10, order.size()); ++k) {
      const size_t i = order[k];
      worst.push_back({HtmlEscape(c.cameras.Text(i, "name")),
                       c.cameras.Text(i, "held") == "1" ? "held" : "",
                       c.cameras.Text(i, "num_points"),
                       Fixed(c.cameras.Double(i, "sigma_position_m"), 4),
                       Fixed(c.cameras.Double(i, "sigma_rotation_deg"), 3)});
    }
    uncertainty_html +=
        "<h3>Least certain images</h3>\n" +
        HtmlTable({"image", "gauge", "points", "centre 1-sigma (" + unit + ")",
                   "rotation 1-sigma (deg)"},
                  worst) +
        "<p>Every image: <a href=\"uncertainty/cameras.csv\">"
        "uncertainty/cameras.csv</a>.</p>\n";
    files.Copy(c.cameras.Path(), "uncertainty/cameras.csv");
    files.Copy(c.dir / "covariance.json", "uncertainty/covariance.json");
    if (c.map) {
      const bool has_svg =
          files.CopyFigure(*c.map, "uncertainty/uncertainty_map.png");
      uncertainty_html += HtmlFigure(
          "uncertainty/uncertainty_map.png", "uncertainty map",
          "The points in plan view (model x, y) in three classes of their "
          "largest-axis sigma against the median (grey: at most the median; "
          "orange: up to 3x; red: weak, above 3x), the cameras on top. Weak "
          "points gather where few images see them (the survey's edges) or "
          "their baselines are short. Coverage gaps, places inside the "
          "survey where the model has no point, are marked in magenta "
          "(docs/covariance.md, \"Map\").",
          has_svg);
    }
    report["uncertainty"] = uncertainty;
  } else {
    uncertainty_html += omit(
        "No uncertainty section: give uwcolmap covariance_estimator's output "
        "folder (or bundle_adjuster --BA.covariance 1's OUTPUT/covariance) "
        "with --covariance.");
  }

  // --------------------------------------------------------- stock vs ours
  std::string compare_html =
      "<h2 id=\"compare\">Stock colmap against uwmetric</h2>\n";
  if (compare_table) {
    const std::map<std::string, std::string> headers = {
        {"method", "method"},
        {"abs_rmse_m", "camera RMSE as delivered (m)"},
        {"sim_rmse_m", "camera RMSE after a similarity (m)"},
        {"sim_percent_of_extent", "... % of the extent"},
        {"scale_error_percent", "scale error (%)"},
        {"surface_rms_m", "surface RMS (m)"},
        {"sagitta_m", "doming sagitta (m)"},
        {"time_s", "time (s)"}};
    std::vector<std::string> header;
    for (const std::string& column : compare_table->Header()) {
      const auto found = headers.find(column);
      header.push_back(found == headers.end() ? column : found->second);
    }
    compare_html +=
        "<p>Each method's model against the truth (uwsim) or the reference "
        "it was compared with (scripts/compare_with_colmap.sh). \"As "
        "delivered\": the model in the frame the method gives it; \"after a "
        "similarity\": after the best rotation, translation and scale onto "
        "the truth, which shows the shape alone. Sagitta &lt; 0 is a "
        "dome.</p>\n" +
        HtmlTable(header, compare_table->Rows()) +
        "<p><a href=\"compare_table.csv\">compare_table.csv</a></p>\n";
    files.Copy(inputs.compare_table_path, "compare_table.csv");
  } else {
    compare_html += omit(
        "No comparison with stock colmap: give compare_with_colmap.sh's "
        "table.csv with --compare_table.");
  }

  // ----------------------------------------------------------------- dense
  std::string dense_html = "<h2 id=\"dense\">Dense surface</h2>\n";
  if (mesh) {
    const double area = MeshArea(*mesh);
    dense_html += "<p>" + std::to_string(mesh->vertices.size()) +
                  " vertices, " + std::to_string(mesh->triangles.size()) +
                  " triangles, " + Fixed(area, 2) +
                  " square model units (m for a metric model).</p>\n";
    report["dense_mesh"] = {{"num_vertices", mesh->vertices.size()},
                            {"num_triangles", mesh->triangles.size()},
                            {"area", area}};
  }
  if (dense) {
    const DenseComparisonSummary& d = *dense;
    dense_html += HtmlTable(
        {"against the true surface", "value"},
        {{"camera-scene distance D (m)", Fixed(d.camera_scene_distance, 3)},
         {"median distance (mm)", Fixed(1000.0 * d.median_distance, 2)},
         {"median / D (%)",
          Fixed(100.0 * d.median_distance / d.camera_scene_distance, 3)},
         {"90th percentile (mm)", Fixed(1000.0 * d.p90_distance, 2)},
         {"RMS (mm)", Fixed(1000.0 * d.rms_distance, 2)},
         {"mean signed (mm, + in front)",
          Signed(1000.0 * d.mean_signed_distance, 2)},
         {"observed area (m2)", Fixed(d.observed_area, 2)},
         {"covered area (m2)", Fixed(d.covered_area, 2)},
         {"coverage (%)", Fixed(100.0 * d.coverage, 1)},
         {"coverage tolerance (mm)", Fixed(1000.0 * d.coverage_tolerance, 1)},
         {"samples", std::to_string(d.num_samples)}});
    report["dense_surface"] = {
        {"camera_scene_distance_m", d.camera_scene_distance},
        {"median_distance_m", d.median_distance},
        {"p90_distance_m", d.p90_distance},
        {"rms_distance_m", d.rms_distance},
        {"mean_signed_distance_m", d.mean_signed_distance},
        {"coverage", d.coverage},
        {"observed_area_m2", d.observed_area}};
    files.Copy(inputs.dense_comparison_path, "dense_compare.json");
  }
  if (mesh && truth && fs::is_regular_file(truth->mesh_path)) {
    const TriangleMesh true_mesh = ReadPly(truth->mesh_path);
    const MeshDistance true_surface(true_mesh.vertices, true_mesh.triangles);
    const TriangleMesh aligned = TransformMesh(truth->true_from_model, *mesh);
    const size_t stride = std::max<size_t>(
        1, (aligned.vertices.size() + options.max_histogram_vertices - 1) /
               options.max_histogram_vertices);
    std::vector<double> millimetres;
    for (size_t i = 0; i < aligned.vertices.size(); i += stride) {
      millimetres.push_back(1000.0 *
                            true_surface.Query(aligned.vertices[i]).distance);
    }
    const double median = Median(millimetres);
    // The few vertices of a fringe far from the truth would squeeze the
    // histogram into a bar or two: they are counted in the caption instead.
    std::vector<double> sorted = millimetres;
    std::sort(sorted.begin(), sorted.end());
    const double p99 = sorted[(sorted.size() - 1) * 99 / 100];
    std::vector<double> shown;
    for (const double d : millimetres) {
      if (d <= p99) shown.push_back(d);
    }
    Figure histogram("Dense mesh vertices: distance to the true surface",
                     "distance (mm)", "vertices", 10.0, 4.8);
    histogram.Histogram(shown, 50, Figure::Colour(0));
    histogram.VerticalLine(median, Figure::Colour(3), "median");
    files.AddFigure("dense_distance_histogram.png", histogram);
    dense_html += HtmlFigure(
        "dense_distance_histogram.png", "dense mesh distance histogram",
        "Distance from " + std::to_string(millimetres.size()) +
            " mesh vertices to the true surface, after the camera-centre "
            "similarity onto the true cameras (no fit of the surface itself; "
            "median " +
            Fixed(median, 2) + " mm; the " +
            std::to_string(millimetres.size() - shown.size()) +
            " beyond the 99th percentile, " + Fixed(p99, 2) +
            " mm, are not drawn). The table's figures use area-uniform "
            "samples instead of vertices.",
        true);
  }
  if (!mesh && !dense) {
    dense_html += omit(
        "No dense surface section: give the mesh with --mesh and "
        "model_comparer's compare.json with --dense_comparison.");
  } else if (!dense) {
    dense_html += omit(
        "No accuracy or coverage: give model_comparer --dense_mesh_path's "
        "compare.json with --dense_comparison.");
  }

  // ------------------------------------------------------------------ time
  std::string time_html = "<h2 id=\"time\">Time per stage</h2>\n";
  std::optional<double> total_s;
  if (!timings.empty()) {
    double sum = 0.0;
    for (const StageTime& stage : timings) {
      if (stage.stage == "total") {
        total_s = stage.seconds;
      } else {
        sum += stage.seconds;
      }
    }
    if (!total_s) total_s = sum;
    std::string table =
        "<table>\n<tr><th>stage</th><th>seconds</th><th>share</th></tr>\n";
    Json stages = Json::array();
    for (const StageTime& stage : timings) {
      const double share =
          *total_s > 0.0 ? std::min(1.0, stage.seconds / *total_s) : 0.0;
      table += "<tr><td>" + HtmlEscape(stage.stage) + "</td><td>" +
               Fixed(stage.seconds, 0) +
               "</td><td style=\"text-align:left\"><div style=\"background:"
               "#2a6f97;height:0.8em;width:" +
               Fixed(200.0 * share, 0) + "px\"></div></td></tr>\n";
      stages.push_back({{"stage", stage.stage}, {"seconds", stage.seconds}});
    }
    time_html += table +
                 "</table>\n<p>The stages not listed (the analyses "
                 "and comparisons between them) make up the "
                 "rest of the total.</p>\n";
    files.Copy(inputs.timings_path, "timings.csv");
    report["timings"] = stages;
    report["total_time_s"] = *total_s;
  } else {
    time_html += omit("No timings: give timings.csv with --timings.");
  }

  // --------------------------------------------------------------- summary
  std::vector<std::vector<std::string>> summary;
  // A log sampled at its own rate names no images: its rows are samples,
  // not images (4484 rows for 25 images on a BlueROV2 dive).
  std::set<std::string> navigation_images;
  for (const NavRecord& record : navigation) {
    if (!record.image_name.empty()) navigation_images.insert(record.image_name);
  }
  const std::string registered = std::to_string(images.size()) + " registered";
  summary.push_back(
      {"Images",
       navigation.empty() ? registered
       : navigation_images.empty()
           ? registered + "; the navigation: " +
                 std::to_string(navigation.size()) + " samples, no image names"
           : registered + " of " + std::to_string(navigation_images.size()) +
                 " images in the navigation"});
  summary.push_back({"Sparse points", std::to_string(model.Points3D().size())});
  report["images"] = {{"registered", images.size()},
                      {"navigation_rows", navigation.size()},
                      {"navigation_images", navigation_images.size()},
                      {"points3D", model.Points3D().size()}};
  if (laser && laser->scale) {
    summary.push_back({"Scale s (multiply by s for metres)",
                       Fixed(*laser->scale, 5) + ", 95 % interval [" +
                           Fixed(laser->ci95_low, 5) + ", " +
                           Fixed(laser->ci95_high, 5) + "]"});
  } else {
    summary.push_back({"Scale s", laser ? "none (no laser image accepted)"
                                        : "not given (--laser_report)"});
  }
  if (truth) {
    Json truth_json = {{"scale", truth->scale},
                       {"camera_rmse_m", truth->camera_rmse_m},
                       {"num_common_images", truth->num_common_images}};
    summary.push_back({"Camera RMSE against the truth (after a similarity)",
                       Fixed(1000.0 * truth->camera_rmse_m, 2) + " mm over " +
                           std::to_string(truth->num_common_images) +
                           " images"});
    if (laser && laser->scale) {
      const double error = *laser->scale / truth->scale - 1.0;
      const bool inside =
          laser->ci95_low <= truth->scale && truth->scale <= laser->ci95_high;
      summary.push_back(
          {"Scale error against the truth",
           Signed(100.0 * error, 3) + " % (true s = " + Fixed(truth->scale, 5) +
               ", " + (inside ? "inside" : "OUTSIDE") + " the 95 % interval)"});
      truth_json["scale_error"] = error;
      truth_json["inside_ci95"] = inside;
    }
    report["truth"] = truth_json;
  }
  if (dense) {
    summary.push_back(
        {"Dense mesh accuracy",
         "median " + Fixed(1000.0 * dense->median_distance, 2) + " mm (" +
             Fixed(
                 100.0 * dense->median_distance / dense->camera_scene_distance,
                 3) +
             " % of the " + Fixed(dense->camera_scene_distance, 2) +
             " m camera-scene distance)"});
    summary.push_back(
        {"Dense mesh coverage", Fixed(100.0 * dense->coverage, 1) + " % of " +
                                    Fixed(dense->observed_area, 1) +
                                    " m2 seen by at least two images"});
  }
  if (ba) {
    summary.push_back({"Navigation weight lambda",
                       Fixed(ba->weight_px_per_m, 4) + " px/m" +
                           (ba->prior_residual_rms_m
                                ? ", prior residual RMS " +
                                      Fixed(*ba->prior_residual_rms_m, 3) + " m"
                                : std::string())});
  }
  if (total_s) {
    summary.push_back({"Total time", Fixed(*total_s, 0) + " s"});
  }
  std::string summary_html = "<div class=\"summary\"><table>\n";
  for (const auto& row : summary) {
    summary_html += "<tr><td><b>" + HtmlEscape(row[0]) + "</b></td><td>" +
                    HtmlEscape(row[1]) + "</td></tr>\n";
  }
  summary_html += "</table></div>\n";

  // ------------------------------------------------------- how to read it
  const std::string read_html =
      "<h2 id=\"read\">How to read this report</h2>\n<ul>\n"
      "<li><b>Scale s.</b> The model's lengths times s are metres. The 95 % "
      "interval is where the true scale lies with 95 % probability, given "
      "the uncertainties the Monte Carlo propagates: spot centres, feature "
      "positions, laser calibration. It does not include errors nobody "
      "modelled; a Birge ratio above 1 says the images disagree more than "
      "those uncertainties explain, and the interval was widened by it. "
      "Segments with intervals that do not overlap mean the scale drifts "
      "along the survey.</li>\n"
      "<li><b>Scale error against the truth.</b> Only with a synthetic survey "
      "(uwsim): s divided by the scale of the similarity that takes the model "
      "onto the true cameras, minus 1.</li>\n"
      "<li><b>Prior residuals.</b> Camera centre minus navigation fix. In "
      "metres they show the navigation's error as the images see it; divided "
      "by the navigation's stated uncertainty (Mahalanobis distance) they "
      "test that uncertainty: about 5 % of the images should exceed the "
      "95 % line.</li>\n"
      "<li><b>&lambda;</b> weighs a metre of navigation error against a "
      "pixel of reprojection error; it is estimated from both noise levels "
      "(docs/uwcolmap.md#bundle_adjuster).</li>\n"
      "<li><b>Dense mesh accuracy</b> is the distance from the mesh to the "
      "true surface; <b>coverage</b> the share of the surface at least two "
      "images saw that the mesh reproduces within the tolerance.</li>\n"
      "<li><b>Doming sagitta</b>: the height of a bowl fitted to the surface "
      "error along the track; negative is a dome, the classic failure of "
      "self-calibrated surveys along a single line.</li>\n"
      "<li>Every figure's numbers are in the CSV and JSON files below; "
      "report.json holds the key figures.</li>\n</ul>\n";

  // ----------------------------------------------------------------- files
  // Listed now, written last: report.json lists every file.
  files.DrawFigures();
  files.Add("report.json", "");
  std::string files_html = "<h2 id=\"files\">Files</h2>\n<ul>\n";
  for (const std::string& name : files.Names()) {
    files_html += "<li><a href=\"" + HtmlEscape(name) + "\">" +
                  HtmlEscape(name) + "</a></li>\n";
  }
  files_html += "<li>inputs: model " + HtmlEscape(inputs.model_path.string()) +
                "</li>\n</ul>\n";

  const std::string body =
      "<h1>" + HtmlEscape(options.title) + "</h1>\n<p>Model <code>" +
      HtmlEscape(inputs.model_path.string()) +
      "</code>. Sections: <a href=\"#map\">map</a> &middot; <a "
      "href=\"#scale\">scale</a> &middot; <a href=\"#overlays\">laser "
      "spots</a> &middot; <a href=\"#navigation\">navigation</a> &middot; "
      "<a href=\"#uncertainty\">uncertainty</a> &middot; "
      "<a href=\"#compare\">stock colmap vs ours</a> &middot; <a "
      "href=\"#dense\">dense surface</a> &middot; <a href=\"#time\">time</a> "
      "&middot; <a href=\"#read\">how to read it</a></p>\n" +
      summary_html + map_html + scale_html + overlays_html + nav_html +
      uncertainty_html + compare_html + dense_html + time_html + read_html +
      files_html;
  const std::string html = HtmlPage(options.title, body);
  files.Add("index.html", html);

  result.index_path = output_dir / "index.html";
  result.num_images = ImageSources(html).size();
  result.files = files.Names();
  report["omitted"] = result.omitted;
  report["files"] = result.files;
  report["num_images_in_index"] = result.num_images;
  files.Replace("report.json", report.dump(2) + "\n");
  files.Write();
  return result;
}

}  // namespace uw
