// remap_bilinear on the real basketball rig's rectification map and one of its frames.

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "stereo/core/bilinear_remap.hpp"
#include "stereo/core/calibration_scaling.hpp"
#include "stereo/io/calibration_file.hpp"

namespace stereoball::stereo {
namespace {

const std::string kBasketballRig = std::string(SB_SHARED_DATA_DIR) + "/real-stereo-basketball/";

TEST(RemapBilinearRealRig, GivenTheRigsLeftMapAtThePlayedSizeThenEveryPathEqualsCvRemap) {
  // Given the rig's left rectification map at the played size (1152x648) and its left frame 10
  const auto calib = load_calibration(kBasketballRig + "calibration/rig_2304x1296.yaml");
  ASSERT_TRUE(calib.ok()) << calib.error();
  const auto half = scale_calibration(*calib, {1152, 648});
  ASSERT_TRUE(half.ok()) << half.error();
  cv::Mat xy, frac;
  cv::initUndistortRectifyMap(cv::Mat(half->k1), cv::Mat(half->d1, true).reshape(1, 1),
                              cv::Mat(half->r1), cv::Mat(half->p1), half->image_size, CV_16SC2, xy,
                              frac);
  const cv::Mat raw = cv::imread(kBasketballRig + "left/left_10.jpg", cv::IMREAD_COLOR);
  ASSERT_FALSE(raw.empty());
  cv::Mat frame;
  cv::resize(raw, frame, half->image_size, 0, 0, cv::INTER_AREA);
  // When every path rectifies it
  cv::Mat expected;
  cv::remap(frame, expected, xy, frac, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  for (const RemapPath path : {RemapPath::kPlain, RemapPath::kSsse3, RemapPath::kAvx2}) {
    cv::Mat ours;
    remap_bilinear(frame, ours, xy, frac, path);
    // Then every byte equals cv::remap's
    ASSERT_EQ(ours.size(), expected.size());
    EXPECT_EQ(cv::countNonZero(ours.reshape(1) != expected.reshape(1)), 0)
        << "path " << static_cast<int>(path);
  }
}

}  // namespace
}  // namespace stereoball::stereo
