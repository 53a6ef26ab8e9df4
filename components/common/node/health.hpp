#pragma once
// Health bookkeeping of a node: per-topic rates and drops, error counters, state.
// The runner publishes it as health/status once per second.

#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace stereoball::node {

class Health {
 public:
  /// One sample received or sent on topic.
  void count(const std::string& topic, uint64_t n = 1);
  /// n samples of topic skipped or lost.
  void drop(const std::string& topic, uint64_t n = 1);
  /// An error of kind name (e.g. "bad_frame_size"); message is kept as last_error.
  void error(const std::string& name, const std::string& message);
  /// Sets a named counter to an absolute value.
  void set_counter(const std::string& name, uint64_t value);
  /// Whether the node can do its job, with a short state text ("waiting for calibration").
  void set_state(bool healthy, const std::string& state);

  struct Rate {
    double rate_hz = 0;
    uint64_t count = 0;
    uint64_t dropped = 0;
  };
  struct Snapshot {
    std::map<std::string, Rate> rates;
    std::map<std::string, uint64_t> counters;
    uint64_t errors = 0;
    std::string last_error;
    bool healthy = true;
    std::string state = "running";
  };
  /// Current figures; rates are over the time since the previous snapshot at now_ns.
  Snapshot snapshot(int64_t now_ns);
  uint64_t counter(const std::string& name) const;

 private:
  struct TopicCounts {
    uint64_t count = 0;
    uint64_t dropped = 0;
    uint64_t count_at_last_snapshot = 0;
  };
  mutable std::mutex mutex_;
  std::map<std::string, TopicCounts> topics_;
  std::map<std::string, uint64_t> counters_;
  uint64_t errors_ = 0;
  std::string last_error_;
  bool healthy_ = true;
  std::string state_ = "running";
  int64_t last_snapshot_ns_ = 0;
};

}  // namespace stereoball::node
