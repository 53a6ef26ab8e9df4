#pragma once
// One helper thread that lends the pipeline's independent tasks the machine's other core
// (StereoPipeline::set_task_runner). The calling thread takes part: tasks are claimed one at a
// time by whichever of the two threads is free, so when the helper cannot get a core (the
// machine busy) the caller simply runs every task itself, as the pipeline would in turn, and
// never waits for a helper that has not started.

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace stereoball::ball_detector {

/// Runs task(0) .. task(n - 1) on the calling thread and one helper thread; returns when all are
/// done, rethrowing the first exception a task threw. A call made from inside a task (nested)
/// runs its tasks in turn.
class TaskHelper {
 public:
  TaskHelper();
  ~TaskHelper();
  TaskHelper(const TaskHelper&) = delete;
  TaskHelper& operator=(const TaskHelper&) = delete;

  void run(int n, const std::function<void(int)>& task);
  /// Threads that run a job's tasks: the caller's and the helper.
  static constexpr int kThreads = 2;

 private:
  void helper_loop();
  // Claims and runs the job's tasks until none is left; call with lock held, returns with it.
  void work(std::unique_lock<std::mutex>& lock);

  std::mutex mutex_;
  std::condition_variable wake_;                    // the helper: a job or the end
  std::condition_variable idle_;                    // the caller: the helper left the job
  const std::function<void(int)>* task_ = nullptr;  // the job in progress, or none
  int n_ = 0, next_ = 0, running_ = 0;
  std::uint64_t job_ = 0;  // number of the job in progress
  bool stopping_ = false;
  std::exception_ptr failed_;  // the first exception a task of the job threw
  std::thread helper_;
};

}  // namespace stereoball::ball_detector
