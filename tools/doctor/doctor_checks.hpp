#pragma once
// stereoball doctor: the checks of a running deployment as pure functions over what the tool
// observed while listening (heartbeats, frames, calibration, e-stop, image measures). No DDS,
// no clocks: every time is in the observations.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace stereoball::doctor {

enum class Verdict { kOk, kWarn, kFail, kNa };

/// "ok", "warn", "FAIL" or "n/a".
const char* to_string(Verdict verdict);

/// One line of the report: what was checked, the verdict, what was seen, how to fix it.
struct Check {
  std::string name;  ///< e.g. "node tracker", "eye order"
  Verdict verdict = Verdict::kNa;
  std::string seen;  ///< what the doctor saw (figures)
  std::string fix;   ///< what to do (warn and FAIL only)
};

/// One heartbeat (health/status) as received.
struct Beat {
  int64_t stamp_ns = 0;    ///< the node's stamp, its clock, ns since epoch
  int64_t receive_ns = 0;  ///< when the doctor took it, the doctor's clock, ns since epoch
};

/// Everything heard from one node (component + host + pid).
struct NodeObservation {
  std::string component;
  std::string host;
  int32_t pid = 0;
  std::vector<Beat> beats;                             ///< in arrival order
  bool healthy = true;                                 ///< of the newest heartbeat
  std::string state;                                   ///< of the newest heartbeat
  std::string last_error;                              ///< of the newest heartbeat
  uint64_t errors = 0;                                 ///< of the newest heartbeat
  std::map<std::string, double> rates_hz;              ///< per topic, newest heartbeat
  std::map<std::string, uint64_t> topic_counts;        ///< per topic since start, newest heartbeat
  std::map<std::string, uint64_t> first_topic_counts;  ///< the same, first heartbeat
  std::map<std::string, uint64_t> counters;            ///< newest heartbeat
  std::map<std::string, uint64_t> first_counters;      ///< first heartbeat (for rates of counters)
};

/// stereo/frame as received.
struct FrameObservation {
  uint64_t count = 0;  ///< samples received
  uint32_t left_width_px = 0, left_height_px = 0;
  uint32_t right_width_px = 0, right_height_px = 0;
  std::string encoding;
  std::string source;
  double receive_rate_hz = 0;  ///< at the doctor (0 with fewer than 2 samples)
};

/// stereo/calibration as received.
struct CalibrationObservation {
  uint32_t width_px = 0, height_px = 0;
  double baseline_m = 0;
  std::string source;
};

/// cmd/estop as received.
struct EstopObservation {
  bool seen = false;  ///< a latched state arrived
  bool engaged = false;
  std::string reason;
  int64_t stamp_ns = 0;
  uint32_t holders = 0;  ///< writers of cmd/estop matched (nodes that hold the stop)
};

/// Exposure and sharpness of one eye.
struct EyeImageStats {
  double mean = 0;             ///< mean grey level, 0..255
  double dark_fraction = 0;    ///< pixels at <= 2
  double bright_fraction = 0;  ///< pixels at >= 253
  double laplacian_var = 0;    ///< variance of the Laplacian (focus / motion blur)
};

/// Measures on a few live pairs after rectification with the live calibration.
struct StereoMeasures {
  int pairs = 0;                   ///< pairs measured (exposure, blur)
  int stereo_pairs = 0;            ///< of them rectified and matched (eye order, row error)
  std::string stereo_error;        ///< why no pair was rectified ("" = fine)
  std::size_t positive = 0;        ///< row-consistent feature matches with x_left > x_right
  std::size_t negative = 0;        ///< ... with x_left < x_right (swapped eyes)
  std::vector<double> abs_row_px;  ///< |dy| of the row-check matches, rectified pixels
  EyeImageStats left, right;       ///< of the newest pair
  std::string error;               ///< why nothing could be measured ("" = fine)
};

/// The camera_server configuration the deployment runs with (its mode and rate).
struct CameraConfig {
  std::string path;
  std::string source;  ///< v4l2 or files
  uint32_t width_px = 0, height_px = 0;
  double rate_hz = 0;
};

/// The doctor's own place in DDS.
struct SelfObservation {
  int domain_id = 0;
  std::string partition;
  std::string host;  ///< the doctor's host name
  bool keyed = false;
  uint32_t key_id = 0;
  uint32_t key_fingerprint = 0;  ///< as the health counter auth_key_fingerprint (0 keyless)
  std::string dds_config;        ///< CYCLONEDDS_URI, or what the keyless participant uses
  std::map<std::string, uint64_t> auth_counters;  ///< auth_<verdict>:<topic> of the doctor
};

struct Observations {
  int64_t listen_start_ns = 0;  ///< the doctor's clock
  int64_t listen_end_ns = 0;
  std::vector<NodeObservation> nodes;
  std::vector<std::string> expected_nodes;  ///< components that must be there (may be empty)
  std::optional<FrameObservation> frames;
  std::optional<CalibrationObservation> calibration;
  EstopObservation estop;
  std::optional<StereoMeasures> measures;
  std::optional<CameraConfig> camera_config;
  std::string camera_config_note;  ///< why no camera configuration is known
  SelfObservation self;
  /// Components heard on the domain in any partition (only looked for when nothing answered).
  std::vector<std::string> other_partition_nodes;
};

/// The bounds of the checks (README: tools/doctor/README.md).
struct Limits {
  double silent_after_s = 3.0;          ///< a node without heartbeat this long is silent
  double rate_warn_fraction = 0.9;      ///< frame rate below this share of the configured: warn
  double rate_fail_fraction = 0.5;      ///< ... below this: FAIL
  double skew_warn_us = 2000;           ///< eye skew p50 above: warn (or max above skew_fail_us)
  double skew_fail_us = 10000;          ///< eye skew p50 above: FAIL
  double row_warn_px = 1.0;             ///< median rectified row error above: warn
  double row_fail_px = 2.0;             ///< ... above: FAIL (ball_detector's epipolar.tolerance_px)
  std::size_t min_row_matches = 20;     ///< fewer: n/a
  std::size_t min_sign_matches = 20;    ///< fewer row-consistent matches: eye order n/a
  double min_positive_share = 2.0 / 3;  ///< positive disparities at least this share: ok
  double clock_warn_s = 0.05;           ///< |offset| above: warn
  double clock_behind_fail_s = 1.0;     ///< stamps older than this on arrival: FAIL (window)
  double clock_ahead_fail_s = 0.5;      ///< stamps this far in the future: FAIL (refused)
  double dark_mean = 40, bright_mean = 215;  ///< mean grey outside: warn
  double black_mean = 10, white_mean = 245;  ///< mean grey outside: FAIL (covered, blinded)
  double clipped_warn_fraction = 0.05;       ///< clipped pixels above: warn
  double blur_warn_laplacian_var = 30;       ///< variance of the Laplacian below: warn
};

/// Nothing heard at all: the likely causes (domain, partition, DDS configuration).
Check check_discovery(const Observations& obs);
/// One check per node seen or expected: alive, healthy, its rates; silent or missing named.
std::vector<Check> check_nodes(const Observations& obs, const Limits& limits);
/// The frame source: frame size and rate against the camera configuration, both eyes delivering.
Check check_cameras(const Observations& obs, const Limits& limits);
/// camera_server's eye_skew_us_p50 / eye_skew_us_max counters (n/a without them).
Check check_eye_skew(const Observations& obs, const Limits& limits);
/// The sign of disparity of matched features: negative = swapped cameras.
Check check_eye_order(const Observations& obs, const Limits& limits);
/// stereo/calibration's image size against stereo/frame's.
Check check_calibration_size(const Observations& obs);
/// Median |dy| of feature matches after rectification.
Check check_row_error(const Observations& obs, const Limits& limits);
/// Exposure (mean, clipping) and blur (variance of the Laplacian) of one eye.
Check check_image(const Observations& obs, bool left, const Limits& limits);
/// The deployment key on every node (health counters auth_key_id, auth_key_fingerprint) and
/// the doctor's own.
Check check_keys(const Observations& obs);
/// Clock offset of each host against the doctor's (heartbeat stamp vs receive time).
Check check_clock(const Observations& obs, const Limits& limits);
/// The latched e-stop and how many nodes hold it.
Check check_estop(const Observations& obs);

/// Every check in report order. When nothing was heard, only discovery and the nodes expected.
std::vector<Check> run_checks(const Observations& obs, const Limits& limits = {});

/// 1 when any check failed, else 0.
int exit_status(const std::vector<Check>& checks);
/// One line per check: "FAIL  name: seen -> fix".
std::string to_text(const std::vector<Check>& checks);
/// {"ok": bool, "checks": [{"name", "verdict", "seen", "fix"}...]} on one line.
std::string to_json(const std::vector<Check>& checks);

/// The node name shown in reports: "component@host".
std::string node_label(const NodeObservation& node);

}  // namespace stereoball::doctor
