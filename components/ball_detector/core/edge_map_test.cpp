// Edge step: image-derived Canny thresholds, staircase thinning, bit packing.

#include "ball_detector/core/edge_map.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <array>
#include <cstdint>

namespace stereoball::ball_detector {
namespace {

int code_of(std::initializer_list<int> bits) {
  int c = 0;
  for (int b : bits) c |= 1 << b;
  return c;
}
// Bit order: E=0, SE=1, S=2, SW=3, W=4, NW=5, N=6, NE=7.

TEST(StaircaseTable, GivenAnLCornerThenTheCornerPixelIsRemovable) {
  const auto& t = staircase_table();
  EXPECT_TRUE(t[code_of({4, 2})]);     // W and S
  EXPECT_TRUE(t[code_of({0, 6})]);     // E and N
  EXPECT_TRUE(t[code_of({4, 2, 3})]);  // W, S and the diagonal between them
}

TEST(StaircaseTable, GivenLinesEndsAndJunctionsThenThePixelIsKept) {
  const auto& t = staircase_table();
  EXPECT_FALSE(t[code_of({0, 4})]);        // horizontal line
  EXPECT_FALSE(t[code_of({1, 5})]);        // diagonal line
  EXPECT_FALSE(t[code_of({0})]);           // line end
  EXPECT_FALSE(t[code_of({0, 2, 4, 6})]);  // cross: removing O leaves a hole in its arms
  EXPECT_FALSE(t[code_of({0, 2, 5})]);     // corner plus a neighbour only reachable through O
  EXPECT_FALSE(t[255]);                    // interior pixel
}

TEST(StaircaseBits, GivenEveryNeighbourCodeAtEveryBitThenEachBitIsTheTablesEntry) {
  const auto& t = staircase_table();
  // Given 64 neighbour codes side by side (bit i of plane k is bit k of code base + i), four
  // times to cover all 256
  for (int base = 0; base < 256; base += 64) {
    std::array<std::uint64_t, 8> planes{};
    for (int i = 0; i < 64; ++i)
      for (int k = 0; k < 8; ++k)
        planes[static_cast<std::size_t>(k)] |= static_cast<std::uint64_t>(((base + i) >> k) & 1)
                                               << i;
    // When the 64 pixels are tested at once
    const std::uint64_t removable = staircase_bits(planes[0], planes[1], planes[2], planes[3],
                                                   planes[4], planes[5], planes[6], planes[7]);
    // Then each bit is the table's entry for its code
    for (int i = 0; i < 64; ++i)
      EXPECT_EQ(((removable >> i) & 1) != 0, t[static_cast<std::size_t>(base + i)]) << base + i;
  }
}

TEST(ThinStaircase, GivenA4ConnectedStaircaseThenItBecomesOnePixelPerColumnAndStaysConnected) {
  cv::Mat m(20, 30, CV_8U, cv::Scalar(0));
  // A staircase: two pixels right, one down, the step pixel makes a 4-connected L.
  int x = 2, y = 2;
  while (x < 26 && y < 17) {
    m.at<uchar>(y, x) = 255;
    m.at<uchar>(y, x + 1) = 255;
    m.at<uchar>(y + 1, x + 1) = 255;
    x += 2;
    y += 1;
  }
  const int before = cv::countNonZero(m);
  const int removed = thin_staircase(m);
  EXPECT_GT(removed, 0);
  EXPECT_EQ(cv::countNonZero(m), before - removed);
  for (int c = 0; c < m.cols; ++c) EXPECT_LE(cv::countNonZero(m.col(c)), 1) << "column " << c;
  cv::Mat labels;
  EXPECT_EQ(cv::connectedComponents(m, labels, 8), 2);  // background + one curve
}

TEST(ThinStaircase, GivenAnAlreadyThinCircleThenNothingIsRemoved) {
  cv::Mat m(60, 60, CV_8U, cv::Scalar(0));
  cv::circle(m, {30, 30}, 20, cv::Scalar(255), 1, cv::LINE_8);
  EXPECT_EQ(thin_staircase(m), 0);
}

TEST(CannyThresholds, GivenTheSameSceneAtLowerContrastThenThresholdsScaleDown) {
  auto scene = [](int lo, int hi) {
    cv::Mat m(100, 100, CV_8U, cv::Scalar(lo));
    cv::circle(m, {50, 50}, 25, cv::Scalar(hi), cv::FILLED, cv::LINE_AA);
    cv::rectangle(m, {5, 5}, {30, 20}, cv::Scalar(hi), cv::FILLED);
    return m;
  };
  EdgeParams p;
  p.min_high_threshold = 1.0;
  EdgeMap strong, weak;
  compute_edge_map(scene(20, 220), p, strong);
  compute_edge_map(scene(100, 140), p, weak);
  EXPECT_LT(weak.high_threshold, strong.high_threshold / 3.0);
  EXPECT_DOUBLE_EQ(weak.low_threshold, weak.high_threshold * p.low_ratio);
  // Both still find the disc outline.
  EXPECT_GT(cv::countNonZero(weak.edges), 100);
  EXPECT_NEAR(cv::countNonZero(weak.edges), cv::countNonZero(strong.edges),
              0.2 * cv::countNonZero(strong.edges));
}

TEST(CannyThresholds, GivenAFlatImageThenTheFloorKeepsNoiseFromBecomingEdges) {
  cv::Mat m(64, 64, CV_8U, cv::Scalar(128));
  cv::Mat noise(64, 64, CV_8U);
  cv::randu(noise, 0, 3);
  m += noise;
  EdgeMap e;
  compute_edge_map(m, EdgeParams{}, e);
  EXPECT_GE(e.high_threshold, EdgeParams{}.min_high_threshold);
  EXPECT_EQ(cv::countNonZero(e.edges), 0);
}

TEST(EdgeMap, GivenABgrDiscThenEdgesAreThinAndLieOnTheOutline) {
  cv::Mat img(120, 160, CV_8UC3, cv::Scalar(40, 90, 60));
  cv::circle(img, {80, 60}, 30, cv::Scalar(20, 30, 230), cv::FILLED, cv::LINE_AA);
  EdgeMap e;
  compute_edge_map(img, EdgeParams{}, e);
  ASSERT_EQ(e.edges.type(), CV_8U);
  int on_outline = 0, total = 0;
  for (int y = 1; y < e.edges.rows - 1; ++y)
    for (int x = 1; x < e.edges.cols - 1; ++x) {
      if (!e.edges.at<uchar>(y, x)) continue;
      ++total;
      on_outline += std::abs(std::hypot(x - 80, y - 60) - 30.0) < 1.5;
      EXPECT_FALSE(staircase_table()[neighbour_code(e.edges, x, y)]) << x << "," << y;
    }
  EXPECT_GT(total, 150);
  EXPECT_EQ(on_outline, total);
}

TEST(BitImage, GivenABinaryImageThenBitsMatchPixelsIncludingAcrossWords) {
  cv::Mat m(3, 150, CV_8U, cv::Scalar(0));
  for (int x : {0, 7, 8, 63, 64, 65, 100, 127, 128, 149}) m.at<uchar>(1, x) = 1;
  BitImage b;
  b.assign(m);
  for (int x = 0; x < 150; ++x) EXPECT_EQ(b.test(x, 1), m.at<uchar>(1, x) != 0) << x;
  EXPECT_EQ(b.bits(1, 60, 10), (1u << 3) | (1u << 4) | (1u << 5));  // pixels 63, 64, 65
  EXPECT_EQ(b.bits(0, 60, 10), 0u);
}

TEST(EdgeParams, GivenOutOfRangeFieldsThenValidateNamesThem) {
  EdgeParams p;
  EXPECT_TRUE(p.validate().ok());
  p.high_percentile = 1.5;
  ASSERT_FALSE(p.validate().ok());
  EXPECT_NE(p.validate().error().find("high_percentile"), std::string::npos);
  p = EdgeParams{};
  p.low_ratio = 0.0;
  EXPECT_NE(p.validate().error().find("low_ratio"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::ball_detector
