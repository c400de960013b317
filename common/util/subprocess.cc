#include "common/util/subprocess.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <deque>
#include <fstream>

#include "common/util/error.h"

extern char** environ;

namespace uw {

int RunProgram(const std::vector<std::string>& argv,
               const std::filesystem::path& log_path) {
  if (argv.empty()) {
    throw Error("RunProgram: no program given");
  }
  const int log_fd =
      open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log_fd < 0) {
    throw ErrorAt(log_path.string(), ": cannot open for writing (",
                  std::strerror(errno), ")");
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, log_fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, log_fd, STDERR_FILENO);
  std::vector<char*> args;
  for (const std::string& arg : argv) {
    args.push_back(const_cast<char*>(arg.c_str()));
  }
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawn_error = posix_spawnp(&pid, argv[0].c_str(), &actions, nullptr,
                                       args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(log_fd);
  if (spawn_error != 0) {
    throw ErrorAt("cannot run ", argv[0], ": ", std::strerror(spawn_error));
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      throw ErrorAt("waiting for ", argv[0], ": ", std::strerror(errno));
    }
  }
  if (WIFSIGNALED(status)) {
    return 128 + WTERMSIG(status);
  }
  return WEXITSTATUS(status);
}

std::string TailOfFile(const std::filesystem::path& path, int max_lines) {
  std::ifstream stream(path);
  std::deque<std::string> lines;
  std::string line;
  while (std::getline(stream, line)) {
    lines.push_back(line);
    if (static_cast<int>(lines.size()) > max_lines) {
      lines.pop_front();
    }
  }
  std::string tail;
  for (const std::string& kept : lines) {
    tail += kept + "\n";
  }
  return tail;
}

}  // namespace uw
