// remap_bilinear against cv::remap, bit for bit.

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <random>
#include <string>

#include "stereo/core/bilinear_remap.hpp"

namespace stereoball::stereo {
namespace {

cv::Mat opencv_remap(const cv::Mat& src, const cv::Mat& xy, const cv::Mat& frac) {
  cv::Mat out;
  cv::remap(src, out, xy, frac, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  return out;
}

constexpr RemapPath kPaths[] = {RemapPath::kPlain, RemapPath::kSsse3, RemapPath::kAvx2};

int differing(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return -1;
  return cv::countNonZero(a.reshape(1) != b.reshape(1));
}

// Fixed-point maps of random source positions from margin pixels outside src to margin
// beyond it (a negative margin keeps them that far inside), every fraction index among them.
void random_maps(cv::Size src, cv::Size dst, float margin, std::mt19937& rng, cv::Mat& xy,
                 cv::Mat& frac) {
  std::uniform_real_distribution<float> ux(-margin, src.width + margin);
  std::uniform_real_distribution<float> uy(-margin, src.height + margin);
  cv::Mat mx(dst, CV_32F), my(dst, CV_32F);
  for (int y = 0; y < dst.height; ++y)
    for (int x = 0; x < dst.width; ++x) {
      mx.at<float>(y, x) = ux(rng);
      my.at<float>(y, x) = uy(rng);
    }
  cv::convertMaps(mx, my, xy, frac, CV_16SC2);
}

TEST(RemapBilinear, GivenRandomColourImagesAndMapsInAndAroundThemThenItEqualsCvRemap) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 60; ++trial) {
    // Given a random BGR image (tiny ones too) and source positions in, on and around it
    const cv::Size src_size(1 + trial * 5 % 97, 1 + trial * 3 % 71);
    cv::Mat src(src_size, CV_8UC3);
    cv::randu(src, 0, 256);
    cv::Mat xy, frac;
    random_maps(src_size, cv::Size(40 + trial, 30 + trial), 3.0f, rng, xy, frac);
    // When both remap it (ours by each of its paths the CPU has)
    const cv::Mat expected = opencv_remap(src, xy, frac);
    for (const RemapPath path : kPaths) {
      cv::Mat ours;
      remap_bilinear(src, ours, xy, frac, path);
      // Then every byte agrees
      ASSERT_EQ(differing(ours, expected), 0)
          << "trial " << trial << " path " << static_cast<int>(path);
    }
  }
}

TEST(RemapBilinear, GivenEveryFractionOnFullPixelsThenItEqualsCvRemap) {
  // Given a saturated and a random image and a map holding every fraction index at every
  // position class (inside, last columns, last row)
  for (const bool saturated : {true, false}) {
    cv::Mat src(8, 9, CV_8UC3);
    if (saturated)
      src.setTo(cv::Scalar::all(255));
    else
      cv::randu(src, 0, 256);
    cv::Mat xy(32, 32 * 9 * 8, CV_16SC2), frac(xy.size(), CV_16UC1);
    for (int y = 0; y < xy.rows; ++y)
      for (int x = 0; x < xy.cols; ++x) {
        const int position = x / 32;
        xy.at<cv::Vec2s>(y, x) =
            cv::Vec2s(static_cast<short>(position % 9), static_cast<short>(position / 9));
        frac.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(y * 32 + x % 32);
      }
    // When both remap it (ours by each of its paths the CPU has)
    for (const RemapPath path : kPaths) {
      cv::Mat ours;
      remap_bilinear(src, ours, xy, frac, path);
      // Then every byte agrees
      EXPECT_EQ(differing(ours, opencv_remap(src, xy, frac)), 0)
          << "saturated " << saturated << " path " << static_cast<int>(path);
    }
  }
}

TEST(RemapBilinear, GivenARegionOfALargerImageAsOutputThenOnlyItIsWrittenAsCvRemapWouldWriteIt) {
  // Given a lens-distortion map (as the rectifier builds it) and a raw frame that is itself a
  // view into a larger buffer
  std::mt19937 rng(7);
  const cv::Size size(160, 120);
  const cv::Matx33d k(150, 0, 80, 0, 150, 60, 0, 0, 1);
  const cv::Matx33d p(140, 0, 82, 0, 140, 58, 0, 0, 1);
  cv::Mat xy, frac;
  cv::initUndistortRectifyMap(k, cv::Vec<double, 5>(-0.2, 0.05, 0.001, -0.002, 0.0),
                              cv::Matx33d::eye(), p, size, CV_16SC2, xy, frac);
  cv::Mat parent(size.height + 10, size.width + 20, CV_8UC3);
  cv::randu(parent, 0, 256);
  const cv::Mat raw = parent(cv::Rect(cv::Point(7, 3), size));
  // When a region of the output is remapped into a view of an image already holding pixels
  const cv::Rect roi(13, 21, 101, 57);
  cv::Mat out(size, CV_8UC3, cv::Scalar(1, 2, 3));
  cv::Mat target = out(roi);
  remap_bilinear(raw, target, xy(roi), frac(roi));
  // Then the region equals cv::remap's, and the pixels around it are untouched
  cv::Mat whole;
  remap_bilinear(raw, whole, xy, frac);
  EXPECT_EQ(differing(whole, opencv_remap(raw, xy, frac)), 0);
  for (const RemapPath path : kPaths) {
    cv::Mat by_path;
    remap_bilinear(raw, by_path, xy, frac, path);
    EXPECT_EQ(differing(by_path, whole), 0) << "path " << static_cast<int>(path);
  }
  EXPECT_EQ(differing(out(roi), whole(roi)), 0);
  cv::Mat outside = out.clone();
  outside(roi).setTo(cv::Scalar(1, 2, 3));
  EXPECT_EQ(differing(outside, cv::Mat(size, CV_8UC3, cv::Scalar(1, 2, 3))), 0);
}

// Every path's output and cv::remap's differ nowhere (else the first path that differs fails).
void expect_every_path_equals_cv_remap(const cv::Mat& src, const cv::Mat& xy, const cv::Mat& frac,
                                       const std::string& what) {
  const cv::Mat expected = opencv_remap(src, xy, frac);
  cv::Mat plain;
  remap_bilinear(src, plain, xy, frac, RemapPath::kPlain);
  for (const RemapPath path : kPaths) {
    cv::Mat ours;
    remap_bilinear(src, ours, xy, frac, path);
    EXPECT_EQ(differing(ours, expected), 0) << what << " path " << static_cast<int>(path);
    EXPECT_EQ(differing(ours, plain), 0) << what << " path " << static_cast<int>(path);
  }
}

TEST(RemapBilinear, GivenOddWidthsWithBorderAndLastColumnPixelsThenEveryPathEqualsCvRemap) {
  std::mt19937 rng(11);
  const cv::Size src_size(37, 23);
  cv::Mat src(src_size, CV_8UC3);
  cv::randu(src, 0, 256);
  for (const int width : {1, 2, 3, 5, 9, 10, 11, 17, 33}) {
    // Given maps of odd widths mostly inside the image (so the eight-pixel blocks run), with
    // positions on the last column and row and outside it sprinkled in
    cv::Mat xy, frac;
    random_maps(src_size, cv::Size(width, 19), -2.0f, rng, xy, frac);
    std::uniform_int_distribution<int> column(0, width - 1), row(0, 18), kind(0, 3);
    for (int k = 0; k < width; ++k) {
      const int sx[] = {src_size.width - 1, src_size.width - 2, -1, src_size.width + 1};
      const int sy[] = {src_size.height - 1, 3, src_size.height - 2, -1};
      const int c = column(rng), r = row(rng), which = kind(rng);
      xy.at<cv::Vec2s>(r, c) =
          cv::Vec2s(static_cast<short>(sx[which]), static_cast<short>(sy[which]));
    }
    // When every path remaps it, then each equals cv::remap and the plain loop
    expect_every_path_equals_cv_remap(src, xy, frac, "width " + std::to_string(width));
  }
}

TEST(RemapBilinear, GivenRowsTooWideForTheBlockOffsetsThenEveryPathEqualsCvRemap) {
  // Given a source whose rows hold more than 32767 bytes (the AVX2 blocks' offset limit)
  std::mt19937 rng(13);
  cv::Mat src(3, 11000, CV_8UC3);
  cv::randu(src, 0, 256);
  cv::Mat xy, frac;
  random_maps(src.size(), cv::Size(64, 3), 1.0f, rng, xy, frac);
  // When every path remaps it, then each equals cv::remap and the plain loop
  expect_every_path_equals_cv_remap(src, xy, frac, "wide rows");
}

TEST(RemapBilinear, GivenGreyImagesOrTheSourceAsOutputThenItStillEqualsCvRemap) {
  std::mt19937 rng(9);
  cv::Mat xy, frac;
  random_maps(cv::Size(50, 40), cv::Size(50, 40), 2.0f, rng, xy, frac);
  // Given a grey image (cv::remap's own path)
  cv::Mat grey(40, 50, CV_8UC1);
  cv::randu(grey, 0, 256);
  cv::Mat ours;
  remap_bilinear(grey, ours, xy, frac);
  EXPECT_EQ(differing(ours, opencv_remap(grey, xy, frac)), 0);
  // Given a colour image remapped onto itself
  cv::Mat colour(40, 50, CV_8UC3);
  cv::randu(colour, 0, 256);
  const cv::Mat expected = opencv_remap(colour, xy, frac);
  remap_bilinear(colour, colour, xy, frac);
  EXPECT_EQ(differing(colour, expected), 0);
}

}  // namespace
}  // namespace stereoball::stereo
