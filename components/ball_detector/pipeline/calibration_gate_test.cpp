// CalibrationGate: a calibration that does not fit the frames never replaces a good one.

#include "ball_detector/pipeline/calibration_gate.hpp"

#include <gtest/gtest.h>

namespace stereoball::ball_detector {
namespace {

const cv::Size kVga(640, 480), kOther(1280, 720);

TEST(CalibrationGate, GivenNoCalibrationYetWhenOneArrivesThenItIsUsed) {
  CalibrationGate gate;
  gate.frame(kOther);  // frames of any size: without a calibration there is nothing to keep
  EXPECT_TRUE(gate.offer(kVga).use);
}

TEST(CalibrationGate, GivenFramesMatchingTheCalibrationWhenAnotherSizeArrivesThenItIsHeldBack) {
  CalibrationGate gate;
  ASSERT_TRUE(gate.offer(kVga).use);
  gate.applied(kVga);
  gate.frame(kVga);
  const auto decision = gate.offer(kOther);
  EXPECT_FALSE(decision.use);
  EXPECT_EQ(decision.reason,
            "it is for 1280x720 images but the frames are 640x480; keeping the 640x480 "
            "calibration until 3 frames of 1280x720 arrive");
  EXPECT_FALSE(gate.frame(kVga));
  EXPECT_EQ(gate.pending(), kOther);
}

TEST(CalibrationGate, GivenAHeldBackCalibrationWhenFramesOfItsSizeKeepComingThenItIsUsed) {
  CalibrationGate gate;
  gate.applied(kVga);
  gate.frame(kVga);
  ASSERT_FALSE(gate.offer(kOther).use);
  EXPECT_FALSE(gate.frame(kOther));
  EXPECT_FALSE(gate.frame(kVga));  // a stray frame restarts the count
  EXPECT_FALSE(gate.frame(kOther));
  EXPECT_FALSE(gate.frame(kOther));
  EXPECT_TRUE(gate.frame(kOther));
}

TEST(CalibrationGate, GivenACalibrationOfTheFramesSizeWhenOfferedThenItReplacesTheOldOne) {
  CalibrationGate gate;
  gate.applied(kVga);
  gate.frame(kVga);
  EXPECT_TRUE(gate.offer(kVga).use);
  EXPECT_FALSE(gate.pending());
}

}  // namespace
}  // namespace stereoball::ball_detector
