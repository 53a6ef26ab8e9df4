#pragma once
// The node's two threads (the one that processes frames and TaskHelper's helper) each on a CPU of
// its own. Left to the scheduler they were often runnable on the same core while the other
// idled (a woken thread is placed beside its waker): a 1152x648 frame waited ~7 ms per thread
// for a core on an idle two-core machine. Pinned, neither waits for the other.

#include <sched.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace stereoball::ball_detector {

/// The first two CPUs of a set, in order; nullopt when it holds fewer than two.
std::optional<std::pair<int, int>> first_two_cpus(const std::vector<int>& cpus);

/// The CPUs set in mask, in order.
std::vector<int> cpus_of(const cpu_set_t& mask);

/// The CPUs this thread may run on (its affinity mask), in order; empty if it cannot be read.
std::vector<int> allowed_cpus();

/// Pins thread tid (0: the calling thread) to cpu; empty on success, else the reason.
std::string pin_thread(int tid, int cpu);

}  // namespace stereoball::ball_detector
