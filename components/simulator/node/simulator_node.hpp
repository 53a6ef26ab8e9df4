#pragma once
// The simulator process: renders the scenario at frame_rate_hz x rate, publishes stereo/frame,
// sim/ground_truth and (once, latched) stereo/calibration; drives the base from cmd/velocity
// through the base's own gate (base/node/base_link.hpp): the e-stop and stale commands stop it.

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "base/core/base_log.hpp"
#include "base/node/base_link.hpp"
#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "simulator/core/render_lead.hpp"
#include "simulator/core/simulator.hpp"
#include "stereo/frame/frame_compressor.hpp"
#include "stereo/frame/preview_publisher.hpp"

namespace stereoball::simulator {

/// Run options of the node (from flags).
struct SimulatorNodeOptions {
  double rate = 1.0;  ///< simulated seconds per wall second
  bool loop = false;  ///< restart the scenario after its duration
  std::string calibration_source = "simulator (true calibration)";  ///< published source text
  stereo::FrameCodecParams output;  ///< raw bgr8 or jpeg/png eyes (must be valid)
  /// Appends the base's events (base/core/base_log.hpp) to this file ("" = none).
  std::string base_log_path;
};

/// Wires a Simulator to its topics and a frame timer on a runner.
class SimulatorNode {
 public:
  /// published is the calibration to announce (the true one, or a file to test a mismatch).
  SimulatorNode(node::Runner& runner, const SimParams& params, const Scenario& scenario,
                const stereo::StereoCalibration& published, const SimulatorNodeOptions& options);
  /// Logs the render lead's range over the run.
  ~SimulatorNode();
  SimulatorNode(const SimulatorNode&) = delete;
  SimulatorNode& operator=(const SimulatorNode&) = delete;

 private:
  void on_command(const base::BaseCommand& command);
  // The frame timer: one frame's work and release, then the timer set for the next frame.
  void tick(int64_t now_ns);
  // Renders, encodes and releases the next frame on the grid at its exposure instant.
  void produce_frame();
  // Sets the frame timer one render lead before the next frame's exposure.
  void schedule_next_frame();
  // Monotonic time of the simulated exposure at sim_time_ns of the current run.
  int64_t exposure_monotonic_ns(int64_t sim_time_ns) const;
  // The first render lead (until frames' own work is timed): this machine's render (+ encode)
  // time plus a margin.
  static int64_t measure_render_lead_ns(const SimParams& params, const Scenario& scenario,
                                        const SimulatorNodeOptions& options);
  static int64_t frame_period_wall_ns(const SimParams& params, const SimulatorNodeOptions& options);
  // Sleeps until the monotonic time; false if the runner is stopping.
  bool wait_until(int64_t due_monotonic_ns) const;
  // The outgoing view of a frame: its raw eyes, or the compressor's streams (timed as
  // encode_us); points into f and the compressor. Error (reported as health error) on failure.
  Result<stereo::FrameView> frame_view(const SimFrame& f, int64_t stamp_ns);
  // Hands the published frame to the preview publisher and reports its counters and errors.
  void offer_preview(const stereo::FrameView& view);
  // One line of the base log (when enabled), written through at once.
  void log_base_event(const base::BaseEvent& event);

  node::Runner& runner_;
  SimParams params_;
  Scenario scenario_;
  SimulatorNodeOptions options_;
  // The scenario at its start, never stepped: a looped scenario restarts from a copy of it
  // (a few ms; building the world again took ~40 ms, which made the first frame of each run
  // late and skipped the next ones).
  const Simulator start_;
  std::unique_ptr<Simulator> sim_;
  stereo::StereoCalibration published_;
  std::string frame_source_;
  // Frames are rendered this long before their exposure instant: the start-up measurement,
  // then the slowest work of the last second of frames (simulator/core/render_lead.hpp).
  RenderLead lead_;
  size_t frame_timer_ = 0;
  std::optional<stereo::FrameCompressor> compressor_;  // jpeg/png only
  dds::DataWriter<stereoball_msg_StereoFrame> frames_;
  dds::DataWriter<stereoball_msg_GroundTruth> truth_;
  dds::DataWriter<stereoball_msg_StereoCalibration> calibration_;
  // The base log (--base-log), opened before the base link exists so no command is missed.
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> base_log_{nullptr, &std::fclose};
  base::BaseLink base_;  // authenticated commands, the e-stop, the base's own gate
  // stereo/preview of raw frames, made only while a viewer reads it (none for jpeg/png).
  std::unique_ptr<stereo::PreviewPublisher> preview_;
  std::string frame_topic_{topics::kStereoFrame.spec.name};
  static constexpr int64_t kLateNs = 1'000'000;  // released later than this: counted late
  int64_t run_start_mono_ns_ = -1;
  int64_t frame_index_ = 0;  // next frame on the grid of the current run of the scenario
  int64_t sim_now_ns_ = 0;
  uint64_t total_frames_ = 0;
};

}  // namespace stereoball::simulator
