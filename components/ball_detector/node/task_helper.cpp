#include "ball_detector/node/task_helper.hpp"

#include <exception>
#include <utility>

namespace stereoball::ball_detector {
namespace {

// Set on a thread while it runs a task: a nested run() then goes in turn (one job at a time).
thread_local bool in_task = false;

void run_in_turn(int n, const std::function<void(int)>& task) {
  for (int i = 0; i < n; ++i) task(i);
}

}  // namespace

TaskHelper::TaskHelper() : helper_([this] { helper_loop(); }) {}

TaskHelper::~TaskHelper() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  helper_.join();
}

void TaskHelper::run(int n, const std::function<void(int)>& task) {
  if (n <= 1 || in_task) return run_in_turn(n, task);
  std::unique_lock<std::mutex> lock(mutex_);
  task_ = &task;
  n_ = n;
  next_ = 0;
  ++job_;
  wake_.notify_one();
  work(lock);
  // Every task is claimed; wait only for those the helper took and is still running.
  idle_.wait(lock, [&] { return running_ == 0; });
  task_ = nullptr;
  if (auto failed = std::exchange(failed_, nullptr)) std::rethrow_exception(failed);
}

void TaskHelper::work(std::unique_lock<std::mutex>& lock) {
  const std::function<void(int)>& task = *task_;
  while (next_ < n_) {
    const int i = next_++;
    ++running_;
    lock.unlock();
    in_task = true;
    std::exception_ptr failed;
    try {
      task(i);
    } catch (...) {
      failed = std::current_exception();  // rethrown by run(), on the caller's thread
    }
    in_task = false;
    lock.lock();
    if (failed && !failed_) failed_ = failed;
    --running_;
  }
}

void TaskHelper::helper_loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  std::uint64_t done = 0;
  while (true) {
    wake_.wait(lock, [&] { return stopping_ || (task_ && job_ != done && next_ < n_); });
    if (stopping_) return;
    done = job_;
    work(lock);
    idle_.notify_one();
  }
}

}  // namespace stereoball::ball_detector
