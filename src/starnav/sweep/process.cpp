#include "starnav/sweep/process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"

namespace starnav::sweep {

namespace {

// Only async-signal-safe calls between fork and exec: everything is prepared before the fork.
struct PreparedExec {
  std::vector<std::string> storage;
  std::vector<char*> argv;
};

PreparedExec prepare(const std::vector<std::string>& args) {
  PreparedExec p;
  p.storage = args;
  for (std::string& s : p.storage) p.argv.push_back(s.data());
  p.argv.push_back(nullptr);
  return p;
}

void write_errno_and_exit(int fd, int err) {
  [[maybe_unused]] const ssize_t n = ::write(fd, &err, sizeof err);
  ::_exit(127);
}

int open_pidfd(pid_t pid) {
#ifdef SYS_pidfd_open
  const long fd = ::syscall(SYS_pidfd_open, pid, 0);
  if (fd >= 0) {
    ::fcntl(static_cast<int>(fd), F_SETFD, FD_CLOEXEC);
    return static_cast<int>(fd);
  }
#endif
  (void)pid;
  return -1;
}

double seconds(const timeval& tv) { return static_cast<double>(tv.tv_sec) + static_cast<double>(tv.tv_usec) * 1e-6; }

}  // namespace

Child::Child(const ChildSpec& spec) {
  std::vector<std::string> args = spec.argv;
  if (args.empty()) throw Error("empty command");
  const std::string program = spec.executable.empty() ? args[0] : spec.executable;
  PreparedExec exec = prepare(args);
  const std::string cwd = spec.cwd;
  const std::string out_path = spec.stdout_path, err_path = spec.stderr_path;
  int status_pipe[2];
  if (::pipe2(status_pipe, O_CLOEXEC) != 0) throw Error(std::string("cannot create a pipe: ") + std::strerror(errno));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(status_pipe[0]);
    ::close(status_pipe[1]);
    throw Error(std::string("cannot start a process: ") + std::strerror(err));
  }
  if (pid == 0) {
    ::close(status_pipe[0]);
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the runner died before the line above
    // Signals the runner ignores or blocks stay so in the child otherwise.
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGQUIT}) ::signal(sig, SIG_DFL);
    if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) write_errno_and_exit(status_pipe[1], errno);
    const int in = ::open("/dev/null", O_RDONLY);
    const int out = ::open(out_path.empty() ? "/dev/null" : out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
    const int err = ::open(err_path.empty() ? "/dev/null" : err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (in < 0 || out < 0 || err < 0) write_errno_and_exit(status_pipe[1], errno);
    if (::dup2(in, 0) < 0 || ::dup2(out, 1) < 0 || ::dup2(err, 2) < 0) write_errno_and_exit(status_pipe[1], errno);
    ::execv(program.c_str(), exec.argv.data());
    write_errno_and_exit(status_pipe[1], errno);
  }
  ::close(status_pipe[1]);
  // The pipe closes at exec (CLOEXEC) with nothing written, or carries the errno of the failure.
  int child_errno = 0;
  ssize_t n;
  do {
    n = ::read(status_pipe[0], &child_errno, sizeof child_errno);
  } while (n < 0 && errno == EINTR);
  ::close(status_pipe[0]);
  pid_ = pid;
  if (n > 0) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    reaped_ = true;
    throw Error("cannot run " + program + (cwd.empty() ? "" : " in " + cwd) + ": " + std::strerror(child_errno));
  }
  pidfd_ = open_pidfd(pid);
}

Child::~Child() {
  if (!reaped_ && pid_ > 0) {
    kill_group(SIGKILL);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  if (pidfd_ >= 0) ::close(pidfd_);
}

std::optional<ChildExit> Child::try_wait() {
  if (reaped_) return std::nullopt;
  // Seen ended but not reaped yet: its process id stays reserved, so the group it led (anything
  // the task started) can be killed without hitting a process that reused the id.
  siginfo_t info{};
  int w;
  do {
    w = ::waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT);
  } while (w < 0 && errno == EINTR);
  if (w == 0 && info.si_pid == 0) return std::nullopt;
  ::kill(-pid_, SIGKILL);
  int status = 0;
  rusage usage{};
  pid_t r;
  do {
    r = ::wait4(pid_, &status, 0, &usage);
  } while (r < 0 && errno == EINTR);
  reaped_ = true;
  ChildExit e;
  if (r < 0) return e;  // reaped by someone else: nothing is known
  e.cpu_s = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  if (WIFEXITED(status)) e.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) e.signal = WTERMSIG(status);
  return e;
}

void Child::kill_group(int sig) const {
  if (pid_ > 0 && !reaped_) {
    ::kill(-pid_, sig);
    ::kill(pid_, sig);
  }
}

std::optional<CapturedRun> run_and_capture(const std::vector<std::string>& argv) {
  if (argv.empty()) return std::nullopt;
  // Find the program on PATH (execv does not search).
  std::string program = argv[0];
  if (program.find('/') == std::string::npos) {
    const char* path = std::getenv("PATH");
    std::string found;
    std::string dirs = path ? path : "/usr/bin:/bin";
    for (std::size_t start = 0; start <= dirs.size();) {
      const std::size_t end = std::min(dirs.find(':', start), dirs.size());
      const std::string candidate = (end > start ? dirs.substr(start, end - start) : ".") + "/" + program;
      if (::access(candidate.c_str(), X_OK) == 0) {
        found = candidate;
        break;
      }
      start = end + 1;
    }
    if (found.empty()) return std::nullopt;
    program = found;
  }
  char out_name[] = "/tmp/starnav_capture_out_XXXXXX";
  char err_name[] = "/tmp/starnav_capture_err_XXXXXX";
  const int out_fd = ::mkstemp(out_name);
  const int err_fd = ::mkstemp(err_name);
  if (out_fd >= 0) ::close(out_fd);
  if (err_fd >= 0) ::close(err_fd);
  if (out_fd < 0 || err_fd < 0) return std::nullopt;
  CapturedRun r;
  try {
    Child child({program, argv, "", out_name, err_name});
    std::optional<ChildExit> e;
    while (!(e = child.try_wait())) {
      pollfd p{child.wait_fd(), POLLIN, 0};
      if (child.wait_fd() >= 0) ::poll(&p, 1, 1000);
      else ::usleep(10000);
    }
    r.exit_code = e->exit_code;
  } catch (const Error&) {
    std::remove(out_name);
    std::remove(err_name);
    return std::nullopt;
  }
  try {
    r.out = read_input_file(out_name, std::uint64_t{1} << 26);
    r.err = read_input_file(err_name, std::uint64_t{1} << 26);
  } catch (const Error&) {
    std::remove(out_name);
    std::remove(err_name);
    throw;
  }
  std::remove(out_name);
  std::remove(err_name);
  return r;
}

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0 || buf[0] == '\0') return "localhost";
  return buf;
}

}  // namespace starnav::sweep
