// The survey report: one self-contained folder (index.html, report.json,
// CSVs, PNGs; relative links only, no network) that a scientist can put in
// a cruise report: what was registered, the scale with its 95 % interval,
// where the survey went, how well the navigation and the images agree,
// stock colmap against uwmetric, the dense surface and the time taken.
// `uwcolmap survey_report`; docs/uwcolmap.md#survey_report.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "report/report_inputs.h"

namespace uw {

struct SurveyReportOptions {
  std::string title = "Survey report";
  // Width of the survey map PNG.
  int map_width_px = 1600;
  // Width of the spot overlays' thumbnails.
  int thumbnail_width_px = 240;
  // Largest number of dense mesh vertices whose distance to the true
  // surface is histogrammed (every k-th vertex beyond that).
  int max_histogram_vertices = 50000;

  void Check() const;  // throws uw::Error naming the bad field
};

struct SurveyReportResult {
  std::filesystem::path index_path;
  std::vector<std::string> files;    // written, relative to the folder
  std::vector<std::string> omitted;  // one note per section left out
  size_t num_images = 0;             // <img> elements of index.html
};

// Reads every given input (inputs.Check() first), draws the figures and
// writes the folder in one atomic set (WriteFilesAtomically): either every
// file is new or none is touched. Files of an older report that this one
// does not write are left alone. Throws uw::Error naming the input that is
// missing or malformed.
SurveyReportResult WriteSurveyReport(const SurveyReportInputs& inputs,
                                     const SurveyReportOptions& options,
                                     const std::filesystem::path& output_dir);

}  // namespace uw
