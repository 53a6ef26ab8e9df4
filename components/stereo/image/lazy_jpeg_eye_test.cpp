// A JPEG eye decoded row by row on demand: the rows made are the whole decode's, rows below the
// lowest one asked for are never decoded, and corrupt data met late is an error naming the eye.

#include "stereo/image/lazy_jpeg_eye.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <atomic>
#include <vector>

namespace stereoball::stereo {
namespace {

// A 320x240 frame with texture everywhere (every MCU row holds detail), JPEG 4:2:0 as OpenCV
// writes it.
std::vector<std::uint8_t> textured_jpeg() {
  cv::Mat img(240, 320, CV_8UC3);
  cv::randu(img, 0, 256);
  cv::GaussianBlur(img, img, cv::Size(5, 5), 1.5);
  cv::circle(img, {160, 150}, 60, cv::Scalar(20, 90, 230), cv::FILLED);
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(".jpg", img, bytes, {cv::IMWRITE_JPEG_QUALITY, 90}));
  return bytes;
}

cv::Mat whole_decode(const std::vector<std::uint8_t>& bytes, int reduction) {
  const auto header = read_image_header(bytes);
  cv::Mat out;
  const Status st = reduction == 1 ? decode_bgr(bytes, *header, out)
                                   : decode_bgr_reduced(bytes, *header, reduction, out);
  EXPECT_TRUE(st.ok()) << st.error();
  return out;
}

TEST(LazyJpegEye, GivenRowsAskedForInAnyOrderThenTheyAreTheWholeDecodesAndNoRowBelowIsMade) {
  const auto bytes = textured_jpeg();
  const auto header = read_image_header(bytes);
  ASSERT_TRUE(header);
  // The searches' patterns: one box; a box then one above it (decoded again from the top); two
  // boxes with rows between; everything; a box, one above, one below.
  const std::vector<std::vector<cv::Range>> orders = {{{100, 140}},
                                                      {{100, 140}, {60, 80}},
                                                      {{30, 45}, {170, 200}},
                                                      {{0, 240}},
                                                      {{130, 150}, {10, 20}, {200, 240}, {0, 5}}};
  LazyJpegEye eye;
  for (const int reduction : {1, 2}) {
    const cv::Mat whole = whole_decode(bytes, reduction);
    for (const auto& order : orders) {
      // Given a JPEG eye started lazily (at full size and halved)
      ASSERT_TRUE(eye.start("right", bytes, *header, reduction).ok());
      EXPECT_EQ(eye.image().size(), whole.size());
      EXPECT_EQ(eye.rows_made(), 0);
      int lowest = 0, asked_rows = 0;
      for (const cv::Range& asked : order) {
        // When the rows of each box are asked for in turn
        const cv::Range rows(asked.start / reduction, asked.end / reduction);
        eye.make_rows(rows.start, rows.end);
        lowest = std::max(lowest, rows.end);
        // Then they hold the whole decode's pixels, bit for bit
        ASSERT_TRUE(eye.status().ok()) << eye.status().error();
        EXPECT_EQ(cv::norm(eye.image().rowRange(rows), whole.rowRange(rows), cv::NORM_INF), 0.0)
            << "reduction " << reduction << ", rows " << rows.start << ".." << rows.end;
        for (int r = rows.start; r < rows.end; ++r) ASSERT_TRUE(eye.row_made(r)) << r;
        asked_rows += rows.size();
      }
      // and no other row was decoded: not those between them, nor any below the lowest
      EXPECT_LE(eye.rows_made(), asked_rows);
      EXPECT_FALSE(eye.row_made(lowest));
    }
  }
}

TEST(LazyJpegEye, GivenAnotherCoreDecodingAheadThenItStopsWhenToldAndRowsStayExact) {
  const auto bytes = textured_jpeg();
  const auto header = read_image_header(bytes);
  ASSERT_TRUE(header);
  const cv::Mat whole = whole_decode(bytes, 2);
  LazyJpegEye eye;
  // Given the other eye done already: nothing is decoded ahead
  std::atomic<bool> stop{true};
  ASSERT_TRUE(eye.start("right", bytes, *header, 2).ok());
  ASSERT_TRUE(eye.decode_ahead(stop).ok());
  EXPECT_EQ(eye.rows_made(), 0);
  // Given it still decoding: every row is, as a whole decode makes it
  stop = false;
  ASSERT_TRUE(eye.start("right", bytes, *header, 2).ok());
  ASSERT_TRUE(eye.decode_ahead(stop).ok());
  EXPECT_EQ(eye.rows_made(), whole.rows);
  EXPECT_EQ(cv::norm(eye.image(), whole, cv::NORM_INF), 0.0);
}

TEST(LazyJpegEye,
     GivenCorruptDataBelowTheFirstRowsThenTheyDecodeAndTheDamageIsReportedWhenReached) {
  // Given a JPEG with a stray marker in its last rows' data (its end marker intact)
  auto bytes = textured_jpeg();
  bytes[bytes.size() - 4] = 0xFF;
  bytes[bytes.size() - 3] = 0xD0;
  const auto header = read_image_header(bytes);
  ASSERT_TRUE(header);
  LazyJpegEye eye;
  for (const int reduction : {1, 2}) {
    const int rows = 240 / reduction;
    // When started and its upper half made
    ASSERT_TRUE(eye.start("right", bytes, *header, reduction).ok());
    eye.make_rows(0, rows / 2);
    // Then the upper half is made without complaint
    EXPECT_TRUE(eye.status().ok()) << eye.status().error();
    // When a box reads its last rows
    eye.make_rows(rows - 8, rows);
    // Then the damage is an error naming the eye, and the rows not made are zero from now on
    ASSERT_FALSE(eye.status().ok());
    EXPECT_EQ(eye.status().error().rfind("right jpeg data is corrupt: ", 0), 0u)
        << eye.status().error();
    EXPECT_EQ(cv::countNonZero(eye.image().rowRange(rows - 1, rows).reshape(1)), 0);
    eye.make_rows(0, rows);  // more reads change nothing and do not crash
    EXPECT_FALSE(eye.status().ok());
  }
}

TEST(LazyJpegEye, GivenATruncatedJpegThenStartReportsItAtOnceAsAWholeDecodeWould) {
  const auto full = textured_jpeg();
  const std::vector<std::uint8_t> cut(full.begin(), full.begin() + full.size() * 3 / 4);
  const auto header = read_image_header(cut);
  ASSERT_TRUE(header);
  LazyJpegEye eye;
  const Status st = eye.start("right", cut, *header, 2);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("right jpeg data is corrupt: "), std::string::npos) << st.error();
  EXPECT_NE(st.error().find("Premature end of JPEG file"), std::string::npos) << st.error();
}

}  // namespace
}  // namespace stereoball::stereo
