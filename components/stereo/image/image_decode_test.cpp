// Bounded JPEG/PNG decoding: header sizes read without decoding, truncated or corrupt streams
// refused, decoded pixels equal to OpenCV's own decoder.

#include "stereo/image/image_decode.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <vector>

#include "crafted_images.hpp"

namespace stereoball::stereo {
namespace {

cv::Mat test_image(int w, int h) {
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(40, 90, 160));
  cv::circle(img, {w / 2, h / 2}, h / 4, cv::Scalar(20, 30, 230), cv::FILLED);
  cv::rectangle(img, {5, 5}, {w / 3, h / 3}, cv::Scalar(200, 200, 10), cv::FILLED);
  return img;
}

std::vector<std::uint8_t> encode(const cv::Mat& img, const char* ext) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(ext, img, bytes));
  return bytes;
}

TEST(ImageDecode, GivenJpegAndPngWhenDecodedThenPixelsEqualOpenCvsDecoder) {
  const cv::Mat img = test_image(96, 64);
  for (const char* ext : {".jpg", ".png"}) {
    const auto bytes = encode(img, ext);
    const auto header = read_image_header(bytes);
    ASSERT_TRUE(header) << header.error();
    EXPECT_EQ(header->width_px, 96);
    EXPECT_EQ(header->height_px, 64);
    cv::Mat out;
    ASSERT_TRUE(decode_bgr(bytes, *header, out).ok()) << ext;
    const cv::Mat reference = cv::imdecode(bytes, cv::IMREAD_COLOR);
    ASSERT_EQ(out.size(), reference.size());
    EXPECT_EQ(cv::norm(out, reference, cv::NORM_INF), 0.0) << ext;
  }
}

TEST(ImageDecode, GivenAJpegWhenDecodedReducedThenItIsTheFullDecodeShrunkWithinAFewLevels) {
  // Given a JPEG of a 96x64 image with sharp colour edges
  const auto bytes = encode(test_image(96, 64), ".jpg");
  const auto header = read_image_header(bytes);
  ASSERT_TRUE(header);
  cv::Mat full, shrunk;
  ASSERT_TRUE(decode_bgr(bytes, *header, full).ok());
  cv::resize(full, shrunk, cv::Size(48, 32), 0, 0, cv::INTER_AREA);
  for (const int reduction : {2, 4}) {
    // When decoded reduced by 2 and by 4
    ASSERT_TRUE(decodes_reduced(*header, reduction));
    cv::Mat out;
    ASSERT_TRUE(decode_bgr_reduced(bytes, *header, reduction, out).ok()) << reduction;
    // Then the image has that size, and at 2 it is the full decode's block means within a few
    // grey levels on average (the blocks' low frequencies transformed back)
    EXPECT_EQ(out.size(), cv::Size(96 / reduction, 64 / reduction));
    EXPECT_EQ(out.type(), CV_8UC3);
    if (reduction == 2) {
      EXPECT_LT(cv::norm(out, shrunk, cv::NORM_L1) / double(out.total() * 3), 3.0);
    }
  }
}

TEST(ImageDecode, GivenAPngOrASizeTheFactorDoesNotDivideThenNotDecodedReduced) {
  // Given a PNG, and a JPEG 90 px wide
  const auto png = encode(test_image(96, 64), ".png");
  const auto jpeg = encode(test_image(90, 64), ".jpg");
  const auto png_header = read_image_header(png), jpeg_header = read_image_header(jpeg);
  ASSERT_TRUE(png_header && jpeg_header);
  // When asked to decode them reduced (by 4; by 3, no JPEG scale)
  cv::Mat out;
  // Then it refuses, saying why, and leaves no image
  EXPECT_FALSE(decodes_reduced(*png_header, 2));
  EXPECT_FALSE(decodes_reduced(*jpeg_header, 4));
  EXPECT_FALSE(decodes_reduced(*jpeg_header, 3));
  EXPECT_TRUE(decodes_reduced(*jpeg_header, 2));
  const Status st = decode_bgr_reduced(jpeg, *jpeg_header, 4, out);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("cannot be decoded reduced by 4"), std::string::npos) << st.error();
  EXPECT_TRUE(out.empty());
}

TEST(ImageDecode, GivenAGreyJpegWhenDecodedThenItComesOutAsBgr) {
  cv::Mat grey;
  cv::cvtColor(test_image(48, 32), grey, cv::COLOR_BGR2GRAY);
  const auto bytes = encode(grey, ".jpg");
  const auto header = read_image_header(bytes);
  ASSERT_TRUE(header);
  cv::Mat out;
  ASSERT_TRUE(decode_bgr(bytes, *header, out).ok());
  EXPECT_EQ(out.type(), CV_8UC3);
  EXPECT_EQ(cv::norm(out, cv::imdecode(bytes, cv::IMREAD_COLOR), cv::NORM_INF), 0.0);
}

// The attack of issue 22: a small file whose header claims 20000x20000.
TEST(ImageDecode, GivenHeadersClaimingAHugeImageWhenReadThenTheLimitCheckRefusesThem) {
  auto jpeg = encode(test_image(64, 48), ".jpg");
  ASSERT_TRUE(stereoball::testing::claim_image_size(jpeg, 20000, 20000));
  auto png = encode(test_image(64, 48), ".png");
  ASSERT_TRUE(stereoball::testing::claim_image_size(png, 20000, 20000));
  for (const auto* bytes : {&jpeg, &png}) {
    const auto header = read_image_header(*bytes);
    ASSERT_TRUE(header) << header.error();
    EXPECT_EQ(header->width_px, 20000);
    const auto refused = check_within(*header, {640, 480});
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().find("header says 20000x20000, larger than the limit 640x480"),
              std::string::npos)
        << refused.error();
  }
  EXPECT_TRUE(check_within(ImageHeader{ImageCodec::kPng, 640, 480}, {640, 480}).ok());
}

TEST(ImageDecode, GivenATruncatedJpegWhenDecodedThenItIsAnErrorNotAnImage) {
  const auto full = encode(test_image(160, 120), ".jpg");
  for (const double keep : {0.5, 0.9, 0.99}) {
    const std::vector<std::uint8_t> cut(full.begin(),
                                        full.begin() + static_cast<long>(full.size() * keep));
    const auto header = read_image_header(cut);
    ASSERT_TRUE(header) << header.error();
    cv::Mat out;
    const auto error = decode_bgr(cut, *header, out);
    ASSERT_FALSE(error.ok()) << "kept " << keep;
    EXPECT_NE(error.error().find("Premature end of JPEG file"), std::string::npos) << error.error();
    EXPECT_TRUE(out.empty());
  }
}

TEST(ImageDecode, GivenATruncatedPngWhenDecodedThenItIsAnError) {
  const auto full = encode(test_image(160, 120), ".png");
  for (const std::size_t drop : {std::size_t{1}, std::size_t{12}, full.size() / 2}) {
    const std::vector<std::uint8_t> cut(full.begin(), full.end() - static_cast<long>(drop));
    const auto header = read_image_header(cut);
    ASSERT_TRUE(header) << header.error();
    cv::Mat out;
    const auto error = decode_bgr(cut, *header, out);
    ASSERT_FALSE(error.ok()) << "dropped " << drop;
    EXPECT_NE(error.error().find("png data"), std::string::npos) << error.error();
  }
}

TEST(ImageDecode, GivenACorruptMarkerInAJpegWhenDecodedThenItIsAnError) {
  auto jpeg = encode(test_image(160, 120), ".jpg");
  // Overwrite the bytes just before the end-of-image marker with a bogus marker sequence.
  jpeg[jpeg.size() - 4] = 0xFF;
  jpeg[jpeg.size() - 3] = 0xD0;
  const auto header = read_image_header(jpeg);
  ASSERT_TRUE(header);
  cv::Mat out;
  EXPECT_FALSE(decode_bgr(jpeg, *header, out).ok());
}

TEST(ImageDecode, GivenNonImagesWhenTheHeaderIsReadThenTheErrorSaysSo) {
  const std::vector<std::uint8_t> text = {'h', 'e', 'l', 'l', 'o'};
  const auto not_image = read_image_header(text);
  ASSERT_FALSE(not_image);
  EXPECT_NE(not_image.error().find("not a jpeg or png image"), std::string::npos);
  const std::vector<std::uint8_t> soi_only = {0xFF, 0xD8, 0xFF};
  const auto bad_jpeg = read_image_header(soi_only);
  ASSERT_FALSE(bad_jpeg);
  EXPECT_NE(bad_jpeg.error().find("jpeg header is corrupt"), std::string::npos) << bad_jpeg.error();
  auto png = encode(test_image(8, 8), ".png");
  png.resize(20);
  const auto short_png = read_image_header(png);
  ASSERT_FALSE(short_png);
  EXPECT_EQ(short_png.error(), "png header is truncated");
}

TEST(ImageDecode, GivenATruncatedOrCorruptJpegWhenDecodedReducedThenItIsAnErrorNotAnImage) {
  // Given a JPEG whose sides 2, 4 and 8 divide, cut short at several points, its end marker
  // lost, or with a stray restart marker before its end
  const auto full = encode(test_image(160, 120), ".jpg");
  std::vector<std::vector<std::uint8_t>> spoiled;
  for (const double keep : {0.5, 0.9, 0.99})
    spoiled.emplace_back(full.begin(), full.begin() + static_cast<long>(full.size() * keep));
  spoiled.emplace_back(full.begin(), full.end() - 2);
  auto marker = full;
  marker[marker.size() - 4] = 0xFF;
  marker[marker.size() - 3] = 0xD0;
  spoiled.push_back(marker);
  for (std::size_t i = 0; i < spoiled.size(); ++i) {
    const auto header = read_image_header(spoiled[i]);
    ASSERT_TRUE(header) << header.error();
    for (const int reduction : {2, 4, 8}) {
      // When decoded reduced into a buffer an earlier image filled
      ASSERT_TRUE(decodes_reduced(*header, reduction));
      cv::Mat out = test_image(20, 15);
      const Status st = decode_bgr_reduced(spoiled[i], *header, reduction, out);
      // Then it is an error naming the corruption, and no image is left
      ASSERT_FALSE(st.ok()) << "case " << i << ", reduction " << reduction;
      EXPECT_EQ(st.error().rfind("jpeg data is corrupt: ", 0), 0u) << st.error();
      if (i < 4) {
        EXPECT_NE(st.error().find("Premature end of JPEG file"), std::string::npos);
      }
      EXPECT_TRUE(out.empty()) << "case " << i << ", reduction " << reduction;
    }
  }
}

}  // namespace
}  // namespace stereoball::stereo
