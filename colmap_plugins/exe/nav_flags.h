// The navigation flags shared by the uwcolmap commands that read a
// navigation log (pose_prior_importer, bundle_adjuster, lcurve,
// model_aligner): the log, image times, rig, and where the camera sits on
// the vehicle, bound to PosePriorImportOptions.
#pragma once

#include <optional>
#include <string>

#include "colmap_plugins/align/alignment_plausibility.h"
#include "colmap_plugins/nav/pose_prior_import.h"
#include "common/cli/flags.h"

namespace uw {

// Adds --nav (required if `nav_required`), --image_times, the rig flag
// named `rig_flag` (pose_prior_importer: --rig_config; bundle_adjuster:
// --Rig.config), --mount, --lever_arm, --boresight and --time_offset.
void AddNavFlags(CommandLine* cli, PosePriorImportOptions* options,
                 bool nav_required, const std::string& rig_flag);

// Adds --time_zone (+hh:mm, -hh:mm or Z) bound to `offset_s` (seconds
// east of UTC; none by default).
void AddTimeZoneFlag(CommandLine* cli, std::optional<int>* offset_s,
                     const std::string& help);

// Adds <prefix>min_range, <prefix>max_range and <prefix>accept_implausible
// (model_aligner: "--"; bundle_adjuster, lcurve: "--Nav.").
void AddPlausibilityFlags(CommandLine* cli,
                          AlignmentPlausibilityOptions* options,
                          const std::string& prefix);

}  // namespace uw
