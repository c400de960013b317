// uwsim map: a top view of a survey for the docs. The world's true mesh,
// the true camera centres coloured by dive, the true vehicle track and the
// navigation track, drawn by the survey report's DrawSurveyMap
// (report/survey_map.h) from an uwsim output folder.
#pragma once

#include <filesystem>

#include "report/survey_map.h"

namespace uw::sim {

// Reads truth/mesh.ply, truth/images.txt (COLMAP text), truth/nav.csv and
// nav.csv under `sim_dir`: the mesh, the true camera centres (dive from
// truth/nav.csv), the true track (truth/nav.csv) and the navigation
// (nav.csv), in file order, with legend labels that say so. Throws
// uw::Error naming a missing file, a malformed nav.csv row (file:line), or
// an image of truth/images.txt with no row in truth/nav.csv.
SurveyMapData ReadSurveyMapData(const std::filesystem::path& sim_dir);

// Reads `sim_dir`, draws the map and writes it to `out` atomically, as PNG
// or JPEG by the extension (.png, .jpg, .jpeg).
void WriteSurveyMap(const std::filesystem::path& sim_dir,
                    const std::filesystem::path& out,
                    const SurveyMapOptions& options);

}  // namespace uw::sim
