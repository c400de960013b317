#include "common/util/subprocess.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <deque>
#include <fstream>

#include "common/util/error.h"

extern char** environ;

namespace uw {
namespace {

// Starts argv[0] (on PATH) with its stdout and stderr on the given
// descriptors, and waits for it; the caller's `while_running` runs in
// between (reading a pipe the program writes to). Returns the exit code, or
// 128 + the signal number.
template <typename WhileRunning>
int Spawn(const std::vector<std::string>& argv, int stdout_fd, int stderr_fd,
          WhileRunning&& while_running) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, stdout_fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, stderr_fd, STDERR_FILENO);
  std::vector<char*> args;
  for (const std::string& arg : argv) {
    args.push_back(const_cast<char*>(arg.c_str()));
  }
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawn_error = posix_spawnp(&pid, argv[0].c_str(), &actions, nullptr,
                                       args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error != 0) {
    throw ErrorAt("cannot run ", argv[0], ": ", std::strerror(spawn_error));
  }
  while_running();
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

// Closes a descriptor when it goes out of scope (also when Spawn throws).
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() { Close(); }
  int fd() const { return fd_; }
  void Close() {
    if (fd_ >= 0) close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

}  // namespace

int RunProgram(const std::vector<std::string>& argv,
               const std::filesystem::path& log_path) {
  if (argv.empty()) {
    throw Error("RunProgram: no program given");
  }
  const Descriptor log(
      open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644));
  if (log.fd() < 0) {
    throw ErrorAt(log_path.string(), ": cannot open for writing (",
                  std::strerror(errno), ")");
  }
  return Spawn(argv, log.fd(), log.fd(), [] {});
}

ProcessResult RunProcess(const std::string& command, bool merge_stderr) {
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0) {
    throw ErrorAt("cannot run '", command, "': no pipe (", std::strerror(errno),
                  ")");
  }
  Descriptor read_end(pipe_fds[0]);
  Descriptor write_end(pipe_fds[1]);
  const Descriptor null(merge_stderr ? -1
                                     : open("/dev/null", O_WRONLY | O_CLOEXEC));
  if (!merge_stderr && null.fd() < 0) {
    throw ErrorAt("/dev/null: cannot open for writing (", std::strerror(errno),
                  ")");
  }
  ProcessResult result;
  result.exit_code = Spawn({"/bin/sh", "-c", command}, write_end.fd(),
                           merge_stderr ? write_end.fd() : null.fd(), [&] {
                             // Only the program holds the write end now: EOF
                             // when it ends.
                             write_end.Close();
                             std::array<char, 4096> buffer;
                             while (true) {
                               const ssize_t count = read(
                                   read_end.fd(), buffer.data(), buffer.size());
                               if (count > 0) {
                                 result.output.append(buffer.data(), count);
                               } else if (count == 0 || errno != EINTR) {
                                 break;
                               }
                             }
                           });
  return result;
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
