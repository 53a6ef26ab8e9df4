// Eye-order check on real pairs: OpenCV's chessboard pairs with their calibration (raw images)
// and the rectified Middlebury Aloe pair.

#include "stereo/core/eye_order.hpp"

#include "stereo/io/calibration_file.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <string>

namespace stereoball::stereo {
namespace {

const std::string kEyeOrderDir = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples/";
const std::string kCalibration =
    std::string(SB_SOURCE_DIR) + "/config/calibration/opencv_samples_stereo.yaml";

cv::Mat sample_grey(const std::string& name) {
  return cv::imread(kEyeOrderDir + name, cv::IMREAD_GRAYSCALE);
}

TEST(EyeOrder, GivenRealRawPairsWhenCheckedAsGivenAndExchangedThenOnlyExchangedIsSwapped) {
  // Given the calibration of the real chessboard rig and three of its raw pairs
  const auto calib = load_calibration(kCalibration);
  ASSERT_TRUE(calib.ok()) << calib.error();
  const Rectifier rectifier = Rectifier::create(calib.value()).value();
  for (const char* id : {"01", "12"}) {
    const cv::Mat l = sample_grey("left" + std::string(id) + ".jpg");
    const cv::Mat r = sample_grey("right" + std::string(id) + ".jpg");
    ASSERT_FALSE(l.empty() || r.empty());
    // When checked in the right order and with the cameras exchanged
    const EyeOrderEvidence given = check_eye_order(rectifier, l, r, false);
    const EyeOrderEvidence exchanged = check_eye_order(rectifier, r, l, false);
    std::printf("pair %s: as given %zu / %zu exchanged; cameras exchanged %zu / %zu\n", id,
                given.matches_as_given, given.matches_swapped, exchanged.matches_as_given,
                exchanged.matches_swapped);
    // Then only the exchanged pair is reported, with the evidence mirrored
    EXPECT_FALSE(given.swapped) << id << ": " << given.matches_as_given << " vs "
                                << given.matches_swapped;
    EXPECT_TRUE(exchanged.swapped)
        << id << ": " << exchanged.matches_as_given << " vs " << exchanged.matches_swapped;
    EXPECT_EQ(describe_swapped_eyes(given, "fix"), std::nullopt);
    const auto text = describe_swapped_eyes(exchanged, "swap the devices");
    ASSERT_TRUE(text.has_value());
    EXPECT_NE(text->find("look swapped"), std::string::npos);
    EXPECT_EQ(text->substr(text->size() - 16), "swap the devices");
  }
}

TEST(EyeOrder, GivenRectifiedAloeWhenCheckedThenOrderFoundEitherWay) {
  const auto calib = load_calibration(kCalibration);
  ASSERT_TRUE(calib.ok()) << calib.error();
  const Rectifier rectifier = Rectifier::create(calib.value()).value();  // unused: rectified
  const cv::Mat l = sample_grey("aloeL.jpg"), r = sample_grey("aloeR.jpg");
  EXPECT_FALSE(check_eye_order(rectifier, l, r, true).swapped);
  EXPECT_TRUE(check_eye_order(rectifier, r, l, true).swapped);
}

TEST(EyeOrder, GivenBlankSceneWhenCheckedThenNoVerdict) {
  const auto calib = load_calibration(kCalibration);
  ASSERT_TRUE(calib.ok()) << calib.error();
  const Rectifier rectifier = Rectifier::create(calib.value()).value();
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(90));
  const EyeOrderEvidence e = check_eye_order(rectifier, blank, blank, false);
  EXPECT_FALSE(e.swapped);
  EXPECT_EQ(e.matches_swapped, 0u);
}

TEST(EyeOrderWatch, GivenBlankThenRealFramesWhenStreamedThenChecksUntilADecisionThenStops) {
  // Given a watch checking every 2nd frame, at most 3 times
  const auto calib = load_calibration(kCalibration);
  ASSERT_TRUE(calib.ok()) << calib.error();
  const Rectifier rectifier = Rectifier::create(calib.value()).value();
  EyeOrderWatch watch(3, 2);
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(90));
  const cv::Mat l = sample_grey("left03.jpg"), r = sample_grey("right03.jpg");
  // When a blank frame, a skipped one, then a swapped real pair arrive (due() saying in advance
  // which frames are checked, so a caller converts only those)
  EXPECT_TRUE(watch.due());
  EXPECT_TRUE(watch.step(rectifier, blank, blank, false).has_value());  // frame 0: checked
  EXPECT_FALSE(watch.due());
  EXPECT_FALSE(watch.step(rectifier, r, l, false).has_value());  // frame 1: not due
  EXPECT_TRUE(watch.due());
  const auto e = watch.step(rectifier, r, l, false);  // frame 2: checked
  // Then the swap is found on the third frame, and nothing is checked after the decision
  ASSERT_TRUE(e.has_value());
  EXPECT_TRUE(e->swapped);
  EXPECT_FALSE(watch.due());
  EXPECT_FALSE(watch.step(rectifier, r, l, false).has_value());
  EXPECT_FALSE(watch.step(rectifier, r, l, false).has_value());
  // and after a reset it checks again
  watch.reset();
  EXPECT_TRUE(watch.step(rectifier, l, r, false).has_value());
}

TEST(EyeOrderWatch, GivenFramesThatCannotBeHadWhenSkippedThenEachDueOneUsesUpACheck) {
  // Given a watch checking every 2nd frame, at most 3 times
  EyeOrderWatch watch(3, 2);
  // When every frame is skipped (its images could not be converted or decoded)
  int due = 0;
  for (int frame = 0; frame < 20 && !watch.given_up(); ++frame) {
    due += watch.due() ? 1 : 0;
    watch.skip();
  }
  // Then the watch gave up after its three due frames and checks nothing more
  EXPECT_TRUE(watch.given_up());
  EXPECT_EQ(due, 3);
  EXPECT_FALSE(watch.due());
  // and after a reset it checks again
  watch.reset();
  EXPECT_FALSE(watch.given_up());
  EXPECT_TRUE(watch.due());
}

}  // namespace
}  // namespace stereoball::stereo
