#include "ball_detector/node/task_helper.hpp"

#include "ball_detector/node/thread_pinning.hpp"

#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <exception>
#include <utility>

namespace stereoball::ball_detector {
namespace {

// Set on a thread while it runs a task: a nested run() then goes in turn (one job at a time).
thread_local bool in_task = false;

void run_in_turn(int n, const std::function<void(int)>& task) {
  for (int i = 0; i < n; ++i) task(i);
}

std::int64_t read_clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

namespace {

// The CPUs a TaskHelper asked to pin uses, or the reason there are none.
std::optional<std::pair<int, int>> cpus_to_pin(bool pin, std::string& problem) {
  if (!pin) return std::nullopt;
  const std::vector<int> allowed = allowed_cpus();
  auto two = first_two_cpus(allowed);
  if (!two)
    problem = "not pinned: " + std::to_string(allowed.size()) + " CPU(s) allowed, two needed";
  return two;
}

}  // namespace

TaskHelper::TaskHelper(bool pin)
    : cpus_(cpus_to_pin(pin, pin_problem_)), helper_([this] { helper_loop(); }) {}

std::string TaskHelper::pin_problem() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pin_problem_;
}

void TaskHelper::pin_caller() {
  caller_pinned_ = true;
  if (!cpus_) return;
  if (std::string problem = pin_thread(0, cpus_->first); !problem.empty()) {
    std::lock_guard<std::mutex> lock(mutex_);
    pin_problem_ += (pin_problem_.empty() ? "caller: " : "; caller: ") + problem;
  }
}

void TaskHelper::record_jobs(bool on) {
  std::lock_guard<std::mutex> lock(mutex_);
  recording_ = on;
}

std::vector<JobTimes> TaskHelper::take_jobs() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(jobs_, {});
}

TaskHelper::~TaskHelper() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  helper_.join();
}

void TaskHelper::run(int n, const std::function<void(int)>& task) {
  if (in_task) return run_in_turn(n, task);
  if (!caller_pinned_) pin_caller();
  if (n <= 1) return run_in_turn(n, task);
  std::unique_lock<std::mutex> lock(mutex_);
  task_ = &task;
  n_ = n;
  next_ = 0;
  ++job_;
  if (recording_) job_times_ = JobTimes{n, 0, read_clock_ns(CLOCK_MONOTONIC)};
  wake_.notify_one();
  work(lock, false);
  // Every task is claimed; wait only for those the helper took and is still running.
  const std::int64_t waiting_ns = recording_ ? read_clock_ns(CLOCK_MONOTONIC) : 0;
  idle_.wait(lock, [&] { return running_ == 0; });
  task_ = nullptr;
  if (recording_) {
    job_times_.end_ns = read_clock_ns(CLOCK_MONOTONIC);
    job_times_.caller_wait_ns = job_times_.end_ns - waiting_ns;
    jobs_.push_back(job_times_);
  }
  if (auto failed = std::exchange(failed_, nullptr)) std::rethrow_exception(failed);
}

void TaskHelper::work(std::unique_lock<std::mutex>& lock, bool helper) {
  const std::function<void(int)>& task = *task_;
  const bool timed = recording_;
  const std::int64_t wall_ns = timed ? read_clock_ns(CLOCK_MONOTONIC) : 0;
  const std::int64_t cpu_ns = timed ? read_clock_ns(CLOCK_THREAD_CPUTIME_ID) : 0;
  if (timed && helper && next_ < n_) job_times_.helper_delay_ns = wall_ns - job_times_.start_ns;
  if (timed && !helper) job_times_.caller_delay_ns = wall_ns - job_times_.start_ns;
  int ran = 0;
  while (next_ < n_) {
    const int i = next_++;
    ++ran;
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
  if (!timed) return;
  // Written under the lock before the caller can see the job end (running_ == 0).
  const std::int64_t busy_ns = read_clock_ns(CLOCK_MONOTONIC) - wall_ns;
  const std::int64_t used_ns = read_clock_ns(CLOCK_THREAD_CPUTIME_ID) - cpu_ns;
  if (helper) {
    job_times_.helper_tasks += ran;
    job_times_.helper_busy_ns += busy_ns;
    job_times_.helper_cpu_ns += used_ns;
  } else {
    job_times_.caller_busy_ns += busy_ns;
    job_times_.caller_cpu_ns += used_ns;
  }
}

void TaskHelper::helper_loop() {
  helper_tid_ = static_cast<int>(syscall(SYS_gettid));
  std::unique_lock<std::mutex> lock(mutex_);
  if (cpus_)
    if (std::string problem = pin_thread(0, cpus_->second); !problem.empty())
      pin_problem_ += (pin_problem_.empty() ? "helper: " : "; helper: ") + problem;
  std::uint64_t done = 0;
  while (true) {
    wake_.wait(lock, [&] { return stopping_ || (task_ && job_ != done && next_ < n_); });
    if (stopping_) return;
    done = job_;
    work(lock, true);
    idle_.notify_one();
  }
}

}  // namespace stereoball::ball_detector
