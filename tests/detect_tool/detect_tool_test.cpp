// `stereoball detect` on image files whose headers claim 20000x20000, or that are cut short:
// it must fail fast with one clear line per file instead of decoding gigabytes.

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <fstream>
#include <vector>

#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/detector_params_file.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "crafted_images.hpp"
#include "process.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;

namespace {

std::vector<uint8_t> encode(const char* ext) {
  cv::Mat img(480, 640, CV_8UC3, cv::Scalar(60, 120, 60));
  cv::circle(img, {320, 240}, 60, cv::Scalar(30, 60, 220), cv::FILLED);
  std::vector<uint8_t> bytes;
  cv::imencode(ext, img, bytes);
  return bytes;
}

std::string write(const std::string& dir, const std::string& name,
                  const std::vector<uint8_t>& bytes) {
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  return path;
}

struct DetectRun {
  int code;
  std::string out;
  double ms;
};

DetectRun detect(const std::vector<std::string>& files) {
  std::vector<std::string> argv{sb::testing::bin("stereoball-detect")};
  argv.insert(argv.end(), files.begin(), files.end());
  const auto start = std::chrono::steady_clock::now();
  auto [code, out] = sb::testing::run(argv, 30s);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return {code, out, ms};
}

long children_peak_rss_kb() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  return usage.ru_maxrss;
}

TEST(DetectTool, GivenAGoodImageThenTheBallIsFound) {
  const auto dir = sb::testing::temp_dir();
  const DetectRun r = detect({write(dir, "ball.png", encode(".png"))});
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("1 circle(s)"), std::string::npos) << r.out;
}

TEST(DetectTool, GivenCoarseThenTheBallIsFoundAtTheSamePlace) {
  // Given the same image searched whole and from the halved image (--coarse)
  const auto dir = sb::testing::temp_dir();
  const std::string path = write(dir, "ball.png", encode(".png"));
  const DetectRun r = detect({"--coarse", path});
  // Then the one ball is reported at its centre and radius
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("1 circle(s)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("x=320."), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("y=240."), std::string::npos) << r.out;
  EXPECT_TRUE(r.out.find("r=59.") != std::string::npos || r.out.find("r=60.") != std::string::npos)
      << r.out;
}

// Issue 38 item 5: a user who tries a photo sees what the robot sees.
TEST(DetectTool, GivenTheShippedConfigThenDetectAndTheNodesDetectorAgreeOnOneImage) {
  // Given an image with a ball and clutter, and the node's detector built from the shipped
  // config/ball_detector.yaml as the node builds it
  const auto dir = sb::testing::temp_dir();
  cv::Mat img(480, 640, CV_8UC3, cv::Scalar(60, 120, 60));
  cv::circle(img, {300, 250}, 70, cv::Scalar(30, 90, 220), cv::FILLED, cv::LINE_AA);
  cv::circle(img, {520, 90}, 9, cv::Scalar(200, 200, 200), cv::FILLED, cv::LINE_AA);
  cv::rectangle(img, {40, 330}, {160, 440}, cv::Scalar(20, 20, 20), cv::FILLED);
  const std::string path = dir + "/ball.png";
  cv::imwrite(path, img);
  const std::string config = std::string(SB_SOURCE_DIR) + "/config/ball_detector.yaml";
  auto params = sb::ball_detector::load_detector_params(config);
  ASSERT_TRUE(params) << params.error();
  sb::ball_detector::PixelToPixelDetector node(params->detector_params());
  cv::Mat scratch;
  const auto expected =
      node.detect(sb::ball_detector::detector_input_image(img, params->input, scratch));
  ASSERT_FALSE(expected.empty());
  // When stereoball detect runs on the image with its defaults
  const DetectRun r = detect({"--config", config, path});
  // Then it reports the same circles, best first, and the core's defaults stay one flag away
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find(std::to_string(expected.size()) + " circle(s)"), std::string::npos) << r.out;
  for (const auto& c : expected)
    EXPECT_NE(r.out.find(cv::format("x=%.2f y=%.2f r=%.2f", c.x_px, c.y_px, c.radius_px)),
              std::string::npos)
        << r.out;
  const DetectRun core = detect({"--core-defaults", path});
  EXPECT_EQ(core.code, 0) << core.out;
  const DetectRun missing = detect({"--config", dir + "/none.yaml", path});
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.out.find("none.yaml"), std::string::npos) << missing.out;
}

// Issue 22: a 28 KB JPEG or 1.1 MB PNG whose header says 20000x20000 ran past 30 s at 4-5 GB.
TEST(DetectTool, GivenHeadersClaiming20000x20000ThenItFailsFastNamingTheLimit) {
  const auto dir = sb::testing::temp_dir();
  // The process's own start-up, for comparison: the same refusal without any image to read.
  const DetectRun missing = detect({dir + "/missing.png"});
  std::printf("[figure] stereoball detect on a missing file (start-up only): exit %d in %.1f ms\n",
              missing.code, missing.ms);
  auto jpeg = encode(".jpg");
  sb::testing::claim_image_size(jpeg, 20000, 20000);
  auto png = encode(".png");
  sb::testing::claim_image_size(png, 20000, 20000);
  for (const auto& [name, bytes] : {std::pair{"huge.jpg", jpeg}, std::pair{"huge.png", png}}) {
    const DetectRun r = detect({write(dir, name, bytes)});
    std::printf("[figure] stereoball detect %s (%zu bytes): exit %d in %.1f ms\n", name,
                bytes.size(), r.code, r.ms);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("header says 20000x20000, larger than the limit 4096x4096"),
              std::string::npos)
        << r.out;
  }
  std::printf("[figure] peak RSS of the detect processes: %ld kB\n", children_peak_rss_kb());
  EXPECT_LT(children_peak_rss_kb(), 500'000) << "a 20000x20000 image is 1.2 GB of pixels";
}

TEST(DetectTool, GivenATruncatedJpegOrAMissingFileThenEachIsNamed) {
  const auto dir = sb::testing::temp_dir();
  auto jpeg = encode(".jpg");
  jpeg.resize(jpeg.size() / 2);
  const DetectRun r = detect({write(dir, "cut.jpg", jpeg), dir + "/missing.png"});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("'" + dir + "/cut.jpg': jpeg data is corrupt: Premature end of JPEG file"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("cannot read image '" + dir + "/missing.png'"), std::string::npos) << r.out;
}

TEST(DetectTool, GivenASmallerLimitThenALargerBmpIsRefusedByOpenCvsPixelLimit) {
  const auto dir = sb::testing::temp_dir();
  const std::string bmp = dir + "/big.bmp";
  cv::imwrite(bmp, cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(100)));
  auto [code, out] = sb::testing::run(
      {sb::testing::bin("stereoball-detect"), "--max-width", "320", "--max-height", "240", bmp},
      30s);
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("big.bmp"), std::string::npos) << out;
}

}  // namespace
