// What the integration tests read off a `uwsim generate` folder.
#pragma once

#include <filesystem>
#include <string>

namespace uw::testing {

// " --mount M --lever_arm x,y,z --boresight r,p,y": the camera's mounting
// on the vehicle as uwsim surveyed with it (sim_dir/truth/sim.json: down,
// or starboard on the scarp), for the uwcolmap commands that take --nav.
std::string SurveyMountFlags(const std::filesystem::path& sim_dir);

}  // namespace uw::testing
