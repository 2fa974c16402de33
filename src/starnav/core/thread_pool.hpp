#pragma once
// A small fixed pool of worker threads for data-parallel loops whose result must not depend on
// the number of threads: work is cut into tasks by the caller (fixed-size chunks), every task
// writes its own slot, and the caller combines the slots in task order. With one thread the
// tasks run inline on the caller's thread.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace starnav {

class ThreadPool {
 public:
  // `threads` workers in all, the caller counted (0: one per hardware thread).
  explicit ThreadPool(unsigned threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  unsigned size() const { return size_; }
  // Calls task(i) once for every i in [0, tasks), spread over the threads; returns when all are
  // done. The first exception thrown by a task is rethrown here.
  void run(std::size_t tasks, const std::function<void(std::size_t)>& task);

 private:
  void work_loop();
  void drain(const std::function<void(std::size_t)>* task, std::size_t tasks);

  unsigned size_ = 1;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(std::size_t)>* task_ = nullptr;
  std::size_t tasks_ = 0;
  std::atomic<std::size_t> next_{0};
  std::size_t finished_ = 0;
  unsigned active_ = 0;  // workers inside drain(); run() returns only when none is
  unsigned generation_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
};

}  // namespace starnav
