#pragma once
// Runner: what every node's main() uses. It owns the participant, a waitset loop
// that dispatches reader callbacks and timers, the health heartbeat, and clean
// shutdown on SIGINT/SIGTERM (run() returns 0).

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/participant.hpp"
#include "common/dds/waitset.hpp"
#include "common/dds/writer.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/health.hpp"

namespace stereoball::node {

/// Wall-clock time, ns since epoch (the stamps of every message).
int64_t now_ns();
/// Monotonic time, ns (for intervals).
int64_t monotonic_ns();

/// Blocks SIGINT/SIGTERM in the calling thread and every thread created after, so the
/// runner's signal thread receives them. Call first thing in main().
void block_termination_signals();

class Runner {
 public:
  Runner(std::string component, const CommonOptions& options);
  ~Runner();
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;

  dds::DomainParticipant& participant() { return *participant_; }
  Health& health() { return health_; }
  const std::string& component() const { return component_; }

  /// Calls callback (on the loop thread) whenever reader has data.
  void on_data(dds::EntityHandle reader, std::function<void()> callback);
  /// Calls callback every period_ns (monotonic) with now_ns(); first call one period after run().
  void every(int64_t period_ns, std::function<void(int64_t)> callback);
  /// A timer the node schedules itself (wake_at): callback(now_ns()) runs once per wake_at, at
  /// or after its deadline; unscheduled until then. Returns the timer's id.
  size_t one_shot(std::function<void(int64_t)> callback);
  /// Schedules (or moves) one_shot timer id to monotonic_ns() time deadline_ns; loop thread
  /// (callbacks) or before run() only.
  void wake_at(size_t id, int64_t deadline_ns);
  /// Heartbeat period (default 1 s); 0 disables.
  void set_heartbeat_period(int64_t period_ns) { heartbeat_period_ns_ = period_ns; }

  /// Runs until SIGINT/SIGTERM or stop(); returns the process exit code (0).
  int run();
  /// Asks run() to return (thread-safe).
  void stop();
  bool stopping() const { return stop_.load(); }

 private:
  struct Timer {
    int64_t period_ns;  // 0: one-shot (wake_at)
    int64_t next_ns;    // INT64_MAX: not scheduled
    std::function<void(int64_t)> callback;
  };
  struct DataHandler {
    std::unique_ptr<dds::ReadCondition> condition;
    std::function<void()> callback;
  };
  void publish_heartbeat(int64_t now);
  void dispatch(std::function<void()>& callback, const char* what);
  int64_t next_timer_ns() const;
  void run_due_timers();

  std::string component_;
  int64_t start_ns_;
  std::unique_ptr<dds::DomainParticipant> participant_;
  std::unique_ptr<dds::WaitSet> waitset_;
  std::unique_ptr<dds::GuardCondition> wake_;
  std::unique_ptr<dds::DataWriter<stereoball_msg_ComponentStatus>> status_writer_;
  std::vector<DataHandler> handlers_;
  std::vector<Timer> timers_;
  Health health_;
  int64_t heartbeat_period_ns_ = 1'000'000'000;
  std::atomic<bool> stop_{false};
  std::thread signal_thread_;
};

}  // namespace stereoball::node
