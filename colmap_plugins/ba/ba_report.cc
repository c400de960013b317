#include "colmap_plugins/ba/ba_report.h"

#include <cmath>
#include <map>
#include <utility>

#include "common/util/json_fields.h"

namespace uw {
namespace {

nlohmann::json Terms(const std::map<std::string, CostTerm>& terms) {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& [name, term] : terms) {
    json[name] = {{"residual_blocks", term.num_residual_blocks},
                  {"weighted_cost", term.weighted_cost},
                  {"mean_squared", term.mean_squared}};
  }
  return json;
}

}  // namespace

nlohmann::json BaReportJson(const NavBundleAdjustmentReport& report,
                            const Reconstruction& model,
                            const nlohmann::json& context) {
  nlohmann::json offsets = nlohmann::json::array();
  for (const DiveOffsetEstimate& offset : report.dive_offsets) {
    nlohmann::json entry = {{"dive", offset.dive},
                            {"num_images", offset.num_images},
                            {"offset_m", ToJson(offset.offset_in_world)}};
    if (offset.covariance) {
      entry["sigma_m"] =
          ToJson(Eigen::Vector3d(offset.covariance->diagonal().cwiseSqrt()));
      entry["covariance_m2"] = ToJson(*offset.covariance);
    }
    offsets.push_back(entry);
  }
  nlohmann::json residuals = nlohmann::json::array();
  double sum_squared = 0.0;
  double max_error = 0.0;
  for (const PriorResidual& residual : report.prior_residuals) {
    const Image* image = model.FindImage(residual.image_id);
    nlohmann::json entry = {{"image_id", residual.image_id},
                            {"name", image != nullptr ? image->name : ""},
                            {"dive", residual.dive},
                            {"error_m", ToJson(residual.error_in_world)},
                            {"error_norm_m", residual.error_in_world.norm()},
                            {"mahalanobis", residual.mahalanobis}};
    if (residual.attitude_error_deg) {
      entry["attitude_error_deg"] = *residual.attitude_error_deg;
    }
    residuals.push_back(entry);
    sum_squared += residual.error_in_world.squaredNorm();
    max_error = std::max(max_error, residual.error_in_world.norm());
  }
  // Per dive: where its priors pull. Without offsets, dives whose
  // navigation disagrees show opposite mean errors of the size of the
  // disagreement.
  std::map<int, std::pair<Eigen::Vector3d, std::pair<double, int>>> dives;
  for (const PriorResidual& residual : report.prior_residuals) {
    auto& [sum, squared_and_count] = dives[residual.dive];
    if (squared_and_count.second == 0) sum.setZero();
    sum += residual.error_in_world;
    squared_and_count.first += residual.error_in_world.squaredNorm();
    ++squared_and_count.second;
  }
  nlohmann::json per_dive = nlohmann::json::array();
  for (const auto& [dive, entry] : dives) {
    const int count = entry.second.second;
    per_dive.push_back(
        {{"dive", dive},
         {"num_images", count},
         {"mean_error_m", ToJson(Eigen::Vector3d(entry.first / count))},
         {"rms_error_m", std::sqrt(entry.second.first / count)}});
  }
  nlohmann::json json = {
      {"format", "uwmetric-ba-report"},
      {"version", 1},
      {"run", context},
      {"weight_px_per_m", report.weight_px_per_m},
      {"weighting", NavWeightingName(report.weighting)},
      {"nav_sigma_m", report.nav_sigma_m},
      {"num_images", report.num_images},
      {"num_points3D", report.num_points},
      {"num_observations", report.num_observations},
      {"gauge", report.gauge},
      {"initial_cost", Terms(report.initial_terms)},
      {"final_cost", Terms(report.final_terms)},
      {"dive_offsets", offsets},
      {"covariance_note", report.covariance_note},
      {"warnings", report.warnings},
      {"prior_residual_rms_m",
       report.prior_residuals.empty()
           ? 0.0
           : std::sqrt(sum_squared / report.prior_residuals.size())},
      {"prior_residual_max_m", max_error},
      {"prior_residuals_by_dive", per_dive},
      {"prior_residuals", residuals},
      {"iterations", report.num_iterations},
      {"continuations", report.num_continuations},
      {"termination", report.termination},
      {"solver", report.solver},
      {"solve_time_s", report.solve_time_s},
      {"covariance_time_s", report.covariance_time_s}};
  return json;
}

}  // namespace uw
