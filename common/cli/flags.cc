#include "common/cli/flags.h"

#include <cmath>

#include "common/util/error.h"

namespace uw {
namespace {

// "--Nav.use_attitude" -> "Nav.use_attitude", as messages name flags.
std::string FlagName(const std::string& flag) {
  return flag.substr(flag.find_first_not_of('-'));
}

template <typename T>
std::string JoinWithCommas(const std::vector<T>& values) {
  std::ostringstream text;
  for (size_t k = 0; k < values.size(); ++k) {
    text << (k > 0 ? "," : "") << values[k];
  }
  return text.str();
}

Eigen::Vector3d ParseVector3(const std::string& name, const std::string& text) {
  const std::vector<std::string> parts = CLI::detail::split(text, ',');
  Eigen::Vector3d value;
  for (int k = 0; k < 3; ++k) {
    if (parts.size() != 3 || !CLI::detail::lexical_cast(parts[k], value(k)) ||
        !std::isfinite(value(k))) {
      throw ErrorAt("--", name, ": expected three numbers x,y,z, got '", text,
                    "'");
    }
  }
  return value;
}

std::string FormatVector3(const Eigen::Vector3d& value) {
  return JoinWithCommas(std::vector<double>{value.x(), value.y(), value.z()});
}

}  // namespace

CommandLine::CommandLine(const std::string& name,
                         const std::string& description)
    : app_(description, name) {}

CLI::Option* CommandLine::Bind(CLI::Option* option, const void* field,
                               size_t size) {
  bindings_.push_back({option, field, size});
  return option;
}

CLI::Option* CommandLine::Add(const std::string& flag, bool* field,
                              const std::string& help) {
  const std::string name = FlagName(flag);
  return Add<bool>(
      flag, field, help,
      [name](const std::string& text) {
        if (text == "1" || text == "true") return true;
        if (text == "0" || text == "false") return false;
        throw ErrorAt("--", name, ": expected 0 or 1, got '", text, "'");
      },
      [](const bool& value) { return std::string(value ? "1" : "0"); });
}

CLI::Option* CommandLine::Add(const std::string& flag, Eigen::Vector3d* field,
                              const std::string& help) {
  const std::string name = FlagName(flag);
  CLI::Option* option = Add<Eigen::Vector3d>(
      flag, field, help,
      [name](const std::string& text) { return ParseVector3(name, text); },
      FormatVector3);
  option->type_name("X,Y,Z");
  return option;
}

CLI::Option* CommandLine::Add(const std::string& flag,
                              std::optional<Eigen::Vector3d>* field,
                              const std::string& help) {
  const std::string name = FlagName(flag);
  CLI::Option* option = Add<std::optional<Eigen::Vector3d>>(
      flag, field, help,
      [name](const std::string& text) {
        return std::optional<Eigen::Vector3d>(ParseVector3(name, text));
      },
      [](const std::optional<Eigen::Vector3d>& value) {
        return value ? FormatVector3(*value) : std::string();
      });
  option->type_name("X,Y,Z");
  return option;
}

CLI::Option* CommandLine::Add(const std::string& flag,
                              std::vector<double>* field,
                              const std::string& help) {
  const std::string name = FlagName(flag);
  return Add<std::vector<double>>(
      flag, field, help,
      [name](const std::string& text) {
        std::vector<double> values;
        for (const std::string& part : CLI::detail::split(text, ',')) {
          double value = 0.0;
          if (!CLI::detail::lexical_cast(part, value) ||
              !std::isfinite(value)) {
            throw ErrorAt("--", name, ": '", part, "' is not a number");
          }
          values.push_back(value);
        }
        return values;
      },
      JoinWithCommas<double>);
}

CLI::Option* CommandLine::Add(const std::string& flag,
                              std::vector<std::string>* field,
                              const std::string& help) {
  return Add<std::vector<std::string>>(
      flag, field, help,
      [](const std::string& text) { return CLI::detail::split(text, ','); },
      JoinWithCommas<std::string>);
}

}  // namespace uw
