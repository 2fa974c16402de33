#pragma once
// CPU time of the calling thread, in seconds: what a computation costs on one core, whatever else
// a shared machine runs meanwhile (wall time is disturbed by it far more).
#include <time.h>

namespace starnav {

inline double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Adds the thread CPU time of its scope to a counter (seconds).
class ScopedCpuTimer {
 public:
  explicit ScopedCpuTimer(double& total) : total_(total), start_(thread_cpu_s()) {}
  ~ScopedCpuTimer() { total_ += thread_cpu_s() - start_; }
  ScopedCpuTimer(const ScopedCpuTimer&) = delete;
  ScopedCpuTimer& operator=(const ScopedCpuTimer&) = delete;

 private:
  double& total_;
  double start_;
};

}  // namespace starnav
