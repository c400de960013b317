// uwcolmap survey_report: the survey report folder (index.html + figures).
#pragma once

#include <string>

#include "common/cli/command.h"
#include "report/survey_report.h"

namespace uw {

struct SurveyReportCommandOptions {
  SurveyReportInputs inputs;
  SurveyReportOptions report;
  std::string output_path;  // the report folder

  // Every given input exists; the report's own rules.
  void Check() const {
    inputs.Check();
    report.Check();
  }
};
Subcommand SurveyReportCommand();

}  // namespace uw
