#include "replay_recording.hpp"

#include <memory>
#include <vector>

#include "ball_detector/node/detection_msg.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/serialized.hpp"
#include "common/dds/writer.hpp"
#include "recorder/io/recording.hpp"
#include "simulator/core/ball_scene.hpp"
#include "stereo/frame/frame_msg.hpp"
#include "stereo/msg/calibration_msg.hpp"
#include "stereoball/idl_text.hpp"
#include "stereoball/topics.hpp"
#include "tracker/core/tracker.hpp"
#include "tracker/node/track_msg.hpp"

namespace stereoball::replay {
namespace {

namespace bd = ball_detector;

// Serializes typed samples of one topic through a reader in the same participant.
template <typename T>
class Serializer {
 public:
  Serializer(const dds::DomainParticipant& p, const topics::Topic<T>& topic)
      : writer_(p, topic), reader_(p, topic.spec, deeper(topic.spec.qos)) {}
  // CDR of sample (local delivery is synchronous, so it can be taken at once).
  std::vector<std::uint8_t> cdr(const T& sample) {
    writer_.write(sample);
    std::vector<dds::SerializedSample> out;
    reader_.take(out, 1);
    return out.empty() ? std::vector<std::uint8_t>{} : std::move(out.front().cdr);
  }

 private:
  static topics::QosSpec deeper(topics::QosSpec q) {
    q.history_depth = 4;
    return q;
  }
  dds::DataWriter<T> writer_;
  dds::SerializedReader reader_;
};

// The scene: a one-colour ball rolling away and across in a plain room, robot standing.
simulator::Scenario scene() {
  simulator::SimBallSetup setup;
  setup.ball_x_m = 1.1;
  setup.ball_y_m = 0.3;
  setup.vx_mps = 0.5;
  setup.vy_mps = -0.3;
  setup.clutter = false;
  setup.plain_room = true;
  setup.uniform_ball = true;
  setup.seed = 9;
  return simulator::make_sim_scenario(setup);
}

// Appends kHeldTrackFrames copies of last (fresh stamps, zero velocity) after the frames, so
// the motion controller ends on a constant target whatever the replay timing.
template <typename Push>
Status push_held_tracks(Serializer<stereoball_msg_BallTrack>& ser, stereoball_msg_BallTrack last,
                        std::int64_t period_ns, Push& push) {
  for (int i = 0; i < kHeldTrackFrames; ++i) {
    last.frame_seq += 1;
    last.capture_stamp_ns += period_ns;
    last.publish_stamp_ns += period_ns;
    if (last.position_valid) last.last_accepted_stamp_ns = last.capture_stamp_ns;
    for (double& v : last.velocity_mps) v = 0.0;
    if (!push(3, ser.cdr(last), last.publish_stamp_ns)) return Error{"held track was not queued"};
  }
  return {};
}

}  // namespace

Status make_replay_recording(const std::string& path, int domain, const std::string& partition) {
  const std::vector<std::string> names = {"stereo/calibration", "stereo/frame", "ball/detection",
                                          "ball/track"};
  std::vector<recorder::RecordedTopic> recorded;
  for (const auto& n : names) {
    for (const auto& spec : topics::all())
      if (spec.name == n)
        recorded.push_back({n, std::string(spec.type_name), std::string(idl_text())});
  }
  recorder::RecordingParams rp;
  rp.path = path;
  auto recording = recorder::Recording::start(rp, recorded);
  if (!recording) return Error{"cannot start the recording: " + recording.error()};

  dds::DomainParticipant participant({domain, partition});
  Serializer<stereoball_msg_StereoCalibration> calib_ser(participant, topics::kStereoCalibration);
  Serializer<stereoball_msg_StereoFrame> frame_ser(participant, topics::kStereoFrame);
  Serializer<stereoball_msg_BallDetection> det_ser(participant, topics::kBallDetection);
  Serializer<stereoball_msg_BallTrack> track_ser(participant, topics::kBallTrack);

  simulator::Simulator sim(simulator::default_sim_params(), scene());
  bd::StereoPipeline pipeline{bd::BallDetectorParams{}};
  if (auto e = pipeline.set_calibration(sim.calibration()); !e)
    return Error{"calibration: " + e.error()};
  tracker::Tracker tracker{tracker::TrackerParams{}};
  tracker::Track last_track;
  const std::string source = "replay_test";
  auto push = [&](std::size_t topic, std::vector<std::uint8_t> cdr, std::int64_t t_ns) {
    const auto ns = static_cast<std::uint64_t>(t_ns);
    return !cdr.empty() && (*recording)->push(topic, std::move(cdr), ns, ns);
  };
  if (!push(
          0,
          calib_ser.cdr(stereo::calibration_to_message(sim.calibration(), kReplayEpochNs, source)),
          kReplayEpochNs))
    return Error{"calibration sample was not serialized or queued"};
  const std::int64_t period_ns = sim.frame_period_ns();
  const auto width = static_cast<std::uint32_t>(sim.calibration().image_size.width);
  stereoball_msg_BallTrack track_msg{};
  for (int i = 0; i < kReplayFrames; ++i) {
    const std::int64_t t_ns = i * period_ns;
    const std::int64_t stamp = kReplayEpochNs + t_ns + period_ns;
    const simulator::SimFrame f = sim.step(std::nullopt, t_ns);
    const auto view = stereo::view_of_images(f.left, f.right, f.seq, stamp);
    if (!view) return Error{"frame: " + view.error()};
    stereoball_msg_StereoFrame frame_msg{};
    stereo::fill_frame_message(*view, source, frame_msg);
    if (!push(1, frame_ser.cdr(frame_msg), stamp))
      return Error{"frame sample was not serialized or queued"};
    const bd::StereoDetection det = pipeline.step(f.left, f.right, false);
    stereoball_msg_BallDetection det_msg{};
    bd::to_message(det, {f.seq, stamp}, 0.0F, stamp + 1'000'000, det_msg);
    if (!push(2, det_ser.cdr(det_msg), stamp + 1'000'000))
      return Error{"detection sample was not serialized or queued"};
    const auto in = tracker::to_detection(det_msg, width);
    last_track = tracker.step(in.detection, stamp);  // track_msg.reason points into it
    tracker::to_message(last_track, f.seq, stamp, stamp + 2'000'000, track_msg);
    if (!push(3, track_ser.cdr(track_msg), stamp + 2'000'000))
      return Error{"track sample was not serialized or queued"};
  }
  if (auto e = push_held_tracks(track_ser, track_msg, period_ns, push); !e) return e;
  if (auto st = (*recording)->stop(); !st) return Error{"closing the recording: " + st.error()};
  return {};
}

}  // namespace stereoball::replay
