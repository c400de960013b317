// The flags of one command, each bound to a field of the command's options
// struct (COLMAP's OptionManager habit, on CLI11): the field's value before
// parsing is the flag's default and what --help shows, so a default is
// written once, in the options header; parsing writes the field. Bindings()
// tells which field every flag writes, so that a test can fail on a flag
// that writes none (UnboundFlags in common/cli/command.h).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Core>

namespace uw {

class CommandLine {
 public:
  // `name` as the user types it ("uwcolmap bundle_adjuster"); `description`
  // is --help's text, ending with an example.
  CommandLine(const std::string& name, const std::string& description);

  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  // Numbers, strings and paths, parsed by CLI11 (a number must be all
  // number: "1abc" is refused).
  template <typename T>
  CLI::Option* Add(const std::string& flag, T* field, const std::string& help) {
    CLI::Option* option = app_.add_option(flag, *field, help);
    option->capture_default_str();
    return Bind(option, field, sizeof(T));
  }

  // A boolean as COLMAP writes it on its command line: 0 or 1 (also false
  // or true).
  CLI::Option* Add(const std::string& flag, bool* field,
                   const std::string& help);

  // x,y,z: three finite numbers.
  CLI::Option* Add(const std::string& flag, Eigen::Vector3d* field,
                   const std::string& help);

  // x,y,z, or nothing given: no value (the field's std::nullopt).
  CLI::Option* Add(const std::string& flag,
                   std::optional<Eigen::Vector3d>* field,
                   const std::string& help);

  // Comma-separated lists (CLI11 splits them): "2,3,4", "A,B".
  CLI::Option* Add(const std::string& flag, std::vector<double>* field,
                   const std::string& help);
  CLI::Option* Add(const std::string& flag, std::vector<std::string>* field,
                   const std::string& help);

  // N comma-separated integers into N fields ("--imagersize 640,480" into
  // a width and a height); `form` names them for the message
  // ("WIDTH,HEIGHT"). The fields' values before parsing are the default.
  CLI::Option* AddIntegers(const std::string& flag,
                           const std::vector<int*>& fields,
                           const std::string& form, const std::string& help);

  // A switch, as mrcal's and most tools' --skip-... flags: given without a
  // value, it sets `*field` to `value_when_given` (--skip_regularization
  // clears `regularization`); absent or "=false", it leaves the field.
  CLI::Option* AddSwitch(const std::string& flag, bool* field,
                         bool value_when_given, const std::string& help);

  // x y z as three arguments ("--colour 1 0 0"), for flags that have always
  // taken them so; CLI11 converts them (a word is a parse error).
  CLI::Option* AddThreeArguments(const std::string& flag,
                                 Eigen::Vector3d* field,
                                 const std::string& help);

  // A value that overrides another source (a configuration file) only
  // when the flag is given: the field stays std::nullopt without it. CLI11
  // parses T, as for Add above; --help shows `shown` as the default, the
  // value that applies without the flag, if there is one to show.
  template <typename T>
  CLI::Option* Add(const std::string& flag, std::optional<T>* field,
                   const std::string& help,
                   const std::optional<T>& shown = std::nullopt) {
    CLI::Option* option = app_.add_option_function<T>(
        flag, [field](const T& value) { *field = value; }, help);
    if (shown) option->default_str(CLI::detail::to_string(*shown));
    return Bind(option, field, sizeof(*field));
  }

  // A value with its own reader and writer: an enum by name, "auto or a
  // number". `parse` may throw uw::Error naming the flag (exit code 1, as
  // for any bad input); `format` gives --help's default.
  template <typename T>
  CLI::Option* Add(const std::string& flag, T* field, const std::string& help,
                   std::function<T(const std::string&)> parse,
                   std::function<std::string(const T&)> format) {
    CLI::Option* option = app_.add_option_function<std::string>(
        flag, [field, parse](const std::string& text) { *field = parse(text); },
        help);
    option->default_str(format(*field));
    return Bind(option, field, sizeof(T));
  }

  // A repeatable flag (--noise 0:0 --noise 0.5:0.25) whose values, each
  // read by `parse`, replace the default list; `format` writes one item of
  // --help's default.
  template <typename T>
  CLI::Option* AddRepeated(const std::string& flag, std::vector<T>* field,
                           const std::string& help,
                           std::function<T(const std::string&)> parse,
                           std::function<std::string(const T&)> format) {
    CLI::Option* option = app_.add_option_function<std::vector<std::string>>(
        flag,
        [field, parse](const std::vector<std::string>& texts) {
          field->clear();
          for (const std::string& text : texts) field->push_back(parse(text));
        },
        help);
    std::string defaults;
    for (size_t k = 0; k < field->size(); ++k) {
      defaults += (k > 0 ? " " : "") + format((*field)[k]);
    }
    option->default_str(defaults);
    return Bind(option, field, sizeof(*field));
  }

  CLI::App& app() { return app_; }

  // The options object the flags are meant to write (MakeSubcommand
  // declares it); UnboundFlags refuses a flag that writes outside it.
  void DeclareOptions(const void* object, size_t size) {
    options_begin_ = static_cast<const char*>(object);
    options_size_ = size;
  }
  bool WritesIntoOptions(const void* field, size_t size) const {
    const char* begin = static_cast<const char*>(field);
    return options_begin_ != nullptr && begin >= options_begin_ &&
           begin + size <= options_begin_ + options_size_;
  }

  // Which flag writes which bytes.
  struct Binding {
    const CLI::Option* option;
    const void* field;
    size_t size;
  };
  const std::vector<Binding>& Bindings() const { return bindings_; }

 private:
  CLI::Option* Bind(CLI::Option* option, const void* field, size_t size);

  CLI::App app_;
  std::vector<Binding> bindings_;
  const char* options_begin_ = nullptr;
  size_t options_size_ = 0;
};

}  // namespace uw
