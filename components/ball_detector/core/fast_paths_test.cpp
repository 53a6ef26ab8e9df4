// The edge step's and the image helpers' speed-ups against plain references: the one-pass
// strongest-channel gradient vs three cv::Sobel passes and a select, the thresholds' gradient
// measured in two row passes vs one whole pass (and the pre-blur decided on part of the rows),
// canny_l1 vs cv::Canny and its vector loop vs its plain loop, canny_thresholds' quantiles vs
// sorting the sampled pixels, the packed staircase thinning vs the byte pass, box_filter vs
// cv::boxFilter, halve_image vs cv::resize (INTER_AREA), channels_equal vs a test per pixel.
// Voting windows: window_rules_test.cpp; the detector's searches and fits:
// detector_paths_test.cpp.

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <iterator>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "ball_detector/core/canny.hpp"
#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/fast_math.hpp"
#include "ball_detector/core/fast_paths_test_support.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/p2p_rules.hpp"
#include "ball_detector/core/same_circles_test_support.hpp"
#include "ball_detector/core/synthetic.hpp"
#include "ball_detector/core/voting.hpp"

namespace stereoball::ball_detector {
namespace {

TEST(CannyL1, GivenRealImagesAndSeveralThresholdsThenEdgesEqualOpenCvCanny) {
  // Given the real sample images (ships with the project's shared data)
  const auto images = real_greys();
  ASSERT_GE(images.size(), 10u) << "expected the OpenCV sample images in " << SB_SHARED_DATA_DIR;
  CannyWorkspace work;
  int compared = 0;
  for (const auto& grey : images) {
    cv::Mat dx, dy;
    sobel(grey, dx, dy);
    // Fractional thresholds too: both floor them.
    for (const double high : {24.0, 60.5, 151.7, 400.0}) {
      // When both compute the edge map
      cv::Mat ours, reference;
      canny_l1(dx, dy, 0.4 * high, high, ours, work);
      cv::Canny(dx, dy, reference, 0.4 * high, high, false);
      // Then every pixel agrees
      ASSERT_EQ(cv::countNonZero(ours != reference), 0) << "high " << high;
      ++compared;
    }
  }
  EXPECT_GE(compared, 40);
}

TEST(CannyL1, GivenCropsTinyImagesAndSwappedThresholdsThenEdgesEqualOpenCvCanny) {
  const auto images = real_greys();
  ASSERT_FALSE(images.empty());
  CannyWorkspace work;
  std::mt19937 rng(7);
  for (int i = 0; i < 60; ++i) {
    // Given random crops (down to 1x1) of a real image, as the node searches boxes
    const cv::Mat& grey = images[static_cast<size_t>(i) % images.size()];
    const int w = 1 + static_cast<int>(rng() % 90), h = 1 + static_cast<int>(rng() % 90);
    const int x = static_cast<int>(rng() % static_cast<unsigned>(grey.cols - w));
    const int y = static_cast<int>(rng() % static_cast<unsigned>(grey.rows - h));
    cv::Mat dx, dy;
    sobel(grey(cv::Rect(x, y, w, h)), dx, dy);
    // When the thresholds come in the wrong order (both swap them)
    cv::Mat ours, reference;
    canny_l1(dx, dy, 120.0, 48.0, ours, work);
    cv::Canny(dx, dy, reference, 120.0, 48.0, false);
    // Then the edge maps are equal
    ASSERT_EQ(cv::countNonZero(ours != reference), 0) << w << "x" << h;
  }
}

// Random derivatives over the whole range canny_l1 takes (|dx|, |dy| < 16384): flat runs (ties
// between neighbours), extremes, and dy on and next to the sector boundaries of dx (|dy| / |dx|
// at tan(22.5 deg) and tan(67.5 deg) in 15-bit fixed point), so every branch of the sector and
// maximum tests is met.
void random_derivatives(cv::Size size, std::mt19937& rng, cv::Mat& dx, cv::Mat& dy) {
  dx.create(size, CV_16S);
  dy.create(size, CV_16S);
  const short extremes[] = {0, 1, -1, 16383, -16383, 1020, -1020};
  const auto value = [&](unsigned kind, const cv::Mat& m, int x, int y) {
    if (kind == 1) return static_cast<int>(rng() % 121) - 60;
    if (kind == 2) return static_cast<int>(extremes[rng() % std::size(extremes)]);
    if (kind == 3 && x > 0) return static_cast<int>(m.at<short>(y, x - 1));
    return static_cast<int>(rng() % 32767) - 16383;
  };
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const int gx = value(rng() % 4, dx, x, y);
      dx.at<short>(y, x) = static_cast<short>(gx);
      const unsigned kind = rng() % 6;
      int gy = value(kind, dy, x, y);
      if (kind >= 4) {
        const int ax = std::abs(gx), near = -1 + static_cast<int>(rng() % 3);
        const int tan22 = (ax * 13573) >> 15;
        gy = std::clamp((kind == 4 ? tan22 : 2 * ax + tan22) + near, 0, 16383);
        if (rng() % 2) gy = -gy;
      }
      dy.at<short>(y, x) = static_cast<short>(gy);
    }
}

TEST(CannyL1, GivenRandomDerivativesOfEveryWidthThenTheVectorAndPlainLoopsGiveTheSameEdges) {
  std::mt19937 rng(29);
  CannyWorkspace vector_work, plain_work;
  plain_work.plain = true;
  // Given random derivatives over their whole range, widths around the 32-pixel step of the
  // vector loop, and thresholds inside, below and above the 16-bit range of its lanes
  for (const cv::Size size : {cv::Size(1, 3), cv::Size(31, 5), cv::Size(32, 4), cv::Size(33, 6),
                              cv::Size(95, 7), cv::Size(200, 9), cv::Size(517, 61)})
    for (const auto& [low, high] : {std::pair{-5.0, 40000.0}, std::pair{40.0, 90.0},
                                    std::pair{400.0, 9000.5}, std::pair{33000.0, 70000.0}}) {
      cv::Mat dx, dy;
      random_derivatives(size, rng, dx, dy);
      // When canny_l1 runs on its vector loop (where the CPU has one) and on the plain loop
      cv::Mat ours, plain;
      canny_l1(dx, dy, low, high, ours, vector_work);
      canny_l1(dx, dy, low, high, plain, plain_work);
      // Then the edge maps are equal, and equal to OpenCV's inside the range it takes
      ASSERT_EQ(cv::countNonZero(ours != plain), 0) << size << " " << low << " " << high;
      if (low >= 0.0 && high < 32768.0) {
        cv::Mat reference;
        cv::Canny(dx, dy, reference, low, high, false);
        ASSERT_EQ(cv::countNonZero(ours != reference), 0) << size << " " << low << " " << high;
      }
    }
}

// canny_thresholds' sampling by its definition: min(|dx| + |dy|, 2048) of every second row and
// column, the q-quantile the smallest value with more than floor(q * n) samples at or below it.
int reference_sampled_quantile(const cv::Mat& dx, const cv::Mat& dy, double q) {
  std::vector<int> samples;
  for (int y = 0; y < dx.rows; y += 2)
    for (int x = 0; x < dx.cols; x += 2)
      samples.push_back(std::min(2048, std::abs(static_cast<int>(dx.at<short>(y, x))) +
                                           std::abs(static_cast<int>(dy.at<short>(y, x)))));
  std::sort(samples.begin(), samples.end());
  const auto target = static_cast<std::size_t>(q * static_cast<double>(samples.size()));
  return target < samples.size() ? samples[target] : 2048;
}

TEST(CannyThresholds, GivenAnyDerivativesAndWidthsThenTheQuantilesAreThoseOfTheSampledPixels) {
  std::mt19937 rng(31);
  EdgeParams params;
  params.contrast_fraction = 1.0;  // high = the quantile itself (noise_factor * median below)
  params.noise_factor = 0.01;
  params.min_high_threshold = 1.0;
  params.max_high_threshold = 2040.0;
  // Given random derivatives (-32768 included), widths across the stretches a row is measured
  // in, odd and even sizes
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(7, 3), cv::Size(1023, 4), cv::Size(1025, 5),
                              cv::Size(2050, 2), cv::Size(3001, 3)}) {
    cv::Mat dx, dy;
    random_derivatives(size, rng, dx, dy);
    dx.at<short>(0, 0) = -32768;
    dy.at<short>(0, 0) = -32768;
    // When the thresholds are measured
    const CannyThresholds t = canny_thresholds(dx, dy, params);
    // Then median and high quantile are those of the sampled pixels, by sorting
    EXPECT_EQ(t.median_gradient, reference_sampled_quantile(dx, dy, 0.5)) << size;
    const int high = reference_sampled_quantile(dx, dy, params.high_percentile);
    EXPECT_EQ(t.high, std::clamp(static_cast<double>(high), 1.0, 2040.0)) << size;
  }
}

// The plain definition: each channel's cv::Sobel (a crop reads its parent around it), then per
// pixel the channel with the largest |dx| + |dy|, the first on ties.
void reference_strongest_gradient(const cv::Mat& bgr, cv::Mat& dx, cv::Mat& dy) {
  std::array<cv::Mat, 3> gx, gy;
  for (int c = 0; c < 3; ++c) {
    // A crop of one channel that still knows its parent: extract the whole channel, crop it.
    cv::Size whole;
    cv::Point at;
    bgr.locateROI(whole, at);
    cv::Mat parent = bgr;
    parent.adjustROI(at.y, whole.height - at.y - bgr.rows, at.x, whole.width - at.x - bgr.cols);
    cv::Mat channel;
    cv::extractChannel(parent, channel, c);
    sobel(channel(cv::Rect(at, bgr.size())), gx[c], gy[c]);
  }
  dx.create(bgr.size(), CV_16S);
  dy.create(bgr.size(), CV_16S);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      int best = -1;
      for (int c = 0; c < 3; ++c) {
        const short a = gx[c].at<short>(y, x), b = gy[c].at<short>(y, x);
        if (std::abs(a) + std::abs(b) > best) {
          best = std::abs(a) + std::abs(b);
          dx.at<short>(y, x) = a;
          dy.at<short>(y, x) = b;
        }
      }
    }
}

TEST(StrongestChannelGradient, GivenRealColourImagesAndCropsThenItEqualsThreeSobelPasses) {
  // Given the real colour sample images, whole and cropped anywhere (borders, 1x1 included)
  const auto images = real_colours();
  ASSERT_GE(images.size(), 10u) << "expected the OpenCV sample images in " << SB_SHARED_DATA_DIR;
  std::array<cv::Mat, 3> planes;
  std::mt19937 rng(11);
  int compared = 0;
  for (const auto& bgr : images) {
    std::vector<cv::Rect> boxes = {cv::Rect(cv::Point(0, 0), bgr.size())};
    for (int i = 0; i < 6; ++i) {
      const int w = 1 + static_cast<int>(rng() % 120), h = 1 + static_cast<int>(rng() % 120);
      const int x = static_cast<int>(rng() % static_cast<unsigned>(bgr.cols - w + 1));
      const int y = static_cast<int>(rng() % static_cast<unsigned>(bgr.rows - h + 1));
      boxes.emplace_back(x, y, w, h);
    }
    boxes.emplace_back(bgr.cols - 17, bgr.rows - 9, 17, 9);  // the bottom-right corner
    for (const cv::Rect& box : boxes) {
      // When both compute the gradient
      cv::Mat dx, dy, ref_dx, ref_dy;
      strongest_channel_gradient(bgr(box), dx, dy, planes);
      reference_strongest_gradient(bgr(box), ref_dx, ref_dy);
      // Then every pixel agrees
      ASSERT_EQ(cv::countNonZero(dx != ref_dx), 0) << box;
      ASSERT_EQ(cv::countNonZero(dy != ref_dy), 0) << box;
      ++compared;
    }
  }
  EXPECT_GE(compared, 80);
}

TEST(StrongestChannelGradient, GivenGreyImagesReadAsColourThenTheOneChannelPathGivesTheSameBits) {
  // Given grey images as three equal channels (the one-channel shortcut), and the same images
  // with one pixel of one channel changed in the last row or the crop's surrounding pixel (the
  // three-channel path must then run, on the whole image and on a crop whose parent differs)
  const auto greys = real_greys();
  ASSERT_GE(greys.size(), 10u) << "expected the OpenCV sample images in " << SB_SHARED_DATA_DIR;
  std::array<cv::Mat, 3> planes;
  int compared = 0;
  for (const auto& grey : greys) {
    if (grey.cols < 40 || grey.rows < 40) continue;
    cv::Mat equal;
    cv::cvtColor(grey, equal, cv::COLOR_GRAY2BGR);
    cv::Mat last_row_differs = equal.clone();
    last_row_differs.at<cv::Vec3b>(grey.rows - 1, grey.cols - 1)[2] ^= 0x40;
    cv::Mat border_differs = equal.clone();
    const cv::Rect box(10, 10, 20, 20);
    border_differs.at<cv::Vec3b>(box.y - 1, box.x + 5)[1] ^= 0x40;  // just above the crop
    for (const cv::Mat& whole : {equal, last_row_differs, border_differs})
      for (const cv::Rect& r : {cv::Rect(cv::Point(), whole.size()), box}) {
        // When both compute the gradient
        cv::Mat dx, dy, ref_dx, ref_dy;
        strongest_channel_gradient(whole(r), dx, dy, planes);
        reference_strongest_gradient(whole(r), ref_dx, ref_dy);
        // Then every pixel agrees
        ASSERT_EQ(cv::countNonZero(dx != ref_dx), 0) << r;
        ASSERT_EQ(cv::countNonZero(dy != ref_dy), 0) << r;
        ++compared;
      }
  }
  EXPECT_GE(compared, 60);
}

TEST(MeasureEdgeThresholds,
     GivenColourImagesCropsAndEveryPreBlurChoiceThenGradientAndThresholdsAreTheFullPasses) {
  // Given the real colour sample images, whole and cropped (odd and one-row heights), with the
  // pre-blur decided by the image (default), always (denoise_median 1) and never (0)
  const auto images = real_colours();
  ASSERT_GE(images.size(), 10u) << "expected the OpenCV sample images in " << SB_SHARED_DATA_DIR;
  std::array<cv::Mat, 3> planes;
  int compared = 0, denoised = 0;
  for (const auto& bgr : images)
    for (const cv::Rect& box : {cv::Rect(cv::Point(0, 0), bgr.size()), cv::Rect(3, 5, 37, 21),
                                cv::Rect(0, 1, bgr.cols, 1)})
      for (const double denoise_median : {EdgeParams{}.denoise_median, 1.0, 0.0}) {
        EdgeParams params;
        params.denoise_median = denoise_median;
        // When the thresholds are measured (the rows they sample first, the rest after)
        EdgeMap work;
        const EdgeThresholds t = measure_edge_thresholds(bgr(box), params, work);
        // Then the decision is the full unblurred gradient's, and the gradient kept and the
        // thresholds are those of the whole image that gradient comes from
        cv::Mat dx, dy;
        strongest_channel_gradient(bgr(box), dx, dy, planes);
        const CannyThresholds unblurred = canny_thresholds(dx, dy, params);
        ASSERT_EQ(t.denoise, denoise_median > 0.0 && unblurred.median_gradient > denoise_median);
        if (t.denoise) strongest_channel_gradient(work.colour, dx, dy, planes);
        const CannyThresholds full = canny_thresholds(dx, dy, params);
        ASSERT_EQ(cv::countNonZero(work.dx != dx), 0) << box;
        ASSERT_EQ(cv::countNonZero(work.dy != dy), 0) << box;
        EXPECT_EQ(t.canny.high, full.high);
        EXPECT_EQ(t.canny.low, full.low);
        EXPECT_EQ(t.canny.median_gradient, full.median_gradient);
        ++compared;
        denoised += t.denoise;
      }
  EXPECT_GE(compared, 90);
  EXPECT_GT(denoised, 0);
  EXPECT_LT(denoised, compared);
}

TEST(MeasureEdgeThresholds, GivenAPreBlurLevelAtTheMedianThenTheDecisionIsTheFullPasses) {
  // Given the real colour images with the pre-blur level at their unblurred median, just below
  // it and a grey level below it (the decision is taken on part of the rows where they settle
  // it)
  const auto images = real_colours();
  ASSERT_GE(images.size(), 10u) << "expected the OpenCV sample images in " << SB_SHARED_DATA_DIR;
  std::array<cv::Mat, 3> planes;
  int denoised = 0, kept = 0;
  for (const auto& bgr : images) {
    cv::Mat dx, dy;
    strongest_channel_gradient(bgr, dx, dy, planes);
    const double median = canny_thresholds(dx, dy, EdgeParams{}).median_gradient;
    for (const double level : {median, median - 0.5, median - 4.0}) {
      if (level <= 0.0) continue;
      EdgeParams params;
      params.denoise_median = level;
      // When the thresholds are measured
      EdgeMap work;
      const EdgeThresholds t = measure_edge_thresholds(bgr, params, work);
      // Then the image is blurred exactly when its median exceeds the level, and the thresholds
      // are those of the gradient kept
      ASSERT_EQ(t.denoise, median > level) << level;
      const CannyThresholds full = canny_thresholds(work.dx, work.dy, params);
      EXPECT_EQ(t.canny.high, full.high);
      EXPECT_EQ(t.canny.median_gradient, full.median_gradient);
      cv::Mat ref_dx, ref_dy;
      strongest_channel_gradient(t.denoise ? work.colour : bgr, ref_dx, ref_dy, planes);
      ASSERT_EQ(cv::countNonZero(work.dx != ref_dx), 0);
      ASSERT_EQ(cv::countNonZero(work.dy != ref_dy), 0);
      (t.denoise ? denoised : kept) += 1;
    }
  }
  EXPECT_GT(denoised, 10);
  EXPECT_GT(kept, 5);
}

// Both thinning passes on one binary image: the packed one must leave the same pixels, and
// its packed copy must match them.
void expect_same_thinning(const cv::Mat& binary) {
  cv::Mat reference = binary.clone(), ours = binary.clone();
  BitImage bits;
  bits.assign(ours);
  const int removed_reference = thin_staircase(reference);
  const int removed = thin_staircase(ours, bits);
  EXPECT_EQ(removed, removed_reference);
  ASSERT_EQ(cv::countNonZero(ours != reference), 0) << binary.size();
  BitImage repacked;
  repacked.assign(reference);
  for (int y = 0; y < binary.rows; ++y)
    for (int x = 0; x < binary.cols; ++x)
      ASSERT_EQ(bits.test(x, y), repacked.test(x, y)) << x << "," << y;
}

TEST(ThinStaircase, GivenRealEdgeMapsThenThePackedPassRemovesTheSamePixels) {
  // Given Canny edge maps of the real images, thick at corners and junctions
  const auto images = real_greys();
  ASSERT_GE(images.size(), 10u) << "expected the OpenCV sample images in " << SB_SHARED_DATA_DIR;
  CannyWorkspace work;
  for (const auto& grey : images) {
    cv::Mat dx, dy, edges;
    sobel(grey, dx, dy);
    canny_l1(dx, dy, 24.0, 60.0, edges, work);
    // When both passes thin it, then they agree pixel for pixel
    expect_same_thinning(edges);
  }
}

TEST(ThinStaircase, GivenRandomBinaryImagesOfAnyWidthThenThePackedPassRemovesTheSamePixels) {
  std::mt19937 rng(21);
  // Given dense random pixels (every neighbour code occurs), widths around word boundaries
  for (const cv::Size size : {cv::Size(3, 3), cv::Size(63, 9), cv::Size(64, 7), cv::Size(65, 12),
                              cv::Size(129, 40), cv::Size(640, 30)}) {
    for (const int percent : {20, 45, 70}) {
      cv::Mat binary(size, CV_8UC1);
      for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x)
          binary.at<uchar>(y, x) = static_cast<int>(rng() % 100) < percent ? 255 : 0;
      // When both passes thin it, then they agree pixel for pixel
      expect_same_thinning(binary);
    }
  }
}

TEST(BoxFilter, GivenRandomVotesAndEveryOddSizeThenSumsEqualCvBoxFilter) {
  std::mt19937 rng(3);
  for (const int size : {1, 3, 5, 7, 9, 11, 31}) {
    for (const cv::Size image : {cv::Size(640, 480), cv::Size(37, 5), cv::Size(3, 40)}) {
      // Given an accumulator with random counts, a few saturated
      cv::Mat acc(image, CV_16UC1);
      cv::randu(acc, 0, 300);
      acc.at<std::uint16_t>(0, 0) = 0xFFFF;
      // When both smooth it
      cv::Mat ours = box_filter(acc, size), reference;
      cv::boxFilter(acc, reference, CV_32S, cv::Size(size, size), cv::Point(-1, -1), false,
                    cv::BORDER_CONSTANT);
      // Then every cell agrees (zero outside the image)
      ASSERT_EQ(cv::countNonZero(ours != reference), 0) << "size " << size << " " << image;
    }
  }
}

TEST(BoxFilter, GivenAnyVotesThenTheReturnedMaximumIsTheSmoothedMapsMaximum) {
  std::mt19937 rng(5);
  cv::Mat smoothed;
  for (int trial = 0; trial < 12; ++trial) {
    // Given accumulators from empty to dense, the strongest cell anywhere (borders included)
    cv::Mat acc = cv::Mat::zeros(60 + trial, 80 + 5 * trial, CV_16UC1);
    if (trial > 0) cv::randu(acc, 0, trial * 40);
    if (trial % 3 == 1) acc.at<std::uint16_t>(acc.rows - 1, acc.cols - 1) = 60000;
    // When it is smoothed
    const int maximum = box_filter(acc, 1 + 2 * (trial % 4), smoothed);
    // Then the value returned is the map's maximum
    double reference = 0.0;
    cv::minMaxLoc(smoothed, nullptr, &reference);
    EXPECT_EQ(maximum, static_cast<int>(reference)) << "trial " << trial;
  }
}

// halve_image against cv::resize(INTER_AREA) on one even-sized image; image may be a crop.
void expect_halved_like_resize(const cv::Mat& image, const std::string& what) {
  cv::Mat half, reference;
  halve_image(image, half);
  cv::resize(image, reference, cv::Size(image.cols / 2, image.rows / 2), 0, 0, cv::INTER_AREA);
  ASSERT_EQ(half.size(), reference.size()) << what;
  ASSERT_EQ(half.type(), reference.type()) << what;
  ASSERT_EQ(cv::norm(half, reference, cv::NORM_INF), 0.0) << what;
}

TEST(HalveImage, GivenRealColourAndGreyImagesWholeAndCroppedThenItEqualsInterAreaResize) {
  // Given the real sample images in colour and grey, whole (even part) and cropped
  const auto colours = real_colours();
  const auto greys = real_greys();
  ASSERT_GE(colours.size(), 10u);
  std::mt19937 rng(53);
  for (const auto* set : {&colours, &greys})
    for (const cv::Mat& image : *set) {
      // When halved, then the bits are cv::resize's
      expect_halved_like_resize(image(cv::Rect(0, 0, image.cols & ~1, image.rows & ~1)), "whole");
      const int x = static_cast<int>(rng() % 40), y = static_cast<int>(rng() % 40);
      const int w = std::min(image.cols - x, 2 + 2 * static_cast<int>(rng() % 150)) & ~1;
      const int h = std::min(image.rows - y, 2 + 2 * static_cast<int>(rng() % 100)) & ~1;
      if (w >= 2 && h >= 2) expect_halved_like_resize(image(cv::Rect(x, y, w, h)), "crop");
    }
}

TEST(HalveImage, GivenRandomImagesOfEveryEvenWidthThenItEqualsInterAreaResize) {
  // Every even width up to 130 (each remainder of the 24- and 32-byte steps), one to four
  // channels (four: the resize path), values up to 255 (the rounding's carries)
  for (const int type : {CV_8UC1, CV_8UC3, CV_8UC4})
    for (int width = 2; width <= 130; width += 2) {
      cv::Mat image(6, width, type);
      cv::randu(image, 0, 256);
      expect_halved_like_resize(image, "width " + std::to_string(width));
    }
}

// The plain test channels_equal's vector path must agree with.
bool channels_equal_reference(const cv::Mat& bgr) {
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      if (p[0] != p[1] || p[0] != p[2]) return false;
    }
  return true;
}

TEST(ChannelsEqual, GivenGreyRowsWithOneChannelChangedAnywhereThenItAgreesWithAPlainTest) {
  std::mt19937 rng(59);
  for (int width = 1; width <= 100; ++width) {
    // Given a grey image read as colour (every row of a width, so each remainder of the 32-byte
    // steps and each phase of the pixels in them occurs), whole and as a crop
    cv::Mat grey(3, width + 2, CV_8UC1);
    cv::randu(grey, 0, 256);
    cv::Mat bgr;
    cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
    const cv::Mat crop = bgr(cv::Rect(1, 0, width, 3));
    ASSERT_TRUE(channels_equal(crop)) << "width " << width;
    ASSERT_TRUE(channels_equal(bgr)) << "width " << width;
    // When one channel of one pixel differs, at every pixel and channel of the crop's middle row
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) {
        cv::Mat changed = bgr.clone();
        cv::Vec3b& p = changed.at<cv::Vec3b>(1, x + 1);
        p[c] = static_cast<std::uint8_t>(p[c] ^ (1u << (rng() % 8)));
        const cv::Mat changed_crop = changed(cv::Rect(1, 0, width, 3));
        // Then the images are told apart as the plain test tells them
        ASSERT_EQ(channels_equal(changed_crop), channels_equal_reference(changed_crop))
            << "width " << width << " x " << x << " c " << c;
        ASSERT_FALSE(channels_equal(changed_crop));
      }
  }
}

}  // namespace
}  // namespace stereoball::ball_detector
