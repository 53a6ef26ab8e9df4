#pragma once
// One helper thread that lends the pipeline's independent tasks the machine's other core
// (StereoPipeline::set_task_runner). The calling thread takes part: tasks are claimed one at a
// time by whichever of the two threads is free, so when the helper cannot get a core (the
// machine busy) the caller simply runs every task itself, as the pipeline would in turn, and
// never waits for a helper that has not started.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace stereoball::ball_detector {

/// How one run() of two or more tasks went (monotonic clock and each thread's CPU clock), ns.
struct JobTimes {
  int tasks = 0;                      ///< how many tasks the job had
  int helper_tasks = 0;               ///< how many of them the helper ran
  std::int64_t start_ns = 0;          ///< run() called
  std::int64_t end_ns = 0;            ///< run() returns
  std::int64_t caller_delay_ns = 0;   ///< run() called to the caller's first task
  std::int64_t caller_busy_ns = 0;    ///< the caller in the job's tasks, wall
  std::int64_t caller_cpu_ns = 0;     ///< the caller in the job's tasks, CPU
  std::int64_t caller_wait_ns = 0;    ///< the caller done, waiting for the helper's last task
  std::int64_t helper_delay_ns = -1;  ///< run() called to the helper's first task (-1: none)
  std::int64_t helper_busy_ns = 0;    ///< the helper in the job's tasks, wall
  std::int64_t helper_cpu_ns = 0;     ///< the helper in the job's tasks, CPU
};

/// Runs task(0) .. task(n - 1) on the calling thread and one helper thread; returns when all are
/// done, rethrowing the first exception a task threw. A call made from inside a task (nested)
/// runs its tasks in turn.
class TaskHelper {
 public:
  /// pin: the two threads each on one of the first two CPUs the constructing thread may run on
  /// (thread_pinning.hpp; the helper's at once, the caller's at its first run()); not with fewer
  /// than two such CPUs.
  explicit TaskHelper(bool pin = false);
  ~TaskHelper();
  TaskHelper(const TaskHelper&) = delete;
  TaskHelper& operator=(const TaskHelper&) = delete;

  void run(int n, const std::function<void(int)>& task);
  /// Threads that run a job's tasks: the caller's and the helper.
  static constexpr int kThreads = 2;
  /// Whether run() keeps a JobTimes of each job it shares (off: it reads no clock).
  void record_jobs(bool on);
  /// The jobs recorded since the last call, oldest first.
  std::vector<JobTimes> take_jobs();
  /// The helper thread's kernel id (its /proc/self/task entry).
  int helper_tid() const { return helper_tid_; }
  /// The CPUs the caller's and the helper's threads are pinned to; nullopt when not pinned.
  std::optional<std::pair<int, int>> pinned_cpus() const { return cpus_; }
  /// Why pinning was asked for but not done (fewer than two CPUs, a refused call); empty if it
  /// was done or not asked for. The helper's part is known once its thread has started.
  std::string pin_problem() const;

 private:
  void helper_loop();
  // Pins the calling thread to cpus_->first (once: the thread that calls run()).
  void pin_caller();
  // Claims and runs the job's tasks until none is left; call with lock held, returns with it.
  // helper: the helper thread (else the caller), for the job's times.
  void work(std::unique_lock<std::mutex>& lock, bool helper);

  mutable std::mutex mutex_;
  std::condition_variable wake_;                    // the helper: a job or the end
  std::condition_variable idle_;                    // the caller: the helper left the job
  const std::function<void(int)>* task_ = nullptr;  // the job in progress, or none
  int n_ = 0, next_ = 0, running_ = 0;
  std::uint64_t job_ = 0;  // number of the job in progress
  bool stopping_ = false;
  std::exception_ptr failed_;  // the first exception a task of the job threw
  bool recording_ = false;
  JobTimes job_times_;          // of the job in progress, when recording
  std::vector<JobTimes> jobs_;  // recorded jobs not yet taken
  std::atomic<int> helper_tid_{0};
  std::string pin_problem_;                  // guarded by mutex_; before cpus_, which sets it
  std::optional<std::pair<int, int>> cpus_;  // pinned to (caller, helper); set before helper_
  bool caller_pinned_ = false;               // the caller's pin attempted (run()'s thread only)
  std::thread helper_;
};

}  // namespace stereoball::ball_detector
