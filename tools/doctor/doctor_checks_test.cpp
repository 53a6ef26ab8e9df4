// The doctor's checks as pure functions: a healthy deployment's observations pass, and each
// fault (silent or missing node, swapped eyes, calibration size, keys, skew, clock, camera
// rate, exposure, nothing heard) gives its check's verdict and a fix.

#include "doctor_checks.hpp"

#include <gtest/gtest.h>

namespace stereoball::doctor {
namespace {

constexpr int64_t kS = 1'000'000'000;
constexpr int64_t kT0 = 1'800'000'000 * kS;

NodeObservation node(const std::string& component, const std::string& host, double listen_s = 4) {
  NodeObservation n;
  n.component = component;
  n.host = host;
  n.pid = 100;
  for (int i = 0; i < static_cast<int>(listen_s); ++i)
    n.beats.push_back({kT0 + i * kS + 2'000'000, kT0 + i * kS + 2'500'000});
  n.state = "running";
  n.counters["auth_key_id"] = 7;
  n.counters["auth_key_fingerprint"] = 0xabcdef01;
  return n;
}

// Observations of a healthy deployment: camera_server at its configured 30 Hz, a calibration
// of the frames' size, live pairs with positive disparities and a small row error.
Observations healthy() {
  Observations obs;
  obs.listen_start_ns = kT0;
  obs.listen_end_ns = kT0 + 4 * kS;
  obs.self = {.domain_id = 3,
              .partition = "",
              .host = "robot",
              .keyed = true,
              .key_id = 7,
              .key_fingerprint = 0xabcdef01,
              .dds_config = "file://lan.xml",
              .auth_counters = {}};
  NodeObservation cam = node("camera_server", "robot");
  cam.rates_hz["stereo/frame"] = 29.8;
  cam.first_counters = {
      {"frames_left", 0}, {"frames_right", 0}, {"unpaired_left", 0}, {"unpaired_right", 0}};
  cam.counters.insert({{"frames_left", 90},
                       {"frames_right", 90},
                       {"unpaired_left", 1},
                       {"unpaired_right", 0},
                       {"eye_skew_us_p50", 300},
                       {"eye_skew_us_max", 900}});
  obs.nodes = {cam, node("motion_controller", "robot"), node("ball_detector", "workstation")};
  obs.expected_nodes = {"camera_server", "motion_controller"};
  obs.frames =
      FrameObservation{120, 640, 480, 640, 480, "bgr8", "v4l2:/dev/video0+/dev/video1", 29.9};
  obs.calibration = CalibrationObservation{640, 480, 0.06, "rig.yaml"};
  obs.estop = {.seen = true,
               .engaged = false,
               .reason = "operator",
               .stamp_ns = kT0 - 60 * kS,
               .holders = 2};
  StereoMeasures m;
  m.pairs = m.stereo_pairs = 3;
  m.positive = 140;
  m.negative = 6;
  for (int i = 0; i < 100; ++i) m.abs_row_px.push_back(0.1 + 0.004 * i);
  m.left = m.right = EyeImageStats{110, 0.001, 0.002, 400};
  obs.measures = m;
  obs.camera_config = CameraConfig{"/etc/stereoball/camera_server.yaml", "v4l2", 640, 480, 30};
  return obs;
}

const Check& find(const std::vector<Check>& checks, const std::string& name) {
  for (const auto& c : checks)
    if (c.name == name) return c;
  static const Check none{"(missing)", Verdict::kNa, "", ""};
  ADD_FAILURE() << "no check named " << name;
  return none;
}

TEST(DoctorChecks, GivenAHealthyDeploymentThenNothingFailsAndExitIsZero) {
  // Given the observations of a healthy two-host deployment
  const auto checks = run_checks(healthy());
  // Then every check is ok (no skew warning, keys agree, clocks agree) and the exit status is 0
  for (const auto& c : checks) {
    EXPECT_EQ(c.verdict, Verdict::kOk) << c.name << ": " << c.seen << " / " << c.fix;
    EXPECT_TRUE(c.fix.empty()) << c.name;
  }
  EXPECT_EQ(exit_status(checks), 0);
  EXPECT_EQ(find(checks, "node ball_detector@workstation").verdict, Verdict::kOk);
}

TEST(DoctorChecks, GivenASilentNodeAndAMissingOneThenBothFailByName) {
  // Given a tracker that stopped sending heartbeats 3.5 s before the end, and motion_controller
  // expected but never heard
  Observations obs = healthy();
  NodeObservation tracker = node("tracker", "workstation", 1);
  obs.nodes.push_back(tracker);
  obs.nodes.erase(obs.nodes.begin() + 1);  // motion_controller
  const auto checks = run_checks(obs);
  // Then each has its own failing line naming it, with a fix
  const Check& silent = find(checks, "node tracker@workstation");
  EXPECT_EQ(silent.verdict, Verdict::kFail);
  EXPECT_NE(silent.seen.find("silent"), std::string::npos) << silent.seen;
  const Check& missing = find(checks, "node motion_controller");
  EXPECT_EQ(missing.verdict, Verdict::kFail);
  EXPECT_NE(missing.seen.find("missing"), std::string::npos);
  EXPECT_FALSE(missing.fix.empty());
  EXPECT_EQ(exit_status(checks), 1);
}

TEST(DoctorChecks, GivenNegativeDisparitiesThenEyeOrderFailsWithTheSwapFix) {
  Observations obs = healthy();
  obs.measures->positive = 8;
  obs.measures->negative = 120;
  const Check c = check_eye_order(obs, {});
  EXPECT_EQ(c.verdict, Verdict::kFail);
  EXPECT_NE(c.fix.find("swap left_device and right_device"), std::string::npos) << c.fix;
  // And with too few matches there is no verdict
  obs.measures->positive = 5;
  obs.measures->negative = 3;
  EXPECT_EQ(check_eye_order(obs, {}).verdict, Verdict::kNa);
}

TEST(DoctorChecks, GivenACalibrationOfAnotherSizeThenItFailsNamingBothSizes) {
  Observations obs = healthy();
  obs.calibration->width_px = 1280;
  obs.calibration->height_px = 720;
  const Check c = check_calibration_size(obs);
  EXPECT_EQ(c.verdict, Verdict::kFail);
  EXPECT_NE(c.seen.find("1280x720"), std::string::npos) << c.seen;
  EXPECT_NE(c.seen.find("640x480"), std::string::npos) << c.seen;
  // And without any calibration it fails too, saying none arrived
  obs.calibration.reset();
  EXPECT_EQ(check_calibration_size(obs).verdict, Verdict::kFail);
}

TEST(DoctorChecks, GivenRowErrorsThenWarnAboveOnePixelAndFailAboveTwo) {
  Observations obs = healthy();
  obs.measures->abs_row_px.assign(50, 1.5);
  EXPECT_EQ(check_row_error(obs, {}).verdict, Verdict::kWarn);
  obs.measures->abs_row_px.assign(50, 3.0);
  EXPECT_EQ(check_row_error(obs, {}).verdict, Verdict::kFail);
  obs.measures->abs_row_px.assign(5, 3.0);
  EXPECT_EQ(check_row_error(obs, {}).verdict, Verdict::kNa);
}

TEST(DoctorChecks, GivenKeysThatDifferOrAreMissingThenKeysFailOrWarn) {
  Observations obs = healthy();
  // A node with another key
  obs.nodes[2].counters["auth_key_id"] = 9;
  Check c = check_keys(obs);
  EXPECT_EQ(c.verdict, Verdict::kFail);
  EXPECT_NE(c.seen.find("key 9 (fingerprint abcdef01): ball_detector@workstation"),
            std::string::npos)
      << c.seen;
  // A node with another key of the same id (two files made by `keys init`)
  obs.nodes[2].counters["auth_key_id"] = 7;
  obs.nodes[2].counters["auth_key_fingerprint"] = 0x12345678;
  c = check_keys(obs);
  EXPECT_EQ(c.verdict, Verdict::kFail);
  EXPECT_NE(c.seen.find("key 7 (fingerprint 12345678): ball_detector@workstation"),
            std::string::npos)
      << c.seen;
  obs.nodes[2].counters["auth_key_fingerprint"] = 0xabcdef01;
  // A node without a key among keyed ones
  obs.nodes[2].counters["auth_key_id"] = 0;
  EXPECT_EQ(check_keys(obs).verdict, Verdict::kFail);
  // The nodes agree but the doctor signs with another key (another id, or the same id)
  obs.nodes[2].counters["auth_key_id"] = 7;
  EXPECT_EQ(check_keys(obs).verdict, Verdict::kOk);
  obs.self.key_id = 8;
  EXPECT_EQ(check_keys(obs).verdict, Verdict::kFail);
  obs.self.key_id = 7;
  obs.self.key_fingerprint = 0x12345678;
  EXPECT_EQ(check_keys(obs).verdict, Verdict::kFail);
  // The doctor has no key: a warning, not a failure
  obs.self.keyed = false;
  obs.self.key_id = 0;
  EXPECT_EQ(check_keys(obs).verdict, Verdict::kWarn);
  // Every node and the doctor keyless: warn (loopback only)
  for (auto& n : obs.nodes) n.counters["auth_key_id"] = 0;
  EXPECT_EQ(check_keys(obs).verdict, Verdict::kWarn);
  // Nodes of an older version report nothing: n/a
  for (auto& n : obs.nodes) n.counters.erase("auth_key_id");
  EXPECT_EQ(check_keys(obs).verdict, Verdict::kNa);
}

TEST(DoctorChecks, GivenEyeSkewCountersThenTheirSizeDecidesAndTheirAbsenceIsNa) {
  Observations obs = healthy();
  EXPECT_EQ(check_eye_skew(obs, {}).verdict, Verdict::kOk);
  obs.nodes[0].counters["eye_skew_us_p50"] = 4000;
  EXPECT_EQ(check_eye_skew(obs, {}).verdict, Verdict::kWarn);
  obs.nodes[0].counters["eye_skew_us_p50"] = 15000;
  obs.nodes[0].counters["eye_skew_us_max"] = 30000;
  const Check c = check_eye_skew(obs, {});
  EXPECT_EQ(c.verdict, Verdict::kFail);
  EXPECT_NE(c.seen.find("15.00 ms"), std::string::npos) << c.seen;
  obs.nodes[0].counters.erase("eye_skew_us_p50");
  EXPECT_EQ(check_eye_skew(obs, {}).verdict, Verdict::kNa);
}

TEST(DoctorChecks, GivenAHostTwoSecondsBehindOrAheadThenClockFailsNamingTheWindow) {
  Observations obs = healthy();
  for (auto& b : obs.nodes[2].beats) b.stamp_ns -= 2 * kS;
  Check c = check_clock(obs, {});
  EXPECT_EQ(c.verdict, Verdict::kFail);
  EXPECT_NE(c.seen.find("workstation -2.0"), std::string::npos) << c.seen;
  EXPECT_NE(c.seen.find("authentication window"), std::string::npos) << c.seen;
  for (auto& b : obs.nodes[2].beats) b.stamp_ns += 4 * kS;
  EXPECT_EQ(check_clock(obs, {}).verdict, Verdict::kFail);
  for (auto& b : obs.nodes[2].beats) b.stamp_ns -= 2 * kS - 100'000'000;
  EXPECT_EQ(check_clock(obs, {}).verdict, Verdict::kWarn);
}

TEST(DoctorChecks, GivenASlowOrWrongModeCameraThenCamerasWarnsOrFails) {
  Observations obs = healthy();
  obs.nodes[0].rates_hz["stereo/frame"] = 24;
  EXPECT_EQ(check_cameras(obs, {}).verdict, Verdict::kWarn);
  obs.nodes[0].rates_hz["stereo/frame"] = 10;
  EXPECT_EQ(check_cameras(obs, {}).verdict, Verdict::kFail);
  obs.nodes[0].rates_hz["stereo/frame"] = 30;
  obs.frames->left_width_px = obs.frames->right_width_px = 320;
  EXPECT_EQ(check_cameras(obs, {}).verdict, Verdict::kFail);
  // A config of another source than the one running: not compared, and said so
  obs.frames->left_width_px = obs.frames->right_width_px = 640;
  obs.frames->source = "files:left*.png+right*.png";
  obs.nodes[0].rates_hz["stereo/frame"] = 10;
  Check other = check_cameras(obs, {});
  EXPECT_EQ(other.verdict, Verdict::kWarn);
  EXPECT_NE(other.seen.find("not the one running"), std::string::npos) << other.seen;
  obs.frames->source = "v4l2:/dev/video0+/dev/video1";
  obs.nodes[0].rates_hz["stereo/frame"] = 30;
  obs.nodes[0].counters["frames_right"] = 0;
  const Check c = check_cameras(obs, {});
  EXPECT_EQ(c.verdict, Verdict::kFail);
  EXPECT_NE(c.seen.find("right eye delivers nothing"), std::string::npos) << c.seen;
}

TEST(DoctorChecks, GivenDarkSaturatedOrBlurredEyesThenImageChecksSaySo) {
  Observations obs = healthy();
  obs.measures->left = EyeImageStats{3, 0.9, 0, 1};
  EXPECT_EQ(check_image(obs, true, {}).verdict, Verdict::kFail);
  obs.measures->right = EyeImageStats{120, 0, 0.2, 300};
  EXPECT_EQ(check_image(obs, false, {}).verdict, Verdict::kWarn);
  obs.measures->right = EyeImageStats{120, 0, 0, 5};
  const Check c = check_image(obs, false, {});
  EXPECT_EQ(c.verdict, Verdict::kWarn);
  EXPECT_NE(c.seen.find("blurred"), std::string::npos);
}

TEST(DoctorChecks, GivenAnEngagedStopThenEstopWarnsWithTheRelease) {
  Observations obs = healthy();
  obs.estop.engaged = true;
  const Check c = check_estop(obs);
  EXPECT_EQ(c.verdict, Verdict::kWarn);
  EXPECT_NE(c.seen.find("ENGAGED"), std::string::npos);
  EXPECT_NE(c.fix.find("stereoball estop release"), std::string::npos);
}

TEST(DoctorChecks, GivenNothingHeardThenDiscoveryFailsWithTheLikelyCauses) {
  // Given a doctor that heard nothing, with nodes answering in another partition
  Observations obs;
  obs.listen_start_ns = kT0;
  obs.listen_end_ns = kT0 + 4 * kS;
  obs.self.partition = "lab";
  obs.self.dds_config = "built-in loopback-only (no key)";
  obs.expected_nodes = {"camera_server"};
  obs.other_partition_nodes = {"camera_server@robot"};
  const auto checks = run_checks(obs);
  // Then only discovery and the expected node report, both failing, naming the causes
  ASSERT_EQ(checks.size(), 2u);
  EXPECT_EQ(checks[0].verdict, Verdict::kFail);
  EXPECT_NE(checks[0].seen.find("another partition of this domain: camera_server@robot"),
            std::string::npos)
      << checks[0].seen;
  EXPECT_NE(checks[0].fix.find("partition"), std::string::npos);
  EXPECT_NE(checks[0].fix.find("DDS configuration"), std::string::npos);
  EXPECT_EQ(checks[1].verdict, Verdict::kFail);
  EXPECT_EQ(exit_status(checks), 1);
}

TEST(DoctorChecks, GivenChecksThenJsonAndTextCarryEveryVerdict) {
  const std::vector<Check> checks{{"a \"q\"", Verdict::kOk, "fine\n", ""},
                                  {"b", Verdict::kFail, "bad", "do x"}};
  EXPECT_EQ(to_json(checks),
            "{\"ok\": false, \"checks\": [{\"name\": \"a \\\"q\\\"\", \"verdict\": \"ok\", "
            "\"seen\": \"fine\\n\", \"fix\": \"\"}, {\"name\": \"b\", \"verdict\": \"FAIL\", "
            "\"seen\": \"bad\", \"fix\": \"do x\"}]}\n");
  const std::string text = to_text(checks);
  EXPECT_NE(text.find("FAIL  b"), std::string::npos) << text;
  EXPECT_NE(text.find("bad; fix: do x"), std::string::npos) << text;
}

}  // namespace
}  // namespace stereoball::doctor
