#include "common/util/figure.h"

#include <stdlib.h>

#include <fstream>
#include <system_error>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "common/util/uwplot_script.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// Debian's interpreter, where python3-matplotlib installs: not whichever
// python3 a virtual environment puts first on PATH.
constexpr char kPython[] = "/usr/bin/python3";
// uwplot.py's exit code when an import fails.
constexpr int kMissingModule = 3;

// A private folder for one batch, removed however the batch ends.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern =
        (fs::temp_directory_path() / "uwplot-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
      throw ErrorAt(pattern, ": cannot create a temporary folder for figures");
    }
    path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out.flush()) throw ErrorAt(path.string(), ": cannot write");
}

}  // namespace

std::string Figure::Colour(int index) {
  return "C" + std::to_string(index % 10);
}

Figure::Figure(std::string title, std::string x_label, std::string y_label,
               double width_in, double height_in)
    : spec_({{"title", std::move(title)},
             {"x_label", std::move(x_label)},
             {"y_label", std::move(y_label)},
             {"width_in", width_in},
             {"height_in", height_in},
             {"series", nlohmann::json::array()}}) {}

void Figure::Add(nlohmann::json series) {
  spec_["series"].push_back(std::move(series));
}

void Figure::Line(const std::vector<double>& x, const std::vector<double>& y,
                  const std::string& colour, const std::string& label) {
  Add({{"kind", "line"},
       {"x", x},
       {"y", y},
       {"colour", colour},
       {"label", label}});
}

void Figure::Points(const std::vector<double>& x, const std::vector<double>& y,
                    const std::string& colour, const std::string& label) {
  Add({{"kind", "points"},
       {"x", x},
       {"y", y},
       {"colour", colour},
       {"label", label}});
}

void Figure::ErrorBars(const std::vector<double>& x,
                       const std::vector<double>& low,
                       const std::vector<double>& high,
                       const std::string& colour, const std::string& label) {
  Add({{"kind", "errorbars"},
       {"x", x},
       {"low", low},
       {"high", high},
       {"colour", colour},
       {"label", label}});
}

void Figure::Bars(const std::vector<double>& x,
                  const std::vector<double>& heights, double width,
                  const std::string& colour, const std::string& label) {
  Add({{"kind", "bars"},
       {"x", x},
       {"y", heights},
       {"width", width},
       {"colour", colour},
       {"label", label}});
}

void Figure::Histogram(const std::vector<double>& values, int num_bins,
                       const std::string& colour, const std::string& label) {
  Add({{"kind", "histogram"},
       {"values", values},
       {"bins", num_bins},
       {"colour", colour},
       {"label", label}});
}

void Figure::HorizontalLine(double y, const std::string& colour,
                            const std::string& label) {
  Add({{"kind", "hline"}, {"y", y}, {"colour", colour}, {"label", label}});
}

void Figure::VerticalLine(double x, const std::string& colour,
                          const std::string& label) {
  Add({{"kind", "vline"}, {"x", x}, {"colour", colour}, {"label", label}});
}

void Figure::ItemAxis(std::vector<std::string> names) {
  spec_["x_categories"] = std::move(names);
}

void Figure::LogX() { spec_["log_x"] = true; }

void Figure::LogY() { spec_["log_y"] = true; }

void Figure::EqualAspect() { spec_["equal_aspect"] = true; }

std::vector<FigureFiles> DrawFigures(const std::vector<Figure>& figures) {
  if (figures.empty()) return {};
  const TemporaryFolder folder;
  nlohmann::json spec = {{"figures", nlohmann::json::array()}};
  for (size_t i = 0; i < figures.size(); ++i) {
    nlohmann::json figure = figures[i].Spec();
    const std::string stem = "figure_" + std::to_string(i);
    figure["png"] = (folder.path() / (stem + ".png")).string();
    figure["svg"] = (folder.path() / (stem + ".svg")).string();
    spec["figures"].push_back(std::move(figure));
  }
  // NaN and infinities are not JSON: nlohmann writes them as null, which
  // uwplot.py leaves out as it does non-finite numbers.
  // Names that are not UTF-8 are drawn with replacement characters rather
  // than refused.
  WriteText(
      folder.path() / "spec.json",
      spec.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  WriteText(folder.path() / "uwplot.py", kUwplotScript);
  const fs::path log = folder.path() / "uwplot.log";
  int code = 0;
  try {
    code = RunProgram({kPython, (folder.path() / "uwplot.py").string(),
                       (folder.path() / "spec.json").string()},
                      log);
  } catch (const Error& error) {
    throw ErrorAt("cannot draw the figures: ", error.what(),
                  " (python3 and python3-matplotlib, installed by "
                  "scripts/setup.sh)");
  }
  if (code == kMissingModule) {
    throw ErrorAt("cannot draw the figures: ", TailOfFile(log, 3),
                  " (python3-matplotlib, installed by scripts/setup.sh)");
  }
  if (code != 0) {
    throw ErrorAt("cannot draw the figures (", kPython,
                  " uwplot.py exited with ", code, "): ", TailOfFile(log, 5));
  }
  std::vector<FigureFiles> files;
  for (size_t i = 0; i < figures.size(); ++i) {
    const std::string stem = "figure_" + std::to_string(i);
    files.push_back({ReadFileToString(folder.path() / (stem + ".png")),
                     ReadFileToString(folder.path() / (stem + ".svg"))});
  }
  return files;
}

std::vector<PendingFile> FigureFileSet(const std::vector<FigureFiles>& drawn,
                                       const std::vector<fs::path>& png_paths) {
  if (drawn.size() != png_paths.size()) {
    throw ErrorAt("FigureFileSet: ", drawn.size(), " figures for ",
                  png_paths.size(), " paths");
  }
  std::vector<PendingFile> pending;
  for (size_t i = 0; i < drawn.size(); ++i) {
    const FigureFiles* files = &drawn[i];
    pending.push_back(
        {png_paths[i], [files](std::ostream& out) { out << files->png; }});
    pending.push_back({fs::path(png_paths[i]).replace_extension(".svg"),
                       [files](std::ostream& out) { out << files->svg; }});
  }
  return pending;
}

void WriteFigures(const std::vector<Figure>& figures,
                  const std::vector<fs::path>& png_paths) {
  if (figures.size() != png_paths.size()) {
    throw ErrorAt("WriteFigures: ", figures.size(), " figures for ",
                  png_paths.size(), " paths");
  }
  const std::vector<FigureFiles> drawn = DrawFigures(figures);
  WriteFilesAtomically(FigureFileSet(drawn, png_paths), true);
}

}  // namespace uw
