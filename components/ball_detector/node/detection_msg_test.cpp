// IDL <-> core conversions: detection message fields, ball/track prior.

#include "ball_detector/node/detection_msg.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace sb = stereoball;
using sb::ball_detector::DetectionStatus;

TEST(DetectionMessage, GivenFoundBall_ThenEveryFieldCopied) {
  sb::ball_detector::StereoDetection det;
  det.status = DetectionStatus::kFound;
  det.reason = "pair score 0.8";
  det.left = {100.5, 200.25, 30.0, 0.8};
  det.right = {80.5, 200.75, 29.0, 0.7};
  det.row_residual_px = 0.5;
  det.position_m = {0.1, -0.2, 1.5};
  det.depth_from_size_m = 1.45;
  det.candidates_left = 3;
  det.candidates_right = 2;
  det.patch_valid = true;
  det.patch_rgb[0] = 200;
  det.patch_rgb[1322] = 7;
  stereoball_msg_BallDetection msg{};
  sb::ball_detector::to_message(det, {42, 1000}, 3.5f, 2000, msg);
  EXPECT_EQ(msg.frame_seq, 42u);
  EXPECT_EQ(msg.capture_stamp_ns, 1000);
  EXPECT_EQ(msg.publish_stamp_ns, 2000);
  EXPECT_EQ(msg.status, stereoball_msg_DETECTION_FOUND);
  EXPECT_STREQ(msg.reason, "pair score 0.8");
  EXPECT_FLOAT_EQ(msg.left.x_px, 100.5f);
  EXPECT_FLOAT_EQ(msg.right.y_px, 200.75f);
  EXPECT_FLOAT_EQ(msg.right.score, 0.7f);
  EXPECT_FLOAT_EQ(msg.row_residual_px, 0.5f);
  EXPECT_DOUBLE_EQ(msg.position_m[2], 1.5);
  EXPECT_FLOAT_EQ(msg.depth_from_size_m, 1.45f);
  EXPECT_EQ(msg.candidates_left, 3u);
  EXPECT_EQ(msg.candidates_right, 2u);
  EXPECT_FLOAT_EQ(msg.processing_ms, 3.5f);
  EXPECT_TRUE(msg.patch_valid);
  EXPECT_EQ(msg.patch_rgb[0], 200);
  EXPECT_EQ(msg.patch_rgb[1322], 7);
}

TEST(DetectionMessage, GivenRejectedPair_ThenNoPositionPublished) {
  sb::ball_detector::StereoDetection det;
  det.status = DetectionStatus::kSizeInconsistent;
  det.position_m = {0.1, 0.2, 5.0};
  stereoball_msg_BallDetection msg{};
  sb::ball_detector::to_message(det, {1, 1}, 1.0f, 1, msg);
  EXPECT_EQ(msg.status, stereoball_msg_DETECTION_SIZE_INCONSISTENT);
  EXPECT_EQ(msg.position_m[2], 0.0);
}

TEST(DetectionMessage, GivenEveryStatus_ThenDistinctIdlValues) {
  EXPECT_EQ(sb::ball_detector::to_message(DetectionStatus::kNoCandidate),
            stereoball_msg_DETECTION_NO_CANDIDATE);
  EXPECT_EQ(sb::ball_detector::to_message(DetectionStatus::kEpipolarMismatch),
            stereoball_msg_DETECTION_EPIPOLAR_MISMATCH);
  EXPECT_EQ(sb::ball_detector::to_message(DetectionStatus::kNoCalibration),
            stereoball_msg_DETECTION_NO_CALIBRATION);
  EXPECT_EQ(sb::ball_detector::to_message(DetectionStatus::kBadFrame),
            stereoball_msg_DETECTION_BAD_FRAME);
  EXPECT_EQ(sb::ball_detector::to_message(DetectionStatus::kOffFloor),
            stereoball_msg_DETECTION_OFF_FLOOR);
  EXPECT_STREQ(sb::ball_detector::to_string(DetectionStatus::kOffFloor), "off_floor");
  EXPECT_EQ(sb::ball_detector::to_message(DetectionStatus::kInteriorMismatch),
            stereoball_msg_DETECTION_INTERIOR_MISMATCH);
  EXPECT_STREQ(sb::ball_detector::to_string(DetectionStatus::kInteriorMismatch),
               "interior_mismatch");
}

// Given a following ball/track sample, then its position, velocity and stamp are kept; a
// non-finite coordinate makes the position invalid (never a prior).
TEST(MessageConversion, GivenBallTrack_ThenTrackedBallAndNonFiniteInvalid) {
  stereoball_msg_BallTrack msg{};
  msg.state = stereoball_msg_TRACK_FOLLOWING;
  msg.position_valid = true;
  msg.position_m[0] = 0.2;
  msg.position_m[2] = 1.5;
  msg.velocity_mps[2] = -0.5;
  msg.capture_stamp_ns = 42;
  auto t = sb::ball_detector::from_message(msg);
  EXPECT_TRUE(t.following);
  EXPECT_TRUE(t.position_valid);
  EXPECT_DOUBLE_EQ(t.position_m[2], 1.5);
  EXPECT_DOUBLE_EQ(t.velocity_mps[2], -0.5);
  EXPECT_EQ(t.capture_stamp_ns, 42);
  msg.velocity_mps[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(sb::ball_detector::from_message(msg).position_valid);
  msg.state = stereoball_msg_TRACK_SEARCHING;
  EXPECT_FALSE(sb::ball_detector::from_message(msg).following);
}
