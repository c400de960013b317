#include "common/cli/command.h"

#include <gtest/gtest.h>

#include "common/util/error_testing.h"

namespace uw {
namespace {

struct ExampleOptions {
  std::string input_path;
  int max_iterations = 100;
  double sigma = 0.5;
  bool refine = true;
  Eigen::Vector3d lever_arm = Eigen::Vector3d(0.6, 0.0, -0.3);
  std::vector<double> distances = {2.0, 3.0};
  std::vector<std::string> names = {"A", "B"};
  bool warp = true;
  Eigen::Vector3d colour = Eigen::Vector3d(1.0, 0.0, 0.0);
  int width = 640;
  int height = 480;
  void Check() const {
    if (max_iterations < 1) throw ErrorAt("--max_iterations must be >= 1");
  }
};

void AddExampleFlags(CommandLine* cli, ExampleOptions* options) {
  cli->Add("--input_path", &options->input_path, "Model")->required();
  cli->Add("--max_iterations", &options->max_iterations, "Iterations");
  cli->Add("--sigma", &options->sigma, "Sigma");
  cli->Add("--refine", &options->refine, "Refine");
  cli->Add("--lever_arm", &options->lever_arm, "Lever arm");
  cli->Add("--distances", &options->distances, "Distances");
  cli->Add("--names", &options->names, "Names");
  cli->AddSwitch("--skip_warp", &options->warp, false, "No warp");
  cli->AddThreeArguments("--colour", &options->colour, "R G B");
  cli->AddIntegers("--size", {&options->width, &options->height},
                   "WIDTH,HEIGHT", "Size");
}

ExampleOptions last_run;
void RunExample(const ExampleOptions& options) { last_run = options; }

Subcommand Example() {
  return MakeSubcommand<ExampleOptions>("example", "an example",
                                        "Example:\n  prog example",
                                        AddExampleFlags, RunExample);
}

// "prog <command> args..." through the program's dispatcher.
int RunCommandLine(const Subcommand& command, std::vector<std::string> args) {
  args.insert(args.begin(), {"prog", command.name});
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  return DispatchSubcommand("prog", "usage", {command},
                            static_cast<int>(argv.size()), argv.data());
}

TEST(CommandLine, DefaultsAreTheFieldsInitialValues) {
  last_run = {};
  ASSERT_EQ(RunCommandLine(Example(), {"--input_path", "m"}), 0);
  const ExampleOptions defaults;
  EXPECT_EQ(last_run.input_path, "m");
  EXPECT_EQ(last_run.max_iterations, defaults.max_iterations);
  EXPECT_EQ(last_run.sigma, defaults.sigma);
  EXPECT_EQ(last_run.refine, defaults.refine);
  EXPECT_EQ(last_run.lever_arm, defaults.lever_arm);
  EXPECT_EQ(last_run.distances, defaults.distances);
  EXPECT_EQ(last_run.names, defaults.names);
  EXPECT_EQ(last_run.warp, defaults.warp);
  EXPECT_EQ(last_run.colour, defaults.colour);
  EXPECT_EQ(last_run.width, defaults.width);
  EXPECT_EQ(last_run.height, defaults.height);
}

TEST(CommandLine, FlagsWriteTheirFields) {
  last_run = {};
  ASSERT_EQ(RunCommandLine(
                Example(),
                {"--input_path", "m", "--max_iterations", "7", "--sigma", "2.5",
                 "--refine", "0", "--lever_arm", "1,-2,3", "--distances",
                 "1.5,4", "--names", "C", "--size", "1024,768"}),
            0);
  EXPECT_EQ(last_run.max_iterations, 7);
  EXPECT_EQ(last_run.sigma, 2.5);
  EXPECT_FALSE(last_run.refine);
  EXPECT_EQ(last_run.lever_arm, Eigen::Vector3d(1, -2, 3));
  EXPECT_EQ(last_run.distances, (std::vector<double>{1.5, 4.0}));
  EXPECT_EQ(last_run.names, std::vector<std::string>{"C"});
  EXPECT_EQ(last_run.width, 1024);
  EXPECT_EQ(last_run.height, 768);
}

TEST(CommandLine, SwitchesTakeNoValueAndThreeArgumentsTakeThree) {
  last_run = {};
  ASSERT_EQ(RunCommandLine(Example(), {"--input_path", "m", "--skip_warp",
                                       "--colour", "0", "0.5", "1"}),
            0);
  EXPECT_FALSE(last_run.warp);
  EXPECT_EQ(last_run.colour, Eigen::Vector3d(0.0, 0.5, 1.0));
  last_run = {};
  ASSERT_EQ(
      RunCommandLine(Example(), {"--input_path", "m", "--skip_warp=false"}), 0);
  EXPECT_TRUE(last_run.warp);
  EXPECT_EQ(
      RunCommandLine(Example(), {"--input_path", "m", "--colour", "1", "0"}),
      2);
  EXPECT_EQ(RunCommandLine(Example(),
                           {"--input_path", "m", "--colour", "1", "x", "0"}),
            2);
}

TEST(CommandLine, BadValuesExitNonZero) {
  // CLI11's own parse errors are 2, a value our readers refuse is 1 (bad
  // input), and so is a Check() failure.
  EXPECT_EQ(RunCommandLine(Example(), {}), 2);
  EXPECT_EQ(RunCommandLine(Example(),
                           {"--input_path", "m", "--max_iterations", "1abc"}),
            2);
  EXPECT_EQ(RunCommandLine(Example(), {"--input_path", "m", "--refine", "yes"}),
            1);
  EXPECT_EQ(
      RunCommandLine(Example(), {"--input_path", "m", "--lever_arm", "1,2"}),
      1);
  EXPECT_EQ(RunCommandLine(Example(),
                           {"--input_path", "m", "--lever_arm", "1,2,nan"}),
            1);
  EXPECT_EQ(
      RunCommandLine(Example(), {"--input_path", "m", "--distances", "1,x"}),
      1);
  EXPECT_EQ(RunCommandLine(Example(), {"--input_path", "m", "--size", "640"}),
            1);
  EXPECT_EQ(
      RunCommandLine(Example(), {"--input_path", "m", "--max_iterations", "0"}),
      1);
  EXPECT_EQ(RunCommandLine(Example(), {"--input_path", "m", "--unknown", "1"}),
            2);
}

TEST(CommandLine, HelpIsAnsweredEvenWhenAReaderRefusesAValue) {
  EXPECT_EQ(RunCommandLine(Example(), {"--refine", "yes", "--help"}), 0);
}

TEST(CommandLine, ReadersNameTheFlag) {
  CommandLine cli("prog example", "");
  ExampleOptions options;
  AddExampleFlags(&cli, &options);
  ExpectErrorContaining(
      [&] { cli.app().parse("--input_path m --lever_arm 1,2", false); },
      "--lever_arm: expected three numbers x,y,z, got '1,2'");
  ExpectErrorContaining(
      [&] { cli.app().parse("--input_path m --refine 2", false); },
      "--refine: expected 0 or 1, got '2'");
  ExpectErrorContaining(
      [&] { cli.app().parse("--input_path m --distances 1,,2", false); },
      "--distances: '' is not a number");
  ExpectErrorContaining(
      [&] { cli.app().parse("--input_path m --size 640x480", false); },
      "--size must be WIDTH,HEIGHT, got '640x480'");
}

// Flags that override another source only when given.
struct OverrideOptions {
  std::optional<uint64_t> seed;
  std::optional<int> limit;
  void Check() const {}
};
void AddOverrideFlags(CommandLine* cli, OverrideOptions* options) {
  cli->Add("--seed", &options->seed, "Seed", std::optional<uint64_t>(1));
  cli->Add("--limit", &options->limit, "Limit");
}
OverrideOptions last_override;
void RunOverride(const OverrideOptions& options) { last_override = options; }

TEST(CommandLine, OptionalFlagsAreSetOnlyWhenGiven) {
  const Subcommand command = MakeSubcommand<OverrideOptions>(
      "override", "", "", AddOverrideFlags, RunOverride);
  last_override = {};
  ASSERT_EQ(RunCommandLine(command, {}), 0);
  EXPECT_FALSE(last_override.seed.has_value());
  EXPECT_FALSE(last_override.limit.has_value());
  ASSERT_EQ(RunCommandLine(command, {"--seed", "7", "--limit", "-3"}), 0);
  EXPECT_EQ(last_override.seed, std::optional<uint64_t>(7));
  EXPECT_EQ(last_override.limit, std::optional<int>(-3));
  EXPECT_EQ(RunCommandLine(command, {"--seed", "x"}), 2);
  EXPECT_EQ(RunCommandLine(command, {"--limit", "1.5"}), 2);
  EXPECT_TRUE(UnboundFlags(command).empty());
  // --help shows the value that applies without the flag, if given one.
  CommandLine cli("prog override", "");
  OverrideOptions options;
  AddOverrideFlags(&cli, &options);
  const std::string help = cli.app().help();
  EXPECT_NE(help.find("--seed UINT=1 "), std::string::npos) << help;
  EXPECT_NE(help.find("--limit INT "), std::string::npos) << help;
  EXPECT_EQ(help.find("--limit INT="), std::string::npos) << help;
}

TEST(UnboundFlags, EveryFlagOfABoundCommandWritesItsOwnField) {
  EXPECT_TRUE(UnboundFlags(Example()).empty());
}

// An optional x,y,z and a repeatable flag with its own reader.
struct ListOptions {
  std::optional<Eigen::Vector3d> target;
  std::vector<int> levels = {0};
  void Check() const {}
};
void AddListFlags(CommandLine* cli, ListOptions* options) {
  cli->Add("--target", &options->target, "Target");
  cli->AddRepeated<int>(
      "--level", &options->levels, "Level, repeatable",
      [](const std::string& text) {
        if (text.empty() ||
            text.find_first_not_of("0123456789") != std::string::npos) {
          throw ErrorAt("--level: '", text, "' is not a level");
        }
        return std::stoi(text);
      },
      [](const int& level) { return std::to_string(level); });
}
ListOptions last_list;
void RunList(const ListOptions& options) { last_list = options; }

TEST(CommandLine, OptionalVectorsAndRepeatableFlags) {
  const Subcommand list =
      MakeSubcommand<ListOptions>("list", "", "", AddListFlags, RunList);
  last_list = {};
  ASSERT_EQ(RunCommandLine(list, {}), 0);
  EXPECT_FALSE(last_list.target.has_value());
  EXPECT_EQ(last_list.levels, std::vector<int>{0});
  ASSERT_EQ(RunCommandLine(
                list, {"--target", "1,2,3", "--level", "4", "--level", "5"}),
            0);
  EXPECT_EQ(last_list.target, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(last_list.levels, (std::vector<int>{4, 5}));
  EXPECT_EQ(RunCommandLine(list, {"--target", "1,2"}), 1);
  EXPECT_EQ(RunCommandLine(list, {"--level", "x"}), 1);
  EXPECT_TRUE(UnboundFlags(list).empty());
  CommandLine cli("prog list", "");
  ListOptions options;
  AddListFlags(&cli, &options);
  ExpectErrorContaining([&] { cli.app().parse("--target 1,x,3", false); },
                        "--target: expected three numbers x,y,z, got '1,x,3'");
}

struct LooseOptions {
  int bound = 0;
  int shared = 0;
  int width = 0;
  void Check() const {}
};
void AddLooseFlags(CommandLine* cli, LooseOptions* options) {
  static int outside = 0;
  cli->Add("--bound", &options->bound, "");
  cli->Add("--outside", &outside, "");  // not a field of the options
  cli->app().add_option("--raw", options->bound, "");  // not bound at all
  cli->Add("--shared", &options->shared, "");
  cli->Add("--shared_again", &options->shared, "");  // the same field
  cli->AddIntegers("--size", {&options->width, &outside}, "W,H", "");
}
void RunLoose(const LooseOptions&) {}

TEST(UnboundFlags, NamesFlagsOutsideTheOptionsUnboundOrShared) {
  const Subcommand loose =
      MakeSubcommand<LooseOptions>("loose", "", "", AddLooseFlags, RunLoose);
  EXPECT_EQ(UnboundFlags(loose),
            (std::vector<std::string>{"--outside", "--raw", "--shared_again",
                                      "--size"}));
}

}  // namespace
}  // namespace uw
