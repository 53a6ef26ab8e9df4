// The shared frame encoder and frame compressor: round trips through
// cv::imdecode (what ball_detector does), sizes, and named errors.

#include "stereo/frame/frame_codec.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>

#include "stereo/frame/frame_compressor.hpp"

// GCC 12 reports a false -Wrestrict on std::string assignment from a literal (GCC PR 105651).
#pragma GCC diagnostic ignored "-Wrestrict"

namespace stereoball::stereo {
namespace {

// A camera-like test image: smooth shading, a few hard-edged discs and mild noise.
cv::Mat scene(int channels, int seed) {
  cv::Mat img(480, 640, CV_8UC3);
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      img.at<cv::Vec3b>(y, x) =
          cv::Vec3b(static_cast<uint8_t>(60 + x / 8), static_cast<uint8_t>(80 + y / 6),
                    static_cast<uint8_t>(120 + (x + y) / 16));
    }
  }
  cv::circle(img, {200 + seed * 10, 240}, 45, {30, 90, 220}, cv::FILLED);
  cv::circle(img, {470, 150}, 20, {240, 240, 240}, cv::FILLED);
  cv::Mat noise(img.size(), CV_8UC3);
  cv::theRNG().state = static_cast<uint64_t>(seed + 1);
  cv::randn(noise, 0, 2);
  img += noise;
  if (channels == 3) return img;
  cv::Mat grey;
  cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

double mean_abs_diff(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  return cv::mean(d)[0];
}

FrameCodecParams codec(const std::string& encoding, int quality = 90,
                       const std::string& chroma = "444") {
  FrameCodecParams p;
  p.frame_encoding = encoding;
  p.jpeg_quality = quality;
  p.jpeg_chroma = chroma;
  return p;
}

TEST(FrameCodecParams, GivenDefaultsThenRawAndValid) {
  const FrameCodecParams p;
  EXPECT_EQ(p.frame_encoding, "raw");
  EXPECT_EQ(p.jpeg_quality, 90);
  EXPECT_EQ(p.jpeg_chroma, "444");
  EXPECT_FALSE(p.compressed());
  EXPECT_TRUE(p.validate()) << p.validate().error();
  EXPECT_TRUE(codec("jpeg").compressed());
  EXPECT_TRUE(codec("png").compressed());
}

TEST(FrameCodecParams, GivenBadValuesThenTheFieldAndRangeAreNamed) {
  const auto bad_encoding = codec("gif").validate();
  ASSERT_FALSE(bad_encoding);
  EXPECT_NE(bad_encoding.error().find("frame_encoding"), std::string::npos) << bad_encoding.error();
  EXPECT_NE(bad_encoding.error().find("'gif'"), std::string::npos) << bad_encoding.error();
  for (int q : {0, 101, -5}) {
    const auto e = codec("jpeg", q).validate();
    ASSERT_FALSE(e) << q;
    EXPECT_NE(
        e.error().find("key 'jpeg_quality': " + std::to_string(q) + " is out of range [1, 100]"),
        std::string::npos)
        << e.error();
  }
  EXPECT_TRUE(codec("jpeg", 1).validate());
  EXPECT_TRUE(codec("jpeg", 100).validate());
  for (const std::string bad : {"411", "4:2:0", ""}) {
    const auto e = codec("jpeg", 90, bad).validate();
    ASSERT_FALSE(e) << bad;
    EXPECT_NE(e.error().find("jpeg_chroma"), std::string::npos) << e.error();
    EXPECT_NE(e.error().find("'" + bad + "'"), std::string::npos) << e.error();
  }
  for (const std::string good : {"444", "422", "420"}) {
    EXPECT_TRUE(codec("jpeg", 90, good).validate()) << good;
  }
}

TEST(EyeEncoder, GivenBgrImageWhenJpegEncodedThenDecodesCloseToItAndMuchSmaller) {
  // Given a 640x480 BGR image and a q90 JPEG encoder
  const cv::Mat img = scene(3, 0);
  EyeEncoder enc(codec("jpeg", 90));
  // When encoded
  ASSERT_TRUE(enc.encode(img).ok());
  // Then the stream decodes to the same size, close to the original, at a fraction of the bytes
  const cv::Mat back = cv::imdecode(enc.bytes(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(back.size(), img.size());
  ASSERT_EQ(back.type(), CV_8UC3);
  EXPECT_LT(mean_abs_diff(back, img), 3.0);
  EXPECT_LT(enc.bytes().size(), img.total() * 3 / 5);
  EXPECT_EQ(enc.bytes()[0], 0xFF);  // JPEG SOI marker
  EXPECT_EQ(enc.bytes()[1], 0xD8);
}

TEST(EyeEncoder, GivenFineColourDetailThenJpegKeepsFullChromaResolution) {
  // Given red and blue stripes 2 px wide (colour detail finer than 4:2:0 chroma keeps)
  cv::Mat img(64, 64, CV_8UC3);
  for (int x = 0; x < img.cols; ++x) {
    img.col(x).setTo((x / 2) % 2 ? cv::Scalar(220, 20, 20) : cv::Scalar(20, 20, 220));
  }
  // When encoded by the publishers' encoder and by OpenCV's imencode (4:2:0), both at q90
  EyeEncoder enc(codec("jpeg", 90));
  ASSERT_TRUE(enc.encode(img).ok());
  std::vector<uint8_t> subsampled;
  ASSERT_TRUE(cv::imencode(".jpg", img, subsampled, {cv::IMWRITE_JPEG_QUALITY, 90}));
  auto red_error = [&](const std::vector<uint8_t>& bytes) {
    cv::Mat back = cv::imdecode(bytes, cv::IMREAD_COLOR), red_back, red;
    cv::extractChannel(back, red_back, 2);
    cv::extractChannel(img, red, 2);
    return mean_abs_diff(red_back, red);
  };
  // Then the red channel (what the ball detector uses) keeps the stripes far better
  const double ours = red_error(enc.bytes()), opencv = red_error(subsampled);
  std::printf("red channel error: 4:4:4 %.2f DN, 4:2:0 %.2f DN\n", ours, opencv);
  EXPECT_LT(ours, 0.25 * opencv);
  EXPECT_LT(ours, 8.0);
}

// Given the camera-like scene, when encoded at q90 with each jpeg_chroma, then every stream
// decodes close to the image (the round trip the detector sees) and halving the colour
// resolution saves bytes: 420 fewer than 422, 422 fewer than 444.
TEST(EyeEncoder, GivenEachChromaWhenJpegEncodedThenCloseToTheImageAndSubsamplingSavesBytes) {
  const cv::Mat img = scene(3, 2);
  std::vector<std::size_t> bytes;
  for (const std::string chroma : {"444", "422", "420"}) {
    EyeEncoder enc(codec("jpeg", 90, chroma));
    ASSERT_TRUE(enc.encode(img).ok()) << chroma;
    const cv::Mat back = cv::imdecode(enc.bytes(), cv::IMREAD_COLOR);
    ASSERT_EQ(back.size(), img.size()) << chroma;
    EXPECT_LT(mean_abs_diff(back, img), 3.0) << chroma;
    EXPECT_LT(cv::norm(back, img, cv::NORM_INF), 80.0) << chroma;
    bytes.push_back(enc.bytes().size());
  }
  EXPECT_LT(bytes[1], bytes[0]);
  EXPECT_LT(bytes[2], bytes[1]);
}

// Red/blue stripes 2 px wide across the image (columns alternate) or down it (rows alternate).
cv::Mat colour_stripes(bool across) {
  cv::Mat img(64, 64, CV_8UC3);
  for (int i = 0; i < img.cols; ++i) {
    (across ? img.col(i) : img.row(i))
        .setTo((i / 2) % 2 ? cv::Scalar(220, 20, 20) : cv::Scalar(20, 20, 220));
  }
  return img;
}

double red_error_after(const cv::Mat& img, const std::string& chroma) {
  EyeEncoder enc(codec("jpeg", 90, chroma));
  EXPECT_TRUE(enc.encode(img).ok()) << chroma;
  cv::Mat back = cv::imdecode(enc.bytes(), cv::IMREAD_COLOR), red_back, red;
  cv::extractChannel(back, red_back, 2);
  cv::extractChannel(img, red, 2);
  return mean_abs_diff(red_back, red);
}

// Given 2 px colour stripes, when encoded with each jpeg_chroma, then the red channel keeps
// them exactly where that chroma keeps full resolution: 444 both ways, 422 only stripes down
// the image (it halves the columns), 420 neither: the setting reaches the encoder as named.
TEST(EyeEncoder, GivenColourStripesThenEachChromaBlursOnlyTheDirectionItHalves) {
  const cv::Mat across = colour_stripes(true), down = colour_stripes(false);
  const double kept = 8.0, blurred = 20.0;
  EXPECT_LT(red_error_after(across, "444"), kept);
  EXPECT_LT(red_error_after(down, "444"), kept);
  EXPECT_GT(red_error_after(across, "422"), blurred);
  EXPECT_LT(red_error_after(down, "422"), kept);
  EXPECT_GT(red_error_after(across, "420"), blurred);
  EXPECT_GT(red_error_after(down, "420"), blurred);
}

// Given a grey image, when encoded with each jpeg_chroma, then the streams are the same bytes:
// grey has no colour to subsample.
TEST(EyeEncoder, GivenAGreyImageThenTheChromaSettingChangesNothing) {
  const cv::Mat grey = scene(1, 3);
  EyeEncoder full(codec("jpeg", 90, "444"));
  ASSERT_TRUE(full.encode(grey).ok());
  for (const std::string chroma : {"422", "420"}) {
    EyeEncoder enc(codec("jpeg", 90, chroma));
    ASSERT_TRUE(enc.encode(grey).ok()) << chroma;
    EXPECT_EQ(enc.bytes(), full.bytes()) << chroma;
  }
}

TEST(EyeEncoder, GivenLowerQualityThenFewerBytesAndLargerError) {
  // Given one image encoded at q95 and q30
  const cv::Mat img = scene(3, 1);
  EyeEncoder high(codec("jpeg", 95)), low(codec("jpeg", 30));
  ASSERT_TRUE(high.encode(img).ok());
  ASSERT_TRUE(low.encode(img).ok());
  // Then the quality setting really reaches the encoder
  EXPECT_LT(low.bytes().size(), high.bytes().size());
  const double err_high = mean_abs_diff(cv::imdecode(high.bytes(), cv::IMREAD_UNCHANGED), img);
  const double err_low = mean_abs_diff(cv::imdecode(low.bytes(), cv::IMREAD_UNCHANGED), img);
  EXPECT_LT(err_high, err_low);
}

TEST(EyeEncoder, GivenPngThenLosslessForGreyAndBgr) {
  for (int channels : {1, 3}) {
    // Given an image and a PNG encoder
    const cv::Mat img = scene(channels, 2);
    EyeEncoder enc(codec("png"));
    // When encoded and decoded
    ASSERT_TRUE(enc.encode(img).ok());
    const cv::Mat back = cv::imdecode(enc.bytes(), cv::IMREAD_UNCHANGED);
    // Then the pixels are exactly the original ones
    ASSERT_EQ(back.type(), img.type()) << channels;
    EXPECT_EQ(cv::norm(back, img, cv::NORM_INF), 0.0) << channels;
  }
}

TEST(EyeEncoder, GivenUnsupportedImagesThenTheProblemIsNamed) {
  EyeEncoder enc(codec("jpeg"));
  const auto empty = enc.encode(cv::Mat());
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().find("empty image"), std::string::npos) << empty.error();
  const auto wide = enc.encode(cv::Mat(10, 10, CV_16UC1, cv::Scalar(3)));
  ASSERT_FALSE(wide.ok());
  EXPECT_NE(wide.error().find("8-bit grey or BGR"), std::string::npos) << wide.error();
}

FrameView decoded_view(const cv::Mat& left, const cv::Mat& right) {
  auto v = view_of_images(left, right, 7, 1'000);
  EXPECT_TRUE(v.ok());
  v->left.capture_stamp_ns = 990;
  v->right.capture_stamp_ns = 1'010;
  return *v;
}

TEST(FrameCompressor, GivenBgrViewWhenCompressedThenBothEyesFollowTheWireContract) {
  // Given a decoded bgr8 frame view with distinct eyes
  const cv::Mat left = scene(3, 3), right = scene(3, 7);
  const FrameView view = decoded_view(left, right);
  FrameCompressor compressor(codec("jpeg"));
  // When compressed
  auto out = compressor.step(view);
  ASSERT_TRUE(out.ok()) << out.error();
  // Then: encoding named once, step 0, decoded size, same seq and stamps, one stream per eye
  EXPECT_EQ(out->encoding, "jpeg");
  EXPECT_EQ(out->seq, 7u);
  EXPECT_EQ(out->stamp_ns, 1'000);
  EXPECT_EQ(out->left.capture_stamp_ns, 990);
  EXPECT_EQ(out->right.capture_stamp_ns, 1'010);
  for (const EyeView* eye : {&out->left, &out->right}) {
    EXPECT_EQ(eye->step_bytes, 0u);
    EXPECT_EQ(eye->width_px, 640u);
    EXPECT_EQ(eye->height_px, 480u);
  }
  const cv::Mat l(1, static_cast<int>(out->left.bytes), CV_8U,
                  const_cast<uint8_t*>(out->left.data));
  const cv::Mat r(1, static_cast<int>(out->right.bytes), CV_8U,
                  const_cast<uint8_t*>(out->right.data));
  const cv::Mat dl = cv::imdecode(l, cv::IMREAD_COLOR), dr = cv::imdecode(r, cv::IMREAD_COLOR);
  // And each eye decodes to its own image (not swapped)
  EXPECT_LT(mean_abs_diff(dl, left), 3.0);
  EXPECT_LT(mean_abs_diff(dr, right), 3.0);
  EXPECT_GT(mean_abs_diff(dl, right), mean_abs_diff(dl, left));
}

TEST(FrameCompressor, GivenMono8ViewWhenPngCompressedThenExactGreyEyes) {
  const cv::Mat left = scene(1, 4), right = scene(1, 5);
  FrameCompressor compressor(codec("png"));
  auto out = compressor.step(decoded_view(left, right));
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out->encoding, "png");
  const cv::Mat r(1, static_cast<int>(out->right.bytes), CV_8U,
                  const_cast<uint8_t*>(out->right.data));
  EXPECT_EQ(cv::norm(cv::imdecode(r, cv::IMREAD_UNCHANGED), right, cv::NORM_INF), 0.0);
}

TEST(FrameCompressor, GivenNativeYuyvViewThenErrorNamesTheEncoding) {
  // Given a view of native (not decoded) camera bytes
  FrameView view = decoded_view(scene(3, 0), scene(3, 1));
  view.encoding = "yuyv";
  FrameCompressor compressor(codec("jpeg"));
  // Then it is refused with the reason
  auto out = compressor.step(view);
  ASSERT_FALSE(out.ok());
  EXPECT_NE(out.error().find("left eye: cannot compress \"yuyv\""), std::string::npos)
      << out.error();
}

}  // namespace
}  // namespace stereoball::stereo
