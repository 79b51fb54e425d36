#include "gnuplot_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace rayspace::plot {
namespace {

void Pipe(int fds[2]) {
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
}

// The child: stdin, stdout, stderr onto the pipes, then exec; 127 when exec fails. Only
// async-signal-safe calls here (the parent may have threads), so `args` is built before the fork.
[[noreturn]] void Child(char* const* args, int in, int out, int err) {
  ::dup2(in, 0);
  ::dup2(out, 1);
  ::dup2(err, 2);
  ::execvp(args[0], args);
  ::_exit(127);
}

// Feeds `input` and drains both outputs at once, so that neither side blocks on a full pipe.
void Exchange(int in, int out, int err, const std::string& input, ProcessResult& r) {
  std::size_t written = 0;
  if (input.empty()) ::close(in), in = -1;
  char buf[65536];
  while (out >= 0 || err >= 0) {
    pollfd fds[3] = {{in, POLLOUT, 0}, {out, POLLIN, 0}, {err, POLLIN, 0}};
    if (::poll(fds, 3, -1) < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error("poll failed");
    }
    if (in >= 0 && (fds[0].revents & (POLLOUT | POLLERR | POLLHUP))) {
      const ssize_t n = ::write(in, input.data() + written, input.size() - written);
      if (n > 0) written += static_cast<std::size_t>(n);
      if (n < 0 || written == input.size()) ::close(in), in = -1;  // n < 0: the reader is gone
    }
    int* fd[2] = {&out, &err};
    std::string* sink[2] = {&r.out, &r.err};
    for (int k = 0; k < 2; ++k)
      if (*fd[k] >= 0 && (fds[k + 1].revents & (POLLIN | POLLERR | POLLHUP))) {
        const ssize_t n = ::read(*fd[k], buf, sizeof buf);
        if (n > 0) sink[k]->append(buf, static_cast<std::size_t>(n));
        else if (n == 0 || errno != EINTR) ::close(*fd[k]), *fd[k] = -1;
      }
  }
  if (in >= 0) ::close(in);
}

}  // namespace

ProcessResult RunProcess(const std::vector<std::string>& argv, const std::string& input) {
  int in[2], out[2], err[2];
  Pipe(in);
  Pipe(out);
  Pipe(err);
  // A reader that exits early must not kill us with SIGPIPE: the write fails with EPIPE instead.
  struct sigaction ignore {}, old{};
  ignore.sa_handler = SIG_IGN;
  ::sigaction(SIGPIPE, &ignore, &old);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) Child(args.data(), in[0], out[1], err[1]);
  ::close(in[0]);
  ::close(out[1]);
  ::close(err[1]);
  ProcessResult r;
  if (pid < 0) {
    ::close(in[1]), ::close(out[0]), ::close(err[0]);
    ::sigaction(SIGPIPE, &old, nullptr);
    throw std::runtime_error("fork failed");
  }
  Exchange(in[1], out[0], err[0], input, r);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
  ::sigaction(SIGPIPE, &old, nullptr);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.started = r.exit_code != 127 || OnPath(argv[0]);
  return r;
}

bool OnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string dirs = path;
  for (std::size_t start = 0; start <= dirs.size();) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::filesystem::path candidate = std::filesystem::path(dirs.substr(start, end - start)) / name;
    if (::access(candidate.c_str(), X_OK) == 0 && std::filesystem::is_regular_file(candidate)) return true;
    start = end + 1;
  }
  return false;
}

}  // namespace rayspace::plot
