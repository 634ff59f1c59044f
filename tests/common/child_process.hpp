// A program a test runs as a child process: fork + exec, with environment settings and stdout / stderr
// sent to files or a descriptor. The test owns it: stop() asks it to end and says how it ended; the
// destructor kills (SIGKILL) and reaps whatever still runs, so a failed assertion leaves no process behind.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace hg::test {

// How to start it: ChildOptions().set_env("NAME", "value").stdout_to("out.txt"), and so on.
struct ChildOptions {
  std::vector<std::pair<std::string, std::string>> env;  // set in the child before exec
  std::string stdout_path, stderr_path;                  // when set: written there (truncated)
  int stdout_fd = -1;                                    // when >= 0: stdout goes to this descriptor
  bool search_path = false;                              // argv[0] looked up in PATH (execvp), not a path

  ChildOptions& set_env(std::string name, std::string value) {
    env.emplace_back(std::move(name), std::move(value));
    return *this;
  }
  ChildOptions& stdout_to(std::string path) {
    stdout_path = std::move(path);
    return *this;
  }
  ChildOptions& stderr_to(std::string path) {
    stderr_path = std::move(path);
    return *this;
  }
  ChildOptions& stdout_to_fd(int fd) {
    stdout_fd = fd;
    return *this;
  }
  ChildOptions& search_in_path() {
    search_path = true;
    return *this;
  }
};

// Exit code, or 128 + the number of the signal that ended it (the shell's convention).
inline int exit_code(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status); }

class ChildProcess {
 public:
  ChildProcess() = default;
  explicit ChildProcess(const std::vector<std::string>& argv, const ChildOptions& o = {}) {
    pid_ = fork();
    if (pid_ != 0) return;
    for (const auto& [name, value] : o.env) setenv(name.c_str(), value.c_str(), 1);
    auto redirect = [](const std::string& path, int fd) {
      const int f = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (f >= 0) dup2(f, fd), close(f);
    };
    if (o.stdout_fd >= 0) dup2(o.stdout_fd, 1);
    if (!o.stdout_path.empty()) redirect(o.stdout_path, 1);
    if (!o.stderr_path.empty()) redirect(o.stderr_path, 2);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    if (o.search_path) execvp(args[0], args.data());
    else
      execv(args[0], args.data());
    _exit(127);
  }
  ChildProcess(ChildProcess&& other) noexcept : pid_(std::exchange(other.pid_, -1)) {}
  ChildProcess& operator=(ChildProcess&& other) noexcept {
    if (this != &other) kill_now(), pid_ = std::exchange(other.pid_, -1);
    return *this;
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess() { kill_now(); }

  pid_t pid() const { return pid_; }
  bool started() const { return pid_ > 0; }
  void signal(int sig) const {
    if (pid_ > 0) ::kill(pid_, sig);
  }
  // Its exit code once it has ended within `limit` (reaped then), nullopt while it still runs.
  std::optional<int> wait(std::chrono::milliseconds limit = std::chrono::milliseconds(0)) {
    if (pid_ <= 0) return std::nullopt;
    const auto end = std::chrono::steady_clock::now() + limit;
    for (;;) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return exit_code(status);
      }
      if (std::chrono::steady_clock::now() >= end) return std::nullopt;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  // Sends `sig`, waits up to `grace` for the end and returns its exit code; past the grace it is killed
  // and the result is -1 (as it is for a process that was never started or has already been reaped).
  int stop(int sig = SIGTERM, std::chrono::milliseconds grace = std::chrono::seconds(10)) {
    if (pid_ <= 0) return -1;
    ::kill(pid_, sig);
    if (const std::optional<int> code = wait(grace)) return *code;
    kill_now();
    return -1;
  }
  void kill_now() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

}  // namespace hg::test
