#include "viewer/bridge/eye_encoder.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstring>

namespace stereoball::viewer {
namespace {

stereoball_msg_EyeImage eye(std::vector<uint8_t>& bytes, uint32_t w, uint32_t h, uint32_t step) {
  stereoball_msg_EyeImage e{};
  e.width_px = w;
  e.height_px = h;
  e.step_bytes = step;
  e.data._buffer = bytes.data();
  e.data._length = static_cast<uint32_t>(bytes.size());
  return e;
}

TEST(EyeEncoder, Bgr8BecomesAJpegOfTheSameImage) {
  // Given a 64x48 BGR image, left half red, right half blue
  cv::Mat img(48, 64, CV_8UC3, cv::Scalar(255, 0, 0));
  img(cv::Rect(0, 0, 32, 48)).setTo(cv::Scalar(0, 0, 255));
  std::vector<uint8_t> bytes(img.data, img.data + img.total() * 3);
  const auto jpeg = EyeEncoder({}).encode(eye(bytes, 64, 48, 64 * 3), "bgr8");
  ASSERT_TRUE(jpeg) << jpeg.error();
  const cv::Mat back = cv::imdecode(jpeg->bytes, cv::IMREAD_COLOR);
  ASSERT_EQ(back.size(), cv::Size(64, 48));
  EXPECT_GT(back.at<cv::Vec3b>(24, 8)[2], 200);   // red on the left
  EXPECT_GT(back.at<cv::Vec3b>(24, 56)[0], 200);  // blue on the right
}

TEST(EyeEncoder, YuyvGivesTheJpegOfTheBgr8EyeOpenCvConvertsItTo) {
  // Given YUYV bytes of random values (every luma and chroma combination counts) in rows
  // padded to 140 bytes, and the BGR image OpenCV's conversion makes of them
  cv::Mat yuyv(48, 70, CV_8UC2);
  cv::randu(yuyv, cv::Scalar::all(0), cv::Scalar::all(256));
  cv::Mat bgr;
  cv::cvtColor(yuyv(cv::Rect(0, 0, 64, 48)), bgr, cv::COLOR_YUV2BGR_YUYV);
  std::vector<uint8_t> packed(yuyv.data, yuyv.data + yuyv.total() * 2);
  std::vector<uint8_t> converted(bgr.data, bgr.data + bgr.total() * 3);
  // When both are encoded
  EyeEncoder encoder({});
  const auto from_yuyv = encoder.encode(eye(packed, 64, 48, 70 * 2), "yuyv");
  const auto from_bgr8 = encoder.encode(eye(converted, 64, 48, 64 * 3), "bgr8");
  // Then the JPEGs are the same bytes: the shared conversion gives OpenCV's pixels exactly
  ASSERT_TRUE(from_yuyv) << from_yuyv.error();
  ASSERT_TRUE(from_bgr8) << from_bgr8.error();
  EXPECT_EQ(from_yuyv->bytes, from_bgr8->bytes);
  EXPECT_EQ(from_yuyv->source_width_px, 64u);
}

TEST(EyeEncoder, WideImagesAreScaledDownToMaxWidth) {
  std::vector<uint8_t> bytes(1280 * 960, 128);
  EyeEncoderParams p;
  p.max_width_px = 640;
  const auto jpeg = EyeEncoder(p).encode(eye(bytes, 1280, 960, 1280), "mono8");
  ASSERT_TRUE(jpeg) << jpeg.error();
  EXPECT_EQ(jpeg->width_px, 640u);
  EXPECT_EQ(jpeg->height_px, 480u);
  // And the size the detections refer to is kept, for drawing them on the smaller image
  EXPECT_EQ(jpeg->source_width_px, 1280u);
  EXPECT_EQ(jpeg->source_height_px, 960u);
}

TEST(EyeEncoder, JpegPassesThroughUnchanged) {
  std::vector<uint8_t> src;
  cv::imencode(".jpg", cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3)), src);
  const auto jpeg = EyeEncoder({}).encode(eye(src, 8, 8, 0), "jpeg");
  ASSERT_TRUE(jpeg);
  EXPECT_EQ(jpeg->bytes, src);
}

TEST(EyeEncoder, PreviewEyesPassThroughWithTheirSourceSize) {
  // Given a 320x240 preview JPEG made from a 640x480 eye
  std::vector<uint8_t> src;
  cv::imencode(".jpg", cv::Mat(240, 320, CV_8UC3, cv::Scalar(10, 120, 200)), src);
  // When it is shown by a viewer at most 640 wide, then it is forwarded unchanged
  const auto jpeg = EyeEncoder({}).encode_preview(eye(src, 320, 240, 0), 640, 480);
  ASSERT_TRUE(jpeg) << jpeg.error();
  EXPECT_EQ(jpeg->bytes, src);
  EXPECT_EQ(jpeg->width_px, 320u);
  // And the detections' pixels are the source's
  EXPECT_EQ(jpeg->source_width_px, 640u);
  EXPECT_EQ(jpeg->source_height_px, 480u);
}

TEST(EyeEncoder, PreviewWiderThanMaxWidthIsScaledHere) {
  // Given a 320x240 preview and a viewer that shows at most 160 px
  std::vector<uint8_t> src;
  cv::imencode(".jpg", cv::Mat(240, 320, CV_8UC3, cv::Scalar(10, 120, 200)), src);
  EyeEncoderParams p;
  p.max_width_px = 160;
  // When it is shown, then it is 160x120 and still refers to the 640x480 source
  const auto jpeg = EyeEncoder(p).encode_preview(eye(src, 320, 240, 0), 640, 480);
  ASSERT_TRUE(jpeg) << jpeg.error();
  EXPECT_EQ(cv::imdecode(jpeg->bytes, cv::IMREAD_COLOR).size(), cv::Size(160, 120));
  EXPECT_EQ(jpeg->source_width_px, 640u);
}

TEST(EyeEncoder, BadPreviewsAreNamed) {
  std::vector<uint8_t> src;
  cv::imencode(".jpg", cv::Mat(24, 32, CV_8UC3, cv::Scalar(1, 2, 3)), src);
  // A source size of zero or beyond the input limit
  auto r = EyeEncoder({}).encode_preview(eye(src, 32, 24, 0), 0, 480);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("source size"), std::string::npos) << r.error();
  r = EyeEncoder({}).encode_preview(eye(src, 32, 24, 0), 100000, 480);
  ASSERT_FALSE(r);
  // Bytes that are not a JPEG
  std::vector<uint8_t> junk(64, 0x42);
  r = EyeEncoder({}).encode_preview(eye(junk, 32, 24, 0), 640, 480);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("JPEG marker"), std::string::npos) << r.error();
}

TEST(EyeEncoder, BadInputIsNamed) {
  std::vector<uint8_t> short_data(100);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 64, 48, 192), "bgr8").error().find("truncated"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 64, 48, 10), "bgr8").error().find("step_bytes"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 99999, 1, 99999), "mono8").error().find("4096"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 8, 8, 0), "jpeg").error().find("JPEG marker"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 8, 8, 0), "png").error().find("png"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 8, 8, 8), "rgb16").error().find("rgb16"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 7, 4, 14), "yuyv").error().find("odd"),
            std::string::npos);
  EXPECT_NE(EyeEncoder({}).encode(eye(short_data, 64, 48, 128), "yuyv").error().find("truncated"),
            std::string::npos);
}

TEST(EyeEncoder, PngIsDecodedOnlyWhenItsHeaderIsWithinTheLimit) {
  // Given an encoder that accepts eyes up to 64x64 and a 100x40 PNG
  EyeEncoderParams p;
  p.max_input_width_px = p.max_input_height_px = 64;
  EyeEncoder encoder(p);
  std::vector<uint8_t> png;
  cv::imencode(".png", cv::Mat(40, 100, CV_8UC3, cv::Scalar(0, 128, 255)), png);
  // When it is encoded, then its header refuses it, naming the size and the limit
  const auto wide = encoder.encode(eye(png, 100, 40, 0), "png");
  ASSERT_FALSE(wide);
  EXPECT_NE(wide.error().find("100x40, larger than the limit 64x64"), std::string::npos)
      << wide.error();
  // And a 48x32 PNG within the limit is shown, at its own size whatever the sample claims
  std::vector<uint8_t> small;
  cv::imencode(".png", cv::Mat(32, 48, CV_8UC3, cv::Scalar(0, 128, 255)), small);
  const auto ok = encoder.encode(eye(small, 9999, 9999, 0), "png");
  ASSERT_TRUE(ok) << ok.error();
  EXPECT_EQ(ok->width_px, 48u);
  EXPECT_EQ(ok->height_px, 32u);
}

TEST(EyeEncoder, ForgedPngHeaderIsRefusedBeforeDecoding) {
  // Given a PNG whose IHDR claims 60000x60000 pixels (10 GB of BGR) in a few bytes
  std::vector<uint8_t> png;
  cv::imencode(".png", cv::Mat(4, 4, CV_8UC3, cv::Scalar::all(7)), png);
  const uint8_t huge[8] = {0, 0, 0xEA, 0x60, 0, 0, 0xEA, 0x60};  // IHDR width, height (BE)
  std::memcpy(png.data() + 16, huge, sizeof huge);
  // When it is encoded, then it is refused from the header, nothing allocated
  const auto r = EyeEncoder({}).encode(eye(png, 4, 4, 0), "png");
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("60000x60000"), std::string::npos) << r.error();
  // And JPEG data sent as png, or a truncated PNG, are named too
  std::vector<uint8_t> jpeg;
  cv::imencode(".jpg", cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3)), jpeg);
  EXPECT_NE(EyeEncoder({}).encode(eye(jpeg, 8, 8, 0), "png").error().find("jpeg data in a png"),
            std::string::npos);
  cv::imencode(".png", cv::Mat(16, 16, CV_8UC3, cv::Scalar::all(9)), png);
  png.resize(png.size() / 2);
  EXPECT_FALSE(EyeEncoder({}).encode(eye(png, 16, 16, 0), "png"));
}

TEST(EyeEncoder, PassedThroughJpegIsCheckedAgainstTheLimitToo) {
  EyeEncoderParams p;
  p.max_input_width_px = p.max_input_height_px = 64;
  std::vector<uint8_t> jpeg;
  cv::imencode(".jpg", cv::Mat(80, 120, CV_8UC3, cv::Scalar(1, 2, 3)), jpeg);
  const auto r = EyeEncoder(p).encode(eye(jpeg, 120, 80, 0), "jpeg");
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("120x80"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace stereoball::viewer
