#pragma once
// Independent offline runs side by side: the benchmarks' --jobs.

#include <cstddef>
#include <functional>

#include "common/util/result.hpp"

namespace stereoball::sim_loop {

/// Calls run(i) for every i in [0, n), jobs calls at a time (each on a thread of its own; jobs
/// <= 1 = one after another on the caller's), claiming i in increasing order. Once a call has
/// failed no further one starts, as one after another nothing would run after it; the answer is
/// the first failure in index order (every call before it has run), or success. run(i) must
/// touch only what belongs to i.
Status run_each(std::size_t n, int jobs, const std::function<Status(std::size_t)>& run);

}  // namespace stereoball::sim_loop
