#include "stereo/core/board_coverage.hpp"

#include <gtest/gtest.h>

namespace stereoball::stereo {
namespace {

// A 4x3-corner board with its top-left corner at (x, y), square side s px, sheared by shear px
// per row (a tilted board).
std::vector<cv::Point2f> board(float x, float y, float s, float shear = 0.0f) {
  std::vector<cv::Point2f> pts;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) pts.emplace_back(x + s * c + shear * r, y + s * r);
  return pts;
}

const cv::Size kBoard{4, 3}, kImage{640, 480};

TEST(BoardViewParams, PositionSizeAndSkew) {
  // Given an upright board at the image's left edge and one at its right edge
  const auto left = board_view_params(board(0, 0, 40), kBoard, kImage);
  const auto right = board_view_params(board(520, 400, 40), kBoard, kImage);
  ASSERT_TRUE(left && right);
  // Then x and y span the range, the size is sqrt(area ratio), an upright board has no skew
  EXPECT_LT(left->x, 0.1);
  EXPECT_GT(right->x, 0.9);
  EXPECT_LT(left->y, 0.1);
  EXPECT_GT(right->y, 0.9);
  EXPECT_NEAR(left->size, std::sqrt(120.0 * 80.0 / (640.0 * 480.0)), 1e-9);
  EXPECT_NEAR(left->skew, 0.0, 1e-6);
  // And a sheared board has skew
  const auto sheared = board_view_params(board(100, 100, 40, 15), kBoard, kImage);
  ASSERT_TRUE(sheared);
  EXPECT_GT(sheared->skew, 0.3);
}

TEST(BoardViewParams, WrongCornerCountIsNoView) {
  EXPECT_FALSE(board_view_params(board(0, 0, 40), cv::Size(5, 3), kImage));
}

TEST(BoardCoverage, ProgressGrowsWithSpreadAndCompletes) {
  // Given no views, then one, then views at the corners, sizes and tilts
  BoardCoverage c;
  EXPECT_EQ(c.progress()[0], 0.0);
  c.add(*board_view_params(board(300, 200, 30), kBoard, kImage));
  EXPECT_FALSE(c.complete());
  EXPECT_EQ(c.progress()[0], 0.0);
  c.add(*board_view_params(board(0, 0, 20), kBoard, kImage));
  c.add(*board_view_params(board(600, 440, 10), kBoard, kImage));
  c.add(*board_view_params(board(100, 50, 120, 60), kBoard, kImage));
  // Then every parameter is covered
  EXPECT_TRUE(c.complete()) << c.progress()[0] << " " << c.progress()[1] << " " << c.progress()[2]
                            << " " << c.progress()[3];
  EXPECT_EQ(c.views(), 4);
}

}  // namespace
}  // namespace stereoball::stereo
