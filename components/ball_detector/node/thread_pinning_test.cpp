// The node's two threads pinned each to a CPU of its own (thread_pinning.hpp, TaskHelper(pin)).

#include "ball_detector/node/thread_pinning.hpp"

#include <gtest/gtest.h>
#include <sched.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "ball_detector/node/task_helper.hpp"

namespace stereoball::ball_detector {
namespace {

// The CPUs thread tid (0: the caller) may run on.
std::vector<int> affinity_of(int tid) {
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(tid, sizeof(mask), &mask) != 0) return {};
  return cpus_of(mask);
}

// Runs body on a thread of its own (pinning must not touch the test's own thread) and waits.
template <typename Body>
void on_own_thread(Body body) {
  std::thread t(body);
  t.join();
}

// Waits, up to two seconds, until the helper thread has started and pinned itself (or not).
void await_helper(const TaskHelper& helper) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (helper.helper_tid() == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

TEST(ThreadPinning, GivenSetsOfCpusThenTheFirstTwoAreChosen) {
  EXPECT_EQ(first_two_cpus({}), std::nullopt);
  EXPECT_EQ(first_two_cpus({3}), std::nullopt);
  EXPECT_EQ(first_two_cpus({2, 5, 7}), (std::pair{2, 5}));
  cpu_set_t mask;
  CPU_ZERO(&mask);
  CPU_SET(1, &mask);
  CPU_SET(4, &mask);
  EXPECT_EQ(cpus_of(mask), (std::vector<int>{1, 4}));
}

TEST(ThreadPinning, GivenACpuOutOfRangeThenTheReasonIsNamed) {
  on_own_thread([] {
    const std::vector<int> before = affinity_of(0);
    EXPECT_NE(pin_thread(0, -1).find("out of range"), std::string::npos);
    EXPECT_NE(pin_thread(0, CPU_SETSIZE).find("out of range"), std::string::npos);
    EXPECT_EQ(affinity_of(0), before);
  });
}

TEST(ThreadPinning, GivenPinningAskedThenCallerAndHelperRunOnOneCpuEach) {
  const std::vector<int> allowed = allowed_cpus();
  if (allowed.size() < 2)
    GTEST_SKIP() << "this process may use " << allowed.size() << " CPU(s): pinning needs two";
  on_own_thread([&] {
    // Given a helper asked to pin
    TaskHelper helper(true);
    ASSERT_EQ(helper.pinned_cpus(), (std::pair{allowed[0], allowed[1]}));
    // When a job runs on this thread
    helper.run(4, [](int) {});
    await_helper(helper);
    // Then this thread runs on the first CPU only and the helper on the second only
    EXPECT_EQ(affinity_of(0), std::vector<int>{allowed[0]});
    EXPECT_EQ(affinity_of(helper.helper_tid()), std::vector<int>{allowed[1]});
    EXPECT_EQ(helper.pin_problem(), "");
  });
}

TEST(ThreadPinning, GivenPinningNotAskedThenNeitherThreadIsPinned) {
  const std::vector<int> allowed = allowed_cpus();
  on_own_thread([&] {
    // Given a helper not asked to pin, When a job runs
    TaskHelper helper;
    helper.run(4, [](int) {});
    await_helper(helper);
    // Then both threads keep every CPU the process has
    EXPECT_EQ(helper.pinned_cpus(), std::nullopt);
    EXPECT_EQ(affinity_of(0), allowed);
    EXPECT_EQ(affinity_of(helper.helper_tid()), allowed);
  });
}

TEST(ThreadPinning, GivenOneCpuAllowedThenNothingIsPinnedAndTheReasonIsNamed) {
  const std::vector<int> allowed = allowed_cpus();
  ASSERT_FALSE(allowed.empty());
  on_own_thread([&] {
    // Given a thread that may use one CPU only (its helper inherits that)
    ASSERT_EQ(pin_thread(0, allowed[0]), "");
    // When a helper asked to pin is made and runs a job
    TaskHelper helper(true);
    helper.run(4, [](int) {});
    // Then nothing is pinned, the reason says why, and the job still ran on both threads' CPU
    EXPECT_EQ(helper.pinned_cpus(), std::nullopt);
    EXPECT_NE(helper.pin_problem().find("1 CPU(s) allowed, two needed"), std::string::npos)
        << helper.pin_problem();
  });
}

}  // namespace
}  // namespace stereoball::ball_detector
