#include "ball_detector/node/frame_times.hpp"

#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>

namespace stereoball::ball_detector {
namespace {

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

int this_tid() {
  return static_cast<int>(syscall(SYS_gettid));
}

double ms(std::int64_t ns) {
  return static_cast<double>(ns) * 1e-6;
}

}  // namespace

ThreadSched thread_sched(int tid) {
  const std::string path = "/proc/self/task/" + std::to_string(tid) + "/schedstat";
  ThreadSched s;
  if (FILE* f = std::fopen(path.c_str(), "r")) {
    long long run = 0, wait = 0;
    if (std::fscanf(f, "%lld %lld", &run, &wait) == 2) s = {run, wait};
    std::fclose(f);
  }
  return s;
}

FrameTimesLog::FrameTimesLog(const std::string& path) : out_(path, std::ios::trunc) {
  // jobs:
  // tasks:helper_tasks:start:wall:caller_delay:caller_busy:caller_cpu:caller_wait:helper_delay:
  // helper_busy:helper_cpu; searches: path:thread(m/h):start:wall:cpu; ms, starts from the
  // frame's processing start.
  out_ << "start_mono_ns,seq,status,search,capture_to_publish_ms,publish_to_callback_ms,decode_ms,"
          "search_ms,"
          "publish_ms,main_cpu_ms,main_runq_ms,helper_cpu_ms,helper_runq_ms,jobs,searches\n";
}

void FrameTimesLog::arrived(std::uint64_t seq, std::int64_t capture_ns, std::int64_t published_ns,
                            int helper_tid) {
  helper_tid_ = helper_tid;
  arrived_wall_ns_ = clock_ns(CLOCK_REALTIME);
  start_ns_ = clock_ns(CLOCK_MONOTONIC);
  seq_ = seq;
  capture_ns_ = capture_ns;
  published_ns_ = published_ns;
  main_tid_ = this_tid();
  main_start_ = thread_sched(main_tid_);
  helper_start_ = thread_sched(helper_tid_);
  decoded_ns_ = stepped_ns_ = start_ns_;
  std::lock_guard<std::mutex> lock(searches_mutex_);
  searches_.clear();
}

void FrameTimesLog::decoded() {
  decoded_ns_ = clock_ns(CLOCK_MONOTONIC);
}

void FrameTimesLog::stepped() {
  stepped_ns_ = clock_ns(CLOCK_MONOTONIC);
}

void FrameTimesLog::search(SearchPath path, bool started) {
  const std::int64_t now_ns = clock_ns(CLOCK_MONOTONIC);
  const std::int64_t cpu_ns = clock_ns(CLOCK_THREAD_CPUTIME_ID);
  const bool on_helper = this_tid() == helper_tid_;
  std::lock_guard<std::mutex> lock(searches_mutex_);
  if (started) {
    searches_.push_back({path, on_helper, now_ns, 0, cpu_ns});
    return;
  }
  // The latest open search of this path on this thread ends (nested searches are other paths).
  for (auto it = searches_.rbegin(); it != searches_.rend(); ++it) {
    if (it->path == path && it->on_helper == on_helper && it->end_ns == 0) {
      it->end_ns = now_ns;
      it->cpu_ns = cpu_ns - it->cpu_ns;
      return;
    }
  }
}

void FrameTimesLog::published(int status, SearchPath last_search,
                              const std::vector<JobTimes>& jobs) {
  const std::int64_t end_ns = clock_ns(CLOCK_MONOTONIC);
  const ThreadSched main_end = thread_sched(main_tid_), helper_end = thread_sched(helper_tid_);
  char line[512];
  std::snprintf(
      line, sizeof line, "%lld,%llu,%d,%s,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,",
      static_cast<long long>(start_ns_), static_cast<unsigned long long>(seq_), status,
      to_string(last_search), ms(published_ns_ - capture_ns_), ms(arrived_wall_ns_ - published_ns_),
      ms(decoded_ns_ - start_ns_), ms(stepped_ns_ - decoded_ns_), ms(end_ns - stepped_ns_),
      ms(main_end.run_ns - main_start_.run_ns), ms(main_end.wait_ns - main_start_.wait_ns),
      ms(helper_end.run_ns - helper_start_.run_ns), ms(helper_end.wait_ns - helper_start_.wait_ns));
  out_ << line;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const JobTimes& j = jobs[i];
    std::snprintf(line, sizeof line, "%s%d:%d:%.3f:%.3f:%.3f:%.3f:%.3f:%.3f:%.3f:%.3f:%.3f",
                  i ? ";" : "", j.tasks, j.helper_tasks, ms(j.start_ns - start_ns_),
                  ms(j.end_ns - j.start_ns), ms(j.caller_delay_ns), ms(j.caller_busy_ns),
                  ms(j.caller_cpu_ns), ms(j.caller_wait_ns),
                  j.helper_delay_ns < 0 ? -1.0 : ms(j.helper_delay_ns), ms(j.helper_busy_ns),
                  ms(j.helper_cpu_ns));
    out_ << line;
  }
  out_ << ',';
  std::lock_guard<std::mutex> lock(searches_mutex_);
  for (std::size_t i = 0; i < searches_.size(); ++i) {
    const SearchTimes& s = searches_[i];
    std::snprintf(line, sizeof line, "%s%s:%c:%.3f:%.3f:%.3f", i ? ";" : "", to_string(s.path),
                  s.on_helper ? 'h' : 'm', ms(s.start_ns - start_ns_), ms(s.end_ns - s.start_ns),
                  ms(s.cpu_ns));
    out_ << line;
  }
  out_ << '\n';
  out_.flush();
}

}  // namespace stereoball::ball_detector
