#include "ball_detector/node/thread_pinning.hpp"

#include <cerrno>
#include <cstring>

namespace stereoball::ball_detector {

std::optional<std::pair<int, int>> first_two_cpus(const std::vector<int>& cpus) {
  if (cpus.size() < 2) return std::nullopt;
  return std::pair{cpus[0], cpus[1]};
}

std::vector<int> cpus_of(const cpu_set_t& mask) {
  std::vector<int> cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &mask)) cpus.push_back(c);
  return cpus;
}

std::vector<int> allowed_cpus() {
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(0, sizeof(mask), &mask) != 0) return {};
  return cpus_of(mask);
}

std::string pin_thread(int tid, int cpu) {
  if (cpu < 0 || cpu >= CPU_SETSIZE) return "CPU " + std::to_string(cpu) + " out of range";
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(cpu, &one);
  if (sched_setaffinity(tid, sizeof(one), &one) != 0)
    return "sched_setaffinity to CPU " + std::to_string(cpu) + ": " + std::strerror(errno);
  return {};
}

}  // namespace stereoball::ball_detector
