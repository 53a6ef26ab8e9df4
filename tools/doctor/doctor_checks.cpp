#include "doctor_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "common/util/enum_names.hpp"
#include "common/util/json_text.hpp"

namespace stereoball::doctor {
namespace {

std::string fmt(const char* format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, value);
  return buf;
}

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : sep) + p;
  return out;
}

Check make(std::string name, Verdict verdict, std::string seen, std::string fix = {}) {
  return Check{std::move(name), verdict, std::move(seen),
               verdict == Verdict::kWarn || verdict == Verdict::kFail ? std::move(fix) : ""};
}

std::string size_text(uint32_t w, uint32_t h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

bool nothing_heard(const Observations& obs) {
  return obs.nodes.empty() && !obs.frames && !obs.calibration && !obs.estop.seen &&
         obs.estop.holders == 0;
}

double listen_s(const Observations& obs) {
  return (obs.listen_end_ns - obs.listen_start_ns) * 1e-9;
}

std::string where(const Observations& obs) {
  return "domain " + std::to_string(obs.self.domain_id) + ", partition " +
         (obs.self.partition.empty() ? std::string("(default)") : "'" + obs.self.partition + "'");
}

// The node that publishes stereo/frame: camera_server first, else the simulator.
const NodeObservation* frame_source(const Observations& obs) {
  for (const char* name : {"camera_server", "simulator"}) {
    for (const auto& n : obs.nodes)
      if (n.component == name) return &n;
  }
  return nullptr;
}

std::optional<uint64_t> counter(const NodeObservation& node, const std::string& name) {
  auto it = node.counters.find(name);
  if (it == node.counters.end()) return std::nullopt;
  return it->second;
}

// Growth of a counter per second between the first and the newest heartbeat.
std::optional<double> counter_rate(const NodeObservation& node, const std::string& name) {
  auto last = node.counters.find(name);
  auto first = node.first_counters.find(name);
  if (last == node.counters.end() || first == node.first_counters.end() || node.beats.size() < 2)
    return std::nullopt;
  const double dt_s = (node.beats.back().stamp_ns - node.beats.front().stamp_ns) * 1e-9;
  if (dt_s <= 0) return std::nullopt;
  return static_cast<double>(last->second - std::min(first->second, last->second)) / dt_s;
}

// A topic's rate over the whole listening time (counts between the first and newest
// heartbeat), else the newest heartbeat's figure (a node's first heartbeat says 0).
double topic_rate(const NodeObservation& node, const std::string& topic) {
  auto last = node.topic_counts.find(topic);
  auto first = node.first_topic_counts.find(topic);
  if (last != node.topic_counts.end() && first != node.first_topic_counts.end() &&
      node.beats.size() >= 2 && last->second >= first->second) {
    const double dt_s = (node.beats.back().stamp_ns - node.beats.front().stamp_ns) * 1e-9;
    if (dt_s > 0) return static_cast<double>(last->second - first->second) / dt_s;
  }
  auto it = node.rates_hz.find(topic);
  return it == node.rates_hz.end() ? 0 : it->second;
}

const char* kDiscoveryFix =
    "run the doctor with the nodes' domain and partition (--domain/--partition, or "
    "$STEREOBALL_DOMAIN/$STEREOBALL_PARTITION as in the launch or systemd environment) and "
    "the same DDS configuration (CYCLONEDDS_URI of the profile; a tool without the key is "
    "confined to loopback and cannot reach nodes on another host); on two hosts check "
    "STEREOBALL_IFACE/STEREOBALL_PEER and that UDP 7400-7700 passes the firewall";

}  // namespace

// The rows are string literals: a name's data() ends in a NUL.
constexpr util::EnumName<Verdict> kDoctorVerdictNames[] = {{Verdict::kOk, "ok"},
                                                           {Verdict::kWarn, "warn"},
                                                           {Verdict::kFail, "FAIL"},
                                                           {Verdict::kNa, "n/a"}};

const char* to_string(Verdict verdict) {
  return util::name_of(kDoctorVerdictNames, verdict, "?").data();
}

std::string node_label(const NodeObservation& node) {
  return node.component + "@" + node.host;
}

Check check_discovery(const Observations& obs) {
  if (!nothing_heard(obs)) {
    return make("discovery", Verdict::kOk,
                std::to_string(obs.nodes.size()) + " node(s) on " + where(obs) +
                    " (DDS configuration: " + obs.self.dds_config + ")");
  }
  std::string seen =
      "nothing heard in " + fmt("%.1f", listen_s(obs)) + " s on " + where(obs) +
      " (no heartbeat, frame, calibration or e-stop; DDS configuration: " + obs.self.dds_config +
      ")";
  if (!obs.other_partition_nodes.empty()) {
    seen += "; in another partition of this domain: " + join(obs.other_partition_nodes, ", ");
  }
  return make("discovery", Verdict::kFail, seen, kDiscoveryFix);
}

std::vector<Check> check_nodes(const Observations& obs, const Limits& limits) {
  std::vector<Check> out;
  std::set<std::string> seen_components;
  for (const auto& node : obs.nodes) {
    seen_components.insert(node.component);
    const std::string name = "node " + node_label(node);
    const double quiet_s = node.beats.empty()
                               ? listen_s(obs)
                               : (obs.listen_end_ns - node.beats.back().receive_ns) * 1e-9;
    if (quiet_s > limits.silent_after_s) {
      out.push_back(make(name, Verdict::kFail,
                         "silent: no heartbeat for the last " + fmt("%.1f", quiet_s) + " s (pid " +
                             std::to_string(node.pid) + ", " + std::to_string(node.beats.size()) +
                             " heartbeat(s) before)",
                         "the process hangs, was stopped or lost the network: read its log "
                         "(stereoball-launch.log or journalctl -u stereoball-*) and restart it"));
      continue;
    }
    std::vector<std::string> rates;
    for (const auto& [topic, hz] : node.rates_hz)
      rates.push_back(topic + " " + fmt("%.1f", topic_rate(node, topic)) + " Hz");
    std::string seen = "alive (" + std::to_string(node.beats.size()) + " heartbeats), '" +
                       node.state + "'" + (rates.empty() ? "" : "; " + join(rates, ", "));
    if (!node.healthy) {
      out.push_back(make(name, Verdict::kWarn,
                         "unhealthy: '" + node.state + "'" +
                             (node.last_error.empty() ? "" : ", last error: " + node.last_error) +
                             (rates.empty() ? "" : "; " + join(rates, ", ")),
                         "its state says what it lacks (input, device, calibration): read its "
                         "log and the checks below"));
    } else {
      out.push_back(make(name, Verdict::kOk, seen));
    }
  }
  for (const auto& expected : obs.expected_nodes) {
    if (seen_components.count(expected)) continue;
    out.push_back(
        make("node " + expected, Verdict::kFail,
             "missing: no heartbeat in " + fmt("%.1f", listen_s(obs)) + " s on " + where(obs),
             "start it (stereoball launch PROFILE, or systemctl start the role's "
             "unit); if it runs, it is on another domain, partition or DDS "
             "configuration, or it cannot start (read its log)"));
  }
  return out;
}

Check check_cameras(const Observations& obs, const Limits& limits) {
  const NodeObservation* source = frame_source(obs);
  if (!source && !obs.frames) {
    return make("cameras", Verdict::kFail,
                "no frame source: no camera_server or simulator heard, no stereo/frame",
                "start camera_server (robot host) or the simulator; see the node checks");
  }
  std::vector<std::string> seen;
  Verdict verdict = Verdict::kOk;
  std::string fix;
  auto rank = [](Verdict v) { return v == Verdict::kFail ? 2 : v == Verdict::kWarn ? 1 : 0; };
  // A finding: the worst verdict wins and its fixes are kept.
  auto worse = [&](Verdict v, const std::string& text, const std::string& how) {
    seen.push_back(text);
    if (rank(v) > rank(verdict)) {
      verdict = v;
      fix = how;
    } else if (rank(v) == rank(verdict)) {
      fix += (fix.empty() ? "" : "; ") + how;
    }
  };
  double rate_hz = 0;
  if (source) {
    rate_hz = topic_rate(*source, "stereo/frame");
    seen.push_back(source->component + " publishes " + fmt("%.1f", rate_hz) + " Hz");
  } else {
    rate_hz = obs.frames->receive_rate_hz;
    seen.push_back("no frame source heartbeat; " + fmt("%.1f", rate_hz) + " Hz received");
  }
  if (obs.frames) {
    const auto& f = *obs.frames;
    seen.push_back(f.encoding + " " + size_text(f.left_width_px, f.left_height_px) + " from '" +
                   f.source + "', " + fmt("%.1f", f.receive_rate_hz) + " Hz received here");
    if (f.left_width_px != f.right_width_px || f.left_height_px != f.right_height_px) {
      worse(Verdict::kFail,
            "eyes differ in size: right " + size_text(f.right_width_px, f.right_height_px),
            "both cameras must run the same mode: set width_px/height_px to a mode both offer "
            "(stereoball cameras)");
    }
  } else {
    worse(Verdict::kFail, "no stereo/frame received",
          "the source publishes nothing the doctor can receive: a camera lost (node check), or "
          "frames lost between hosts (deploy/README.md, kernel settings)");
  }
  const bool is_camera_server = source && source->component == "camera_server";
  // The config found by the search order may not be the one camera_server runs with: the
  // frames' source ("v4l2:..." / "files:...") must agree with its source before comparing.
  const bool config_fits = !obs.camera_config || !obs.frames ||
                           obs.frames->source.rfind(obs.camera_config->source + ":", 0) == 0;
  if (is_camera_server && obs.camera_config && !config_fits) {
    worse(Verdict::kWarn,
          "the camera config found (" + obs.camera_config->path + ", source " +
              obs.camera_config->source + ") is not the one running: mode and rate not compared",
          "name the config camera_server runs with: --camera-config FILE or --profile NAME");
  } else if (is_camera_server && obs.camera_config) {
    const auto& cfg = *obs.camera_config;
    seen.push_back("configured " + cfg.source + " " + size_text(cfg.width_px, cfg.height_px) +
                   " at " + fmt("%.1f", cfg.rate_hz) + " Hz (" + cfg.path + ")");
    const std::string rate_fix =
        "the cameras do not keep the configured rate: a mode they offer at that rate "
        "(stereoball cameras), enough USB bandwidth (one controller per camera, or MJPEG), "
        "more light (auto exposure lengthens frames in the dark)";
    if (rate_hz < limits.rate_fail_fraction * cfg.rate_hz) {
      worse(Verdict::kFail,
            "rate below " + fmt("%.0f", limits.rate_fail_fraction * 100) + " % of the configured",
            rate_fix);
    } else if (rate_hz < limits.rate_warn_fraction * cfg.rate_hz) {
      worse(Verdict::kWarn,
            "rate below " + fmt("%.0f", limits.rate_warn_fraction * 100) + " % of the configured",
            rate_fix);
    }
    if (obs.frames && cfg.source == "v4l2" &&
        (obs.frames->left_width_px != cfg.width_px ||
         obs.frames->left_height_px != cfg.height_px)) {
      worse(Verdict::kFail, "frames are not the configured size",
            "camera_server does not run the configured mode: restart it and read its log");
    }
  } else if (is_camera_server) {
    seen.push_back("configured mode unknown (" + obs.camera_config_note + ")");
  }
  if (is_camera_server) {
    const auto left = counter_rate(*source, "frames_left");
    const auto right = counter_rate(*source, "frames_right");
    if (left && right) {
      seen.push_back("eyes " + fmt("%.1f", *left) + " / " + fmt("%.1f", *right) + " Hz");
      if ((*left == 0) != (*right == 0)) {
        worse(
            Verdict::kFail, std::string(*left == 0 ? "left" : "right") + " eye delivers nothing",
            "a camera stopped (USB power or bandwidth, cable): replug it, see camera_server's log");
      }
    }
    const auto unpaired_l = counter_rate(*source, "unpaired_left");
    const auto unpaired_r = counter_rate(*source, "unpaired_right");
    if (unpaired_l && unpaired_r && left && right && *left + *right > 0) {
      const double share = (*unpaired_l + *unpaired_r) / (*left + *right);
      if (share > 0.1) {
        worse(Verdict::kWarn, fmt("%.0f", share * 100) + " % of the frames unpaired",
              "the eyes' stamps drift apart (free-running cameras or a late camera): see eye skew");
      }
    }
  }
  return make("cameras", verdict, join(seen, "; "), fix);
}

Check check_eye_skew(const Observations& obs, const Limits& limits) {
  const NodeObservation* source = frame_source(obs);
  if (!source) return make("eye skew", Verdict::kNa, "no frame source heard");
  const auto p50 = counter(*source, "eye_skew_us_p50");
  const auto max = counter(*source, "eye_skew_us_max");
  if (!p50 || !max) {
    return make("eye skew", Verdict::kNa,
                source->component == "simulator"
                    ? "simulated eyes are exposed together"
                    : source->component + " reports no eye_skew_us_p50/eye_skew_us_max");
  }
  const std::string seen = "left-right capture skew p50 " + fmt("%.2f", *p50 / 1000.0) +
                           " ms, max " + fmt("%.2f", *max / 1000.0) + " ms";
  const std::string fix =
      "the cameras expose at different moments (free-running): cameras with a sync input or "
      "one stereo camera; the same model and mode on separate USB controllers; calibrate with "
      "a board held still (stereoball calibrate --live)";
  if (static_cast<double>(*p50) > limits.skew_fail_us)
    return make("eye skew", Verdict::kFail, seen, fix);
  if (static_cast<double>(*p50) > limits.skew_warn_us ||
      static_cast<double>(*max) > limits.skew_fail_us)
    return make("eye skew", Verdict::kWarn, seen, fix);
  return make("eye skew", Verdict::kOk, seen);
}

namespace {
// Why there are no image measures, for the n/a lines.
std::string no_measures(const Observations& obs) {
  if (!obs.frames) return "no stereo/frame received";
  if (!obs.measures) return "not measured";
  return obs.measures->error;
}
bool measured(const Observations& obs) {
  return obs.measures && obs.measures->error.empty() && obs.measures->pairs > 0;
}
std::string no_stereo(const Observations& obs) {
  if (!measured(obs)) return no_measures(obs);
  return obs.measures->stereo_error.empty() ? "no pair rectified" : obs.measures->stereo_error;
}
bool stereo_measured(const Observations& obs) {
  return measured(obs) && obs.measures->stereo_error.empty() && obs.measures->stereo_pairs > 0;
}
}  // namespace

Check check_eye_order(const Observations& obs, const Limits& limits) {
  if (!stereo_measured(obs)) return make("eye order", Verdict::kNa, no_stereo(obs));
  const auto& m = *obs.measures;
  const std::size_t total = m.positive + m.negative;
  const std::string seen = std::to_string(m.positive) + " of " + std::to_string(total) +
                           " ORB features matched on nearby rectified rows have positive "
                           "disparity (" +
                           std::to_string(m.negative) + " negative; " +
                           std::to_string(m.stereo_pairs) + " live pairs)";
  if (total < limits.min_sign_matches) {
    return make("eye order", Verdict::kNa,
                seen + ": too few to decide (a blank, dark or blurred scene)");
  }
  const std::string fix =
      "left and right are swapped: swap left_device and right_device in the camera_server "
      "config (file source: left_glob and right_glob), or the two cameras' cables";
  if (m.negative > m.positive) return make("eye order", Verdict::kFail, seen, fix);
  const double share = static_cast<double>(m.positive) / static_cast<double>(total);
  if (share < limits.min_positive_share) {
    return make("eye order", Verdict::kWarn, seen,
                "no clear order: point the rig at a textured scene 1-5 m away and run again; "
                "if it stays mixed, calibrate again");
  }
  return make("eye order", Verdict::kOk, seen);
}

Check check_calibration_size(const Observations& obs) {
  if (!obs.calibration) {
    std::string seen = "no stereo/calibration received";
    uint64_t refused = 0;
    for (const auto& [name, value] : obs.self.auth_counters) {
      if (name.find(":stereo/calibration") != std::string::npos &&
          name.rfind("auth_accepted", 0) != 0 && name.rfind("auth_duplicate", 0) != 0)
        refused += value;
    }
    if (refused > 0) {
      seen += " (" + std::to_string(refused) + " refused by the doctor's key check: see keys)";
    }
    return make("calibration size", Verdict::kFail, seen,
                "set calibration_file in the camera_server config (stereoball calibrate makes "
                "one; camera_server refuses a file made for another image size, see its log)");
  }
  const auto& c = *obs.calibration;
  const std::string calib = size_text(c.width_px, c.height_px) + " (baseline " +
                            fmt("%.4f", c.baseline_m) + " m, " + c.source + ")";
  if (!obs.frames)
    return make("calibration size", Verdict::kNa,
                "calibration " + calib + "; no frames to compare");
  const auto& f = *obs.frames;
  if (c.width_px != f.left_width_px || c.height_px != f.left_height_px) {
    return make("calibration size", Verdict::kFail,
                "calibration is for " + calib + ", frames are " +
                    size_text(f.left_width_px, f.left_height_px),
                "calibrate at the capture size (stereoball calibrate with pairs of this mode) or "
                "set width_px/height_px to the calibration's size");
  }
  return make("calibration size", Verdict::kOk, "calibration and frames " + calib);
}

Check check_row_error(const Observations& obs, const Limits& limits) {
  if (!stereo_measured(obs)) return make("row error", Verdict::kNa, no_stereo(obs));
  std::vector<double> dy = obs.measures->abs_row_px;
  if (dy.size() < limits.min_row_matches) {
    return make("row error", Verdict::kNa,
                std::to_string(dy.size()) + " features matched after rectification: too few");
  }
  std::nth_element(dy.begin(), dy.begin() + dy.size() / 2, dy.end());
  const double median = dy[dy.size() / 2];
  const std::string seen = "median |dy| " + fmt("%.2f", median) + " px over " +
                           std::to_string(dy.size()) + " live feature matches";
  const std::string fix =
      "the calibration no longer fits the rig (a camera moved, a lens refocused, or another "
      "rig's file): tighten the mounts and calibrate again (stereoball calibrate --live)";
  if (median > limits.row_fail_px)
    return make("row error", Verdict::kFail,
                seen + " (the detector pairs within " + fmt("%.1f", limits.row_fail_px) + " px)",
                fix);
  if (median > limits.row_warn_px) return make("row error", Verdict::kWarn, seen, fix);
  return make("row error", Verdict::kOk, seen);
}

Check check_image(const Observations& obs, bool left, const Limits& limits) {
  const std::string name = left ? "image left" : "image right";
  if (!measured(obs)) return make(name, Verdict::kNa, no_measures(obs));
  const EyeImageStats& s = left ? obs.measures->left : obs.measures->right;
  const std::string seen = "mean " + fmt("%.0f", s.mean) + ", " +
                           fmt("%.1f", s.dark_fraction * 100) + " % black, " +
                           fmt("%.1f", s.bright_fraction * 100) + " % white, sharpness " +
                           fmt("%.0f", s.laplacian_var) + " (variance of the Laplacian)";
  const std::string exposure_fix =
      "controls.auto_exposure: true, or adjust controls.exposure_us / controls.gain in the "
      "camera_server config; more light; check the lens cap";
  if (s.mean < limits.black_mean || s.mean > limits.white_mean)
    return make(name, Verdict::kFail, seen + ": the eye sees nothing usable", exposure_fix);
  if (s.mean < limits.dark_mean || s.mean > limits.bright_mean ||
      s.dark_fraction > limits.clipped_warn_fraction ||
      s.bright_fraction > limits.clipped_warn_fraction)
    return make(name, Verdict::kWarn, seen + ": badly exposed", exposure_fix);
  if (s.laplacian_var < limits.blur_warn_laplacian_var)
    return make(name, Verdict::kWarn, seen + ": blurred",
                "focus and clean the lens; a shorter exposure (controls.exposure_us) against "
                "motion blur");
  return make(name, Verdict::kOk, seen);
}

namespace {
// A key as nodes report it: id and fingerprint (0 when the node does not report one).
struct KeyName {
  uint32_t id = 0;
  uint32_t fingerprint = 0;
  auto operator<=>(const KeyName&) const = default;
};
std::string key_text(const KeyName& k) {
  if (k.id == 0) return "no key";
  char buf[64];
  std::snprintf(buf, sizeof buf, "key %u (fingerprint %08x)", k.id, k.fingerprint);
  return buf;
}
}  // namespace

Check check_keys(const Observations& obs) {
  std::map<KeyName, std::vector<std::string>> by_key;
  std::vector<std::string> unknown;
  for (const auto& node : obs.nodes) {
    if (auto id = counter(node, "auth_key_id")) {
      const KeyName k{static_cast<uint32_t>(*id),
                      static_cast<uint32_t>(counter(node, "auth_key_fingerprint").value_or(0))};
      by_key[k].push_back(node_label(node));
    } else {
      unknown.push_back(node_label(node));
    }
  }
  const KeyName mine{obs.self.key_id, obs.self.key_fingerprint};
  const std::string self =
      obs.self.keyed ? "doctor signs with " + key_text(mine) : "doctor has no key";
  if (by_key.empty()) {
    return make(
        "keys", Verdict::kNa,
        (unknown.empty() ? std::string("no node heard")
                         : "no node reports auth_key_id (older version): " + join(unknown, ", ")) +
            "; " + self);
  }
  std::vector<std::string> groups;
  for (const auto& [k, nodes] : by_key) groups.push_back(key_text(k) + ": " + join(nodes, ", "));
  if (!unknown.empty()) groups.push_back("not reported: " + join(unknown, ", "));
  const std::string seen = join(groups, "; ") + "; " + self;
  const std::string fix =
      "give every node of every host the same deployment key file (--key-file or "
      "$STEREOBALL_KEY_FILE, as the systemd env file does; stereoball keys init makes one, "
      "copy it with mode 0600; stereoball keys show prints its fingerprint); nodes signing "
      "with another key, or none, are ignored by the rest";
  if (by_key.size() > 1) return make("keys", Verdict::kFail, seen, fix);
  const KeyName theirs = by_key.begin()->first;
  if (theirs.id == 0) {
    if (obs.self.keyed)
      return make("keys", Verdict::kWarn, seen + " (the nodes are unauthenticated)",
                  "the nodes run without a key (loopback only, anything on the host can "
                  "command the robot): give them the deployment key");
    return make("keys", Verdict::kWarn, "every node unauthenticated (loopback only); " + self,
                "for a robot give every node the deployment key (stereoball keys init; "
                "STEREOBALL_KEY_FILE); unauthenticated nodes cannot reach another host");
  }
  if (!obs.self.keyed) {
    return make("keys", Verdict::kWarn, seen,
                "run the doctor with the deployment key (--key-file or $STEREOBALL_KEY_FILE): "
                "without it the tools (estop) cannot sign and the authenticated topics are "
                "not checked");
  }
  if (mine.id != theirs.id || (theirs.fingerprint != 0 && mine.fingerprint != theirs.fingerprint)) {
    return make("keys", Verdict::kFail, seen + " (the doctor's key differs)",
                "the doctor's key file is not the deployment's: use the key file the nodes use "
                "(a stop signed with another key is refused by every node)");
  }
  return make("keys", Verdict::kOk, seen);
}

Check check_clock(const Observations& obs, const Limits& limits) {
  // Per host, the largest stamp - receive over its heartbeats: transit delays only lower it,
  // so the largest is the closest to the true offset.
  std::map<std::string, double> offset_s;
  for (const auto& node : obs.nodes) {
    for (const Beat& b : node.beats) {
      const double d = (b.stamp_ns - b.receive_ns) * 1e-9;
      auto [it, inserted] = offset_s.emplace(node.host, d);
      if (!inserted) it->second = std::max(it->second, d);
    }
  }
  if (offset_s.empty()) return make("clock", Verdict::kNa, "no heartbeat heard");
  std::vector<std::string> parts;
  Verdict verdict = Verdict::kOk;
  std::string why;
  for (const auto& [host, off] : offset_s) {
    parts.push_back(host + (host == obs.self.host ? " (this host) " : " ") + fmt("%+.3f", off) +
                    " s");
    if (off > limits.clock_ahead_fail_s) {
      verdict = Verdict::kFail;
      why = host + " is ahead by more than " + fmt("%.1f", limits.clock_ahead_fail_s) +
            " s: the others refuse its signed samples as from the future";
    } else if (-off > limits.clock_behind_fail_s) {
      verdict = Verdict::kFail;
      why = host + " is behind by more than the " + fmt("%.1f", limits.clock_behind_fail_s) +
            " s authentication window: its new links and commands are refused as stale";
    } else if (std::abs(off) > limits.clock_warn_s && verdict == Verdict::kOk) {
      verdict = Verdict::kWarn;
      why = "hosts disagree by more than " + fmt("%.0f", limits.clock_warn_s * 1000) + " ms";
    }
  }
  const std::string seen = "heartbeat stamp - arrival per host: " + join(parts, ", ") +
                           (why.empty() ? "" : " (" + why + ")");
  return make("clock", verdict, seen,
              "synchronise every host's clock to one time server (chrony or "
              "systemd-timesyncd; check with chronyc tracking or timedatectl)");
}

Check check_estop(const Observations& obs) {
  const auto& e = obs.estop;
  if (!e.seen && e.holders == 0)
    return make("e-stop", Verdict::kNa,
                "no node holds the stop here (no motion_controller or base)");
  const std::string held = "held by " + std::to_string(e.holders) + " node(s)";
  if (!e.seen)
    return make("e-stop", Verdict::kOk,
                "released (never engaged since the holders started), " + held);
  const double age_s = (obs.listen_end_ns - e.stamp_ns) * 1e-9;
  if (e.engaged) {
    return make("e-stop", Verdict::kWarn,
                "ENGAGED " + fmt("%.0f", age_s) + " s ago ('" + e.reason + "'), " + held,
                "the robot will not move until released: stereoball estop release");
  }
  return make("e-stop", Verdict::kOk,
              "released " + fmt("%.0f", age_s) + " s ago ('" + e.reason + "'), " + held);
}

std::vector<Check> run_checks(const Observations& obs, const Limits& limits) {
  std::vector<Check> out{check_discovery(obs)};
  auto nodes = check_nodes(obs, limits);
  out.insert(out.end(), nodes.begin(), nodes.end());
  if (nothing_heard(obs)) return out;
  out.push_back(check_cameras(obs, limits));
  out.push_back(check_eye_skew(obs, limits));
  out.push_back(check_eye_order(obs, limits));
  out.push_back(check_calibration_size(obs));
  out.push_back(check_row_error(obs, limits));
  out.push_back(check_image(obs, true, limits));
  out.push_back(check_image(obs, false, limits));
  out.push_back(check_keys(obs));
  out.push_back(check_clock(obs, limits));
  out.push_back(check_estop(obs));
  return out;
}

int exit_status(const std::vector<Check>& checks) {
  for (const auto& c : checks)
    if (c.verdict == Verdict::kFail) return 1;
  return 0;
}

std::string to_text(const std::vector<Check>& checks) {
  std::string out;
  for (const auto& c : checks) {
    char head[64];
    std::snprintf(head, sizeof head, "%-4s  %-22s ", to_string(c.verdict), c.name.c_str());
    out += head + c.seen + (c.fix.empty() ? "" : "; fix: " + c.fix) + "\n";
  }
  return out;
}

std::string to_json(const std::vector<Check>& checks) {
  std::string out = "{\"ok\": ";
  out += exit_status(checks) == 0 ? "true" : "false";
  out += ", \"checks\": [";
  for (std::size_t i = 0; i < checks.size(); ++i) {
    const auto& c = checks[i];
    out += std::string(i ? ", " : "") + "{\"name\": \"" + util::json_escape(c.name) +
           "\", \"verdict\": \"" + to_string(c.verdict) + "\", \"seen\": \"" +
           util::json_escape(c.seen) + "\", \"fix\": \"" + util::json_escape(c.fix) + "\"}";
  }
  return out + "]}\n";
}

}  // namespace stereoball::doctor
