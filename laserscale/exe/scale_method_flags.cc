#include "laserscale/exe/scale_method_flags.h"

namespace uw {

CLI::Option* AddScaleMethodFlag(CommandLine* cli, const std::string& flag,
                                ScaleMethod* field, const std::string& help) {
  return cli->Add<ScaleMethod>(flag, field, help, ScaleMethodFromName,
                               ScaleMethodName);
}

CLI::Option* AddScaleMethodsFlag(CommandLine* cli, const std::string& flag,
                                 std::vector<ScaleMethod>* field,
                                 const std::string& help) {
  return cli->Add<std::vector<ScaleMethod>>(
      flag, field, help,
      [](const std::string& text) {
        std::vector<ScaleMethod> methods;
        for (const std::string& name : CLI::detail::split(text, ',')) {
          methods.push_back(ScaleMethodFromName(name));
        }
        return methods;
      },
      [](const std::vector<ScaleMethod>& methods) {
        std::string text;
        for (size_t k = 0; k < methods.size(); ++k) {
          text += (k > 0 ? "," : "") + ScaleMethodName(methods[k]);
        }
        return text;
      });
}

}  // namespace uw
