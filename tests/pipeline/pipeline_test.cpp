// The whole pipeline as separate processes (simulator, ball_detector, tracker,
// motion_controller) on a private domain: the closed loop works, and losing the tracker
// stops the robot.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <thread>
#include <tuple>

#include "common/dds/reader.hpp"
#include "common/node/node_runner.hpp"
#include "process.hpp"
#include "supervisor.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;

namespace {

struct PipelineRun {
  explicit PipelineRun(const std::string& scenario, bool restart_tracker = true)
      : partition(sb::testing::unique_partition()),
        participant({sb::testing::test_domain(), partition}),
        truth(participant, sb::topics::kGroundTruth),
        track(participant, sb::topics::kBallTrack),
        command(participant, sb::topics::kVelocityCommand) {
    auto loaded = sb::launch::load_profile("all-in-one", SB_SOURCE_DIR);
    if (!loaded) throw std::runtime_error(loaded.error());
    profile = *loaded;
    for (auto& node : profile.nodes) {
      if (node.name == "tracker") node.restart = restart_tracker;
    }
    log_dir = sb::testing::temp_dir();
    sb::launch::SupervisorOptions options;
    options.bin_dir = std::string(SB_BIN_DIR);
    options.log_path = log_dir + "/nodes.log";
    options.extra_args = {"--domain", std::to_string(sb::testing::test_domain()), "--partition",
                          partition};
    options.node_args["simulator"] = {"--scenario", scenario};
    supervisor =
        std::make_unique<sb::launch::Supervisor>(profile, options, [](const std::string&) {});
    auto started = supervisor->start_all(sb::node::monotonic_ns());
    if (!started) throw std::runtime_error(started.error());
  }
  ~PipelineRun() { supervisor->stop_all(); }

  // Takes what arrived; returns the newest truth sample seen so far.
  void drain() {
    for (auto& s : truth.take(256)) truths.push_back(*s);
    for (auto& s : track.take(256)) states.push_back(s->state);
    for (auto& s : command.take(256))
      commands.emplace_back(sb::node::monotonic_ns(), s->linear_mps, s->angular_radps);
    supervisor->poll(sb::node::monotonic_ns());
  }
  std::string log() const {
    std::ifstream in(log_dir + "/nodes.log");
    return std::string((std::istreambuf_iterator<char>(in)), {});
  }

  std::string partition;
  sb::launch::Profile profile;
  std::string log_dir;
  sb::dds::DomainParticipant participant;
  sb::dds::DataReader<stereoball_msg_GroundTruth> truth;
  sb::dds::DataReader<stereoball_msg_BallTrack> track;
  sb::dds::DataReader<stereoball_msg_VelocityCommand> command;
  std::vector<std::tuple<int64_t, double, double>> commands;  // (receive time, linear, angular)
  std::unique_ptr<sb::launch::Supervisor> supervisor;
  std::vector<stereoball_msg_GroundTruth> truths;  // scalar fields only are used
  std::vector<stereoball_msg_TrackState> states;
};

double ball_distance_m(const stereoball_msg_GroundTruth& gt) {
  return std::hypot(gt.ball_world_m[0] - gt.robot_x_m, gt.ball_world_m[1] - gt.robot_y_m);
}

// Given a ball in front of the robot, when the system runs, then the tracker follows it and
// the robot ends near the controller's target distance, facing the ball.
TEST(Pipeline, RobotEndsNearTheBall) {
  PipelineRun run("ball_still");
  ASSERT_TRUE(sb::testing::eventually(
      [&] {
        run.drain();
        return !run.truths.empty() && run.truths.back().sim_time_s > 12.0;
      },
      60s))
      << run.log();
  EXPECT_NE(std::find(run.states.begin(), run.states.end(), stereoball_msg_TRACK_FOLLOWING),
            run.states.end())
      << "tracker never reported FOLLOWING\n"
      << run.log();
  // The controller steers the robot's centreline at the ball and holds the target distance;
  // judged by the median over the last 2 simulated seconds (the loop keeps correcting).
  std::vector<double> bearings, distances;
  const double end_s = run.truths.back().sim_time_s;
  for (const auto& gt : run.truths) {
    if (gt.sim_time_s < end_s - 2.0) continue;
    const double angle =
        std::atan2(gt.ball_world_m[1] - gt.robot_y_m, gt.ball_world_m[0] - gt.robot_x_m);
    bearings.push_back(std::abs(std::remainder(angle - gt.robot_yaw_rad, 2 * M_PI)));
    distances.push_back(ball_distance_m(gt));
  }
  ASSERT_FALSE(bearings.empty());
  std::sort(bearings.begin(), bearings.end());
  std::sort(distances.begin(), distances.end());
  const double bearing = bearings[bearings.size() / 2], distance = distances[distances.size() / 2];
  EXPECT_TRUE(run.truths.back().ball_visible_left && run.truths.back().ball_visible_right);
  // Facing the ball: a loose bound (the ±5° acceptance figure belongs to the benchmark).
  EXPECT_LT(bearing, 20.0 * M_PI / 180) << "median bearing from the robot centreline " << bearing;
  // target distance 1 m (config/motion_controller.yaml), measured from the robot centre
  EXPECT_NEAR(distance, 1.0, 0.35) << "median distance " << distance;
}

// Given the robot following a rolling ball, when the tracker process is killed, then the
// controller commands zero and the simulated base comes to rest (both times printed). How soon
// is the controller core's business (its 300 ms stale-track timeout, unit-tested at simulated
// time in motion_controller_test); here the events must happen, within deadlines for load.
TEST(Pipeline, KillingTheTrackerStopsTheRobot) {
  PipelineRun run("ball_rolling_away", /*restart_tracker=*/false);
  ASSERT_TRUE(sb::testing::eventually(
      [&] {
        run.drain();
        return !run.truths.empty() && std::abs(run.truths.back().robot_linear_mps) > 0.1;
      },
      60s))
      << "robot never moved\n"
      << run.log();
  run.supervisor->signal_node("tracker", SIGKILL);
  const int64_t killed_mono = sb::node::monotonic_ns();
  const double killed_at = run.truths.back().sim_time_s;
  const double speed_at_kill = run.truths.back().robot_linear_mps;
  int64_t zero_cmd_mono = -1;
  double stopped_at = -1;
  // Measured (zero command / at rest after the kill): 0.30-0.32 s / 0.43 s (simulated) in 5
  // runs on the shared 2-core machine while compiling; the deadline is 10 s.
  ASSERT_TRUE(sb::testing::eventually(
      [&] {
        run.drain();
        for (const auto& [t, linear, angular] : run.commands) {
          if (zero_cmd_mono < 0 && t > killed_mono && linear == 0.0 && angular == 0.0)
            zero_cmd_mono = t;
        }
        const auto& gt = run.truths.back();
        if (std::abs(gt.robot_linear_mps) < 0.01 && std::abs(gt.robot_angular_radps) < 0.02)
          stopped_at = gt.sim_time_s;
        return zero_cmd_mono > 0 && stopped_at >= 0;
      },
      10s))
      << (zero_cmd_mono > 0 ? "the base never came to rest" : "no zero command after the kill")
      << "\n"
      << run.log();
  const double zero_after_s = (zero_cmd_mono - killed_mono) * 1e-9;
  std::printf(
      "killed at %.2f m/s: zero command %.3f s after the tracker was killed; robot at rest %.3f s "
      "(simulated) after\n",
      speed_at_kill, zero_after_s, stopped_at - killed_at);
}

}  // namespace
