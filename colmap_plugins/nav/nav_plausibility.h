// What a navigation log alone can tell about its units (issue 17). A
// command with a model to align judges far more (alignment_plausibility.h);
// pose_prior_importer has only the log, and a log of latitude/longitude in
// degrees read as metres otherwise goes into the database as a survey a
// few centimetres across.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "colmap_plugins/nav/nav_csv.h"

namespace uw {

// A warning (naming `nav_name`) when x and y look like longitude and
// latitude in degrees: every x within ±180 and y within ±90 (or the
// other way round), spanning less than 0.01 (1 km is 0.009 deg of latitude)
// over at least two rows, and lying at least 0.5 from the origin, where a
// local metric frame would put a survey. A metric log can look so only for
// a camera that stayed within a centimetre, half a metre from the origin.
std::optional<std::string> DegreesLikePositionsWarning(
    const std::vector<NavRecord>& nav, const std::string& nav_name);

// A warning when the vehicle's median speed between consecutive rows of a
// dive lies outside [min_speed_mps, max_speed_mps] (defaults 1 mm/s and
// 10 m/s: ROVs and AUVs survey at 0.1 to 3 m/s). Centimetres or
// millimetres read as metres give tens to thousands of m/s; a stationary
// lander or tripod legitimately gives ~0, and is told so.
std::optional<std::string> SpeedWarning(const std::vector<NavRecord>& nav,
                                        const std::string& nav_name,
                                        double min_speed_mps = 1e-3,
                                        double max_speed_mps = 10.0);

}  // namespace uw
