#include "common/cli/flags.h"

#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/util/error.h"

namespace uw {
namespace {

// "--Nav.use_attitude" -> "Nav.use_attitude", as messages name flags.
std::string FlagName(const std::string& flag) {
  return flag.substr(flag.find_first_not_of('-'));
}

// A list flag's value as it is typed, "1,2.5,3"; numbers as %g, the way a
// stream prints them.
std::string JoinNumbers(const std::vector<double>& values) {
  return fmt::format("{:g}", fmt::join(values, ","));
}

std::string JoinTexts(const std::vector<std::string>& values) {
  return fmt::format("{}", fmt::join(values, ","));
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
  return JoinNumbers({value.x(), value.y(), value.z()});
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
      JoinNumbers);
}

CLI::Option* CommandLine::Add(const std::string& flag,
                              std::vector<std::string>* field,
                              const std::string& help) {
  return Add<std::vector<std::string>>(
      flag, field, help,
      [](const std::string& text) { return CLI::detail::split(text, ','); },
      JoinTexts);
}

CLI::Option* CommandLine::AddIntegers(const std::string& flag,
                                      const std::vector<int*>& fields,
                                      const std::string& form,
                                      const std::string& help) {
  const std::string name = FlagName(flag);
  CLI::Option* option = app_.add_option_function<std::string>(
      flag,
      [fields, name, form](const std::string& text) {
        const std::vector<std::string> parts = CLI::detail::split(text, ',');
        std::vector<int> values(fields.size());
        for (size_t k = 0; k < fields.size(); ++k) {
          if (parts.size() != fields.size() ||
              !CLI::detail::lexical_cast(parts[k], values[k])) {
            throw ErrorAt("--", name, " must be ", form, ", got '", text, "'");
          }
        }
        for (size_t k = 0; k < fields.size(); ++k) *fields[k] = values[k];
      },
      help);
  std::vector<int> defaults;
  for (const int* field : fields) defaults.push_back(*field);
  option->default_str(fmt::format("{}", fmt::join(defaults, ",")));
  for (int* field : fields) Bind(option, field, sizeof(int));
  return option;
}

CLI::Option* CommandLine::AddSwitch(const std::string& flag, bool* field,
                                    bool value_when_given,
                                    const std::string& help) {
  CLI::Option* option = app_.add_flag_function(
      flag,
      [field, value_when_given](std::int64_t count) {
        if (count > 0) *field = value_when_given;
      },
      help);
  return Bind(option, field, sizeof(bool));
}

CLI::Option* CommandLine::AddThreeArguments(const std::string& flag,
                                            Eigen::Vector3d* field,
                                            const std::string& help) {
  CLI::Option* option = app_.add_option_function<std::vector<double>>(
      flag,
      [field](const std::vector<double>& values) {
        *field = Eigen::Vector3d(values[0], values[1], values[2]);
      },
      help);
  option->expected(3);
  option->default_str("[" + JoinNumbers({field->x(), field->y(), field->z()}) +
                      "]");
  return Bind(option, field, sizeof(Eigen::Vector3d));
}

}  // namespace uw
