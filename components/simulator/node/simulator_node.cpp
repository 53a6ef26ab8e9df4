#include "simulator/node/simulator_node.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <thread>

#include "common/util/clock_stamp.hpp"
#include "common/util/log.hpp"
#include "simulator/node/ground_truth_msg.hpp"
#include "stereo/frame/frame_msg.hpp"
#include "stereo/msg/calibration_msg.hpp"

namespace stereoball::simulator {
namespace {

// The eyes render at once: the left on a second thread, the right on this one.
void run_on_two_threads(const std::function<void()>& left, const std::function<void()>& right) {
  auto done = std::async(std::launch::async, left);
  right();
  done.get();  // rethrows what the left eye threw
}

}  // namespace

SimulatorNode::SimulatorNode(node::Runner& runner, const SimParams& params,
                             const Scenario& scenario, const stereo::StereoCalibration& published,
                             const SimulatorNodeOptions& options)
    : runner_(runner),
      params_(params),
      scenario_(scenario),
      options_(options),
      start_(params, scenario),
      sim_(std::make_unique<Simulator>(start_)),
      published_(published),
      frame_source_("simulator:" + scenario.name),
      // Before the writers exist, so a subscriber's first frames are not delayed by it.
      lead_(measure_render_lead_ns(params, scenario, options),
            frame_period_wall_ns(params, options),
            static_cast<int>(std::ceil(params.frame_rate_hz))),
      frames_(runner.participant(), topics::kStereoFrame),
      truth_(runner.participant(), topics::kGroundTruth),
      calibration_(runner.participant(), topics::kStereoCalibration),
      base_log_(
          options.base_log_path.empty() ? nullptr : std::fopen(options.base_log_path.c_str(), "a"),
          &std::fclose),
      base_(runner, base::VelocityGateParams{params.robot.command_timeout_ns},
            [this](const base::BaseCommand& c) { on_command(c); }) {
  if (options_.output.compressed()) compressor_.emplace(options_.output);
  if (!options_.base_log_path.empty() && !base_log_)
    runner_.health().error("base_log", "cannot append to " + options_.base_log_path);
  if (!options_.output.compressed() && options_.output.preview_max_width_px > 0)
    preview_ = std::make_unique<stereo::PreviewPublisher>(runner.participant(), options_.output,
                                                          frame_source_);
  // Transient-local: written once, every late joiner still receives it.
  calibration_.write(
      stereo::calibration_to_message(published_, node::now_ns(), options_.calibration_source));
  log::info("frames rendered ", lead_.lead_ns() / 1000,
            " us ahead of their exposure (render time here; then each frame's own)");
  frame_timer_ = runner_.one_shot([this](int64_t now) { tick(now); });
  runner_.wake_at(frame_timer_, node::monotonic_ns() + frame_period_wall_ns(params_, options_));
  runner_.health().set_state(true, "running scenario " + scenario_.name);
}

SimulatorNode::~SimulatorNode() {
  log::info("render lead over the run: ", lead_.min_lead_ns() / 1000, " to ",
            lead_.max_lead_ns() / 1000, " us (last ", lead_.lead_ns() / 1000, " us)");
}

void SimulatorNode::on_command(const base::BaseCommand& command) {
  // The gate's output, not the raw command: zero while the e-stop is engaged.
  stereoball_msg_VelocityCommand gated{};
  gated.stamp_ns = command.stamp_ns;
  gated.linear_mps = command.output.velocity.linear_mps;
  gated.angular_radps = command.output.velocity.angular_radps;
  sim_->advance(command_from_msg(gated, node::now_ns(), sim_now_ns_, options_.rate), sim_now_ns_);
  if (base_log_) {
    base::BaseEvent e;
    e.kind = command.from_estop ? base::BaseEventKind::kEstop : base::BaseEventKind::kCommand;
    e.time_ns = command.received_ns;
    e.stamp_ns = command.stamp_ns;
    e.seq = command.seq;
    e.key_id = command.key_id;
    e.authenticated = command.authenticated;
    e.estop_engaged = base_.estop_engaged();
    e.state = command.output.state;
    e.linear_mps = command.output.velocity.linear_mps;
    e.angular_radps = command.output.velocity.angular_radps;
    e.source = command.source;
    log_base_event(e);
  }
  runner_.health().set_state(true, "running scenario " + scenario_.name + ", base " +
                                       std::string(base::to_string(command.output.state)));
}

int64_t SimulatorNode::exposure_monotonic_ns(int64_t sim_time_ns) const {
  // The simulated exposure happens on the frame grid of this run of the scenario, mapped to
  // the monotonic clock by the rate.
  return run_start_mono_ns_ + std::llround(static_cast<double>(sim_time_ns) / options_.rate);
}

int64_t SimulatorNode::frame_period_wall_ns(const SimParams& params,
                                            const SimulatorNodeOptions& options) {
  return static_cast<int64_t>(std::llround(1e9 / (params.frame_rate_hz * options.rate)));
}

int64_t SimulatorNode::measure_render_lead_ns(const SimParams& params, const Scenario& scenario,
                                              const SimulatorNodeOptions& options) {
  // Render (and encode) a few frames of a scratch copy of the scenario: the lead is what that
  // takes here (the slowest of them, plus a margin for the loop's timer), never a period.
  Simulator scratch(params, scenario);
  std::optional<stereo::EyeEncoder> encoder;
  if (options.output.compressed()) encoder.emplace(options.output);
  int64_t slowest = 0;
  for (int i = 1; i <= 3; ++i) {
    const int64_t start = node::monotonic_ns();
    const SimFrame f =
        scratch.step(std::nullopt, i * scratch.frame_period_ns(), run_on_two_threads);
    if (encoder) {
      (void)encoder->encode(f.left);  // errors show on the real frames
      (void)encoder->encode(f.right);
    }
    slowest = std::max(slowest, node::monotonic_ns() - start);
  }
  constexpr int64_t kMarginNs = 2'000'000;
  const int64_t period_ns = frame_period_wall_ns(params, options);
  return std::clamp<int64_t>(slowest * 5 / 4 + kMarginNs, kMarginNs, period_ns - kMarginNs / 2);
}

void SimulatorNode::tick(int64_t /*now_ns*/) {
  produce_frame();
  schedule_next_frame();
}

void SimulatorNode::schedule_next_frame() {
  const int64_t next_exposure = exposure_monotonic_ns(frame_index_ * sim_->frame_period_ns());
  runner_.wake_at(frame_timer_, next_exposure - lead_.lead_ns());
}

void SimulatorNode::produce_frame() {
  // A camera's frame exists once its exposure ends; the simulator renders it ahead by the
  // lead (on the timer) and releases it at that instant, so its render time is not part of
  // the robot's latency, and no earlier than the lead needs, so the render does not run beside
  // the previous frame's processing. Simulated time follows the wall clock (x rate) on the
  // frame grid; a frame whose exposure has passed before rendering starts is skipped.
  const int64_t mono = node::monotonic_ns();
  if (run_start_mono_ns_ < 0) run_start_mono_ns_ = mono + lead_.lead_ns();
  const int64_t period = sim_->frame_period_ns();
  const auto sim_elapsed = static_cast<double>(mono - run_start_mono_ns_) * options_.rate;
  int64_t index = std::max<int64_t>(frame_index_, std::ceil(sim_elapsed / period));
  if (options_.loop && index * period > static_cast<int64_t>(scenario_.duration_s * 1e9)) {
    sim_ = std::make_unique<Simulator>(start_);
    // The new run's first frame is rendered now and released one lead later, as at start.
    run_start_mono_ns_ = node::monotonic_ns() + lead_.lead_ns();
    index = frame_index_ = 0;
    sim_now_ns_ = 0;
    runner_.health().count("scenario_restarts");
  }
  if (index > frame_index_) runner_.health().drop(frame_topic_, index - frame_index_);
  const SimFrame f = sim_->step(std::nullopt, index * period, run_on_two_threads);
  runner_.health().set_counter("render_us",
                               static_cast<uint64_t>((node::monotonic_ns() - mono) / 1000));
  sim_now_ns_ = f.sim_time_ns;
  frame_index_ = index + 1;
  // Encoding and the message are the camera's work before the release, too.
  const int64_t exposure = exposure_monotonic_ns(index * period);
  const int64_t stamp_ns = monotonic_to_epoch_ns(exposure, node::monotonic_ns(), node::now_ns());
  const auto view = frame_view(f, stamp_ns);
  if (!view) return;
  stereoball_msg_StereoFrame frame{};
  stereo::fill_frame_message(*view, frame_source_, frame);
  lead_.add_work(node::monotonic_ns() - mono);
  runner_.health().set_counter("lead_us", static_cast<uint64_t>(lead_.lead_ns() / 1000));
  if (!wait_until(exposure)) return;
  if (node::monotonic_ns() > exposure + kLateNs) runner_.health().count("late_frames");
  frames_.write(frame, stamp_ns);
  runner_.health().count(frame_topic_);
  stereoball_msg_GroundTruth truth = ground_truth_to_msg(f.truth, stamp_ns, scenario_.name);
  truth.frame_seq = total_frames_;
  truth_.write(truth, stamp_ns);
  runner_.health().count(std::string(topics::kGroundTruth.spec.name));
  runner_.health().set_counter("frames", ++total_frames_);
  if (base_log_) {
    base::BaseEvent e;
    e.kind = base::BaseEventKind::kFrame;
    e.time_ns = stamp_ns;
    e.estop_engaged = base_.estop_engaged();
    e.linear_mps = f.truth.robot.linear_mps;
    e.angular_radps = f.truth.robot.angular_radps;
    log_base_event(e);
  }
  // Last: the preview's copy (only while watched) delays neither the frame nor its truth.
  offer_preview(*view);
}

bool SimulatorNode::wait_until(int64_t due_monotonic_ns) const {
  // At most the lead (a few ms): commands received meanwhile are handled right after.
  while (!runner_.stopping()) {
    const int64_t left = due_monotonic_ns - node::monotonic_ns();
    if (left <= 0) return true;
    std::this_thread::sleep_for(std::chrono::nanoseconds(left));
  }
  return false;
}

Result<stereo::FrameView> SimulatorNode::frame_view(const SimFrame& f, int64_t stamp_ns) {
  auto raw = stereo::view_of_images(f.left, f.right, total_frames_, stamp_ns);
  if (!raw) {
    runner_.health().error("bad_frame", raw.error());
    return raw;
  }
  // Free-running eyes (calibration scenes' eye skew): the right eye's own capture stamp.
  raw->right.capture_stamp_ns = stamp_ns + (f.right_time_ns - f.sim_time_ns);
  if (!compressor_) return raw;
  const int64_t start = node::monotonic_ns();
  auto compressed = compressor_->step(*raw);
  if (!compressed) {
    runner_.health().error("encode", compressed.error());
    return compressed;
  }
  runner_.health().set_counter("encode_us",
                               static_cast<uint64_t>((node::monotonic_ns() - start) / 1000));
  return compressed;
}

void SimulatorNode::log_base_event(const base::BaseEvent& event) {
  const std::string line = base::format_base_event(event) + "\n";
  if (std::fputs(line.c_str(), base_log_.get()) < 0 || std::fflush(base_log_.get()) != 0)
    runner_.health().error("base_log", "cannot write to " + options_.base_log_path);
}

void SimulatorNode::offer_preview(const stereo::FrameView& view) {
  if (!preview_) return;
  preview_->offer(view);
  runner_.health().set_counter("preview_frames", preview_->published());
  runner_.health().set_counter("preview_encode_us", preview_->encode_us());
  if (auto error = preview_->take_error()) runner_.health().error("preview", *error);
}

}  // namespace stereoball::simulator
