#pragma once
// Task runners for pipeline tests: what the node's two threads may do with a job's tasks.

#include <functional>
#include <thread>
#include <vector>

namespace stereoball::ball_detector::testing {

/// Every task but the first on a thread of its own, all at once; counts the calls with n > 1.
struct AtOnceRunner {
  int calls = 0;
  void operator()(int n, const std::function<void(int)>& task) {
    if (n > 1) ++calls;
    std::vector<std::thread> threads;
    for (int i = 1; i < n; ++i) threads.emplace_back([&task, i] { task(i); });
    if (n > 0) task(0);
    for (auto& t : threads) t.join();
  }
};

/// Every task in turn on the calling thread; counts the calls with n > 1.
struct InTurnRunner {
  int calls = 0;
  void operator()(int n, const std::function<void(int)>& task) {
    if (n > 1) ++calls;
    for (int i = 0; i < n; ++i) task(i);
  }
};

}  // namespace stereoball::ball_detector::testing
