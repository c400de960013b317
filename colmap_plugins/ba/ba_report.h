// ba_report.json: what a navigation-fused adjustment did (docs/formats.md).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

// The report as JSON; image ids are given with their names from `model`.
// `context` (strategy, inputs, flags) is stored under "run".
nlohmann::json BaReportJson(const NavBundleAdjustmentReport& report,
                            const Reconstruction& model,
                            const nlohmann::json& context);

}  // namespace uw
