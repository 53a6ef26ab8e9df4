// Robot and workstation as two hosts: two network namespaces joined by veth, the robot profile
// in one and a workstation profile in the other (LAN configuration, unicast peers), observed
// from inside the robot namespace.
//  - TwoHostVision: the real workstation profile (ball_detector + tracker): the closed loop
//    across the link, the stop when the link is cut, the resume when it returns, netem.
//  - TwoHostVisionJpeg: the same with the robot-jpeg profile (JPEG frames across the link).
//  - TwoHostLink: the workstation runs sb_truth_tracker (ball/track from ground truth, a
//    stand-in for vision), so the link-safety checks hold whatever the detector's quality.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>

#include "common/node/node_runner.hpp"
#include "two_host_system.hpp"

namespace sb = stereoball;
namespace sd = stereoball::distributed;
using namespace std::chrono_literals;

namespace {

constexpr int64_t kMs = 1'000'000;

// Polls pred on fresh robot-namespace logs every 50 ms until true or the deadline.
bool wait_until(sd::TwoHostSystem& system, std::chrono::milliseconds timeout,
                const std::function<bool(const sd::ObserverLog&)>& pred) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (pred(system.robot_log())) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(50ms);
  }
}

bool is_zero(const sd::CommandRx& c) {
  return c.linear_mps == 0.0 && c.angular_radps == 0.0;
}

// The robot drives toward the ball: forward speed and heading within ~35 degrees of the ball.
bool moving_toward_ball(const sd::TruthRx& g) {
  const double dx = g.ball_x_m - g.robot_x_m, dy = g.ball_y_m - g.robot_y_m;
  const double norm = std::hypot(dx, dy);
  if (norm < 1e-6 || g.linear_mps < 0.1) return false;
  return (std::cos(g.robot_yaw_rad) * dx + std::sin(g.robot_yaw_rad) * dy) / norm > 0.8;
}

// Number of FOLLOWING tracks received after t_ns.
size_t following_after(const sd::ObserverLog& log, int64_t t_ns) {
  return std::count_if(log.tracks.begin(), log.tracks.end(), [&](const sd::TrackRx& t) {
    return t.rx_ns > t_ns && t.state == sd::kTrackFollowing;
  });
}

// "a/b/c..." counts of key(item) for keys 0..max.
template <typename T, typename Key>
std::string histogram(const std::vector<T>& items, Key key) {
  std::vector<int> counts;
  for (const auto& item : items) {
    const int k = key(item);
    if (k < 0 || k > 16) continue;
    if (static_cast<int>(counts.size()) <= k) counts.resize(k + 1);
    ++counts[k];
  }
  std::string out;
  for (size_t i = 0; i < counts.size(); ++i) out += (i ? "/" : "") + std::to_string(counts[i]);
  return out.empty() ? "none" : out;
}

// Waits until FOLLOWING tracks from the link drive the robot toward the ball.
::testing::AssertionResult wait_following_and_moving(sd::TwoHostSystem& system,
                                                     std::chrono::milliseconds timeout) {
  const int64_t since = sb::node::now_ns();
  const bool ok = wait_until(system, timeout, [&](const sd::ObserverLog& log) {
    if (following_after(log, since) < 5) return false;
    size_t run = 0;  // consecutive ground-truth samples moving toward the ball
    for (const auto& g : log.truths) {
      run = (g.rx_ns > since && moving_toward_ball(g)) ? run + 1 : 0;
      if (run >= 10) return true;
    }
    return false;
  });
  if (ok) return ::testing::AssertionSuccess();
  const auto log = system.robot_log();
  return ::testing::AssertionFailure()
         << "no FOLLOWING track driving the robot toward the ball within " << timeout.count()
         << " ms (robot namespace received " << log.tracks.size() << " tracks, "
         << following_after(log, since) << " FOLLOWING since the wait began, "
         << log.commands.size() << " commands, " << log.truths.size()
         << " ground-truth samples; track states idle/following/searching "
         << histogram(log.tracks, [](const sd::TrackRx& t) { return t.state; })
         << "; detection statuses found/no_candidate/epipolar/size/no_calib/bad_frame in the "
            "workstation namespace "
         << histogram(system.workstation_log().detections,
                      [](const sd::DetectionRx& d) { return d.status; })
         << ")";
}

// Why following did not resume after the link came back: what the robot side received since.
std::string resume_failure(sd::TwoHostSystem& system, int64_t restore_ns) {
  const auto log = system.robot_log();
  double max_linear_mps = 0.0, last_range_m = -1.0;
  for (const auto& c : log.commands)
    if (c.rx_ns > restore_ns) max_linear_mps = std::max(max_linear_mps, c.linear_mps);
  if (!log.truths.empty() && log.truths.back().rx_ns > restore_ns) {
    const auto& g = log.truths.back();
    last_range_m = std::hypot(g.ball_x_m - g.robot_x_m, g.ball_y_m - g.robot_y_m);
  }
  std::vector<sd::TrackRx> since;
  std::copy_if(log.tracks.begin(), log.tracks.end(), std::back_inserter(since),
               [&](const sd::TrackRx& t) { return t.rx_ns > restore_ns; });
  std::ostringstream out;
  out << "following did not resume after the link came back (since then: track states "
         "idle/following/searching "
      << histogram(since, [](const sd::TrackRx& t) { return t.state; })
      << ", largest forward command " << max_linear_mps << " m/s, last ball range " << last_range_m
      << " m)";
  return out.str();
}

// Given the robot following across the link: cut the robot's end of the link, check the
// stop, restore it, check following resumes (nothing restarted).
void cut_and_restore_link(sd::TwoHostSystem& system) {
  ASSERT_TRUE(wait_following_and_moving(system, 30s));
  const double speed_at_cut = system.robot_log().truths.back().linear_mps;

  // When the robot's end of the link goes down
  const int64_t cut_ns = sb::node::now_ns();
  ASSERT_TRUE(system.hosts().set_robot_link(false).ok());
  struct LinkGuard {  // the link comes back even if an assertion fails
    sd::TwoHosts& hosts;
    ~LinkGuard() { hosts.set_robot_link(true); }
  } guard{system.hosts()};

  // Then the robot's own controller commands zero and the base comes to rest (how soon is the
  // controller core's stale timeout, unit-tested at simulated time; the times are printed).
  // Measured: zero command 578 ms, at rest 749 ms after the cut, plus 500 ms still (one run at
  // load 15 on the shared 2-core machine); the deadline is 10 s.
  std::optional<int64_t> zero_cmd_ns, stopped_ns;
  ASSERT_TRUE(wait_until(system, 10s, [&](const sd::ObserverLog& log) {
    zero_cmd_ns.reset();
    for (const auto& c : log.commands) {
      if (c.rx_ns <= cut_ns) continue;
      if (!is_zero(c)) {
        zero_cmd_ns.reset();
      } else if (!zero_cmd_ns) {
        zero_cmd_ns = c.stamp_ns;
      }
    }
    stopped_ns.reset();
    for (const auto& g : log.truths) {
      if (g.stamp_ns <= cut_ns) continue;
      const bool still = std::abs(g.linear_mps) < 0.01 && std::abs(g.angular_radps) < 0.02;
      if (!still) {
        stopped_ns.reset();
      } else if (!stopped_ns) {
        stopped_ns = g.stamp_ns;
      }
    }
    return zero_cmd_ns && stopped_ns && log.truths.back().stamp_ns - *stopped_ns > 500 * kMs;
  })) << "robot did not stop (and stay still) after the link was cut";
  const double zero_cmd_ms = static_cast<double>(*zero_cmd_ns - cut_ns) / 1e6;
  const double stopped_ms = static_cast<double>(*stopped_ns - cut_ns) / 1e6;
  std::printf("link cut at %.2f m/s: zero command after %.0f ms, base at rest after %.0f ms\n",
              speed_at_cut, zero_cmd_ms, stopped_ms);

  // When the link comes back (nothing restarted)
  const int64_t restore_ns = sb::node::now_ns();
  ASSERT_TRUE(system.hosts().set_robot_link(true).ok());
  // Then FOLLOWING tracks arrive again and the robot is driven forward again
  EXPECT_TRUE(wait_until(system, 20s, [&](const sd::ObserverLog& log) {
    return following_after(log, restore_ns) >= 5 &&
           std::any_of(log.commands.begin(), log.commands.end(), [&](const sd::CommandRx& c) {
             return c.rx_ns > restore_ns && c.linear_mps > 0.05;
           });
  })) << resume_failure(system, restore_ns);
  const auto log = system.robot_log();
  for (const auto& t : log.tracks) {
    if (t.rx_ns > restore_ns && t.state == sd::kTrackFollowing) {
      std::printf("FOLLOWING track again %.0f ms after the link came back\n",
                  static_cast<double>(t.rx_ns - restore_ns) / 1e6);
      break;
    }
  }
}

// A workstation profile whose only node turns ground truth into tracks (written once).
std::string oracle_profile() {
  const std::string path = sb::testing::temp_dir() + "/workstation-oracle.yaml";
  std::ofstream(path) << "description: \"test workstation: sb_truth_tracker instead of vision\"\n"
                      << "cyclonedds: \"" << sb::testing::source_path("config/cyclonedds/lan.xml")
                      << "\"\nnodes:\n  - name: truth_tracker\n    program: sb_truth_tracker\n";
  return path;
}

// deploy/robot.yaml (or robot-jpeg.yaml) with the simulator's scenario restarting when it ends
// (written once per variant). Without the restart the ball comes to rest 9 m out after 14 s;
// how far behind the robot is by the time the link is cut depends on how fast the detector
// runs (2-3x slower under the sanitizers), and a ball out of sight at the link's return made
// the resume check fail for a reason that has nothing to do with the link. With it, the ball is
// back 1.2 m ahead within one 15 s scenario whatever happened before.
std::string looping_robot_profile(bool jpeg) {
  const std::string path =
      sb::testing::temp_dir() + (jpeg ? "/robot-jpeg-looping.yaml" : "/robot-looping.yaml");
  std::ofstream(path) << "description: \"test robot: deploy/robot" << (jpeg ? "-jpeg" : "")
                      << ".yaml, the scenario restarting when it ends\"\n"
                      << "cyclonedds: \"" << sb::testing::source_path("config/cyclonedds/lan.xml")
                      << "\"\nnodes:\n  - name: simulator\n    program: simulator\n    args: ["
                      << (jpeg ? "\"--frame-encoding\", \"jpeg\", " : "") << "\"--loop\"]\n"
                      << "  - name: motion_controller\n    program: motion_controller\n";
  return path;
}

// What runs on the two hosts: vision (ball_detector + tracker) or the ground-truth stand-in on
// the workstation, and raw or JPEG frames from the robot.
enum class Setup { kLink, kVision, kVisionJpeg };

// One running system per suite (starting it costs seconds); the tests of a suite run in order.
// The suites with kNetem (cases on a link with delay and loss) first check that the kernel
// offers netem and start nothing without it: they are a ctest entry of their own
// (distributed_test.needs_netem) that skips with the reason.
template <Setup kSetup, bool kNetem = false>
class TwoHostBase : public ::testing::Test {
 protected:
  static constexpr bool kVision = kSetup != Setup::kLink;
  static void SetUpTestSuite() {
    if constexpr (kNetem) {
      if (auto e = sd::netem_available(); !e) {
        reason_ = e.error();
        unavailable_ = true;
        return;
      }
    }
    sd::SystemOptions o;
    o.domain = sb::testing::test_domain();
    const char* names[] = {"link.", "vision.", "jpeg."};
    o.partition =
        std::string("sbtest.") + names[static_cast<int>(kSetup)] + std::to_string(::getpid());
    o.workstation_profile = kVision ? "workstation" : oracle_profile();
    if (kVision) o.workstation_observer_topics = {"detection"};  // for failure messages
    if (kVision) o.robot_profile = looping_robot_profile(kSetup == Setup::kVisionJpeg);
    if (kSetup == Setup::kVisionJpeg)
      o.workstation_observer_topics.push_back("frame");  // JPEG frames: cheap to observe
    system_ = new sd::TwoHostSystem(o);
    if (auto e = system_->start(); !e) reason_ = e.error();
  }
  static void TearDownTestSuite() {
    delete system_;
    system_ = nullptr;
  }
  void SetUp() override {
    if (reason_.empty()) return;
    if (unavailable_ || system_->unavailable()) GTEST_SKIP() << reason_;
    FAIL() << reason_;
  }
  void TearDown() override {
    if (HasFailure() && system_) std::printf("%s\n", system_->diagnostics().c_str());
  }
  // Later tests need the closed loop; without it they fail at once instead of waiting again.
  bool closed_loop_seen() {
    if (!closed_loop_failed_) return true;
    ADD_FAILURE() << "the closed loop across the link never worked (see the first test)";
    return false;
  }
  void expect_closed_loop(std::chrono::milliseconds timeout) {
    const auto following = wait_following_and_moving(*system_, timeout);
    closed_loop_failed_ = !following;
    ASSERT_TRUE(following);
  }
  void netem_case(std::chrono::milliseconds closed_loop_timeout) {
    // Given the closed loop working across the link
    expect_closed_loop(closed_loop_timeout);
    if (HasFatalFailure()) return;
    // And then 20 ms delay and 1% loss on the link (netem)
    if (auto e = system_->hosts().add_netem(20, 1.0); !e) FAIL() << e.error();
    struct NetemGuard {
      sd::TwoHosts& hosts;
      ~NetemGuard() { hosts.remove_netem(); }
    } guard{system_->hosts()};
    // When the system runs on it, then the robot still follows the ball
    EXPECT_TRUE(wait_following_and_moving(*system_, 30s));
  }

  static sd::TwoHostSystem* system_;
  static std::string reason_;
  static bool unavailable_;
  static bool closed_loop_failed_;
};
template <Setup kSetup, bool kNetem>
sd::TwoHostSystem* TwoHostBase<kSetup, kNetem>::system_ = nullptr;
template <Setup kSetup, bool kNetem>
std::string TwoHostBase<kSetup, kNetem>::reason_;
template <Setup kSetup, bool kNetem>
bool TwoHostBase<kSetup, kNetem>::unavailable_ = false;
template <Setup kSetup, bool kNetem>
bool TwoHostBase<kSetup, kNetem>::closed_loop_failed_ = false;

using TwoHostVision = TwoHostBase<Setup::kVision>;
using TwoHostVisionJpeg = TwoHostBase<Setup::kVisionJpeg>;
using TwoHostLink = TwoHostBase<Setup::kLink>;
using TwoHostVisionNetem = TwoHostBase<Setup::kVision, true>;
using TwoHostLinkNetem = TwoHostBase<Setup::kLink, true>;

TEST_F(TwoHostVision, DetectionsFromTheWorkstationDriveTheRobot) {
  // Given the robot profile in one namespace and the workstation profile in the other
  // When the system runs
  // Then tracks computed in the workstation namespace reach the robot namespace and the
  // simulated robot drives toward the ball
  expect_closed_loop(40s);
  if (HasFatalFailure()) return;
  // And the vision nodes really run on the workstation side only
  auto has = [](const std::vector<std::string>& names, const std::string& n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  const auto robot = system_->programs(system_->hosts().robot());
  const auto workstation = system_->programs(system_->hosts().workstation());
  EXPECT_TRUE(has(robot, "simulator"));
  EXPECT_TRUE(has(robot, "motion_controll"));  // comm is cut at 15 characters
  EXPECT_FALSE(has(robot, "ball_detector"));
  EXPECT_FALSE(has(robot, "tracker"));
  EXPECT_TRUE(has(workstation, "ball_detector"));
  EXPECT_TRUE(has(workstation, "tracker"));
}

TEST_F(TwoHostVision, CuttingTheLinkStopsTheRobotAndRestoringItResumesFollowing) {
  if (!closed_loop_seen()) return;
  cut_and_restore_link(*system_);
}

TEST_F(TwoHostVisionJpeg, JpegFramesAcrossTheLinkDriveTheRobot) {
  // Given the robot-jpeg profile (the simulator publishes JPEG q90 eyes) in one namespace and
  // the unchanged workstation profile in the other
  // When the system runs, then detections from the JPEG frames drive the robot to the ball
  expect_closed_loop(40s);
  if (HasFatalFailure()) return;
  // And the frames that crossed the link were JPEG, a small fraction of a raw pair
  const auto frames = system_->workstation_log().frames;
  ASSERT_FALSE(frames.empty());
  for (const auto& f : frames) {
    ASSERT_EQ(f.encoding, "jpeg");
    ASSERT_LT(f.bytes, 2u * 640 * 480 * 3 / 8);
  }
}

TEST_F(TwoHostVisionJpeg, CuttingTheLinkStopsTheRobotAndRestoringItResumesFollowing) {
  if (!closed_loop_seen()) return;
  cut_and_restore_link(*system_);
}

TEST_F(TwoHostLink, TracksFromTheWorkstationDriveTheRobot) {
  // Given the robot profile and a workstation whose tracks come from ground truth
  // When the system runs, then the tracks cross the link and drive the robot to the ball
  expect_closed_loop(30s);
}

TEST_F(TwoHostLink, CuttingTheLinkStopsTheRobotAndRestoringItResumesFollowing) {
  if (!closed_loop_seen()) return;
  cut_and_restore_link(*system_);
}

TEST_F(TwoHostVisionNetem, FollowsWithTwentyMillisecondsDelayAndOnePercentLoss) {
  netem_case(40s);
}

TEST_F(TwoHostLinkNetem, FollowsWithTwentyMillisecondsDelayAndOnePercentLoss) {
  netem_case(30s);
}

}  // namespace
