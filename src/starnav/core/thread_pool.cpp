#include "starnav/core/thread_pool.hpp"

#include <algorithm>

namespace starnav {

ThreadPool::ThreadPool(unsigned threads) {
  if (threads == 0) threads = std::max(1U, std::thread::hardware_concurrency());
  size_ = std::min(threads, 256U);
  for (unsigned i = 1; i < size_; ++i) workers_.emplace_back([this] { work_loop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ThreadPool::drain(const std::function<void(std::size_t)>* task, std::size_t tasks) {
  std::size_t done = 0;
  for (std::size_t i; (i = next_.fetch_add(1)) < tasks;) {
    try {
      (*task)(i);
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    ++done;
  }
  std::lock_guard lock(mutex_);
  finished_ += done;
  if (finished_ == tasks_) done_.notify_all();
}

void ThreadPool::work_loop() {
  unsigned seen = 0;
  for (;;) {
    const std::function<void(std::size_t)>* task = nullptr;
    std::size_t tasks = 0;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      task = task_;
      tasks = tasks_;
      if (tasks == 0) continue;  // woke after that run had finished
      ++active_;
    }
    drain(task, tasks);
    {
      std::lock_guard lock(mutex_);
      --active_;
    }
    done_.notify_all();
  }
}

void ThreadPool::run(std::size_t tasks, const std::function<void(std::size_t)>& task) {
  if (tasks == 0) return;
  if (workers_.empty() || tasks == 1) {
    for (std::size_t i = 0; i < tasks; ++i) task(i);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    task_ = &task;
    tasks_ = tasks;
    finished_ = 0;
    error_ = nullptr;
    next_.store(0);
    ++generation_;
  }
  wake_.notify_all();
  {
    std::lock_guard lock(mutex_);
    ++active_;
  }
  drain(&task, tasks);
  std::exception_ptr error;
  {
    std::unique_lock lock(mutex_);
    --active_;
    done_.wait(lock, [&] { return finished_ == tasks_ && active_ == 0; });
    // Workers that woke late find no task left; keep them off the next run's counter.
    tasks_ = 0;
    task_ = nullptr;
    error = error_;
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace starnav
