// Edge step: image-derived Canny thresholds, staircase thinning, bit packing.

#include "ball_detector/core/edge_map.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <array>
#include <cmath>
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

// halve_edge_map in plain loops: each pixel the OR of its 2 x 2 block, the derivatives the
// block's sums, then the byte thinning pass (or, not thinned, the frame cleared).
EdgeMap reference_halved(const EdgeMap& full, bool thin) {
  const int w = full.edges.cols / 2, h = full.edges.rows / 2;
  EdgeMap r;
  r.edges = cv::Mat::zeros(h, w, CV_8UC1);
  r.dx.create(h, w, CV_16S);
  r.dy.create(h, w, CV_16S);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int any = 0, sx = 0, sy = 0;
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
          any |= full.edges.at<uchar>(2 * y + j, 2 * x + i);
          sx += full.dx.at<short>(2 * y + j, 2 * x + i);
          sy += full.dy.at<short>(2 * y + j, 2 * x + i);
        }
      r.edges.at<uchar>(y, x) = any != 0 ? 255 : 0;
      r.dx.at<short>(y, x) = cv::saturate_cast<short>(sx);
      r.dy.at<short>(y, x) = cv::saturate_cast<short>(sy);
    }
  if (thin) {
    r.removed_staircase = thin_staircase(r.edges);
  } else if (w > 0 && h > 0) {
    r.edges.row(0).setTo(0);
    r.edges.row(h - 1).setTo(0);
    r.edges.col(0).setTo(0);
    r.edges.col(w - 1).setTo(0);
  }
  r.bits.assign(r.edges);
  list_edge_points(r.bits, r.dx, r.dy, r.points);
  return r;
}

bool same_mat(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         (a.empty() || cv::countNonZero(cv::abs(a != b)) == 0);
}

void expect_reference_halved(const EdgeMap& full, bool thin, const cv::Mat& half_image) {
  EdgeMap half;
  halve_edge_map(full, half_image, thin, half);
  const EdgeMap ref = reference_halved(full, thin);
  EXPECT_TRUE(same_mat(half.edges, ref.edges));
  EXPECT_TRUE(same_mat(half.dx, ref.dx));
  EXPECT_TRUE(same_mat(half.dy, ref.dy));
  EXPECT_EQ(half.removed_staircase, ref.removed_staircase);
  ASSERT_EQ(half.bits.width(), ref.bits.width());
  ASSERT_EQ(half.bits.height(), ref.bits.height());
  const int words = (ref.bits.width() + 63) / 64;
  for (int y = 0; y < ref.bits.height(); ++y)
    for (int i = 0; i < words; ++i) ASSERT_EQ(half.bits.row(y)[i], ref.bits.row(y)[i]) << y;
  EXPECT_EQ(half.points.x, ref.points.x);
  EXPECT_EQ(half.points.y, ref.points.y);
  EXPECT_EQ(half.points.gx, ref.points.gx);
  EXPECT_EQ(half.points.gy, ref.points.gy);
  EXPECT_EQ(half.points.row_start, ref.points.row_start);
  EXPECT_EQ(half.high_threshold, full.high_threshold);
  EXPECT_EQ(half.frame_px, cv::Rect2d(0.5 * full.frame_px.x, 0.5 * full.frame_px.y,
                                      std::floor(0.5 * full.frame_px.width),
                                      std::floor(0.5 * full.frame_px.height)));
}

TEST(HalveEdgeMap, GivenEdgeMapsOfTexturedImagesThenEachIsThePlainLoopsResult) {
  // Given colour images of blurred noise (many short edges in every direction) of even and odd
  // sizes, some crossing a packed word of the halved row, and their edge maps
  cv::RNG rng(31);
  for (const cv::Size size : {cv::Size(640, 480), cv::Size(203, 97), cv::Size(130, 66),
                              cv::Size(257, 9), cv::Size(5, 5)}) {
    cv::Mat image(size, CV_8UC3);
    rng.fill(image, cv::RNG::UNIFORM, 0, 256);
    cv::GaussianBlur(image, image, cv::Size(5, 5), 1.5);
    EdgeMap full;
    compute_edge_map(image, EdgeParams{}, full);
    cv::Mat half_image;
    cv::resize(image(cv::Rect(0, 0, size.width / 2 * 2, size.height / 2 * 2)), half_image,
               cv::Size(size.width / 2, size.height / 2), 0, 0, cv::INTER_AREA);
    for (const bool thin : {true, false}) {
      SCOPED_TRACE(testing::Message() << size << " thin " << thin);
      // When halved, Then every plane and list equals the plain loops' (and the halved colour
      // image is the map's source)
      expect_reference_halved(full, thin, half_image);
    }
    EdgeMap half;
    halve_edge_map(full, half_image, true, half);
    EXPECT_EQ(half.colour.data, half_image.data);
    EXPECT_TRUE(half.grey.empty());
  }
}

TEST(HalveEdgeMap, GivenDerivativesNearTheirLimitsThenTheBlockSumsSaturate) {
  // Given a hand-made map: random edge pixels and derivatives over the whole 16-bit range
  cv::RNG rng(5);
  EdgeMap full;
  cv::Mat noise(150, 301, CV_8UC1);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  full.edges = noise > 200;
  full.bits.assign(full.edges);
  full.dx.create(noise.size(), CV_16S);
  full.dy.create(noise.size(), CV_16S);
  rng.fill(full.dx, cv::RNG::UNIFORM, -32768, 32768);
  rng.fill(full.dy, cv::RNG::UNIFORM, -32768, 32768);
  full.frame_px = cv::Rect2d(-10, -4, 400, 200);
  // When halved, Then it is the plain loops' result, saturated sums included
  expect_reference_halved(full, true, cv::Mat());
  EdgeMap half;
  halve_edge_map(full, cv::Mat(), true, half);
  EXPECT_EQ(half.frame_px, cv::Rect2d(-5, -2, 200, 100));
  EXPECT_GT(cv::countNonZero(half.dx == 32767), 0) << "premise: some sums saturate";
}

}  // namespace
}  // namespace stereoball::ball_detector
