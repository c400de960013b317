// uwcolmap model_converter / model_analyzer: same flags and output as
// COLMAP's commands of the same name, on our reader and writer.
#pragma once

#include <string>

#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"

namespace uw {

struct ModelConverterOptions {
  std::string input_path;
  std::string output_path;
  // BIN or TXT, any case (COLMAP's other export formats are refused).
  std::string output_type;
  // Accepted for COLMAP compatibility; only COLMAP's export formats use it.
  bool skip_distortion = false;

  ModelFormat OutputFormat() const;
  // The output type, and an output folder that is not the input.
  void Check() const;
};
Subcommand ModelConverterCommand();

struct ModelAnalyzerOptions {
  std::string path;
  void Check() const {}
};
Subcommand ModelAnalyzerCommand();

}  // namespace uw
