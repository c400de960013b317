#include "laserscale/scale_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/util/csv.h"
#include "common/util/error.h"
#include "common/util/figure.h"
#include "common/util/file.h"
#include "common/util/html.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

constexpr char kFormat[] = "uwmetric-laser-scale";
constexpr int kVersion = 1;

// Iteration by iteration, the weighted mean of the runs' valid scales (NaN
// where none is valid); runs[k] has weights[k].
std::vector<double> WeightedPerIteration(
    const std::vector<const std::vector<double>*>& runs,
    const std::vector<double>& weights) {
  std::vector<double> combined(runs.front()->size());
  for (size_t n = 0; n < combined.size(); ++n) {
    double sum = 0.0;
    double used = 0.0;
    for (size_t k = 0; k < runs.size(); ++k) {
      const double s = (*runs[k])[n];
      if (std::isnan(s)) continue;
      sum += weights[k] * s;
      used += weights[k];
    }
    combined[n] = used > 0.0 ? sum / used : std::nan("");
  }
  return combined;
}

CombinedScale Combine(const std::vector<ImageEstimate>& images,
                      const std::vector<size_t>& members) {
  CombinedScale combined;
  combined.images = members;
  if (members.empty()) return combined;
  // Inverse-variance weights; equal weights when an image has no spread
  // (noise-free inputs), where every image is equally exact.
  std::vector<double> weights;
  bool all_spread = true;
  for (const size_t i : members) {
    all_spread = all_spread && images[i].result->monte_carlo.std_dev > 0.0;
  }
  for (const size_t i : members) {
    const double sigma = images[i].result->monte_carlo.std_dev;
    weights.push_back(all_spread ? 1.0 / (sigma * sigma) : 1.0);
  }
  double weight_sum = 0.0;
  double nominal = 0.0;
  for (size_t k = 0; k < members.size(); ++k) {
    nominal += weights[k] * *images[members[k]].result->nominal;
    weight_sum += weights[k];
  }
  nominal /= weight_sum;
  combined.nominal = nominal;
  std::vector<const std::vector<double>*> runs;
  for (const size_t i : members)
    runs.push_back(&images[i].result->per_iteration);
  combined.per_iteration = WeightedPerIteration(runs, weights);
  combined.monte_carlo = Summarize(combined.per_iteration);
  if (members.size() >= 2 && all_spread) {
    double chi2 = 0.0;
    for (size_t k = 0; k < members.size(); ++k) {
      const double d = *images[members[k]].result->nominal - nominal;
      chi2 += weights[k] * d * d;
    }
    combined.birge_ratio = std::sqrt(chi2 / (members.size() - 1.0));
  }
  // Each source sampled alone, combined with the same weights.
  for (const auto& first_run : images[members[0]].result->per_source) {
    const ScaleSource source = first_run.first;
    std::vector<const std::vector<double>*> source_runs;
    for (const size_t i : members) {
      for (const auto& run : images[i].result->per_source) {
        if (run.first == source) source_runs.push_back(&run.second);
      }
    }
    if (source_runs.size() != members.size()) continue;  // not in every one
    combined.source_sigmas.emplace_back(
        source, Summarize(WeightedPerIteration(source_runs, weights)).std_dev);
  }
  const double widen = std::max(1.0, combined.birge_ratio);
  const SampleSummary& mc = combined.monte_carlo;
  combined.sigma = widen * mc.std_dev;
  combined.ci95_low = nominal - widen * (mc.p50 - mc.p2_5);
  combined.ci95_high = nominal + widen * (mc.p97_5 - mc.p50);
  return combined;
}

nlohmann::json SummaryJson(const SampleSummary& s) {
  return {{"num_samples", s.num_samples},
          {"mean", s.mean},
          {"std", s.std_dev},
          {"p2_5", s.p2_5},
          {"p16", s.p16},
          {"p50", s.p50},
          {"p84", s.p84},
          {"p97_5", s.p97_5}};
}

nlohmann::json CombinedJson(const CombinedScale& c,
                            const std::vector<ImageEstimate>& images) {
  nlohmann::json names = nlohmann::json::array();
  for (const size_t i : c.images) names.push_back(images[i].name);
  nlohmann::json json = {
      {"scale", c.nominal ? nlohmann::json(*c.nominal) : nlohmann::json()},
      {"sigma", c.sigma},
      {"ci95", {c.ci95_low, c.ci95_high}},
      {"birge_ratio", c.birge_ratio},
      {"monte_carlo", SummaryJson(c.monte_carlo)},
      {"images", names}};
  if (!c.source_sigmas.empty()) {
    nlohmann::json shares = nlohmann::json::object();
    for (const auto& [source, sigma] : c.source_sigmas) {
      shares[ScaleSourceName(source)] = {{"sigma", sigma},
                                         {"share", c.VarianceShare(sigma)}};
    }
    json["variance_by_source"] = shares;
  }
  return json;
}

std::string Percent(double scale) {
  return fmt::format("{:+.3f} %", 100.0 * (scale - 1.0));
}

std::string Fixed(double value, int digits = 5) {
  return fmt::format("{:.{}f}", value, digits);
}

// mean, std, p2.5, p97.5; empty fields without samples.
std::string SummaryCsv(const SampleSummary& s) {
  if (s.num_samples == 0) return ",,,";
  return Fixed(s.mean, 7) + "," + Fixed(s.std_dev, 7) + "," + Fixed(s.p2_5, 7) +
         "," + Fixed(s.p97_5, 7);
}

}  // namespace

double CombinedScale::VarianceShare(double source_sigma) const {
  const double variance = monte_carlo.std_dev * monte_carlo.std_dev;
  return variance > 0.0 ? source_sigma * source_sigma / variance : 0.0;
}

std::optional<NavigationScaleCheck> CheckAgainstNavigation(
    const CombinedScale& scale, double log_scale_sigma) {
  const double sigma =
      std::sqrt(scale.sigma * scale.sigma + log_scale_sigma * log_scale_sigma);
  // Without any uncertainty on either side there is no test to make.
  if (!scale.nominal || !(sigma > 0.0)) return std::nullopt;
  NavigationScaleCheck check;
  check.log_scale_sigma = log_scale_sigma;
  check.z = (*scale.nominal - 1.0) / sigma;
  check.consistent = std::abs(check.z) <= 3.0;
  return check;
}

void CombineOptions::Check() const {
  if (!(segment_radius > 0.0) || !std::isfinite(segment_radius)) {
    throw ErrorAt("segment_radius must be > 0, got ", segment_radius);
  }
}

ModelScaleReport CombineImages(std::vector<ImageEstimate> images,
                               ScaleMethod method,
                               const MonteCarloOptions& monte_carlo,
                               const CombineOptions& options) {
  options.Check();
  ModelScaleReport report;
  report.method = method;
  report.monte_carlo = monte_carlo;
  report.images = std::move(images);
  std::vector<size_t> accepted;
  for (size_t i = 0; i < report.images.size(); ++i) {
    const ImageEstimate& image = report.images[i];
    if (image.result && image.result->accepted && image.result->nominal &&
        image.result->monte_carlo.num_samples > 0) {
      accepted.push_back(i);
    }
  }
  report.model = Combine(report.images, accepted);
  // Leader clustering of the images' hits: the first image out of reach of
  // every segment starts one; a segment's centre is its members' mean.
  std::vector<std::vector<size_t>> members;
  for (const size_t i : accepted) {
    if (!report.images[i].hit_centroid) continue;
    const Eigen::Vector3d& at = *report.images[i].hit_centroid;
    bool placed = false;
    for (size_t s = 0; s < members.size() && !placed; ++s) {
      if ((report.segments[s].centre - at).norm() <= options.segment_radius) {
        members[s].push_back(i);
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (const size_t m : members[s]) sum += *report.images[m].hit_centroid;
        report.segments[s].centre =
            sum / static_cast<double>(members[s].size());
        placed = true;
      }
    }
    if (!placed) {
      members.push_back({i});
      Segment segment;
      segment.centre = at;
      report.segments.push_back(segment);
    }
  }
  for (size_t s = 0; s < members.size(); ++s) {
    report.segments[s].scale = Combine(report.images, members[s]);
  }
  return report;
}

std::string ScaleJsonText(const ModelScaleReport& report) {
  nlohmann::json images = nlohmann::json::array();
  for (const ImageEstimate& image : report.images) {
    nlohmann::json entry = {{"name", image.name}};
    if (!image.result) {
      entry["accepted"] = false;
      entry["rejection"] = image.problem;
      images.push_back(entry);
      continue;
    }
    const ImageScaleResult& r = *image.result;
    entry["accepted"] = r.accepted;
    entry["rejection"] = r.rejection;
    entry["model_draws"] = r.num_model_draws;
    if (!r.model_note.empty()) entry["model_note"] = r.model_note;
    entry["nominal"] =
        r.nominal ? nlohmann::json(*r.nominal) : nlohmann::json();
    entry["monte_carlo"] = SummaryJson(r.monte_carlo);
    if (image.hit_centroid) entry["hit_centroid"] = ToJson(*image.hit_centroid);
    nlohmann::json items = nlohmann::json::array();
    for (const ItemResult& item : r.items) {
      items.push_back(
          {{"item", item.item.name},
           {"nominal", item.nominal.scale ? nlohmann::json(*item.nominal.scale)
                                          : nlohmann::json()},
           {"problem", item.nominal.problem},
           {"monte_carlo", SummaryJson(item.monte_carlo)},
           {"num_invalid", item.num_invalid},
           {"first_invalid_reason", item.first_problem}});
    }
    entry["items"] = items;
    images.push_back(entry);
  }
  nlohmann::json segments = nlohmann::json::array();
  for (const Segment& segment : report.segments) {
    nlohmann::json entry = CombinedJson(segment.scale, report.images);
    entry["centre"] = ToJson(segment.centre);
    segments.push_back(entry);
  }
  nlohmann::json json = CombinedJson(report.model, report.images);
  json["format"] = kFormat;
  json["version"] = kVersion;
  json["convention"] =
      "s = m / m_hat: multiply the model by s to get metres; a metric "
      "model's scale error is s - 1";
  json["method"] = ScaleMethodName(report.method);
  json["num_iterations"] = report.monte_carlo.num_iterations;
  json["seed"] = report.monte_carlo.seed;
  json["num_images"] = report.images.size();
  json["num_accepted"] = report.model.images.size();
  json["model_draws"] = {
      {"count", report.num_model_draws},
      {"gauge", report.model_gauge},
      {"meaning",
       report.num_model_draws > 0
           ? "the model's intrinsics, points and surface re-sampled from "
             "the bundle adjustment's covariance (deformation only)"
           : "none: the model was taken as exact, so its own error is not "
             "in the interval (laserscale estimate --covariance)"}};
  if (report.navigation) {
    const NavigationScaleCheck& check = *report.navigation;
    json["navigation"] = {{"log_scale_sigma", check.log_scale_sigma},
                          {"z", check.z},
                          {"consistent", check.consistent},
                          {"meaning",
                           "z = (s - 1) / sqrt(sigma^2 + log_scale_sigma^2):"
                           " the laser scale against the navigation's own "
                           "scale of the fused model; |z| > 3: one is wrong"}};
  }
  json["segments"] = segments;
  json["per_image"] = images;
  return json.dump(2) + "\n";
}

void WriteScaleReport(const ModelScaleReport& report,
                      const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const CombinedScale& model = report.model;
  // Figures.
  std::vector<Figure> figures;
  std::vector<std::string> figure_names;
  Figure scales("Scale per image: nominal, 95 % Monte Carlo interval, items",
                "laser image", "scale s", 10.0, 5.2);
  std::vector<std::string> names;
  std::vector<double> x, nominal, low, high, item_x, item_y;
  for (size_t i = 0; i < report.images.size(); ++i) {
    const ImageEstimate& image = report.images[i];
    names.push_back(image.name);
    if (!image.result || !image.result->nominal) continue;
    const ImageScaleResult& r = *image.result;
    x.push_back(static_cast<double>(i));
    nominal.push_back(*r.nominal);
    low.push_back(r.monte_carlo.p2_5);
    high.push_back(r.monte_carlo.p97_5);
    for (const ItemResult& item : r.items) {
      if (!item.nominal.scale) continue;
      item_x.push_back(static_cast<double>(i) + 0.15);
      item_y.push_back(*item.nominal.scale);
    }
  }
  scales.ItemAxis(names);
  scales.ErrorBars(x, low, high, Figure::Colour(0), "image 95 % interval");
  scales.Points(x, nominal, Figure::Colour(3), "image nominal");
  scales.Points(item_x, item_y, Figure::Colour(2), "laser / pair nominal");
  if (model.nominal) {
    scales.HorizontalLine(*model.nominal, Figure::Colour(1), "model scale");
    scales.HorizontalLine(model.ci95_low, Figure::Colour(7), "model 95 % CI");
    scales.HorizontalLine(model.ci95_high, Figure::Colour(7));
  }
  figures.push_back(scales);
  figure_names.push_back("scales");
  if (model.monte_carlo.num_samples > 0) {
    Figure histogram("Monte Carlo distribution of the model's scale", "scale s",
                     "iterations", 7.0, 4.5);
    histogram.Histogram(model.per_iteration, 40, Figure::Colour(0));
    histogram.VerticalLine(*model.nominal, Figure::Colour(1), "scale");
    histogram.VerticalLine(model.ci95_low, Figure::Colour(7), "95 % CI");
    histogram.VerticalLine(model.ci95_high, Figure::Colour(7));
    figures.push_back(histogram);
    figure_names.push_back("histogram");
    Figure convergence("Monte Carlo convergence (running mean \u00b1 \u03c3)",
                       "iterations", "scale s", 7.0, 4.5);
    std::vector<double> n, mean, minus, plus;
    double sum = 0.0, squares = 0.0;
    size_t count = 0;
    for (size_t k = 0; k < model.per_iteration.size(); ++k) {
      const double s = model.per_iteration[k];
      if (!std::isnan(s)) {
        sum += s;
        squares += s * s;
        ++count;
      }
      if (count < 2 || (k + 1) % 25 != 0) continue;
      const double m = sum / count;
      const double sd =
          std::sqrt(std::max(0.0, (squares - count * m * m) / (count - 1.0)));
      n.push_back(static_cast<double>(k + 1));
      mean.push_back(m);
      minus.push_back(m - sd);
      plus.push_back(m + sd);
    }
    convergence.Line(n, mean, Figure::Colour(0), "mean");
    convergence.Line(n, minus, Figure::Colour(2), "mean \u2212 \u03c3");
    convergence.Line(n, plus, Figure::Colour(2), "mean + \u03c3");
    figures.push_back(convergence);
    figure_names.push_back("convergence");
  }
  // Tables.
  std::ostringstream images_csv;
  images_csv << "image,accepted,rejection,nominal,mc_mean,mc_std,p2_5,p97_5,"
                "num_samples\n";
  std::ostringstream items_csv;
  items_csv << "image,item,nominal,problem,mc_mean,mc_std,p2_5,p97_5,"
               "num_invalid\n";
  for (const ImageEstimate& image : report.images) {
    if (!image.result) {
      images_csv << CsvField(image.name) << ",0," << CsvField(image.problem)
                 << ",,,,,,0\n";
      continue;
    }
    const ImageScaleResult& r = *image.result;
    const SampleSummary& mc = r.monte_carlo;
    images_csv << CsvField(image.name) << "," << r.accepted << ","
               << CsvField(r.rejection) << ","
               << (r.nominal ? Fixed(*r.nominal, 7) : "") << ","
               << SummaryCsv(mc) << "," << mc.num_samples << "\n";
    for (const ItemResult& item : r.items) {
      const SampleSummary& s = item.monte_carlo;
      items_csv << CsvField(image.name) << "," << CsvField(item.item.name)
                << ","
                << (item.nominal.scale ? Fixed(*item.nominal.scale, 7) : "")
                << "," << CsvField(item.nominal.problem) << "," << SummaryCsv(s)
                << "," << item.num_invalid << "\n";
    }
  }
  std::ostringstream segments_csv;
  segments_csv << "segment,x,y,z,num_images,scale,sigma,ci95_low,ci95_high,"
                  "birge_ratio\n";
  for (size_t s = 0; s < report.segments.size(); ++s) {
    const Segment& segment = report.segments[s];
    segments_csv << s + 1 << "," << segment.centre.x() << ","
                 << segment.centre.y() << "," << segment.centre.z() << ","
                 << segment.scale.images.size() << ","
                 << Fixed(*segment.scale.nominal, 7) << ","
                 << Fixed(segment.scale.sigma, 7) << ","
                 << Fixed(segment.scale.ci95_low, 7) << ","
                 << Fixed(segment.scale.ci95_high, 7) << ","
                 << Fixed(segment.scale.birge_ratio, 3) << "\n";
  }
  // The page.
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>"
          "laserscale report</title><style>body{font-family:sans-serif;"
          "margin:2em;max-width:1100px}table{border-collapse:collapse}"
          "td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}"
          "td:first-child{text-align:left}.bad{color:#b00}</style></head>"
          "<body>\n<h1>Scale of the model from laser images</h1>\n";
  if (model.nominal) {
    html << "<p><b>Scale s = " << Fixed(*model.nominal) << "</b>, 95 % "
         << "interval [" << Fixed(model.ci95_low) << ", "
         << Fixed(model.ci95_high) << "], &sigma; = " << Fixed(model.sigma)
         << " (scale error of a metric model s &minus; 1 = "
         << Percent(*model.nominal) << "), from " << model.images.size()
         << " of " << report.images.size() << " laser images, method "
         << ScaleMethodName(report.method) << ", "
         << report.monte_carlo.num_iterations
         << " Monte Carlo iterations. Multiply the model by s to get metres "
            "(<code>laserscale apply</code>).</p>\n";
    if (model.birge_ratio > 1.0) {
      html << "<p class=\"bad\">The images disagree more than their "
              "uncertainties allow (Birge ratio "
           << Fixed(model.birge_ratio, 2)
           << "); the interval is widened by it. A scale that varies along "
              "the model (see the segments) or an unmodelled error.</p>\n";
    }
    if (report.num_model_draws > 0) {
      html << "<p>The model's own error is in the interval: "
           << report.num_model_draws << " draws of its covariance (gauge "
           << HtmlEscape(report.model_gauge)
           << ") re-sample its intrinsics, points and surface.</p>\n";
    } else {
      html << "<p class=\"bad\">The model was taken as exact (no "
              "<code>--covariance</code>): its own error, often the largest "
              "source, is not in the interval.</p>\n";
    }
    if (!model.source_sigmas.empty()) {
      html << "<p>Share of the variance, each source sampled alone:";
      for (const auto& [source, sigma] : model.source_sigmas) {
        html << " " << ScaleSourceName(source) << " "
             << fmt::format("{:.0f}", 100.0 * model.VarianceShare(sigma))
             << " % (&sigma; " << Fixed(sigma) << ")";
      }
      html << ".</p>\n";
    }
    if (report.navigation) {
      const NavigationScaleCheck& check = *report.navigation;
      html << "<p" << (check.consistent ? "" : " class=\"bad\"")
           << ">Against the navigation's own scale of this fused model "
              "(log-scale &sigma; "
           << Fixed(check.log_scale_sigma, 4)
           << "): z = " << fmt::format("{:+.2f}", check.z)
           << (check.consistent ? ", consistent."
                                : ": beyond 3 &sigma;, the laser scale and the "
                                  "navigation disagree; one of them is wrong.")
           << "</p>\n";
    }
  } else {
    html << "<p class=\"bad\">No laser image was accepted: no scale. See "
            "the reasons below.</p>\n";
  }
  html << "<p>How to read it: docs/laserscale.md. Files: scale.json, "
          "images.csv, items.csv, segments.csv.</p>\n";
  html << "<h2>Per image</h2><a href=\"scales.svg\"><img src=\"scales.png\" "
          "width=\"1000\"></a>\n";
  if (model.monte_carlo.num_samples > 0) {
    html << "<h2>Monte Carlo</h2><a href=\"histogram.svg\"><img "
            "src=\"histogram.png\" width=\"700\"></a><a "
            "href=\"convergence.svg\"><img src=\"convergence.png\" "
            "width=\"700\"></a>\n";
  }
  html << "<h2>Segments</h2><table><tr><th>segment</th><th>images</th>"
          "<th>scale</th><th>95 % interval</th><th>Birge ratio</th></tr>\n";
  for (size_t s = 0; s < report.segments.size(); ++s) {
    const CombinedScale& c = report.segments[s].scale;
    html << "<tr><td>" << s + 1 << "</td><td>" << c.images.size() << "</td><td>"
         << Fixed(*c.nominal) << "</td><td>[" << Fixed(c.ci95_low) << ", "
         << Fixed(c.ci95_high) << "]</td><td>" << Fixed(c.birge_ratio, 2)
         << "</td></tr>\n";
  }
  html << "</table>\n<h2>Images</h2><table><tr><th>image</th><th>nominal</th>"
          "<th>MC mean &plusmn; &sigma;</th><th>95 % interval</th><th>status"
          "</th><th>spots</th></tr>\n";
  for (const ImageEstimate& image : report.images) {
    html << "<tr><td>" << HtmlEscape(image.name) << "</td>";
    if (!image.result) {
      html << "<td></td><td></td><td></td><td class=\"bad\">"
           << HtmlEscape(image.problem) << "</td><td></td></tr>\n";
      continue;
    }
    const ImageScaleResult& r = *image.result;
    html << "<td>" << (r.nominal ? Fixed(*r.nominal) : "") << "</td><td>"
         << Fixed(r.monte_carlo.mean) << " &plusmn; "
         << Fixed(r.monte_carlo.std_dev) << "</td><td>["
         << Fixed(r.monte_carlo.p2_5) << ", " << Fixed(r.monte_carlo.p97_5)
         << "]</td><td" << (r.accepted ? ">accepted" : " class=\"bad\">")
         << HtmlEscape(r.rejection) << "</td><td>";
    if (!image.overlay.empty()) {
      html << "<a href=\"" << HtmlEscape(image.overlay) << "\">overlay</a>";
    }
    html << "</td></tr>\n";
  }
  html << "</table>\n</body></html>\n";
  const auto text = [](const std::string& content) {
    return [content](std::ostream& out) { out << content; };
  };
  std::vector<PendingFile> files = {
      {dir / "scale.json", text(ScaleJsonText(report))},
      {dir / "images.csv", text(images_csv.str())},
      {dir / "items.csv", text(items_csv.str())},
      {dir / "segments.csv", text(segments_csv.str())},
      {dir / "index.html", text(html.str())}};
  const std::vector<FigureFiles> drawn = DrawFigures(figures);
  for (size_t i = 0; i < drawn.size(); ++i) {
    files.push_back({dir / (figure_names[i] + ".png"), text(drawn[i].png)});
    files.push_back({dir / (figure_names[i] + ".svg"), text(drawn[i].svg)});
  }
  WriteFilesAtomically(files, true);
}

ScaleJson ReadScaleFromJson(const std::filesystem::path& path) {
  const nlohmann::json json =
      ParseJsonText(ReadFileToString(path), path.string());
  if (!json.is_object() || json.value("format", "") != kFormat) {
    throw ErrorAt(path.string(), ": not a laserscale scale.json (format \"",
                  kFormat, "\")");
  }
  const auto scale = json.find("scale");
  if (scale == json.end() || !scale->is_number()) {
    throw ErrorAt(path.string(),
                  ": no scale (no laser image was accepted; see index.html)");
  }
  ScaleJson result;
  result.scale = scale->get<double>();
  if (!std::isfinite(result.scale) || !(result.scale > 0.0)) {
    throw ErrorAt(path.string(), ": the scale ", result.scale,
                  " is not positive");
  }
  try {
    if (json.contains("model_draws")) {
      result.num_model_draws = json["model_draws"].at("count").get<int>();
    }
    if (json.contains("navigation")) {
      const nlohmann::json& navigation = json["navigation"];
      NavigationScaleCheck check;
      check.log_scale_sigma = navigation.at("log_scale_sigma").get<double>();
      check.z = navigation.at("z").get<double>();
      check.consistent = navigation.at("consistent").get<bool>();
      result.navigation = check;
    }
  } catch (const nlohmann::json::exception& error) {
    throw ErrorAt(path.string(), ": ", error.what());
  }
  return result;
}

}  // namespace uw
