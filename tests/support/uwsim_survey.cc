#include "tests/support/uwsim_survey.h"

#include <sstream>

#include <nlohmann/json.hpp>

#include "common/util/file.h"

namespace uw::testing {

std::string SurveyMountFlags(const std::filesystem::path& sim_dir) {
  const nlohmann::json sim =
      nlohmann::json::parse(ReadFileToString(sim_dir / "truth" / "sim.json"));
  const nlohmann::json& survey = sim.at("survey_options");
  const auto triple = [&](const char* key) {
    std::ostringstream text;
    text.precision(10);
    const auto& value = survey.at(key);
    text << value[0].get<double>() << "," << value[1].get<double>() << ","
         << value[2].get<double>();
    return text.str();
  };
  // The world's own mount: the scarp's wall is surveyed to starboard.
  return " --mount " + sim.at("truth").at("camera_mount").get<std::string>() +
         " --lever_arm " + triple("lever_arm_m") + " --boresight " +
         triple("boresight_deg");
}

}  // namespace uw::testing
