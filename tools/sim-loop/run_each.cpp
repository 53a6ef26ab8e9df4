#include "run_each.hpp"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace stereoball::sim_loop {

Status run_each(std::size_t n, int jobs, const std::function<Status(std::size_t)>& run) {
  std::vector<Status> done(n);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  auto worker = [&] {
    for (std::size_t i = next++; i < n && !failed; i = next++) {
      done[i] = run(i);
      if (!done[i].ok()) failed = true;
    }
  };
  std::vector<std::thread> threads;
  const auto workers = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(jobs, 1)));
  for (std::size_t j = 1; j < workers; ++j) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();
  for (const Status& s : done)
    if (!s.ok()) return s;
  return {};
}

}  // namespace stereoball::sim_loop
