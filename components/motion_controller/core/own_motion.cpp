#include "motion_controller/core/own_motion.hpp"

#include <algorithm>

namespace stereoball::motion_controller {
namespace {

// Integral of u (L - u) du from 0 to u, seconds^3.
double weight_integral(double u, double l) {
  return l * u * u / 2.0 - u * u * u / 3.0;
}

}  // namespace

void OwnMotionHistory::record(std::int64_t t_ns, const Velocity& v) {
  if (!entries_.empty() && entries_.back().t_ns >= t_ns) {
    entries_.back().v = v;  // same instant: the newest command wins
    return;
  }
  entries_.push_back({t_ns, v});
}

void OwnMotionHistory::forget_before(std::int64_t t_ns) {
  while (entries_.size() >= 2 && entries_[1].t_ns <= t_ns) entries_.pop_front();
}

Velocity OwnMotionHistory::at(std::int64_t t_ns) const {
  Velocity v;
  for (const Entry& e : entries_) {
    if (e.t_ns > t_ns) break;
    v = e.v;
  }
  return v;
}

Velocity OwnMotionHistory::slope_weighted_mean(std::int64_t from_ns, std::int64_t to_ns) const {
  return weighted_mean(from_ns, to_ns, true);
}

Velocity OwnMotionHistory::mean(std::int64_t from_ns, std::int64_t to_ns) const {
  return weighted_mean(from_ns, to_ns, false);
}

Velocity OwnMotionHistory::weighted_mean(std::int64_t from_ns, std::int64_t to_ns,
                                         bool slope_weights) const {
  if (to_ns <= from_ns) return at(to_ns);
  const double l = static_cast<double>(to_ns - from_ns) * 1e-9;
  const auto integral = [&](std::int64_t t_ns) {
    const double u = static_cast<double>(t_ns - from_ns) * 1e-9;
    return slope_weights ? weight_integral(u, l) : u;
  };
  Velocity sum;
  // Segment k holds entries_[k].v from its time to the next entry's (before the first: zero).
  for (std::size_t k = 0; k <= entries_.size(); ++k) {
    const std::int64_t seg_start = k == 0 ? from_ns : std::max(from_ns, entries_[k - 1].t_ns);
    const std::int64_t seg_end = k == entries_.size() ? to_ns : std::min(to_ns, entries_[k].t_ns);
    if (seg_end <= seg_start) continue;
    const Velocity v = k == 0 ? Velocity{} : entries_[k - 1].v;
    const double w = integral(seg_end) - integral(seg_start);
    sum.linear_mps += w * v.linear_mps;
    sum.angular_radps += w * v.angular_radps;
  }
  const double total = integral(to_ns);
  sum.linear_mps /= total;
  sum.angular_radps /= total;
  return sum;
}

}  // namespace stereoball::motion_controller
