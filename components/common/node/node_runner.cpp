#include "common/node/node_runner.hpp"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <climits>

#include "common/dds/auth_session.hpp"
#include "common/util/clock.hpp"
#include "common/util/log.hpp"

namespace stereoball::node {

int64_t now_ns() {
  return util::wall_ns();
}

int64_t monotonic_ns() {
  return util::monotonic_ns();
}

namespace {
sigset_t termination_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}
}  // namespace

void block_termination_signals() {
  const sigset_t set = termination_signals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

Runner::Runner(std::string component, const CommonOptions& options)
    : component_(std::move(component)), start_ns_(monotonic_ns()) {
  // Before any DDS thread exists, so all of them inherit the blocked mask.
  block_termination_signals();
  log::Level level = log::Level::kInfo;
  log::parse_level(options.log_level, level);
  log::init(component_, level);
  // Said once the parameters loaded, so a bad file is still reported in one line.
  if (!options.config_path.empty()) {
    log::info("parameters from ", options.config_path, " (", options.config_origin, ")");
  }
  participant_ = std::make_unique<dds::DomainParticipant>(
      dds::ParticipantOptions{options.domain_id, options.partition, options.key_file});
  waitset_ = std::make_unique<dds::WaitSet>(*participant_);
  wake_ = std::make_unique<dds::GuardCondition>(*participant_);
  waitset_->attach(wake_->handle(), -1);
  status_writer_ = std::make_unique<dds::DataWriter<stereoball_msg_ComponentStatus>>(
      *participant_, topics::kComponentStatus);
  signal_thread_ = std::thread([this] {
    const sigset_t set = termination_signals();
    int signal_number = 0;
    sigwait(&set, &signal_number);
    if (!stop_.load())
      log::info("received ", signal_number == SIGINT ? "SIGINT" : "SIGTERM", ", stopping");
    stop();
  });
}

Runner::~Runner() {
  stop();
  // The signal thread sits in sigwait(); a directed signal releases it.
  pthread_kill(signal_thread_.native_handle(), SIGTERM);
  signal_thread_.join();
  handlers_.clear();
  status_writer_.reset();
  waitset_.reset();
  wake_.reset();
  participant_.reset();
}

void Runner::stop() {
  stop_.store(true);
  if (wake_) wake_->trigger();
}

void Runner::on_data(dds::EntityHandle reader, std::function<void()> callback) {
  DataHandler handler{std::make_unique<dds::ReadCondition>(reader), std::move(callback)};
  waitset_->attach(handler.condition->handle(), static_cast<intptr_t>(handlers_.size()));
  handlers_.push_back(std::move(handler));
}

void Runner::every(int64_t period_ns, std::function<void(int64_t)> callback) {
  timers_.push_back(Timer{period_ns, monotonic_ns() + period_ns, std::move(callback)});
}

void Runner::dispatch(std::function<void()>& callback, const char* what) {
  // A failing callback is counted and logged; it never takes the node down.
  try {
    callback();
  } catch (const std::exception& e) {
    health_.error("callback_exception", std::string(what) + ": " + e.what());
    log::error(what, ": ", e.what());
  }
}

size_t Runner::one_shot(std::function<void(int64_t)> callback) {
  timers_.push_back(Timer{0, INT64_MAX, std::move(callback)});
  return timers_.size() - 1;
}

void Runner::wake_at(size_t id, int64_t deadline_ns) {
  timers_.at(id).next_ns = deadline_ns;
}

int64_t Runner::next_timer_ns() const {
  int64_t next = INT64_MAX;
  for (const auto& timer : timers_) next = std::min(next, timer.next_ns);
  return next;
}

void Runner::run_due_timers() {
  const int64_t mono = monotonic_ns();
  // By index: a callback may schedule a one-shot timer (wake_at) but never adds one.
  for (size_t i = 0; i < timers_.size(); ++i) {
    Timer& timer = timers_[i];
    if (timer.next_ns > mono) continue;
    if (timer.period_ns == 0) {
      timer.next_ns = INT64_MAX;  // fired; the callback may schedule it again
    } else {
      // Skip missed periods rather than firing a burst after a stall.
      while (timer.next_ns <= mono) timer.next_ns += timer.period_ns;
    }
    std::function<void()> call = [&timer] { timer.callback(now_ns()); };
    dispatch(call, "timer");
  }
}

void Runner::publish_heartbeat(int64_t now) {
  // Samples dropped by authentication (forged, replayed, unsigned...) are counted per topic.
  for (const auto& [name, value] : participant_->auth().counters())
    health_.set_counter(name, value);
  health_.set_counter("auth_keyed", participant_->auth().keyed() ? 1 : 0);
  // Which deployment key signs (0 = unauthenticated; fingerprint: the first 8 hex digits of
  // `stereoball keys show`): `stereoball doctor` compares nodes.
  health_.set_counter("auth_key_id", participant_->auth().signing_key_id());
  health_.set_counter("auth_key_fingerprint", participant_->auth().signing_key_fingerprint());
  const Health::Snapshot snap = health_.snapshot(now);
  std::vector<std::string> names;
  std::vector<stereoball_msg_TopicRate> rates;
  std::vector<stereoball_msg_Counter> counters;
  names.reserve(snap.rates.size() + snap.counters.size());
  for (const auto& [topic, rate] : snap.rates) {
    names.push_back(topic);
    rates.push_back(
        {names.back().data(), static_cast<float>(rate.rate_hz), rate.count, rate.dropped});
  }
  for (const auto& [name, value] : snap.counters) {
    names.push_back(name);
    counters.push_back({names.back().data(), value});
  }
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  std::string state = snap.state;
  std::string last_error = snap.last_error;
  stereoball_msg_ComponentStatus msg{};
  msg.component = component_.data();
  msg.host = host;
  msg.pid = static_cast<int32_t>(getpid());
  msg.stamp_ns = now;
  msg.uptime_s = (monotonic_ns() - start_ns_) * 1e-9;
  msg.healthy = snap.healthy;
  msg.state = state.data();
  msg.rates._length = msg.rates._maximum = static_cast<uint32_t>(rates.size());
  msg.rates._buffer = rates.data();
  msg.counters._length = msg.counters._maximum = static_cast<uint32_t>(counters.size());
  msg.counters._buffer = counters.data();
  msg.errors = snap.errors;
  msg.last_error = last_error.data();
  status_writer_->write(msg);
}

int Runner::run() {
  if (heartbeat_period_ns_ > 0) {
    every(heartbeat_period_ns_, [this](int64_t now) { publish_heartbeat(now); });
  }
  log::info("running on domain ", participant_->options().domain_id,
            participant_->options().partition.empty()
                ? std::string()
                : ", partition '" + participant_->options().partition + "'");
  while (!stop_.load()) {
    // At most a second: nothing scheduled (a one-shot timer not set) means no deadline.
    const int64_t timeout = std::min<int64_t>(
        1'000'000'000, timers_.empty() ? INT64_MAX : next_timer_ns() - monotonic_ns());
    const auto triggered = waitset_->wait(std::max<int64_t>(timeout, 0));
    for (intptr_t token : triggered) {
      if (token < 0 || stop_.load()) continue;
      dispatch(handlers_[static_cast<size_t>(token)].callback, "reader");
    }
    if (!stop_.load()) run_due_timers();
  }
  log::info("stopped");
  return 0;
}

}  // namespace stereoball::node
