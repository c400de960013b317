#include "common/util/subprocess.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

std::filesystem::path TestLog(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "uw_subprocess_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / name;
  std::filesystem::remove(path);
  return path;
}

TEST(RunProgram, PassesArgumentsUnquotedAndLogsBothStreams) {
  const std::filesystem::path log = TestLog("args.log");
  // A shell would split this argument and expand $HOME.
  const int code = RunProgram(
      {"sh", "-c", "echo \"$1\"; echo err >&2; exit 3", "sh", "a b $HOME"},
      log);
  EXPECT_EQ(code, 3);
  EXPECT_EQ(ReadFileToString(log), "a b $HOME\nerr\n");
  EXPECT_EQ(TailOfFile(log, 1), "err\n");
}

TEST(RunProgram, ReportsSignals) {
  EXPECT_EQ(RunProgram({"sh", "-c", "kill -9 $$"}, TestLog("signal.log")),
            128 + 9);
}

TEST(RunProgram, MissingProgramIsAnErrorNamingIt) {
  try {
    RunProgram({"uw-no-such-program"}, TestLog("missing.log"));
    FAIL() << "expected uw::Error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("uw-no-such-program"),
              std::string::npos);
  }
  EXPECT_THROW(RunProgram({}, TestLog("empty.log")), Error);
}

TEST(RunProcess, CapturesStdoutAndStderrOnlyWhenMerged) {
  const ProcessResult merged =
      RunProcess("echo out; echo err >&2; exit 2", true);
  EXPECT_EQ(merged.exit_code, 2);
  EXPECT_EQ(merged.output, "out\nerr\n");
  const ProcessResult alone = RunProcess("echo out; echo err >&2", false);
  EXPECT_EQ(alone.exit_code, 0);
  EXPECT_EQ(alone.output, "out\n");
}

TEST(RunProcess, RunsShellCommandLines) {
  // Pipes, `cd dir &&`, quoting, and more output than one pipe buffer.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "uw_subprocess_test" / "a dir";
  std::filesystem::create_directories(dir);
  const ProcessResult result = RunProcess(
      "cd '" + dir.string() + "' && pwd && seq 100000 | tail -n 1", false);
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_EQ(result.output, dir.string() + "\n100000\n");
  EXPECT_EQ(RunProcess("seq 100000", false).output.size(), 588895u);
  EXPECT_EQ(RunProcess("kill -9 $$", true).exit_code, 128 + 9);
  EXPECT_EQ(RunProcess("uw-no-such-program", false).exit_code, 127);
}

}  // namespace
}  // namespace uw
