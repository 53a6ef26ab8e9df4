// LiveCalibration on a board carried in front of the synthetic rig: poses are taken only when
// the board stood still in both eyes, and the verdict judges the calibration they give. Then
// LiveStation (what the terminal tool and the browser page run): its state for the page, its
// failures, and the file written only for a passing verdict.

#include "live_calibration.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <random>

#include "live_output.hpp"
#include "live_station.hpp"
#include "stereo/io/calibration_file.hpp"

#include "stereo/core/synthetic_rig.hpp"

namespace stereoball::calibrate_live {
namespace {

constexpr int64_t kFramePeriodNs = 33'333'333;  // 30 Hz
const cv::Size kBoard{9, 6};
constexpr double kSquareM = 0.03;

struct BoardPose {
  cv::Vec3d rvec;  // board -> left camera rotation
  cv::Vec3d t_m;   // board origin in the left camera frame
};

// Poses spread over the view, two depths and tilts in both directions (the rig is 640x480).
std::vector<BoardPose> spread_poses() {
  std::vector<BoardPose> poses;
  const double depths[] = {0.75, 1.5};
  const double tilts[] = {-0.35, 0.0, 0.35};
  int i = 0;
  for (double z : depths) {
    for (double fx : {-0.3, 0.0, 0.3}) {
      for (double fy : {-0.22, 0.22}) {
        const double tilt = tilts[i++ % 3];
        const double w = (kBoard.width - 1) * kSquareM, h = (kBoard.height - 1) * kSquareM;
        // Centre the board at the fraction (fx, fy) of the field both eyes share at depth z
        // (its middle is halfway between the cameras, 0.06 m to the right).
        const double cx = 0.06 + fx * z * 0.75 - w / 2, cy = fy * z * 0.75 - h / 2;
        poses.push_back({cv::Vec3d(tilt * 0.6, tilt, 0.05 * i), cv::Vec3d(cx, cy, z)});
      }
    }
  }
  return poses;
}

std::vector<cv::Point3d> board_points() {
  std::vector<cv::Point3d> pts;
  for (int r = 0; r < kBoard.height; ++r)
    for (int c = 0; c < kBoard.width; ++c) pts.emplace_back(c * kSquareM, r * kSquareM, 0);
  return pts;
}

// Interpolates between two board poses (u in [0, 1]).
BoardPose blend(const BoardPose& a, const BoardPose& b, double u) {
  return {a.rvec * (1 - u) + b.rvec * u, a.t_m * (1 - u) + b.t_m * u};
}

// The corners one eye sees of a board pose, with pixel noise; empty if any leaves the image.
std::vector<cv::Point2f> corners(const stereo::SyntheticRig& rig, const BoardPose& pose,
                                 bool right_eye, std::mt19937& rng, double noise_px) {
  cv::Matx33d rot;
  cv::Rodrigues(pose.rvec, rot);
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<cv::Point2f> out;
  for (const auto& p : board_points()) {
    const cv::Vec3d q = rot * cv::Vec3d(p.x, p.y, p.z) + pose.t_m;
    const cv::Point3d in_left(q[0], q[1], q[2]);
    const cv::Point2d px = right_eye ? rig.project_right(in_left) : rig.project_left(in_left);
    if (px.x < 2 || px.y < 2 || px.x > rig.size.width - 3 || px.y > rig.size.height - 3) return {};
    out.emplace_back(static_cast<float>(px.x + noise(rng)), static_cast<float>(px.y + noise(rng)));
  }
  return out;
}

// A person carrying the board: hold each pose hold_frames, then move to the next over
// move_frames; the right eye captures skew_ns after the left (free-running cameras).
struct Carry {
  int hold_frames = 15;
  int move_frames = 20;
  int64_t skew_ns = 0;
  double noise_px = 0.05;
};

BoardPose pose_at(const std::vector<BoardPose>& poses, const Carry& carry, int64_t t_ns) {
  const int64_t hold_ns = carry.hold_frames * kFramePeriodNs;
  const int64_t move_ns = carry.move_frames * kFramePeriodNs;
  const int64_t cycle_ns = hold_ns + move_ns;
  const size_t i = std::min<size_t>(t_ns / cycle_ns, poses.size() - 1);
  const int64_t in_cycle = t_ns - static_cast<int64_t>(i) * cycle_ns;
  if (i + 1 >= poses.size() || in_cycle <= hold_ns) return poses[i];
  return blend(poses[i], poses[i + 1], static_cast<double>(in_cycle - hold_ns) / move_ns);
}

LiveParams params() {
  LiveParams p;
  p.board.inner_corners = kBoard;
  p.board.square_m = kSquareM;
  p.target_poses = 12;
  return p;
}

// Feeds the carried board to a session; returns the number of poses taken.
int carry_board(LiveCalibration& live, const stereo::SyntheticRig& rig,
                const std::vector<BoardPose>& poses, const Carry& carry) {
  std::mt19937 rng(7);
  // The last pose is held like the others, then the board is put down.
  const int frames = static_cast<int>(poses.size() - 1) * (carry.hold_frames + carry.move_frames) +
                     carry.hold_frames;
  int taken = 0;
  for (int f = 0; f < frames; ++f) {
    const int64_t t_left = f * kFramePeriodNs, t_right = t_left + carry.skew_ns;
    auto l = corners(rig, pose_at(poses, carry, t_left), false, rng, carry.noise_px);
    auto r = corners(rig, pose_at(poses, carry, t_right), true, rng, carry.noise_px);
    if (live.add_frame(1'000'000'000 + t_left, l, 1'000'000'000 + t_right, r)) ++taken;
  }
  return taken;
}

TEST(LiveCalibration, TheTestPosesAreSeenByBothEyes) {
  const auto rig = stereo::default_synthetic_rig();
  std::mt19937 rng(1);
  for (const auto& pose : spread_poses()) {
    EXPECT_FALSE(corners(rig, pose, false, rng, 0).empty());
    EXPECT_FALSE(corners(rig, pose, true, rng, 0).empty());
  }
}

TEST(LiveCalibration, StillPosesGiveTheRigWithinHalfAPercent) {
  // Given the synthetic rig and a board held still at twelve poses
  const auto rig = stereo::default_synthetic_rig();
  LiveCalibration live(params(), rig.size);
  // When it is carried through them
  const int taken = carry_board(live, rig, spread_poses(), Carry{});
  // Then every pose is taken once and the verdict passes with the true focal and baseline
  EXPECT_EQ(taken, 12);
  ASSERT_TRUE(live.enough_poses());
  auto verdict = live.finish();
  ASSERT_TRUE(verdict) << verdict.error();
  EXPECT_TRUE(verdict->pass) << (verdict->failures.empty() ? "" : verdict->failures.front());
  const auto& c = verdict->result.calibration;
  EXPECT_NEAR(std::abs(c.t[0]), 0.12, 0.12 * 0.005);
  EXPECT_NEAR(c.k1(0, 0), 600.0, 600.0 * 0.005);
  EXPECT_LT(verdict->result.mean_rectified_row_error_px, 0.2);
  EXPECT_EQ(verdict->per_pose.size(), 12u);
  EXPECT_GT(live.progress().depth_coverage, 0.9);  // 0.75 m and 1.5 m: twice as far
}

TEST(LiveCalibration, FreeRunningEyesKeepTheErrorWithTheStillRule) {
  // Given eyes 15 ms apart while the board moves quickly between the holds
  const auto rig = stereo::default_synthetic_rig();
  Carry carry;
  carry.skew_ns = 15'000'000;
  carry.move_frames = 6;
  LiveCalibration live(params(), rig.size);
  // When the board is carried through the same poses
  carry_board(live, rig, spread_poses(), carry);
  // Then the still rule keeps the rows as good as with synchronised eyes
  auto verdict = live.finish();
  ASSERT_TRUE(verdict) << verdict.error();
  EXPECT_TRUE(verdict->pass);
  EXPECT_LT(verdict->result.mean_rectified_row_error_px, 0.2);
  EXPECT_NEAR(std::abs(verdict->result.calibration.t[0]), 0.12, 0.12 * 0.005);
}

TEST(LiveCalibration, ABoardThatNeverStandsStillGivesNoPoseAndNoCalibration) {
  // Given a board that keeps moving (one move after another, no hold)
  const auto rig = stereo::default_synthetic_rig();
  Carry carry;
  carry.hold_frames = 0;
  LiveCalibration live(params(), rig.size);
  // When it is carried
  const int taken = carry_board(live, rig, spread_poses(), carry);
  // Then no pose is taken and finish says why
  EXPECT_EQ(taken, 0);
  auto verdict = live.finish();
  ASSERT_FALSE(verdict);
  EXPECT_NE(verdict.error().find("still poses"), std::string::npos) << verdict.error();
}

TEST(LiveCalibration, TheSamePlaceTwiceIsTakenOnce) {
  // Given the board held at one pose, moved away (out of view) and held there again
  const auto rig = stereo::default_synthetic_rig();
  const auto poses = spread_poses();
  LiveCalibration live(params(), rig.size);
  std::mt19937 rng(3);
  int taken = 0;
  int64_t t = 0;
  for (int visit = 0; visit < 2; ++visit) {
    for (int f = 0; f < 20; ++f, t += kFramePeriodNs) {
      auto l = corners(rig, poses[0], false, rng, 0.05),
           r = corners(rig, poses[0], true, rng, 0.05);
      taken += live.add_frame(t, l, t, r).has_value();
    }
    for (int f = 0; f < 5; ++f, t += kFramePeriodNs) live.add_frame(t, {}, t, {});
  }
  // Then one pose is kept and the second visit is counted as a duplicate
  EXPECT_EQ(taken, 1);
  EXPECT_EQ(live.progress().skipped_duplicates, 1);
}

TEST(LiveCalibration, ABoardSeenByOneEyeOnlyEarnsAHintNamingTheEye) {
  // Given the board in the left view only for three seconds
  const auto rig = stereo::default_synthetic_rig();
  LiveCalibration live(params(), rig.size);
  std::mt19937 rng(5);
  for (int f = 0; f < 90; ++f) {
    const int64_t t = f * kFramePeriodNs;
    live.add_frame(t, corners(rig, spread_poses()[0], false, rng, 0.05), t, {});
  }
  // Then the hint names the eye that sees it and no pose is taken
  const auto progress = live.progress();
  EXPECT_EQ(progress.poses, 0);
  EXPECT_NE(progress.hint.find("left eye only"), std::string::npos) << progress.hint;
}

TEST(LiveCalibration, NoBoardOfTheConfiguredSizeIsNamed) {
  // Given frames for two seconds in which no board is found
  const auto rig = stereo::default_synthetic_rig();
  LiveCalibration live(params(), rig.size);
  for (int f = 0; f < 60; ++f) live.add_frame(f * kFramePeriodNs, {}, f * kFramePeriodNs, {});
  // Then the hint and finish name the board size the session looks for
  EXPECT_NE(live.progress().hint.find("no 9x6 board found"), std::string::npos);
  auto verdict = live.finish();
  ASSERT_FALSE(verdict);
  EXPECT_NE(verdict.error().find("no 9x6 board found in any of 60 frames"), std::string::npos)
      << verdict.error();
}

TEST(LiveCalibration, SwappedEyesFailTheVerdictWithTheFix) {
  // Given a rig whose cameras are plugged the other way round (right images as left)
  const auto rig = stereo::default_synthetic_rig();
  LiveCalibration live(params(), rig.size);
  std::mt19937 rng(9);
  const auto poses = spread_poses();
  Carry carry;
  int64_t t = 0;
  for (size_t i = 0; i < poses.size(); ++i) {
    for (int f = 0; f < carry.hold_frames; ++f, t += kFramePeriodNs)
      live.add_frame(t, corners(rig, poses[i], true, rng, 0.05), t,
                     corners(rig, poses[i], false, rng, 0.05));
    for (int f = 0; f < 3; ++f, t += kFramePeriodNs) live.add_frame(t, {}, t, {});
  }
  // Then the verdict fails and says to swap the devices
  auto verdict = live.finish();
  ASSERT_TRUE(verdict) << verdict.error();
  EXPECT_FALSE(verdict->pass);
  ASSERT_FALSE(verdict->failures.empty());
  EXPECT_NE(verdict->failures.front().find("swap left_device"), std::string::npos);
}

TEST(LiveCalibration, ABaselineOutsideTheRigsRangeFails) {
  // Given a rig expected to have a 0.20-0.25 m baseline (a wrong square size would do this)
  const auto rig = stereo::default_synthetic_rig();
  auto p = params();
  p.min_baseline_m = 0.20;
  p.max_baseline_m = 0.25;
  LiveCalibration live(p, rig.size);
  carry_board(live, rig, spread_poses(), Carry{});
  // Then the verdict names the baseline and the square size
  auto verdict = live.finish();
  ASSERT_TRUE(verdict) << verdict.error();
  EXPECT_FALSE(verdict->pass);
  ASSERT_EQ(verdict->failures.size(), 1u);
  EXPECT_NE(verdict->failures.front().find("square size"), std::string::npos);
}

TEST(LiveParams, RejectsATargetBelowTheMinimumPairsAndAnInvertedBaselineRange) {
  auto p = params();
  p.target_poses = 2;
  EXPECT_NE(p.validate().error().find("target_poses"), std::string::npos);
  p = params();
  p.min_baseline_m = 0.3;
  p.max_baseline_m = 0.1;
  EXPECT_NE(p.validate().error().find("baseline"), std::string::npos);
  EXPECT_TRUE(params().validate());
}

TEST(DepthProgress, GrowsWithTheRatioOfNearToFar) {
  EXPECT_EQ(depth_progress({}), 0);
  EXPECT_EQ(depth_progress({40, 40}), 0);
  EXPECT_NEAR(depth_progress({40, 60}), (1 - 40.0 / 60) / 0.5, 1e-9);
  EXPECT_EQ(depth_progress({30, 60, 90}), 1);
}

// ---- LiveStation ----

StationParams station_params() {
  StationParams p;
  p.live = params();
  return p;
}

// A frame of the rig's size (the station reads only the size: corners are given).
StationFrame frame_at(const stereo::SyntheticRig& rig, int64_t t_left, int64_t t_right) {
  static const cv::Mat eye(cv::Size(640, 480), CV_8UC1, cv::Scalar(0));
  StationFrame f;
  f.left = f.right = eye(cv::Rect({0, 0}, rig.size));
  f.left_stamp_ns = t_left;
  f.right_stamp_ns = t_right;
  f.seq = static_cast<uint64_t>(t_left / kFramePeriodNs);
  f.source = "test";
  return f;
}

// Carries the board in front of the station (as carry_board); swap feeds the right eye's
// corners as the left (cameras in the wrong order). Returns the poses taken.
int carry_to_station(LiveStation& station, const stereo::SyntheticRig& rig,
                     const std::vector<BoardPose>& poses, const Carry& carry, bool swap = false) {
  std::mt19937 rng(7);
  const int frames = static_cast<int>(poses.size() - 1) * (carry.hold_frames + carry.move_frames) +
                     carry.hold_frames;
  int taken = 0;
  for (int f = 0; f < frames; ++f) {
    const int64_t t_left = 1'000'000'000 + f * kFramePeriodNs, t_right = t_left + carry.skew_ns;
    auto l =
        corners(rig, pose_at(poses, carry, t_left - 1'000'000'000), false, rng, carry.noise_px);
    auto r =
        corners(rig, pose_at(poses, carry, t_right - 1'000'000'000), true, rng, carry.noise_px);
    if (swap) std::swap(l, r);
    taken += station.add_corners(frame_at(rig, t_left, t_right), l, r, t_left).pose.has_value();
  }
  return taken;
}

TEST(LiveStation, ACarriedBoardGivesAPassingVerdictThatIsWrittenAndReadBack) {
  // Given a station and the board carried through twelve still poses
  const auto rig = stereo::default_synthetic_rig();
  LiveStation station(station_params());
  const int taken = carry_to_station(station, rig, spread_poses(), Carry{});
  // Then the verdict is in and passes, and the page's state shows poses, corners and figures
  EXPECT_EQ(taken, 12);
  ASSERT_TRUE(station.verdict().has_value()) << station.message();
  const auto state = station.state(0);
  EXPECT_EQ(state["phase"], "verdict");
  EXPECT_EQ(state["poses"].size(), 12u);
  EXPECT_EQ(state["corners"]["left"].size(), 54u);
  EXPECT_EQ(state["progress"]["poses"], 12);
  EXPECT_TRUE(state["verdict"]["pass"].get<bool>());
  EXPECT_TRUE(state["verdict"]["eyes_in_order"].get<bool>());
  EXPECT_NEAR(state["verdict"]["baseline_m"].get<double>(), 0.12, 0.12 * 0.005);
  EXPECT_EQ(state["verdict"]["per_pose"].size(), 12u);
  // When the passing verdict is written
  const auto verdict = station.writable_verdict();
  ASSERT_TRUE(verdict) << verdict.error();
  const auto path = std::filesystem::temp_directory_path() /
                    ("live_station_" + std::to_string(::getpid()) + ".yaml");
  ASSERT_TRUE(write_live_calibration(path.string(), station.params().live, *verdict, "test"));
  // Then the file holds that calibration (and no temporary is left beside it)
  const auto back = stereo::load_calibration(path.string());
  ASSERT_TRUE(back) << back.error();
  EXPECT_NEAR(std::abs(back->t[0]), std::abs(verdict->result.calibration.t[0]), 1e-9);
  EXPECT_EQ(back->image_size, rig.size);
  EXPECT_FALSE(std::filesystem::exists(
      path.parent_path() / (".live_station_" + std::to_string(::getpid()) + ".writing.yaml")));
  std::filesystem::remove(path);
}

TEST(LiveStation, SwappedEyesFailTheVerdictAndNothingMayBeWritten) {
  // Given the cameras in the wrong order
  const auto rig = stereo::default_synthetic_rig();
  LiveStation station(station_params());
  carry_to_station(station, rig, spread_poses(), Carry{}, /*swap=*/true);
  // Then the verdict fails naming the order and the fix, and writing is refused
  ASSERT_TRUE(station.verdict().has_value()) << station.message();
  const auto state = station.state(0);
  EXPECT_FALSE(state["verdict"]["pass"].get<bool>());
  EXPECT_FALSE(state["verdict"]["eyes_in_order"].get<bool>());
  EXPECT_NE(station.message().find("swap left_device and right_device"), std::string::npos)
      << station.message();
  const auto verdict = station.writable_verdict();
  ASSERT_FALSE(verdict);
  EXPECT_NE(verdict.error().find("nothing written"), std::string::npos);
  EXPECT_FALSE(
      write_live_calibration("/tmp/never.yaml", station.params().live, *station.verdict(), "test"));
}

TEST(LiveStation, ABoardNeverStillEndsWithTheReasonAndNoVerdict) {
  // Given a board that keeps moving
  const auto rig = stereo::default_synthetic_rig();
  Carry carry;
  carry.hold_frames = 0;
  LiveStation station(station_params());
  carry_to_station(station, rig, spread_poses(), carry);
  EXPECT_EQ(station.state(0)["phase"], "collecting");
  EXPECT_EQ(station.message(), "hold the board still");
  // When collecting ends (the page's button or the timeout)
  station.finish_now();
  // Then the page says why there is no calibration and nothing may be written
  EXPECT_EQ(station.state(0)["phase"], "failed");
  EXPECT_NE(station.message().find("still poses"), std::string::npos) << station.message();
  EXPECT_FALSE(station.writable_verdict());
}

TEST(LiveStation, ABoardInOneEyeOnlyIsNamedInTheMessage) {
  // Given the board seen by the left eye only for three seconds
  const auto rig = stereo::default_synthetic_rig();
  LiveStation station(station_params());
  std::mt19937 rng(2);
  const auto pose = spread_poses()[0];
  for (int f = 0; f < 90; ++f) {
    const int64_t t = 1'000'000'000 + f * kFramePeriodNs;
    station.add_corners(frame_at(rig, t, t), corners(rig, pose, false, rng, 0.05), {}, t);
  }
  // Then the message names the eye that sees it
  EXPECT_NE(station.message().find("left eye only"), std::string::npos) << station.message();
  EXPECT_TRUE(station.state(0)["progress"]["board_left"].get<bool>());
  EXPECT_FALSE(station.state(0)["progress"]["board_right"].get<bool>());
}

TEST(LiveStation, ABoardOfAnotherSizeIsNeverFoundAndTheMessageSaysCheckBoard) {
  // Given frames in which no 9x6 board is found (what a 7x5 board gives)
  const auto rig = stereo::default_synthetic_rig();
  LiveStation station(station_params());
  for (int f = 0; f < 45; ++f) {
    const int64_t t = 1'000'000'000 + f * kFramePeriodNs;
    station.add_corners(frame_at(rig, t, t), {}, {}, t);
  }
  // Then the message says so, and finishing names the board size
  EXPECT_NE(station.message().find("no 9x6 board found"), std::string::npos) << station.message();
  station.finish_now();
  EXPECT_NE(station.fatal().find("check --board"), std::string::npos) << station.fatal();
}

TEST(LiveStation, CamerasThatStopAreReportedOnceAndFramesThatComeBackClearIt) {
  // Given a station that got one frame
  const auto rig = stereo::default_synthetic_rig();
  LiveStation station(station_params());
  station.add_corners(frame_at(rig, 0, 0), {}, {}, 1'000'000'000);
  // When no frame arrives for 2.5 s
  EXPECT_EQ(station.check_stall(2'000'000'000), "");
  const std::string stall = station.check_stall(3'500'000'000);
  // Then it is said once, and shown, until frames come back
  EXPECT_NE(stall.find("no frames for 2.5 s"), std::string::npos) << stall;
  EXPECT_EQ(station.check_stall(4'000'000'000), "");
  EXPECT_TRUE(station.state(4'000'000'000)["stalled"].get<bool>());
  EXPECT_EQ(station.message(), stall);
  station.add_corners(frame_at(rig, 1, 1), {}, {}, 4'100'000'000);
  EXPECT_FALSE(station.stalled());
}

TEST(LiveStation, RectifiedFramesAndASizeChangeStopTheSession) {
  // Given rectified frames
  const auto rig = stereo::default_synthetic_rig();
  LiveStation rectified(station_params());
  auto frame = frame_at(rig, 0, 0);
  frame.rectified = true;
  rectified.add_corners(frame, {}, {}, 0);
  // Then the session stops with the fix
  EXPECT_NE(rectified.fatal().find("rectify: false"), std::string::npos) << rectified.fatal();
  // Given a size change during calibration
  LiveStation resized(station_params());
  resized.add_corners(frame_at(rig, 0, 0), {}, {}, 0);
  const cv::Mat small(cv::Size(320, 240), CV_8UC1, cv::Scalar(0));
  auto other = frame_at(rig, 1, 1);
  other.left = other.right = small;
  resized.add_corners(other, {}, {}, 1);
  // Then it stops naming both sizes, and nothing may be written
  EXPECT_NE(resized.fatal().find("640x480 to 320x240"), std::string::npos) << resized.fatal();
  EXPECT_FALSE(resized.writable_verdict());
  EXPECT_EQ(resized.state(0)["phase"], "failed");
}

}  // namespace
}  // namespace stereoball::calibrate_live
