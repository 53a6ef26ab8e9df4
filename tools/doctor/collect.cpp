#include "collect.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "common/dds/auth_session.hpp"
#include "common/dds/reader.hpp"
#include "common/dds/waitset.hpp"
#include "common/node/node_runner.hpp"
#include "image_measures.hpp"
#include "stereo/frame/frame_decoder.hpp"
#include "stereo/msg/calibration_msg.hpp"

namespace stereoball::doctor {
namespace {

std::string text(const char* s) {
  return s ? s : "";
}

std::string host_name() {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  return host;
}

std::string dds_config_text(bool keyed) {
  if (!keyed) return "built-in loopback-only (no key)";
  const char* uri = std::getenv("CYCLONEDDS_URI");
  return uri && *uri ? std::string(uri) : "Cyclone's default (CYCLONEDDS_URI unset)";
}

// A live pair kept for the image measures.
struct KeptPair {
  cv::Mat left, right;
  bool rectified = false;
};

class Listener {
 public:
  explicit Listener(const CollectOptions& options)
      : options_(options),
        participant_({options.common.domain_id, options.common.partition, options.common.key_file}),
        health_(participant_, topics::kComponentStatus),
        frames_(participant_, topics::kStereoFrame),
        calibration_(participant_, topics::kStereoCalibration),
        estop_(participant_, topics::kEmergencyStop),
        waitset_(participant_),
        c_health_(health_.handle()),
        c_frames_(frames_.handle()),
        c_calibration_(calibration_.handle()),
        c_estop_(estop_.handle()) {
    waitset_.attach(c_health_.handle(), 0);
    waitset_.attach(c_frames_.handle(), 1);
    waitset_.attach(c_calibration_.handle(), 2);
    waitset_.attach(c_estop_.handle(), 3);
  }

  Observations run() {
    Observations obs;
    obs.self.domain_id = options_.common.domain_id;
    obs.self.partition = options_.common.partition;
    obs.self.host = host_name();
    obs.self.keyed = participant_.auth().keyed();
    obs.self.key_id = participant_.auth().signing_key_id();
    obs.self.key_fingerprint = participant_.auth().signing_key_fingerprint();
    obs.self.dds_config = dds_config_text(obs.self.keyed);
    obs.listen_start_ns = node::now_ns();
    const int64_t start_mono = node::monotonic_ns();
    const int64_t listen_ns = static_cast<int64_t>(options_.listen_s * 1e9);
    const int64_t end_mono = start_mono + listen_ns;
    // Pairs are kept spread over the listening time (the scene may change).
    const int pairs = std::max(options_.pairs, 0);
    int kept = 0;
    auto next_pair_mono = [&] { return start_mono + listen_ns * (kept + 1) / (pairs + 2); };
    while (node::monotonic_ns() < end_mono) {
      waitset_.wait(std::min<int64_t>(end_mono - node::monotonic_ns(), 100'000'000));
      take_health();
      take_calibration();
      take_estop();
      const bool want_pair = kept < pairs && node::monotonic_ns() >= next_pair_mono();
      if (take_frames(want_pair)) ++kept;
    }
    obs.listen_end_ns = node::now_ns();
    for (auto& [key, node] : nodes_) obs.nodes.push_back(std::move(node));
    if (frame_count_ > 0) {
      frame_.count = frame_count_;
      if (frame_count_ > 1 && last_frame_ns_ > first_frame_ns_)
        frame_.receive_rate_hz = (frame_count_ - 1) * 1e9 / (last_frame_ns_ - first_frame_ns_);
      obs.frames = frame_;
    }
    if (calibration_msg_) obs.calibration = calibration_obs_;
    obs.estop = estop_state_;
    obs.estop.holders = estop_.matched_writers();
    obs.self.auth_counters = participant_.auth().counters();
    obs.measures = measure();
    return obs;
  }

 private:
  void take_health() {
    for (auto& s : health_.take(64)) {
      const std::string component = text(s->component), host = text(s->host);
      const std::string key = component + "|" + host + "|" + std::to_string(s->pid);
      auto [it, inserted] = nodes_.try_emplace(key);
      NodeObservation& n = it->second;
      n.component = component;
      n.host = host;
      n.pid = s->pid;
      n.beats.push_back({s->stamp_ns, node::now_ns()});
      n.healthy = s->healthy;
      n.state = text(s->state);
      n.last_error = text(s->last_error);
      n.errors = s->errors;
      n.rates_hz.clear();
      n.topic_counts.clear();
      for (uint32_t i = 0; i < s->rates._length; ++i) {
        n.rates_hz[text(s->rates._buffer[i].topic)] = s->rates._buffer[i].rate_hz;
        n.topic_counts[text(s->rates._buffer[i].topic)] = s->rates._buffer[i].count;
      }
      n.counters.clear();
      for (uint32_t i = 0; i < s->counters._length; ++i)
        n.counters[text(s->counters._buffer[i].name)] = s->counters._buffer[i].value;
      if (inserted) {
        n.first_counters = n.counters;
        n.first_topic_counts = n.topic_counts;
      }
    }
  }

  void take_calibration() {
    auto latest = calibration_.take_latest();
    if (!latest) return;
    const auto& m = **latest;
    calibration_obs_.width_px = m.width_px;
    calibration_obs_.height_px = m.height_px;
    calibration_obs_.baseline_m = -m.t[0];
    calibration_obs_.source = text(m.source);
    calibration_msg_ = true;
    auto calib = stereo::calibration_from_message(m);
    if (!calib) {
      calibration_error_ = "the live calibration is refused: " + calib.error();
      rectifier_.reset();
      return;
    }
    calibration_error_.clear();
    auto rectifier = stereo::Rectifier::create(*calib);
    if (!rectifier) {
      calibration_error_ = "the live calibration cannot rectify: " + rectifier.error();
      rectifier_.reset();
      return;
    }
    rectifier_ = std::make_unique<stereo::Rectifier>(std::move(*rectifier));
  }

  void take_estop() {
    // Only newer authenticated states are delivered: the last one taken is the newest.
    for (auto& s : estop_.take()) {
      estop_state_.seen = true;
      estop_state_.engaged = s->engaged;
      estop_state_.reason = text(s->reason);
      estop_state_.stamp_ns = s->auth.stamp_ns ? s->auth.stamp_ns : s->stamp_ns;
    }
  }

  // Takes the frames that arrived; keeps a decoded copy of the newest when keep. True if kept.
  bool take_frames(bool keep) {
    auto samples = frames_.take_loaned();
    bool kept = false;
    const auto newest = samples.latest_valid();
    for (size_t i = 0; i < samples.size(); ++i) {
      if (!samples.valid(i)) continue;
      const auto& f = samples[i];
      const int64_t now = node::now_ns();
      if (frame_count_ == 0) first_frame_ns_ = now;
      last_frame_ns_ = now;
      ++frame_count_;
      frame_.left_width_px = f.left.width_px;
      frame_.left_height_px = f.left.height_px;
      frame_.right_width_px = f.right.width_px;
      frame_.right_height_px = f.right.height_px;
      frame_.encoding = text(f.encoding);
      frame_.source = text(f.source);
      if (keep && newest && i == *newest) {
        cv::Mat left, right;
        const cv::Size size(static_cast<int>(f.left.width_px), static_cast<int>(f.left.height_px));
        if (auto st = decoder_.decode(f, size, left, right); !st) {
          decode_error_ = "live frames cannot be decoded: " + st.error();
        } else {
          pairs_.push_back({left.clone(), right.clone(), f.rectified});
          kept = true;
        }
      }
    }
    return kept;
  }

  std::optional<StereoMeasures> measure() {
    if (frame_count_ == 0) return std::nullopt;
    StereoMeasures m;
    if (pairs_.empty()) {
      m.error = decode_error_.empty() ? "no live pair kept" : decode_error_;
      return m;
    }
    for (const auto& p : pairs_) add_pair(m, rectifier_.get(), p.left, p.right, p.rectified);
    if (!calibration_msg_)
      m.stereo_error = "no stereo/calibration to rectify with";
    else if (!calibration_error_.empty())
      m.stereo_error = calibration_error_;
    return m;
  }

  CollectOptions options_;
  dds::DomainParticipant participant_;
  dds::DataReader<stereoball_msg_ComponentStatus> health_;
  dds::DataReader<stereoball_msg_StereoFrame> frames_;
  dds::DataReader<stereoball_msg_StereoCalibration> calibration_;
  dds::DataReader<stereoball_msg_EmergencyStop> estop_;
  dds::WaitSet waitset_;
  dds::ReadCondition c_health_, c_frames_, c_calibration_, c_estop_;

  std::map<std::string, NodeObservation> nodes_;
  FrameObservation frame_;
  uint64_t frame_count_ = 0;
  int64_t first_frame_ns_ = 0, last_frame_ns_ = 0;
  stereo::FrameDecoder decoder_;
  std::vector<KeptPair> pairs_;
  std::string decode_error_;
  bool calibration_msg_ = false;
  CalibrationObservation calibration_obs_;
  std::string calibration_error_;
  std::unique_ptr<stereo::Rectifier> rectifier_;
  EstopObservation estop_state_;
};

// Components that answer on the domain in any partition (DDS partition wildcard "*").
std::vector<std::string> heard_in_any_partition(const CollectOptions& options, double listen_s) {
  dds::DomainParticipant participant({options.common.domain_id, "*", options.common.key_file});
  dds::DataReader<stereoball_msg_ComponentStatus> health(participant, topics::kComponentStatus);
  std::set<std::string> names;
  const int64_t end = node::monotonic_ns() + static_cast<int64_t>(listen_s * 1e9);
  while (node::monotonic_ns() < end) {
    for (auto& s : health.take(64)) names.insert(text(s->component) + "@" + text(s->host));
    usleep(50'000);
  }
  return {names.begin(), names.end()};
}

}  // namespace

Observations collect(const CollectOptions& options) {
  Observations obs;
  {
    Listener listener(options);
    obs = listener.run();
  }
  if (options.probe_partitions && obs.nodes.empty() && !obs.frames && !obs.calibration) {
    obs.other_partition_nodes = heard_in_any_partition(options, 2.0);
  }
  return obs;
}

}  // namespace stereoball::doctor
