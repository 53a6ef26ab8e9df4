// TaskHelper: the pipeline's tasks on the caller and one helper thread.

#include "ball_detector/node/task_helper.hpp"

#include <gtest/gtest.h>

#include <atomic>
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

}  // namespace
}  // namespace stereoball::ball_detector
