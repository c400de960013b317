// uwcolmap survey_report: the survey report folder (index.html + figures).
#pragma once

namespace uw {

int RunSurveyReport(int argc, char** argv);

}  // namespace uw
