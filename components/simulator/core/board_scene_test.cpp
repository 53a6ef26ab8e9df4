#include "simulator/core/board_scene.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "simulator/core/simulator.hpp"
#include "stereo/core/board_coverage.hpp"

namespace stereoball::simulator {
namespace {

SimParams params() {
  SimParams p;
  p.sensor.noise_sigma_dn = 0.0;
  return p;
}

CalibrationScene two_poses() {
  CalibrationScene s;
  BoardHold a, b;
  a.pose.centre_m = {-0.05, 0.02, 0.6};
  a.hold_s = 1.0;
  a.move_s = 1.0;
  b.pose.centre_m = {0.08, -0.03, 0.8};
  b.pose.tilt_y_rad = 0.4;
  b.hold_s = 1.0;
  s.holds = {a, b};
  return s;
}

// Detected corners of one eye, in the true corners' order (the detector may start at
// either end of the grid).
std::vector<cv::Point2f> detect(const cv::Mat& bgr, const CalibrationBoard& b,
                                const std::vector<cv::Point2d>& truth) {
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  std::vector<cv::Point2f> c;
  if (!cv::findChessboardCorners(grey, {b.cols, b.rows}, c, cv::CALIB_CB_ADAPTIVE_THRESH))
    return {};
  cv::cornerSubPix(grey, c, {5, 5}, {-1, -1},
                   {cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 1e-3});
  if (cv::norm(cv::Point2d(c.front()) - truth.front()) >
      cv::norm(cv::Point2d(c.back()) - truth.front()))
    std::reverse(c.begin(), c.end());
  return c;
}

TEST(BoardScene, RenderedCornersLieOnTheTrueProjection) {
  // Given the true rig (lens distortion included) and the board at two poses
  const SimParams p = params();
  const StereoRig rig(p);
  const CalibrationScene scene = two_poses();
  const BoardRenderer renderer(rig, scene);
  for (const BoardHold& h : scene.holds) {
    for (Eye eye : {Eye::kLeft, Eye::kRight}) {
      // When one eye is rendered and the corners are detected
      cv::Mat img;
      renderer.render(eye, h.pose, img);
      const auto truth = board_corners_px(rig, eye, scene.board, h.pose);
      const auto found = detect(img, scene.board, truth);
      // Then the corners lie on their true projections within what cornerSubPix resolves on
      // 8-bit images (no bias, mean < 0.1 px)
      ASSERT_EQ(found.size(), truth.size());
      double worst = 0.0, sum = 0.0;
      cv::Point2d bias;
      for (std::size_t i = 0; i < truth.size(); ++i) {
        bias += (cv::Point2d(found[i]) - truth[i]) * (1.0 / truth.size());
        const double e = cv::norm(cv::Point2d(found[i]) - truth[i]);
        worst = std::max(worst, e);
        sum += e;
      }
      std::printf("eye %d: mean %.4f px, max %.4f px bias %.4f %.4f\n", static_cast<int>(eye),
                  sum / truth.size(), worst, bias.x, bias.y);
      EXPECT_LT(sum / static_cast<double>(truth.size()), 0.1) << "eye " << static_cast<int>(eye);
      EXPECT_LT(worst, 0.2) << "eye " << static_cast<int>(eye);
      EXPECT_LT(cv::norm(bias), 0.05) << "eye " << static_cast<int>(eye);
    }
  }
}

TEST(BoardScene, HoldsThenMovesSmoothly) {
  // Given two holds of 1 s with a 1 s move between them
  const CalibrationScene s = two_poses();
  // Then the board is at the first pose through the first hold, halfway at mid-move, at the
  // second pose after it, and the hold index says which
  EXPECT_DOUBLE_EQ(s.duration_s(), 3.0);
  EXPECT_DOUBLE_EQ(board_pose_at(s, 0.9).centre_m.x, -0.05);
  EXPECT_EQ(hold_index_at(s, 0.9), 0);
  EXPECT_NEAR(board_pose_at(s, 1.5).centre_m.x, 0.015, 1e-12);
  EXPECT_EQ(hold_index_at(s, 1.5), -1);
  EXPECT_DOUBLE_EQ(board_pose_at(s, 2.5).tilt_y_rad, 0.4);
  EXPECT_EQ(hold_index_at(s, 2.5), 1);
  EXPECT_EQ(hold_index_at(s, 9.0), 1);
}

TEST(BoardScene, SkewedEyesSeeTheMovingBoardAtDifferentPoses) {
  // Given a calibration scenario with the right eye 15 ms late
  Scenario sc;
  sc.calibration = two_poses();
  sc.calibration->eye_skew_s = 0.015;
  ASSERT_TRUE(Simulator::check(params(), sc));
  Simulator sim(params(), sc);
  // When a frame is taken during the hold and one during the move
  const SimFrame still = sim.step(std::nullopt, 500'000'000);
  const SimFrame moving = sim.step(std::nullopt, 1'500'000'000);
  // Then each eye carries its own capture time, and only the moving board differs between them
  EXPECT_EQ(moving.right_time_ns - moving.sim_time_ns, 15'000'000);
  ASSERT_TRUE(still.board && moving.board);
  EXPECT_EQ(still.board->left_hold, 0);
  EXPECT_EQ(still.board->right_hold, 0);
  EXPECT_DOUBLE_EQ(still.board->left_pose.centre_m.x, still.board->right_pose.centre_m.x);
  EXPECT_GT(moving.board->right_pose.centre_m.x - moving.board->left_pose.centre_m.x, 1e-3);
  EXPECT_EQ(moving.left.size(), cv::Size(640, 480));
}

TEST(BoardScene, DrawnPosesAreInViewAndCoverTheImage) {
  // Given the generator asked for 18 poses
  const StereoRig rig(params());
  CalibrationBoard board;
  BoardPoseRanges r;
  r.count = 18;
  const auto holds = draw_board_holds(rig, board, r, 7);
  // Then every pose shows the whole board to both eyes, and the left eye's views cover
  // skew as ROS camera_calibration wants and most of its x, y and size ranges (a board near
  // enough for the full size goal, or at the very edge of one eye, is not whole in the other)
  ASSERT_EQ(holds.size(), 18u);
  stereo::BoardCoverage coverage;
  for (const BoardHold& h : holds) {
    EXPECT_TRUE(board_in_view(rig, board, h.pose, 8.0));
    std::vector<cv::Point2f> px;
    for (const auto& p : board_corners_px(rig, Eye::kLeft, board, h.pose)) px.emplace_back(p);
    const auto vp =
        *stereo::board_view_params(px, {board.cols, board.rows}, {rig.width_px(), rig.height_px()});
    coverage.add(vp);
  }
  const auto pr = coverage.progress();
  std::printf("coverage x %.2f y %.2f size %.2f skew %.2f\n", pr[0], pr[1], pr[2], pr[3]);
  EXPECT_GE(pr[0], 0.8);
  EXPECT_GE(pr[1], 0.8);
  EXPECT_GE(pr[2], 0.5);
  EXPECT_GE(pr[3], 1.0);
  // And the same seed gives the same poses, another seed others
  const auto again = draw_board_holds(rig, board, r, 7);
  const auto other = draw_board_holds(rig, board, r, 8);
  EXPECT_DOUBLE_EQ(again[5].pose.centre_m.x, holds[5].pose.centre_m.x);
  EXPECT_NE(other[5].pose.centre_m.x, holds[5].pose.centre_m.x);
}

TEST(BoardScene, BadSceneNamesTheField) {
  CalibrationScene s = two_poses();
  s.holds[1].pose.centre_m.z = 0.0;
  auto e = s.validate();
  ASSERT_FALSE(e);
  EXPECT_NE(e.error().find("calibration.poses[1].z_m"), std::string::npos) << e.error();
  s = two_poses();
  s.board.cols = s.board.rows;
  EXPECT_FALSE(s.validate());
  s = two_poses();
  s.random_poses = BoardPoseRanges{};
  e = s.validate();
  ASSERT_FALSE(e);
  EXPECT_NE(e.error().find("not both"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::simulator
