// stereoball doctor against real processes on a private domain: camera_server playing the
// real OpenCV pairs with their calibration and motion_controller (the e-stop holder), all with
// a deployment key. The doctor passes the healthy deployment and finds each injected fault:
// a silent and a missing node, swapped eyes, a calibration of another size, a node with
// another key and a doctor without one, skewed eyes and a clock 2 s off (test heartbeats), and
// a doctor on another partition or domain than the nodes; and an engaged stop. Each asserts the
// check's verdict (and, for faults, the exit status).

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "process.hpp"
#include "stereo/io/calibration_file.hpp"
#include "stereo/msg/calibration_msg.hpp"

namespace sb = stereoball;
using sb::testing::Process;
using namespace std::chrono_literals;

namespace {

const std::string kSamples = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples";
const std::string kCalibration =
    sb::testing::source_path("config/calibration/opencv_samples_stereo.yaml");

// The verdict the doctor's --json gives check name ("" if the check is not listed).
std::string verdict(const std::string& json, const std::string& name) {
  const std::string head = "{\"name\": \"" + name + "\", \"verdict\": \"";
  const auto at = json.find(head);
  if (at == std::string::npos) return "";
  const auto start = at + head.size();
  return json.substr(start, json.find('"', start) - start);
}

// Heartbeats published from the test (a node that reports skew, a host with a shifted clock,
// a node that falls silent).
class FakeNode {
 public:
  FakeNode(sb::dds::DomainParticipant& participant, std::string component, std::string host,
           std::map<std::string, uint64_t> counters, int64_t clock_shift_ns = 0,
           std::map<std::string, float> rates = {})
      : writer_(participant, sb::topics::kComponentStatus),
        component_(std::move(component)),
        host_(std::move(host)),
        counters_(std::move(counters)),
        rates_(std::move(rates)),
        shift_ns_(clock_shift_ns),
        thread_([this] { loop(); }) {}
  ~FakeNode() { stop(); }
  void stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }

 private:
  void loop() {
    while (!stop_) {
      std::vector<std::string> names;
      std::vector<stereoball_msg_Counter> counters;
      std::vector<stereoball_msg_TopicRate> rates;
      names.reserve(counters_.size() + rates_.size());
      for (const auto& [name, value] : counters_) {
        names.push_back(name);
        counters.push_back({names.back().data(), value});
      }
      for (const auto& [topic, hz] : rates_) {
        names.push_back(topic);
        rates.push_back({names.back().data(), hz, 10, 0});
      }
      std::string state = "running";
      stereoball_msg_ComponentStatus msg{};
      msg.component = component_.data();
      msg.host = host_.data();
      msg.pid = 4242;
      msg.stamp_ns = sb::node::now_ns() + shift_ns_;
      msg.healthy = true;
      msg.state = state.data();
      msg.counters._length = msg.counters._maximum = static_cast<uint32_t>(counters.size());
      msg.counters._buffer = counters.data();
      msg.rates._length = msg.rates._maximum = static_cast<uint32_t>(rates.size());
      msg.rates._buffer = rates.data();
      msg.last_error = const_cast<char*>("");
      writer_.write(msg);
      for (int i = 0; i < 20 && !stop_; ++i) std::this_thread::sleep_for(10ms);
    }
  }
  sb::dds::DataWriter<stereoball_msg_ComponentStatus> writer_;
  std::string component_, host_;
  std::map<std::string, uint64_t> counters_;
  std::map<std::string, float> rates_;
  int64_t shift_ns_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

class Doctor : public ::testing::Test {
 protected:
  Doctor()
      : dir_(sb::testing::temp_dir()),
        key_(sb::testing::make_key_file(dir_, "deployment.key")),
        partition_(sb::testing::unique_partition()),
        participant_({sb::testing::test_domain(), partition_, key_}),
        health_(participant_, sb::topics::kComponentStatus) {}

  // camera_server playing the real pairs (swapped: left and right globs exchanged).
  std::string camera_config(bool swapped = false, bool with_calibration = true) {
    const std::string left = kSamples + (swapped ? "/right*.jpg" : "/left*.jpg");
    const std::string right = kSamples + (swapped ? "/left*.jpg" : "/right*.jpg");
    const std::string path = dir_ + "/camera_server.yaml";
    std::ofstream(path) << "source: files\nleft_glob: " << left << "\nright_glob: " << right
                        << "\nwidth_px: 640\nheight_px: 480\nrate_hz: 10\n"
                        << "preview_max_width_px: 0\n"
                        << (with_calibration ? "calibration_file: " + kCalibration + "\n" : "");
    return path;
  }

  void start(const std::string& program, std::vector<std::string> args = {},
             const std::string& key = "") {
    std::vector<std::string> argv{sb::testing::bin(program), "--domain",
                                  std::to_string(sb::testing::test_domain()), "--partition",
                                  partition_};
    argv.insert(argv.end(), args.begin(), args.end());
    nodes_.push_back(Process::start(argv, {"STEREOBALL_KEY_FILE=" + (key.empty() ? key_ : key)}));
  }

  // Waits until every component has sent a heartbeat.
  void wait_for(const std::vector<std::string>& components) {
    std::set<std::string> heard;
    const bool all = sb::testing::eventually(
        [&] {
          for (auto& s : health_.take(64)) heard.insert(s->component ? s->component : "");
          for (const auto& c : components)
            if (!heard.count(c)) return false;
          return true;
        },
        30s);
    std::string logs;
    for (auto& n : nodes_) logs += n.output();
    ASSERT_TRUE(all) << logs;
  }

  // Starts the doctor (--json) on the nodes' domain and partition unless args say otherwise.
  Process start_doctor(std::vector<std::string> args, bool with_key = true, bool own_place = true,
                       int listen_s = 5) {
    std::vector<std::string> argv{sb::testing::bin("stereoball-doctor"), "--json", "--listen-s",
                                  std::to_string(listen_s)};
    if (own_place) {
      argv.insert(argv.end(), {"--domain", std::to_string(sb::testing::test_domain()),
                               "--partition", partition_});
    }
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<std::string> env;
    if (with_key) env.push_back("STEREOBALL_KEY_FILE=" + key_);
    return Process::start(argv, env);
  }

  // The exit status (-1 when it did not end within 90 s) and output of a started doctor.
  static std::pair<int, std::string> finish(Process& doctor) {
    const auto code = doctor.wait_for_exit(90s);
    std::pair<int, std::string> result{code.value_or(-1), doctor.output()};
    std::printf("%s\n", result.second.c_str());
    return result;
  }

  // Runs the doctor to its end (see start_doctor).
  std::pair<int, std::string> doctor(std::vector<std::string> args, bool with_key = true,
                                     bool own_place = true, int listen_s = 5) {
    Process p = start_doctor(std::move(args), with_key, own_place, listen_s);
    return finish(p);
  }

  std::string dir_, key_, partition_;
  sb::dds::DomainParticipant participant_;
  sb::dds::DataReader<stereoball_msg_ComponentStatus> health_;
  std::vector<Process> nodes_;
};

TEST_F(Doctor, GivenAHealthyDeploymentThenEveryCheckPassesAndTheExitStatusIsZero) {
  // Given camera_server on the real pairs with their calibration and motion_controller, keyed
  const std::string config = camera_config();
  start("camera_server", {"--config", config});
  start("motion_controller");
  wait_for({"camera_server", "motion_controller"});
  // When the doctor (with the key) checks them
  auto [code, out] =
      doctor({"--camera-config", config, "--expect", "camera_server,motion_controller"});
  // Then nothing fails, and the live checks passed on real images
  EXPECT_EQ(code, 0) << out;
  for (const char* name : {"discovery", "eye order", "calibration size", "row error", "image left",
                           "image right", "keys", "e-stop"}) {
    EXPECT_EQ(verdict(out, name), "ok") << name;
  }
  // (rate and clock figures depend on the machine's load: they may warn, never fail)
  for (const char* name : {"cameras", "clock", "node camera_server@", "node motion_controller@"})
    EXPECT_NE(out.find(std::string("\"name\": \"") + name), std::string::npos) << name;
  EXPECT_EQ(out.find("\"verdict\": \"FAIL\""), std::string::npos);
  EXPECT_EQ(verdict(out, "eye skew"), "n/a");  // this camera_server reports no skew (yet)
}

TEST_F(Doctor, GivenAnEngagedStopThenEstopSaysSoWithTheRelease) {
  // Given motion_controller holding a stop the operator engaged
  start("motion_controller");
  wait_for({"motion_controller"});
  auto [estop_code, estop_out] = sb::testing::run(
      {sb::testing::bin("stereoball-estop"), "engage", "--reason", "doctor test", "--domain",
       std::to_string(sb::testing::test_domain()), "--partition", partition_},
      30s, {"STEREOBALL_KEY_FILE=" + key_});
  ASSERT_EQ(estop_code, 0) << estop_out;
  // When the doctor checks
  auto [code, out] = doctor({});
  // Then the e-stop line warns that it is engaged, with its reason and the release command
  EXPECT_EQ(verdict(out, "e-stop"), "warn");
  EXPECT_NE(out.find("ENGAGED"), std::string::npos);
  EXPECT_NE(out.find("doctor test"), std::string::npos);
  EXPECT_NE(out.find("stereoball estop release"), std::string::npos);
}

TEST_F(Doctor, GivenSwappedEyesThenEyeOrderFails) {
  // Given camera_server with the left and right images exchanged (the calibration is right)
  start("camera_server", {"--config", camera_config(/*swapped=*/true)});
  wait_for({"camera_server"});
  // When the doctor checks
  auto [code, out] = doctor({});
  // Then the eye order fails with the swap fix, and the exit status is 1
  EXPECT_EQ(verdict(out, "eye order"), "FAIL");
  EXPECT_NE(out.find("swap left_device and right_device"), std::string::npos);
  EXPECT_EQ(code, 1);
}

TEST_F(Doctor, GivenACalibrationOfAnotherSizeThenCalibrationSizeFails) {
  // Given frames of 640x480 and a (keyed) calibration published for 1280x960
  start("camera_server", {"--config", camera_config(false, /*with_calibration=*/false)});
  auto calib = sb::stereo::load_calibration(kCalibration);
  ASSERT_TRUE(calib.ok()) << calib.error();
  calib->image_size = {1280, 960};
  sb::dds::DataWriter<stereoball_msg_StereoCalibration> writer(participant_,
                                                               sb::topics::kStereoCalibration);
  const std::string source = "wrong_size.yaml";
  auto msg = sb::stereo::calibration_to_message(*calib, sb::node::now_ns(), source);
  writer.write(msg);
  wait_for({"camera_server"});
  // When the doctor checks
  auto [code, out] = doctor({});
  // Then the calibration size fails naming both sizes
  EXPECT_EQ(verdict(out, "calibration size"), "FAIL");
  EXPECT_NE(out.find("1280x960"), std::string::npos);
  EXPECT_EQ(code, 1);
}

TEST_F(Doctor, GivenANodeWithAnotherKeyOrADoctorWithoutOneThenKeysSaySo) {
  // Given motion_controller signing with another key than camera_server
  start("camera_server", {"--config", camera_config()});
  start("motion_controller", {}, sb::testing::make_key_file(dir_, "other.key"));
  wait_for({"camera_server", "motion_controller"});
  // When the doctor checks with the deployment key, and (listening at the same time, as it
  // only observes) a doctor without any key
  Process keyed = start_doctor({});
  Process keyless = start_doctor({}, /*with_key=*/false);
  auto [code, out] = finish(keyed);
  auto [code2, out2] = finish(keyless);
  // Then keys fail
  EXPECT_EQ(verdict(out, "keys"), "FAIL");
  EXPECT_EQ(code, 1);
  // And the doctor without any key is warned that it has none
  EXPECT_NE(verdict(out2, "keys"), "ok");
  EXPECT_NE(out2.find("doctor has no key"), std::string::npos);
}

TEST_F(Doctor, GivenSkewedEyesThenEyeSkewFails) {
  // Given a camera_server's heartbeat that reports 15 ms median skew between the eyes
  FakeNode camera(participant_, "camera_server", "robot",
                  {{"eye_skew_us_p50", 15000}, {"eye_skew_us_max", 31000}, {"auth_key_id", 0}}, 0,
                  {{"stereo/frame", 30.0f}});
  wait_for({"camera_server"});
  // When the doctor checks
  auto [code, out] = doctor({});
  // Then the eye skew fails
  EXPECT_EQ(verdict(out, "eye skew"), "FAIL");
  EXPECT_NE(out.find("15.00 ms"), std::string::npos);
  EXPECT_EQ(code, 1);
}

TEST_F(Doctor, GivenAHostWhoseClockIsTwoSecondsOffThenClockFails) {
  // Given a node on another host whose heartbeats are stamped 2 s behind
  FakeNode node(participant_, "tracker", "workstation", {}, -2'000'000'000);
  wait_for({"tracker"});
  // When the doctor checks
  auto [code, out] = doctor({});
  // Then the clock fails, naming the authentication window
  EXPECT_EQ(verdict(out, "clock"), "FAIL");
  EXPECT_NE(out.find("authentication window"), std::string::npos);
  EXPECT_EQ(code, 1);
}

TEST_F(Doctor, GivenASilentNodeAndAMissingOneThenBothAreNamed) {
  // Given a node that sends heartbeats for a moment and then falls silent, and a tracker that
  // is expected but does not run
  auto silent = std::make_unique<FakeNode>(participant_, "ball_detector", "robot",
                                           std::map<std::string, uint64_t>{});
  wait_for({"ball_detector"});
  std::thread stopper([&] {
    std::this_thread::sleep_for(3s);
    silent->stop();
  });
  // When the doctor checks (listening 8 s: the node stops about 3 s in)
  auto [code, out] = doctor({"--expect", "tracker"}, true, true, 8);
  stopper.join();
  // Then the silent node and the missing one each fail
  EXPECT_NE(out.find("silent"), std::string::npos);
  EXPECT_EQ(verdict(out, "node tracker"), "FAIL");
  EXPECT_EQ(code, 1);
}

TEST_F(Doctor, GivenADoctorOnAnotherPartitionOrDomainThenDiscoveryFailsWithTheCauses) {
  // Given a node answering on the test's domain and partition
  FakeNode node(participant_, "camera_server", "robot", {{"auth_key_id", 0}});
  wait_for({"camera_server"});
  // When one doctor listens on another partition of the same domain and, at the same time,
  // another on another domain (its own partition, so no concurrent test answers)
  Process other_partition = start_doctor({"--domain", std::to_string(sb::testing::test_domain()),
                                          "--partition", partition_ + "_other"},
                                         true, /*own_place=*/false);
  Process other_domain =
      start_doctor({"--domain", std::to_string((sb::testing::test_domain() + 97) % 230),
                    "--partition", partition_ + "_elsewhere"},
                   true, false);
  auto [code, out] = finish(other_partition);
  auto [code2, out2] = finish(other_domain);
  // Then discovery fails, names the node heard in another partition and the likely causes
  EXPECT_EQ(verdict(out, "discovery"), "FAIL");
  EXPECT_NE(out.find("another partition of this domain: camera_server@robot"), std::string::npos);
  EXPECT_EQ(code, 1);
  // And on the other domain the same
  EXPECT_EQ(verdict(out2, "discovery"), "FAIL");
  EXPECT_NE(out2.find("--domain"), std::string::npos);
  EXPECT_EQ(code2, 1);
}

}  // namespace
