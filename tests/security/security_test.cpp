// Security of the robot with real processes on a private domain and a deployment key:
//  - Attack: a rogue on the same host sends unsigned, forged and replayed commands, tracks,
//    detections, e-stop releases and calibrations: none is accepted, the robot never moves,
//    the operator's stop is never cleared, and every rejection is counted in health/status.
//  - Estop: the stop outlives the operator's tool and the restart of every node; release
//    needs a deliberate action.
//  - KeyRotation: the running robot keeps moving while the deployment key is rotated (staged,
//    or in one step: nothing is refused either way).
//  - KeyFile: a key file others can read stops a node with a clear error.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>

#include <cmath>
#include <functional>
#include <map>
#include <thread>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "process.hpp"

namespace sb = stereoball;
using sb::testing::Process;
using namespace std::chrono_literals;

namespace {

using Counters = std::map<std::string, uint64_t>;

// Nodes, tools and a keyed observer on one private domain and partition.
class SecuredSystem {
 public:
  SecuredSystem()
      : dir_(sb::testing::temp_dir()),
        key_(sb::testing::make_key_file(dir_, "deployment.key")),
        partition_(sb::testing::unique_partition()),
        participant_({sb::testing::test_domain(), partition_, key_}),
        truth_(participant_, sb::topics::kGroundTruth),
        health_(participant_, sb::topics::kComponentStatus) {}

  const std::string& key() const { return key_; }
  const std::string& dir() const { return dir_; }
  sb::dds::DomainParticipant& participant() { return participant_; }

  std::vector<std::string> flags() const {
    return {"--domain", std::to_string(sb::testing::test_domain()), "--partition", partition_};
  }
  std::vector<std::string> env(const std::string& key) const {
    return {"STEREOBALL_KEY_FILE=" + key};
  }

  void start(const std::string& node, std::vector<std::string> args = {}) {
    std::vector<std::string> argv{sb::testing::bin(node)};
    for (const auto& f : flags()) argv.push_back(f);
    argv.insert(argv.end(), args.begin(), args.end());
    nodes_.erase(node);
    nodes_.emplace(node, Process::start(argv, env(key_)));
  }
  void stop(const std::string& node) {
    auto it = nodes_.find(node);
    if (it == nodes_.end()) return;
    it->second.signal(SIGTERM);
    it->second.wait_for_exit(10s);
    nodes_.erase(it);
    latest_.erase(node);
    stamp_ns_.erase(node);
  }
  Process& node(const std::string& name) { return nodes_.at(name); }

  // A tool run to completion with the deployment key.
  std::pair<int, std::string> tool(const std::string& program, std::vector<std::string> args,
                                   const std::string& key = "") {
    std::vector<std::string> argv{sb::testing::bin(program)};
    argv.insert(argv.end(), args.begin(), args.end());
    for (const auto& f : flags()) argv.push_back(f);
    return sb::testing::run(argv, 30s, env(key.empty() ? key_ : key));
  }

  // Takes what arrived: ground truth poses and the newest heartbeat of each component.
  void drain() {
    for (auto& s : truth_.take(256)) {
      poses_.push_back({s->robot_x_m, s->robot_y_m, s->robot_yaw_rad, s->robot_linear_mps});
      truth_rx_ns_ = sb::node::now_ns();
    }
    for (auto& s : health_.take(256)) {
      Counters counters;
      for (uint32_t i = 0; i < s->counters._length; ++i) {
        counters[s->counters._buffer[i].name] = s->counters._buffer[i].value;
      }
      latest_[s->component] = counters;
      stamp_ns_[s->component] = s->stamp_ns;
    }
  }
  // True once each of components has sent a heartbeat stamped after t_ns and ground truth
  // was received after t_ns.
  bool heard_after(const std::vector<std::string>& components, int64_t t_ns) {
    drain();
    for (const auto& c : components)
      if (!stamp_ns_.count(c) || stamp_ns_[c] <= t_ns) return false;
    return truth_rx_ns_ > t_ns;
  }
  // Counter of component's newest heartbeat (0 if absent).
  uint64_t counter(const std::string& component, const std::string& name) {
    drain();
    auto it = latest_.find(component);
    if (it == latest_.end()) return 0;
    auto c = it->second.find(name);
    return c == it->second.end() ? 0 : c->second;
  }
  // "name=value ..." of component's newest heartbeat (failure messages).
  std::string describe(const std::string& component) {
    drain();
    std::string out = component + ":";
    for (const auto& [name, value] : latest_[component])
      out += " " + name + "=" + std::to_string(value);
    return out;
  }
  bool has_heartbeat(const std::string& component) {
    drain();
    return latest_.count(component) > 0;
  }
  // Waits until component's heartbeat shows counter == value.
  bool wait_counter(const std::string& component, const std::string& name, uint64_t value,
                    std::chrono::milliseconds timeout) {
    return sb::testing::eventually(
        [&] { return has_heartbeat(component) && counter(component, name) == value; }, timeout);
  }
  // Rejections of topic by reason, summed over components.
  uint64_t rejected(const std::vector<std::string>& components, const std::string& reason,
                    const std::string& topic) {
    uint64_t sum = 0;
    for (const auto& c : components) sum += counter(c, "auth_" + reason + ":" + topic);
    return sum;
  }

  struct Pose {
    double x_m, y_m, yaw_rad, linear_mps;
  };
  const std::vector<Pose>& poses() {
    drain();
    return poses_;
  }

 private:
  std::string dir_;
  std::string key_;
  std::string partition_;
  sb::dds::DomainParticipant participant_;
  sb::dds::DataReader<stereoball_msg_GroundTruth> truth_;
  sb::dds::DataReader<stereoball_msg_ComponentStatus> health_;
  std::map<std::string, Process> nodes_;
  std::map<std::string, Counters> latest_;
  std::map<std::string, int64_t> stamp_ns_;  // of the newest heartbeat of each component
  std::vector<Pose> poses_;
  int64_t truth_rx_ns_ = 0;  // when ground truth last arrived
};

}  // namespace

// Given the robot with the operator's stop engaged, when a rogue on the same host sends
// unsigned, forged (another key) and replayed samples of every topic that can move the robot
// or change what it believes, then none is accepted, the robot does not move by a millimetre,
// the stop stays engaged, and each kind of rejection is counted in the nodes' health/status.
TEST(Attack, SameHostRogueMovesNothingAndClearsNoStop) {
  SecuredSystem sys;
  const std::string rogue_key = sb::testing::make_key_file(sys.dir(), "rogue.key");
  sys.start("simulator", {"--scenario", "ball_still"});
  sys.start("motion_controller");
  sys.start("tracker");
  for (const char* c : {"simulator", "motion_controller", "tracker"}) {
    ASSERT_TRUE(sb::testing::eventually([&] { return sys.has_heartbeat(c); }, 30s)) << c;
  }
  // The replaying rogue listens first, so it captures the operator's release below.
  std::vector<std::string> rogue_flags = sys.flags();
  auto rogue = [&](std::vector<std::string> args, const std::string& key) {
    std::vector<std::string> argv{sb::testing::bin("sb_rogue")};
    argv.insert(argv.end(), args.begin(), args.end());
    argv.insert(argv.end(), rogue_flags.begin(), rogue_flags.end());
    return Process::start(argv, {"STEREOBALL_KEY_FILE=" + key});
  };
  Process replay = rogue({"--attack", "replay", "--capture", "5", "--duration", "5"}, rogue_key);
  std::this_thread::sleep_for(1s);
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"engage", "--reason", "test"}, {"release", "--confirm"}, {"engage"}}) {
    auto [code, output] = sys.tool("stereoball-estop", args);
    ASSERT_EQ(code, 0) << output;
  }
  ASSERT_TRUE(sys.wait_counter("simulator", "estop_engaged", 1, 10s));
  ASSERT_FALSE(sys.poses().empty());
  const auto start = sys.poses().back();

  // When the rogues attack
  Process unsigned_rogue = rogue({"--attack", "unsigned", "--duration", "5"}, "");
  Process forged_rogue = rogue({"--attack", "forged", "--duration", "5"}, rogue_key);
  for (Process* p : {&replay, &unsigned_rogue, &forged_rogue}) {
    const auto code = p->wait_for_exit(40s);
    ASSERT_TRUE(code.has_value()) << p->output();
    ASSERT_EQ(*code, 0) << p->output();
    EXPECT_NE(p->output().find("rogue: sent"), std::string::npos) << p->output();
  }
  EXPECT_EQ(replay.output().find("rogue: captured 0"), std::string::npos) << replay.output();
  // (the counters come with the heartbeats after the last sample, and ground truth must cover
  // the base's command timeout, 300 ms, after it: wait for both, 500 ms after the attacks)
  const std::vector<std::string> all{"simulator", "motion_controller", "tracker"};
  const int64_t attacks_over_ns = sb::node::now_ns() + 500'000'000;
  ASSERT_TRUE(sb::testing::eventually([&] { return sys.heard_after(all, attacks_over_ns); }, 10s))
      << sys.describe("simulator") << "\n"
      << sys.describe("motion_controller") << "\n"
      << sys.describe("tracker");

  // Then the robot never moved
  double moved_m = 0, turned_rad = 0;
  for (const auto& p : sys.poses()) {
    moved_m = std::max(moved_m, std::hypot(p.x_m - start.x_m, p.y_m - start.y_m));
    turned_rad = std::max(turned_rad, std::abs(p.yaw_rad - start.yaw_rad));
  }
  EXPECT_LT(moved_m, 1e-3);
  EXPECT_LT(turned_rad, 1e-3);
  // And the stop is still engaged everywhere
  EXPECT_EQ(sys.counter("simulator", "estop_engaged"), 1u);
  EXPECT_EQ(sys.counter("motion_controller", "estop_engaged"), 1u);
  auto [code, status] = sys.tool("stereoball-estop", {"status"});
  EXPECT_EQ(code, 0) << status;
  EXPECT_NE(status.find("state: ENGAGED"), std::string::npos) << status;
  // And nothing hostile was accepted (only the simulator's calibration reached the tracker)
  EXPECT_EQ(sys.counter("tracker", "auth_accepted:ball/detection"), 0u);
  EXPECT_EQ(sys.counter("tracker", "auth_accepted:stereo/calibration"), 1u);
  EXPECT_EQ(sys.counter("motion_controller", "auth_accepted:ball/track"), 0u);
  // And every kind of attack reached the readers and was counted
  for (const char* topic :
       {"cmd/velocity", "cmd/estop", "ball/track", "ball/detection", "stereo/calibration"}) {
    EXPECT_GT(sys.rejected(all, "unsigned", topic), 0u) << topic;
    EXPECT_GT(sys.rejected(all, "forged", topic), 0u) << topic;
  }
  EXPECT_GT(
      sys.rejected(all, "replayed", "cmd/velocity") + sys.rejected(all, "stale", "cmd/velocity"),
      0u);
  EXPECT_GT(sys.rejected(all, "replayed", "cmd/estop"), 0u);  // the captured release
}

// Given the stop engaged by the operator's tool (which exits), when each node that obeys it
// restarts, then it gets the stop back from the other holder; release without confirmation
// is refused; with --confirm every holder releases.
TEST(Estop, SurvivesRestartsAndNeedsADeliberateRelease) {
  SecuredSystem sys;
  sys.start("simulator", {"--scenario", "ball_still"});
  sys.start("motion_controller");
  ASSERT_TRUE(sb::testing::eventually([&] { return sys.has_heartbeat("simulator"); }, 30s));
  ASSERT_TRUE(sb::testing::eventually([&] { return sys.has_heartbeat("motion_controller"); }, 30s));
  auto [code, output] = sys.tool("stereoball-estop", {"engage", "--reason", "restart test"});
  ASSERT_EQ(code, 0) << output;
  EXPECT_NE(output.find("delivered to"), std::string::npos) << output;
  ASSERT_TRUE(sys.wait_counter("motion_controller", "estop_engaged", 1, 10s));
  ASSERT_TRUE(sys.wait_counter("simulator", "estop_engaged", 1, 10s));

  for (const char* node : {"motion_controller", "simulator"}) {
    sys.stop(node);
    sys.start(node, std::string(node) == "simulator"
                        ? std::vector<std::string>{"--scenario", "ball_still"}
                        : std::vector<std::string>{});
    EXPECT_TRUE(sys.wait_counter(node, "estop_engaged", 1, 20s)) << node << " lost the stop";
  }

  auto [refused, why] = sys.tool("stereoball-estop", {"release"});
  EXPECT_EQ(refused, 2) << why;
  EXPECT_NE(why.find("release needs --confirm"), std::string::npos) << why;
  std::this_thread::sleep_for(1500ms);
  EXPECT_EQ(sys.counter("simulator", "estop_engaged"), 1u);

  auto [released, text] = sys.tool("stereoball-estop", {"release", "--confirm"});
  ASSERT_EQ(released, 0) << text;
  EXPECT_TRUE(sys.wait_counter("simulator", "estop_engaged", 0, 10s));
  EXPECT_TRUE(sys.wait_counter("motion_controller", "estop_engaged", 0, 10s));
}

// The robot driving after a followed ball while rotate() rotates the key: the robot never
// stops, no sample is refused for its key, and the commands end up signed by new_key_id.
static void robot_keeps_moving_through(const std::function<void(SecuredSystem&)>& rotate,
                                       uint32_t new_key_id) {
  SecuredSystem sys;
  sys.start("simulator", {"--scenario", "no_ball"});
  sys.start("motion_controller");
  sb::dds::DataWriter<stereoball_msg_BallTrack> tracks(sys.participant(), sb::topics::kBallTrack);
  sb::dds::DataReader<stereoball_msg_VelocityCommand> commands(sys.participant(),
                                                               sb::topics::kVelocityCommand);
  std::atomic<bool> publishing{true};
  std::thread publisher([&] {
    // A ball that stays 2 m ahead: the controller keeps driving toward it.
    char reason[] = "test";
    for (uint64_t seq = 0; publishing; ++seq) {
      stereoball_msg_BallTrack t{};
      t.frame_seq = seq;
      t.capture_stamp_ns = t.publish_stamp_ns = t.last_accepted_stamp_ns = sb::node::now_ns();
      t.state = stereoball_msg_TRACK_FOLLOWING;
      t.verdict = stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED;
      t.reason = reason;
      t.position_valid = true;
      t.position_m[2] = 2.0;
      t.distance_m = 2.0;
      tracks.write(t);
      std::this_thread::sleep_for(33ms);
    }
  });
  struct Join {
    std::atomic<bool>& flag;
    std::thread& thread;
    ~Join() {
      flag = false;
      thread.join();
    }
  } join{publishing, publisher};

  ASSERT_TRUE(sb::testing::eventually(
      [&] { return !sys.poses().empty() && sys.poses().back().linear_mps > 0.1; }, 30s))
      << "the robot never started following";
  const size_t moving_from = sys.poses().size();

  rotate(sys);
  bool new_key_seen = false;
  sb::testing::eventually(
      [&] {
        for (auto& c : commands.take(64))
          new_key_seen = new_key_seen || c->auth.key_id == new_key_id;
        return new_key_seen;
      },
      10s);
  std::this_thread::sleep_for(2s);

  EXPECT_TRUE(new_key_seen) << "commands are not signed with the rotated key";
  double slowest = 1e9;
  const auto& poses = sys.poses();
  for (size_t i = moving_from; i < poses.size(); ++i)
    slowest = std::min(slowest, poses[i].linear_mps);
  EXPECT_GT(slowest, 0.05) << "the robot slowed down or stopped during the rotation";
  for (const char* node : {"simulator", "motion_controller"}) {
    EXPECT_GE(sys.counter(node, "auth_key_reloads"), 1u) << node;
    uint64_t refused = 0;
    for (const char* topic : {"cmd/velocity", "ball/track", "cmd/estop"}) {
      refused += sys.counter(node, std::string("auth_unknown_key:") + topic) +
                 sys.counter(node, std::string("auth_forged:") + topic);
    }
    EXPECT_EQ(refused, 0u) << node;
  }
}

static int run_keys(const std::vector<std::string>& args) {
  std::vector<std::string> argv{sb::testing::bin("stereoball-keys")};
  argv.insert(argv.end(), args.begin(), args.end());
  auto [code, text] = sb::testing::run(argv, 20s);
  EXPECT_EQ(code, 0) << text;
  return code;
}

// Given the robot following, when the next key is staged, copied (here: the same file) and
// then rotated, then the robot keeps moving and nothing is refused.
TEST(KeyRotation, StagedThenRotatedRunningRobotKeepsMoving) {
  robot_keeps_moving_through(
      [](SecuredSystem& sys) {
        ASSERT_EQ(run_keys({"rotate", "--stage", "--file", sys.key()}), 0);
        std::this_thread::sleep_for(2500ms);  // every process re-reads the file within a second
        ASSERT_EQ(run_keys({"rotate", "--file", sys.key()}), 0);
      },
      2);
}

// Given the robot following, when the key is rotated in one step (no staging; what the chaos
// bench does), then the signers keep the old key until every process sharing the file knows
// the new one: the robot keeps moving and not one command, track or stop is refused.
TEST(KeyRotation, OneShotRotateRefusesNothing) {
  robot_keeps_moving_through(
      [](SecuredSystem& sys) {
        ASSERT_EQ(run_keys({"rotate", "--file", sys.key()}), 0);
      },
      2);
}

// Given a key file others can read, then a node and the keys tool refuse it and say how to fix
// it; keys init does not overwrite a key in use.
TEST(KeyFile, ReadableByOthersIsRefusedWithTheFix) {
  const std::string dir = sb::testing::temp_dir();
  const std::string key = sb::testing::make_key_file(dir, "deployment.key");
  struct stat st {};
  ASSERT_EQ(::stat(key.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  auto [again, again_text] =
      sb::testing::run({sb::testing::bin("stereoball-keys"), "init", "--file", key}, 20s);
  EXPECT_NE(again, 0);
  EXPECT_NE(again_text.find("exists"), std::string::npos) << again_text;

  ::chmod(key.c_str(), 0644);
  auto [code, output] = sb::testing::run(
      {sb::testing::bin("motion_controller"), "--domain",
       std::to_string(sb::testing::test_domain()), "--partition", sb::testing::unique_partition()},
      20s, {"STEREOBALL_KEY_FILE=" + key});
  EXPECT_NE(code, 0) << output;
  EXPECT_NE(output.find("accessible by others (mode 0644)"), std::string::npos) << output;
  EXPECT_NE(output.find("chmod 600 " + key), std::string::npos) << output;
  auto [show, show_text] =
      sb::testing::run({sb::testing::bin("stereoball-keys"), "show", "--file", key}, 20s);
  EXPECT_NE(show, 0);
  EXPECT_NE(show_text.find("accessible by others"), std::string::npos) << show_text;
}
