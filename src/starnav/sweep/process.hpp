#pragma once
// Child processes for the sweep runner: a command started as an argument vector (no shell), in a
// folder, with its output in files, in a process group of its own (so a terminal's Ctrl-C reaches
// the runner, which stops its tasks itself), and killed when the runner dies (PR_SET_PDEATHSIG),
// so a runner killed with SIGKILL leaves no task running.
#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace starnav::sweep {

struct ChildSpec {
  std::string executable;  // run instead of argv[0]
  std::vector<std::string> argv;
  std::string cwd;
  std::string stdout_path, stderr_path;  // created (truncated)
};

struct ChildExit {
  int exit_code = -1;  // -1 when ended by a signal
  int signal = 0;
  double cpu_s = 0.0;  // user + system time of the child and the children it waited for
};

class Child {
 public:
  // Starts the child; Error when it cannot be started (the program missing, the folder gone).
  explicit Child(const ChildSpec& spec);
  ~Child();  // kills and reaps a child still running
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  pid_t pid() const { return pid_; }
  // A file descriptor that becomes readable when the child ends (a pidfd), or -1 where the kernel
  // has none (then poll try_wait()).
  int wait_fd() const { return pidfd_; }
  // The exit once the child has ended, without blocking.
  std::optional<ChildExit> try_wait();
  // Sends `sig` to the child's process group.
  void kill_group(int sig) const;
  bool running() const { return !reaped_; }

 private:
  pid_t pid_ = -1;
  int pidfd_ = -1;
  bool reaped_ = false;
};

// Runs `argv` (no shell) to completion and returns its exit code and standard output; nullopt
// when the program cannot be started. For small queries (scontrol, sbatch).
struct CapturedRun {
  int exit_code = -1;
  std::string out, err;
};
std::optional<CapturedRun> run_and_capture(const std::vector<std::string>& argv);

// This machine's host name ("localhost" when unknown).
std::string host_name();

}  // namespace starnav::sweep
