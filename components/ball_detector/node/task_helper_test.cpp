// TaskHelper: the pipeline's tasks on the caller and one helper thread.

#include "ball_detector/node/task_helper.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <thread>
#include <vector>

namespace stereoball::ball_detector {
namespace {

TEST(TaskHelper, GivenManyJobsThenEveryTaskRunsExactlyOnce) {
  // Given a helper
  TaskHelper helper;
  for (int job = 0; job < 200; ++job) {
    // When a job of n tasks runs (n from 0 to 9)
    const int n = job % 10;
    std::vector<std::atomic<int>> runs(static_cast<std::size_t>(n));
    helper.run(n, [&](int i) { runs[static_cast<std::size_t>(i)]++; });
    // Then each task ran once, and all had finished when run returned
    for (int i = 0; i < n; ++i) ASSERT_EQ(runs[static_cast<std::size_t>(i)].load(), 1) << job;
  }
}

TEST(TaskHelper, GivenSlowTasksThenBothThreadsTakePart) {
  // Given tasks that take a while each
  TaskHelper helper;
  std::vector<std::thread::id> ran_on(8);
  // When they run
  helper.run(8, [&](int i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ran_on[static_cast<std::size_t>(i)] = std::this_thread::get_id();
  });
  // Then the caller ran some and the helper the others
  int on_caller = 0;
  for (const auto& id : ran_on) on_caller += id == std::this_thread::get_id() ? 1 : 0;
  EXPECT_GT(on_caller, 0);
  EXPECT_LT(on_caller, 8);
}

TEST(TaskHelper, GivenATaskThatRunsTasksThenTheInnerOnesRunInTurnOnItsThread) {
  // Given a job whose tasks start jobs of their own
  TaskHelper helper;
  std::atomic<int> inner{0};
  std::atomic<bool> other_thread{false};
  helper.run(2, [&](int) {
    const auto outer_id = std::this_thread::get_id();
    helper.run(3, [&](int) {
      ++inner;
      if (std::this_thread::get_id() != outer_id) other_thread = true;
    });
  });
  // Then every inner task ran, each on the thread of the task that started it
  EXPECT_EQ(inner.load(), 6);
  EXPECT_FALSE(other_thread.load());
}

TEST(TaskHelper, GivenATaskThatThrowsThenRunRethrowsAndTheHelperStillWorks) {
  // Given a job one of whose tasks throws
  TaskHelper helper;
  std::atomic<int> done{0};
  EXPECT_THROW(helper.run(4,
                          [&](int i) {
                            if (i == 2) throw std::runtime_error("task 2 failed");
                            ++done;
                          }),
               std::runtime_error);
  // Then the other tasks ran, and the next job runs normally
  EXPECT_EQ(done.load(), 3);
  std::atomic<int> next{0};
  helper.run(5, [&](int) { ++next; });
  EXPECT_EQ(next.load(), 5);
}

// Some CPU work that the compiler cannot drop.
std::uint64_t task_helper_spin(int rounds) {
  volatile std::uint64_t x = 1;
  for (int i = 0; i < rounds; ++i) x = x * 6364136223846793005ull + 1442695040888963407ull;
  return x;
}

TEST(TaskHelper, GivenRecordingThenEachSharedJobIsTimedAndNestedOrSingleOnesAreNot) {
  // Given a helper that records its jobs
  TaskHelper helper;
  helper.run(3, [](int) {});
  EXPECT_TRUE(helper.take_jobs().empty()) << "not recording yet";
  helper.record_jobs(true);
  // When jobs of 1, 4 (each starting a nested job) and 2 tasks run
  helper.run(1, [](int) { task_helper_spin(1000); });
  helper.run(4, [&](int) {
    task_helper_spin(200000);
    helper.run(2, [](int) { task_helper_spin(1000); });
  });
  helper.run(2, [](int) { task_helper_spin(200000); });
  const std::vector<JobTimes> jobs = helper.take_jobs();
  // Then the two shared jobs are recorded, in order, each whole and consistent
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].tasks, 4);
  EXPECT_EQ(jobs[1].tasks, 2);
  for (const JobTimes& j : jobs) {
    EXPECT_GE(j.helper_tasks, 0);
    EXPECT_LE(j.helper_tasks, j.tasks);
    EXPECT_EQ(j.helper_delay_ns < 0, j.helper_tasks == 0);
    EXPECT_GE(j.end_ns, j.start_ns);
    EXPECT_GE(j.caller_delay_ns, 0);
    EXPECT_GE(j.caller_wait_ns, 0);
    EXPECT_GT(j.caller_busy_ns + j.helper_busy_ns, 0);
    EXPECT_GT(j.caller_cpu_ns + j.helper_cpu_ns, 0) << "the tasks' CPU work";
    EXPECT_LE(j.caller_busy_ns + j.caller_delay_ns + j.caller_wait_ns, j.end_ns - j.start_ns);
    EXPECT_LE(j.helper_busy_ns, j.end_ns - j.start_ns);
  }
  EXPECT_LE(jobs[0].start_ns + (jobs[0].end_ns - jobs[0].start_ns), jobs[1].start_ns);
  // And taking them empties the record, and no job is kept once recording stops
  EXPECT_TRUE(helper.take_jobs().empty());
  helper.record_jobs(false);
  helper.run(2, [](int) {});
  EXPECT_TRUE(helper.take_jobs().empty());
}

}  // namespace
}  // namespace stereoball::ball_detector
