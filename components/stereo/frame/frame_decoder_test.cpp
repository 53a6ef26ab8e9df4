// FrameDecoder: raw and compressed stereo/frame samples, and every malformed case.

#include "stereo/frame/frame_decoder.hpp"

#include "stereo/frame/frame_codec.hpp"
#include "stereo/frame/frame_sample_builder.hpp"
#include "stereo/image/yuyv_convert.hpp"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <functional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace sb = stereoball;
using sb::Status;
using sb::stereo::FrameDecoder;

namespace {

const cv::Size kSize(64, 48);

using FrameBuilder = sb::stereo::testing::FrameSampleBuilder;

// A grey ramp in every channel (forEach over the bytes of a 3-channel image would set only
// its first third and leave the rest as the allocator found it).
cv::Mat gradient(int type) {
  cv::Mat grey(kSize, CV_8UC1);
  grey.forEach<uint8_t>(
      [](uint8_t& v, const int* p) { v = static_cast<uint8_t>(p[0] * 3 + p[1]); });
  cv::Mat m;
  cv::merge(std::vector<cv::Mat>(static_cast<std::size_t>(CV_MAT_CN(type)), grey), m);
  return m;
}

std::string decode_error(FrameBuilder& f) {
  FrameDecoder d;
  cv::Mat l, r;
  const Status st = d.decode(f.get(), kSize, l, r);
  return st ? "" : st.error();
}

}  // namespace

TEST(FrameDecoder, GivenBgr8_ThenZeroCopyViewsWithTheBytes) {
  const cv::Mat img(kSize, CV_8UC3, cv::Scalar(10, 20, 30));
  FrameBuilder f;
  f.raw(img, img);
  FrameDecoder d;
  cv::Mat l, r;
  ASSERT_TRUE(d.decode(f.get(), kSize, l, r).ok());
  EXPECT_EQ(l.type(), CV_8UC3);
  EXPECT_EQ(l.size(), kSize);
  EXPECT_EQ(l.data, f.left.data());  // a view, not a copy
  EXPECT_EQ(r.at<cv::Vec3b>(5, 5), cv::Vec3b(10, 20, 30));
}

TEST(FrameDecoder, GivenMono8WithPaddedRows_ThenStepRespected) {
  cv::Mat padded(kSize.height, kSize.width + 16, CV_8UC1, cv::Scalar(7));
  FrameBuilder f;
  f.encoding = "mono8";
  f.raw(padded, padded);
  f.msg.left.width_px = f.msg.right.width_px = static_cast<uint32_t>(kSize.width);
  FrameDecoder d;
  cv::Mat l, r;
  ASSERT_TRUE(d.decode(f.get(), kSize, l, r).ok());
  EXPECT_EQ(l.type(), CV_8UC1);
  EXPECT_EQ(l.step, static_cast<size_t>(kSize.width + 16));
}

TEST(FrameDecoder, GivenPngAndJpeg_ThenDecodedToBgr) {
  const cv::Mat img = gradient(CV_8UC3);
  for (const std::string ext : {"png", "jpg"}) {
    FrameBuilder f;
    f.encoded(ext, img, img);
    FrameDecoder d;
    cv::Mat l, r;
    ASSERT_TRUE(d.decode(f.get(), kSize, l, r).ok()) << ext;
    EXPECT_EQ(l.type(), CV_8UC3);
    EXPECT_EQ(l.size(), kSize);
    if (ext == "png") {
      EXPECT_EQ(cv::norm(l, img, cv::NORM_INF), 0.0);
    }
  }
}

TEST(FrameDecoder, GivenWrongEncoding_ThenErrorNamesItAndTheAcceptedOnes) {
  const cv::Mat img(kSize, CV_8UC3, cv::Scalar::all(1));
  FrameBuilder f;
  f.raw(img, img);
  f.encoding = "nv12";
  EXPECT_EQ(decode_error(f), "encoding 'nv12' is not supported (bgr8, mono8, yuyv, jpeg, png)");
}

TEST(FrameDecoder, GivenWrongSize_ThenErrorNamesEyeAndSizes) {
  const cv::Mat img(kSize, CV_8UC3, cv::Scalar::all(1));
  const cv::Mat small(24, 32, CV_8UC3, cv::Scalar::all(1));
  FrameBuilder f;
  f.raw(img, small);
  const std::string e = decode_error(f);
  EXPECT_NE(e.find("right image is 32x24"), std::string::npos) << e;
  EXPECT_NE(e.find("64x48"), std::string::npos) << e;
}

TEST(FrameDecoder, GivenTruncatedData_ThenErrorSaysTruncated) {
  const cv::Mat img(kSize, CV_8UC3, cv::Scalar::all(1));
  FrameBuilder f;
  f.raw(img, img);
  f.msg.left.data._length -= 100;
  const std::string e = decode_error(f);
  EXPECT_NE(e.find("left"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
}

TEST(FrameDecoder, GivenStepSmallerThanRow_ThenError) {
  const cv::Mat img(kSize, CV_8UC3, cv::Scalar::all(1));
  FrameBuilder f;
  f.raw(img, img);
  f.msg.right.step_bytes = 64;  // one byte per pixel for a bgr8 frame
  EXPECT_NE(decode_error(f).find("step_bytes"), std::string::npos) << decode_error(f);
}

TEST(FrameDecoder, GivenGarbageJpeg_ThenErrorNotCrash) {
  const cv::Mat img = gradient(CV_8UC3);
  FrameBuilder f;
  f.encoded("jpg", img, img);
  std::fill(f.right.begin(), f.right.end(), uint8_t{0x5a});
  EXPECT_NE(decode_error(f).find("right jpeg data: not a jpeg or png image"), std::string::npos)
      << decode_error(f);
  f.msg.right.data._length = 0;
  EXPECT_NE(decode_error(f).find("empty"), std::string::npos) << decode_error(f);
}

TEST(FrameDecoder, GivenPngOfOtherSize_ThenTheHeaderSizeIsRefusedBeforeDecoding) {
  const cv::Mat big(96, 128, CV_8UC3, cv::Scalar::all(1));
  FrameBuilder f;
  f.encoded("png", big, big);
  f.msg.left.width_px = f.msg.right.width_px = 64;  // the sample claims the right size
  f.msg.left.height_px = f.msg.right.height_px = 48;
  EXPECT_EQ(decode_error(f), "left png header says 128x96 but the calibration is for 64x48");
}

// Issue 22: a truncated JPEG was processed as a valid frame (libjpeg only warns about it).
TEST(FrameDecoder, GivenATruncatedJpeg_ThenItIsABadFrameNotAnImage) {
  const cv::Mat img = gradient(CV_8UC3);
  FrameBuilder f;
  f.encoded("jpg", img, img);
  f.msg.left.data._length = static_cast<uint32_t>(f.left.size() * 2 / 3);
  EXPECT_NE(decode_error(f).find("left jpeg data is corrupt: Premature end of JPEG file"),
            std::string::npos)
      << decode_error(f);
}

TEST(FrameDecoder, GivenPngBytesInAJpegFrame_ThenTheMismatchIsNamed) {
  const cv::Mat img = gradient(CV_8UC3);
  FrameBuilder f;
  f.encoded("png", img, img);
  f.encoding = "jpeg";
  EXPECT_EQ(decode_error(f), "left image is png data in a jpeg frame");
}

namespace {

// A runner that gives task 1 to a thread of its own while this one runs task 0 (as the
// detector's helper core does), or runs every task in turn.
void run_eyes_on_two_threads(int n, const std::function<void(int)>& task) {
  ASSERT_EQ(n, 2);
  std::thread other([&] { task(1); });
  task(0);
  other.join();
}

}  // namespace

// Given JPEG and PNG frames, when the eyes are decoded as two tasks at the same time,
// then the images are those of decoding one eye after the other, and both tasks ran.
TEST(FrameDecoder, GivenCompressedEyes_WhenDecodedAtTheSameTime_ThenTheSameImages) {
  const cv::Mat left = gradient(CV_8UC3);
  cv::Mat right;
  cv::flip(left, right, 1);
  for (const std::string ext : {"jpg", "png"}) {
    FrameBuilder f;
    f.encoded(ext, left, right);
    FrameDecoder in_turn, together;
    cv::Mat l1, r1, l2, r2;
    ASSERT_TRUE(in_turn.decode(f.get(), kSize, l1, r1).ok()) << ext;
    int tasks = 0;
    const Status st = together.decode(f.get(), kSize, l2, r2, [&](int n, const auto& task) {
      tasks = n;
      run_eyes_on_two_threads(n, task);
    });
    ASSERT_TRUE(st.ok()) << ext << ": " << st.error();
    EXPECT_EQ(tasks, 2) << ext;
    EXPECT_EQ(cv::norm(l1, l2, cv::NORM_INF), 0.0) << ext;
    EXPECT_EQ(cv::norm(r1, r2, cv::NORM_INF), 0.0) << ext;
    EXPECT_GT(cv::norm(l2, r2, cv::NORM_INF), 0.0) << ext << ": the eyes were not kept apart";
  }
}

// Given a frame whose eyes are both broken, when decoded at the same time, then the error is
// the one decoding in turn gives (the left eye's); with only the right broken, the right's.
TEST(FrameDecoder, GivenBrokenEyes_WhenDecodedAtTheSameTime_ThenTheSameErrorAsInTurn) {
  const cv::Mat img = gradient(CV_8UC3);
  for (const bool left_too : {true, false}) {
    FrameBuilder f;
    f.encoded("jpg", img, img);
    std::fill(f.right.begin(), f.right.end(), uint8_t{0x5a});
    if (left_too) f.msg.left.data._length = 0;
    FrameDecoder d;
    cv::Mat l, r;
    const Status st = d.decode(f.get(), kSize, l, r, run_eyes_on_two_threads);
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error(), decode_error(f));
    EXPECT_NE(st.error().find(left_too ? "left jpeg data is empty" : "right jpeg data"),
              std::string::npos)
        << st.error();
  }
}

// Given raw frames, when decoded with a runner, then they are views as before and the runner
// is not asked to run anything (nothing to decode).
TEST(FrameDecoder, GivenRawEyes_WhenDecodedWithARunner_ThenViewsWithoutTasks) {
  const cv::Mat img = gradient(CV_8UC3);
  FrameBuilder f;
  f.raw(img, img);
  FrameDecoder d;
  cv::Mat l, r;
  bool ran = false;
  ASSERT_TRUE(d.decode(f.get(), kSize, l, r, [&](int, const auto&) { ran = true; }).ok());
  EXPECT_FALSE(ran);
  EXPECT_EQ(l.data, f.left.data());
}

TEST(FrameDecoder, GivenAReduction_WhenJpegEyesDecoded_ThenReducedAndPngAtItsSize) {
  // Given a decoder told to reduce by 2, and the same eyes as JPEG and as PNG
  const cv::Mat img = gradient(CV_8UC3);
  FrameDecoder d;
  d.set_reduction(2);
  for (const std::string ext : {"jpg", "png"}) {
    FrameBuilder f;
    f.encoded(ext, img, img);
    cv::Mat l, r;
    // When decoded
    ASSERT_TRUE(d.decode(f.get(), kSize, l, r).ok()) << ext;
    // Then JPEG eyes come out at half the size (close to the full decode shrunk by block means)
    // and PNG eyes, which cannot be decoded reduced, at their own
    const cv::Size want = ext == "jpg" ? cv::Size(kSize.width / 2, kSize.height / 2) : kSize;
    EXPECT_EQ(l.size(), want) << ext;
    EXPECT_EQ(r.size(), want) << ext;
  }
}

namespace {

// One JPEG eye spoiled in each way a link or a sender can spoil it: cut short inside the coded
// data, its end-of-image marker lost, a stray restart marker before the end, and garbage over
// the first segment's length and content (a corrupt header).
std::vector<std::pair<std::string, std::vector<uint8_t>>> spoiled_jpegs(
    const std::vector<uint8_t>& whole) {
  std::vector<std::pair<std::string, std::vector<uint8_t>>> spoiled;
  spoiled.emplace_back("cut at 2/3",
                       std::vector<uint8_t>(whole.begin(), whole.begin() + whole.size() * 2 / 3));
  spoiled.emplace_back("no end marker", std::vector<uint8_t>(whole.begin(), whole.end() - 2));
  auto marker = whole;
  marker[marker.size() - 4] = 0xFF;
  marker[marker.size() - 3] = 0xD0;
  spoiled.emplace_back("stray restart marker", marker);
  auto header = whole;
  std::fill(header.begin() + 4, header.begin() + 12, uint8_t{0x5a});
  spoiled.emplace_back("garbled header", header);
  return spoiled;
}

// Runs both eyes' tasks one after the other on this thread.
void run_eyes_in_turn(int n, const std::function<void(int)>& task) {
  for (int i = 0; i < n; ++i) task(i);
}

// Both eyes of img as JPEG: by OpenCV ("opencv") or by the publishers' encoder with that
// jpeg_chroma ("444", "422", "420").
FrameBuilder jpeg_frame(const cv::Mat& img, const std::string& how) {
  FrameBuilder f;
  if (how == "opencv") {
    f.encoded("jpg", img, img);
    return f;
  }
  sb::stereo::FrameCodecParams codec;
  codec.frame_encoding = "jpeg";
  codec.jpeg_chroma = how;
  sb::stereo::EyeEncoder encoder(codec);
  EXPECT_TRUE(encoder.encode(img).ok()) << how;
  f.jpeg(encoder.bytes(), encoder.bytes(), img.size());
  return f;
}

// Decodes whole with each spoiled_jpegs version of one eye, in turn and as two tasks, and
// expects every frame refused naming that eye, with neither eye handed out.
void expect_spoiled_eye_refused(const FrameBuilder& whole, bool spoil_left, int reduction,
                                const std::string& what) {
  const cv::Mat earlier = gradient(CV_8UC3);
  const std::string eye = spoil_left ? "left" : "right";
  for (const auto& [how, bytes] : spoiled_jpegs(spoil_left ? whole.left : whole.right)) {
    FrameBuilder f = whole;
    (spoil_left ? f.left : f.right) = bytes;
    (spoil_left ? f.msg.left : f.msg.right).data._length = static_cast<uint32_t>(bytes.size());
    for (const bool two_tasks : {false, true}) {
      FrameDecoder d;
      d.set_reduction(reduction);
      cv::Mat l = earlier.clone(), r = earlier.clone();  // what an earlier frame left there
      const Status st = two_tasks ? d.decode(f.get(), kSize, l, r, run_eyes_in_turn)
                                  : d.decode(f.get(), kSize, l, r);
      ASSERT_FALSE(st.ok()) << what << ", " << eye << ", " << how;
      EXPECT_EQ(st.error().rfind(eye + " jpeg data", 0), 0u)
          << what << ", " << how << ": " << st.error();
      EXPECT_TRUE(l.empty()) << what << ", " << eye << ", " << how;
      EXPECT_TRUE(r.empty()) << what << ", " << eye << ", " << how;
    }
  }
}

}  // namespace

// Given eyes from the publishers' encoder at each jpeg_chroma, when decoded at full size and
// reduced by 2, then full size gives OpenCV's decode of the same stream bit for bit and the
// reduction gives that decode's 2x2 means within a few levels.
TEST(FrameDecoder, GivenEachJpegChroma_WhenDecoded_ThenOpenCvsPixelsAndReducedCloseToThem) {
  // A smooth colour ramp with a red disc on it: a colour edge for the chroma to blur.
  cv::Mat img(kSize, CV_8UC3);
  img.forEach<cv::Vec3b>([](cv::Vec3b& v, const int* p) {
    v = cv::Vec3b(static_cast<uint8_t>(40 + 2 * p[1]), static_cast<uint8_t>(60 + 3 * p[0]), 90);
  });
  cv::circle(img, {30, 24}, 12, {20, 40, 230}, cv::FILLED);
  for (const std::string chroma : {"444", "422", "420"}) {
    FrameBuilder f = jpeg_frame(img, chroma);
    const cv::Mat reference = cv::imdecode(f.left, cv::IMREAD_COLOR);
    cv::Mat shrunk;
    cv::resize(reference, shrunk, {kSize.width / 2, kSize.height / 2}, 0, 0, cv::INTER_AREA);
    for (const int reduction : {1, 2}) {
      FrameDecoder d;
      d.set_reduction(reduction);
      cv::Mat l, r;
      ASSERT_TRUE(d.decode(f.get(), kSize, l, r).ok()) << chroma << ", " << reduction;
      ASSERT_EQ(l.size(), reduction == 1 ? kSize : shrunk.size()) << chroma;
      if (reduction == 1) {
        EXPECT_EQ(cv::norm(l, reference, cv::NORM_INF), 0.0) << chroma;
        EXPECT_EQ(cv::norm(r, reference, cv::NORM_INF), 0.0) << chroma;
      } else {
        EXPECT_LT(cv::norm(l, shrunk, cv::NORM_L1) / double(l.total() * 3), 3.0) << chroma;
      }
    }
  }
}

// Given a decoder at full size or reducing by 2, when either eye of a frame (OpenCV's JPEG or
// the publishers' at each jpeg_chroma) arrives truncated or corrupt, then decoding (in turn,
// and as two tasks) refuses the frame with an error naming that eye, and hands out neither
// eye (nothing crashes).
TEST(FrameDecoder, GivenAnyChroma_WhenAJpegEyeIsTruncatedOrCorrupt_ThenTheFrameIsRefused) {
  const cv::Mat img = gradient(CV_8UC3);
  for (const std::string maker : {"opencv", "444", "422", "420"}) {
    const FrameBuilder whole = jpeg_frame(img, maker);
    for (const int reduction : {1, 2}) {
      for (const bool spoil_left : {true, false}) {
        expect_spoiled_eye_refused(whole, spoil_left, reduction,
                                   maker + ", reduction " + std::to_string(reduction));
      }
    }
  }
}

// Given JPEG frames at each jpeg_chroma, full size and reduced by 2, when the right eye is
// decoded lazily (the tasks in turn, or the right one on a thread of its own), then the left eye
// and every row of the right one, once made, are decode()'s; a right eye spoiled below its first
// rows is refused at once or reported by its status once its rows are made, naming the right
// eye; a raw frame's right eye is whole.
TEST(FrameDecoder, GivenJpegEyes_WhenTheRightIsDecodedLazily_ThenItsRowsAreDecodesOnceMade) {
  const cv::Mat img = gradient(CV_8UC3);
  for (const std::string chroma : {"444", "422", "420"}) {
    FrameBuilder f = jpeg_frame(img, chroma);
    for (const int reduction : {1, 2}) {
      FrameDecoder whole, lazy;
      whole.set_reduction(reduction);
      lazy.set_reduction(reduction);
      cv::Mat l1, r1;
      ASSERT_TRUE(whole.decode(f.get(), kSize, l1, r1).ok());
      for (const bool two_threads : {false, true}) {
        const std::string what = chroma + ", reduction " + std::to_string(reduction) +
                                 (two_threads ? ", two threads" : ", in turn");
        cv::Mat l2;
        sb::stereo::RowSource* r2 = nullptr;
        const Status st = lazy.decode_right_lazily(
            f.get(), kSize, l2, r2, two_threads ? run_eyes_on_two_threads : run_eyes_in_turn);
        ASSERT_TRUE(st.ok()) << what << ": " << st.error();
        ASSERT_NE(r2, nullptr);
        EXPECT_EQ(cv::norm(l1, l2, cv::NORM_INF), 0.0) << what;
        const int rows = r1.rows;
        r2->make_rows(rows / 3, rows / 2);
        EXPECT_EQ(cv::norm(r1.rowRange(rows / 3, rows / 2),
                           r2->image().rowRange(rows / 3, rows / 2), cv::NORM_INF),
                  0.0)
            << what;
        r2->make_all();
        ASSERT_TRUE(r2->status().ok()) << what;
        EXPECT_EQ(cv::norm(r1, r2->image(), cv::NORM_INF), 0.0) << what;
      }
      for (const auto& [how, bytes] : spoiled_jpegs(f.right)) {
        FrameBuilder spoiled = f;
        spoiled.right = bytes;
        spoiled.msg.right.data._length = static_cast<uint32_t>(bytes.size());
        cv::Mat l;
        sb::stereo::RowSource* r = nullptr;
        Status st = lazy.decode_right_lazily(spoiled.get(), kSize, l, r, run_eyes_in_turn);
        if (st.ok()) {
          r->make_all();
          st = r->status();
        } else {
          EXPECT_EQ(r, nullptr) << how;
          EXPECT_TRUE(l.empty()) << how;
        }
        ASSERT_FALSE(st.ok()) << chroma << ", " << how;
        EXPECT_EQ(st.error().rfind("right jpeg data", 0), 0u) << how << ": " << st.error();
      }
    }
  }
  FrameBuilder raw;
  raw.raw(img, img);
  FrameDecoder d;
  cv::Mat l;
  sb::stereo::RowSource* r = nullptr;
  ASSERT_TRUE(d.decode_right_lazily(raw.get(), kSize, l, r, run_eyes_in_turn).ok());
  EXPECT_EQ(cv::norm(r->image(), img, cv::NORM_INF), 0.0);
}

// Given a decoder that decodes JPEG eyes reduced by 2, when an eye's JPEG header disagrees with
// the calibration (twice its size, which reduced would come out at the calibration's size; or
// half of it) while the sample's size fields agree, then the frame is refused by the header's
// size, naming the eye, before a pixel is decoded, and neither eye is handed out.
TEST(FrameDecoder, GivenAReduction_WhenAJpegHeaderDisagreesWithTheCalibration_ThenRefused) {
  const cv::Mat right_size = gradient(CV_8UC3);
  for (const cv::Size wrong : {cv::Size(128, 96), cv::Size(32, 24)}) {
    cv::Mat wrong_eye;
    cv::resize(right_size, wrong_eye, wrong);
    for (const bool wrong_left : {true, false}) {
      FrameBuilder f;
      f.encoded("jpg", wrong_left ? wrong_eye : right_size, wrong_left ? right_size : wrong_eye);
      f.msg.left.width_px = f.msg.right.width_px = static_cast<uint32_t>(kSize.width);
      f.msg.left.height_px = f.msg.right.height_px = static_cast<uint32_t>(kSize.height);
      FrameDecoder d;
      d.set_reduction(2);
      cv::Mat l = right_size.clone(), r = right_size.clone();
      const Status st = d.decode(f.get(), kSize, l, r, run_eyes_in_turn);
      ASSERT_FALSE(st.ok()) << wrong;
      EXPECT_EQ(st.error(), std::string(wrong_left ? "left" : "right") + " jpeg header says " +
                                std::to_string(wrong.width) + "x" + std::to_string(wrong.height) +
                                " but the calibration is for 64x48");
      EXPECT_TRUE(l.empty()) << wrong;
      EXPECT_TRUE(r.empty()) << wrong;
    }
  }
}

namespace {

// A camera's YUYV bytes as a two-channel image (Y0 U Y1 V per pixel pair), random so every
// table entry and clamp of the conversion is met; seed keeps the eyes apart.
cv::Mat random_yuyv_eye(cv::Size size, int seed) {
  cv::Mat m(size, CV_8UC2);
  cv::RNG rng(static_cast<uint64_t>(seed));
  rng.fill(m, cv::RNG::UNIFORM, 0, 256);
  return m;
}

// The shared conversion (camera_server's) of one eye of a sample.
cv::Mat converted(const stereoball_msg_EyeImage& eye) {
  cv::Mat bgr;
  const Status st = sb::stereo::yuyv_to_bgr(
      {eye.data._buffer, eye.data._length}, static_cast<int>(eye.width_px),
      static_cast<int>(eye.height_px), static_cast<int>(eye.step_bytes), bgr);
  EXPECT_TRUE(st.ok()) << st.error();
  return bgr;
}

FrameBuilder yuyv_frame(cv::Size size) {
  FrameBuilder f;
  f.encoding = "yuyv";
  f.raw(random_yuyv_eye(size, 1), random_yuyv_eye(size, 2));
  return f;
}

}  // namespace

// Given a yuyv frame (a camera's native bytes, camera_server publish_encoding: native), when
// decoded in turn and as two tasks, then both eyes are BGR of the calibration's size with the
// bits of the shared conversion of the same bytes (which equals OpenCV's), left kept apart
// from right.
TEST(FrameDecoder, GivenYuyv_ThenBgrWithTheBitsOfTheSharedConversion) {
  FrameBuilder f = yuyv_frame(kSize);
  const auto& msg = f.get();
  const cv::Mat want_left = converted(msg.left), want_right = converted(msg.right);
  cv::Mat opencv_left;
  cv::cvtColor(cv::Mat(kSize, CV_8UC2, f.left.data()), opencv_left, cv::COLOR_YUV2BGR_YUYV);
  ASSERT_EQ(cv::norm(want_left, opencv_left, cv::NORM_INF), 0.0);
  for (const bool two_tasks : {false, true}) {
    FrameDecoder d;
    cv::Mat l, r;
    int tasks = 0;
    const Status st = two_tasks ? d.decode(f.get(), kSize, l, r,
                                           [&](int n, const auto& task) {
                                             tasks = n;
                                             run_eyes_on_two_threads(n, task);
                                           })
                                : d.decode(f.get(), kSize, l, r);
    ASSERT_TRUE(st.ok()) << st.error();
    EXPECT_EQ(tasks, two_tasks ? 2 : 0);
    ASSERT_EQ(l.type(), CV_8UC3);
    ASSERT_EQ(l.size(), kSize);
    ASSERT_EQ(r.size(), kSize);
    EXPECT_EQ(cv::norm(l, want_left, cv::NORM_INF), 0.0) << "two tasks " << two_tasks;
    EXPECT_EQ(cv::norm(r, want_right, cv::NORM_INF), 0.0) << "two tasks " << two_tasks;
  }
}

// Given a yuyv frame whose rows are padded (step larger than 2 x width), then the padding is
// skipped: the eyes are the conversion of the pixels only.
TEST(FrameDecoder, GivenYuyvWithPaddedRows_ThenThePaddingIsSkipped) {
  const cv::Mat padded = random_yuyv_eye({kSize.width + 8, kSize.height}, 3);
  FrameBuilder f;
  f.encoding = "yuyv";
  f.raw(padded, padded);
  f.msg.left.width_px = f.msg.right.width_px = static_cast<uint32_t>(kSize.width);
  FrameDecoder d;
  cv::Mat l, r;
  ASSERT_TRUE(d.decode(f.get(), kSize, l, r).ok());
  cv::Mat want;
  cv::cvtColor(padded(cv::Rect({0, 0}, kSize)), want, cv::COLOR_YUV2BGR_YUYV);
  EXPECT_EQ(cv::norm(l, want, cv::NORM_INF), 0.0);
}

// Given yuyv frames spoiled one way each in one eye (cut short, a step smaller than two bytes
// per pixel, a size other than the calibration's), when decoded in turn and as two tasks, then
// the frame is refused with an error naming the eye and the problem, and neither eye is handed
// out.
TEST(FrameDecoder, GivenBrokenYuyvEyes_ThenRefusedNamingTheEye) {
  struct Case {
    const char* what;
    std::function<void(stereoball_msg_EyeImage&)> spoil;
    std::string error;
  };
  const std::vector<Case> cases = {
      {"truncated", [](auto& eye) { eye.data._length -= 100; }, "data bytes"},
      {"step", [](auto& eye) { eye.step_bytes = 64; },
       "step_bytes 64 is smaller than width * channels = 128"},
      {"size", [](auto& eye) { eye.height_px = 24; }, "image is 64x24 but the calibration is"},
  };
  for (const auto& c : cases) {
    for (const bool spoil_left : {true, false}) {
      for (const bool two_tasks : {false, true}) {
        FrameBuilder f = yuyv_frame(kSize);
        c.spoil(spoil_left ? f.msg.left : f.msg.right);
        FrameDecoder d;
        cv::Mat l = gradient(CV_8UC3), r = gradient(CV_8UC3);  // an earlier frame's eyes
        const Status st = two_tasks ? d.decode(f.get(), kSize, l, r, run_eyes_in_turn)
                                    : d.decode(f.get(), kSize, l, r);
        const std::string eye = spoil_left ? "left " : "right ";
        ASSERT_FALSE(st.ok()) << c.what;
        EXPECT_EQ(st.error().rfind(eye, 0), 0u) << c.what << ": " << st.error();
        EXPECT_NE(st.error().find(c.error), std::string::npos) << c.what << ": " << st.error();
        EXPECT_TRUE(l.empty()) << c.what;
        EXPECT_TRUE(r.empty()) << c.what;
      }
    }
  }
  FrameBuilder cut = yuyv_frame(kSize);
  cut.msg.right.data._length -= 100;
  EXPECT_NE(decode_error(cut).find("(truncated)"), std::string::npos) << decode_error(cut);
}

// Given a calibration of odd width and a yuyv frame of that width (YUYV pairs two pixels),
// then the frame is refused naming the eye and the width, not read past its last pair.
TEST(FrameDecoder, GivenYuyvOfOddWidth_ThenRefusedNamingTheWidth) {
  const cv::Size odd(63, 48);
  FrameBuilder f;
  f.encoding = "yuyv";
  const cv::Mat eye = random_yuyv_eye(odd, 4);
  f.raw(eye, eye);
  FrameDecoder d;
  cv::Mat l, r;
  const Status st = d.decode(f.get(), odd, l, r);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error(), "left yuyv width 63 is odd (YUYV pairs two pixels)");
  EXPECT_TRUE(l.empty());
  EXPECT_TRUE(r.empty());
}

// Given a decoder told to reduce by 2 (the detector's working size), when a yuyv frame
// arrives, then its eyes are converted at their full size, bit for bit, as bgr8 eyes are
// handed out at theirs: the detector shrinks both the same way.
TEST(FrameDecoder, GivenAReduction_WhenYuyvEyesDecoded_ThenConvertedAtTheirFullSize) {
  FrameBuilder f = yuyv_frame(kSize);
  FrameDecoder d;
  d.set_reduction(2);
  cv::Mat l, r;
  ASSERT_TRUE(d.decode(f.get(), kSize, l, r, run_eyes_in_turn).ok());
  EXPECT_EQ(l.size(), kSize);
  EXPECT_EQ(cv::norm(l, converted(f.get().left), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(r, converted(f.get().right), cv::NORM_INF), 0.0);
}
