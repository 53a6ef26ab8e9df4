#include "common/node/health.hpp"

namespace stereoball::node {

void Health::count(const std::string& topic, uint64_t n) {
  std::lock_guard lock(mutex_);
  topics_[topic].count += n;
}

void Health::drop(const std::string& topic, uint64_t n) {
  std::lock_guard lock(mutex_);
  topics_[topic].dropped += n;
}

void Health::error(const std::string& name, const std::string& message) {
  std::lock_guard lock(mutex_);
  ++counters_[name];
  ++errors_;
  last_error_ = message;
}

void Health::set_counter(const std::string& name, uint64_t value) {
  std::lock_guard lock(mutex_);
  counters_[name] = value;
}

void Health::set_state(bool healthy, const std::string& state) {
  std::lock_guard lock(mutex_);
  healthy_ = healthy;
  state_ = state;
}

uint64_t Health::counter(const std::string& name) const {
  std::lock_guard lock(mutex_);
  auto it = counters_.find(name);
  return it == counters_.end() ? 0 : it->second;
}

Health::Snapshot Health::snapshot(int64_t now_ns) {
  std::lock_guard lock(mutex_);
  Snapshot out;
  const double window_s = last_snapshot_ns_ > 0 ? (now_ns - last_snapshot_ns_) * 1e-9 : 0.0;
  for (auto& [topic, counts] : topics_) {
    Rate rate;
    rate.count = counts.count;
    rate.dropped = counts.dropped;
    if (window_s > 0) rate.rate_hz = (counts.count - counts.count_at_last_snapshot) / window_s;
    counts.count_at_last_snapshot = counts.count;
    out.rates[topic] = rate;
  }
  out.counters = counters_;
  out.errors = errors_;
  out.last_error = last_error_;
  out.healthy = healthy_;
  out.state = state_;
  last_snapshot_ns_ = now_ns;
  return out;
}

}  // namespace stereoball::node
