// Integration test: the real camera_server process with the file source on the 13 real
// OpenCV sample pairs; a subscriber checks the frames byte for byte and gets the calibration
// as a late joiner. Configuration errors: one line, non-zero exit.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <thread>

#include <opencv2/imgproc.hpp>

#include "common/dds/reader.hpp"
#include "process.hpp"
#include "stereo/core/calibration_scaling.hpp"
#include "stereo/core/rectifier.hpp"
#include "stereo/io/calibration_file.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;
using sb::testing::Process;

namespace {

const std::string kSamples = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples";
const std::string kCalibration =
    sb::testing::source_path("config/calibration/opencv_samples_stereo.yaml");

const std::string kRig = std::string(SB_SHARED_DATA_DIR) + "/real-stereo-basketball";
const std::string kRigCalibration = kRig + "/calibration/rig_2304x1296.yaml";

std::string write_config(const std::string& body) {
  const std::string path = sb::testing::temp_dir() + "/camera_server.yaml";
  std::ofstream(path) << body;
  return path;
}

std::string files_config(const std::string& left_glob, const std::string& right_glob) {
  return write_config(
      "source: files\nleft_glob: " + left_glob + "\nright_glob: " + right_glob +
      "\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\ncalibration_file: " + kCalibration + "\n");
}

std::vector<std::string> sample_names(const std::string& prefix) {
  std::vector<std::string> out;
  for (int n : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14}) {
    char name[32];
    std::snprintf(name, sizeof name, "/%s%02d.jpg", prefix.c_str(), n);
    out.push_back(kSamples + name);
  }
  return out;
}

bool same_pixels(const stereoball_msg_EyeImage& eye, const cv::Mat& ref) {
  if (eye.width_px != static_cast<uint32_t>(ref.cols) ||
      eye.height_px != static_cast<uint32_t>(ref.rows) ||
      eye.data._length != ref.total() * ref.elemSize()) {
    return false;
  }
  return std::equal(ref.data, ref.data + eye.data._length, eye.data._buffer);
}

std::pair<int, std::string> run_node_with(const std::string& config,
                                          const std::vector<std::string>& extra) {
  std::vector<std::string> argv{sb::testing::bin("camera_server"),
                                "--config",
                                config,
                                "--domain",
                                std::to_string(sb::testing::test_domain()),
                                "--partition",
                                sb::testing::unique_partition()};
  argv.insert(argv.end(), extra.begin(), extra.end());
  return sb::testing::run(argv, 20s);
}

std::pair<int, std::string> run_node(const std::string& config) {
  return run_node_with(config, {});
}

// camera_server started on config (and extra flags) on the test's domain and this partition.
Process start_node(const std::string& config, const std::string& partition,
                   const std::vector<std::string>& extra = {}) {
  std::vector<std::string> argv{sb::testing::bin("camera_server"), "--config", config};
  argv.insert(argv.end(), extra.begin(), extra.end());
  argv.insert(argv.end(),
              {"--domain", std::to_string(sb::testing::test_domain()), "--partition", partition});
  return Process::start(argv);
}

TEST(CameraServerNode, GivenAPreviewReaderThenRawFramesComeWithJpegPreviewsOfTheSamePairs) {
  // Given the real pairs played raw and a reader of stereo/preview (what stereoball view does)
  const std::string partition = sb::testing::unique_partition();
  Process node =
      start_node(files_config(kSamples + "/left*.jpg", kSamples + "/right*.jpg"), partition);
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_StereoPreview> previews(participant,
                                                             sb::topics::kStereoPreview);
  // The preview writer appears with the first raw frame.
  ASSERT_TRUE(previews.wait_for_writers(1, 20'000'000'000)) << node.output();
  // When previews arrive, then each eye is a JPEG of the 640x480 pair it was made from
  int checked = 0;
  sb::testing::eventually(
      [&] {
        for (auto& p : previews.take()) {
          EXPECT_EQ(p->source_width_px, 640u);
          EXPECT_EQ(p->source_height_px, 480u);
          EXPECT_EQ(p->left.capture_stamp_ns, p->stamp_ns);
          const std::vector<uint8_t> bytes(p->left.data._buffer,
                                           p->left.data._buffer + p->left.data._length);
          const cv::Mat img = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
          EXPECT_EQ(img.cols, 640) << "seq " << p->seq;
          EXPECT_EQ(img.rows, 480) << "seq " << p->seq;
          EXPECT_LT(bytes.size(), 640u * 480u / 2) << "seq " << p->seq;
          ++checked;
        }
        return checked >= 5;
      },
      20s);
  EXPECT_GE(checked, 5) << node.output();
}

TEST(CameraServerNode, GivenJpegFramesThenNoPreviewIsOffered) {
  // Given frames published as JPEG (nothing for a preview to save)
  const std::string partition = sb::testing::unique_partition();
  const std::string config =
      write_config("source: files\nleft_glob: " + kSamples + "/left*.jpg\nright_glob: " + kSamples +
                   "/right*.jpg\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\n" +
                   "frame_encoding: jpeg\ncalibration_file: " + kCalibration + "\n");
  Process node = start_node(config, partition);
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_StereoPreview> previews(participant,
                                                             sb::topics::kStereoPreview);
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame);
  // When JPEG frames arrive
  int received = 0;
  sb::testing::eventually(
      [&] {
        received += static_cast<int>(frames.take().size());
        return received >= 10;
      },
      20s);
  ASSERT_GE(received, 10) << node.output();
  // Then no stereo/preview writer exists (a viewer reads the frames themselves)
  EXPECT_EQ(previews.matched_writers(), 0u);
}

TEST(CameraServerNode, GivenRealPairsWhenPlayedThenFramesByteIdenticalAndCalibrationLatched) {
  std::vector<cv::Mat> left, right;
  for (const auto& f : sample_names("left")) left.push_back(cv::imread(f, cv::IMREAD_UNCHANGED));
  for (const auto& f : sample_names("right")) right.push_back(cv::imread(f, cv::IMREAD_UNCHANGED));
  const std::string partition = sb::testing::unique_partition();
  Process node =
      start_node(files_config(kSamples + "/left*.jpg", kSamples + "/right*.jpg"), partition);
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame);
  ASSERT_TRUE(frames.wait_for_writers(1, 10'000'000'000)) << node.output();

  // Given 13 pairs played in glob order, when 20 frames arrive, then each is byte-identical.
  std::map<uint64_t, bool> seen;
  sb::testing::eventually(
      [&] {
        for (auto& s : frames.take()) {
          const size_t i = s->seq % left.size();
          EXPECT_STREQ(s->encoding, "mono8");
          EXPECT_FALSE(s->rectified);
          EXPECT_TRUE(same_pixels(s->left, left[i])) << "left of seq " << s->seq;
          EXPECT_TRUE(same_pixels(s->right, right[i])) << "right of seq " << s->seq;
          EXPECT_EQ(s->left.capture_stamp_ns, s->stamp_ns);
          seen[s->seq] = true;
        }
        return seen.size() >= 20;
      },
      15s);
  ASSERT_GE(seen.size(), 20u) << node.output();

  // Then a reader created now (late joiner) still receives the calibration.
  sb::dds::DataReader<stereoball_msg_StereoCalibration> calib(participant,
                                                              sb::topics::kStereoCalibration);
  auto expected = sb::stereo::load_calibration(kCalibration);
  ASSERT_TRUE(expected.ok()) << expected.error();
  bool got = false;
  sb::testing::eventually(
      [&] {
        for (auto& c : calib.take()) {
          got = true;
          EXPECT_EQ(c->width_px, 640u);
          EXPECT_EQ(c->height_px, 480u);
          EXPECT_DOUBLE_EQ(c->k1[0], expected->k1(0, 0));
          EXPECT_DOUBLE_EQ(c->p2[3], expected->p2(0, 3));
          EXPECT_EQ(c->d1._length, expected->d1.size());
        }
        return got;
      },
      10s);
  EXPECT_TRUE(got) << "no calibration for a late joiner\n" << node.output();

  node.signal(SIGINT);
  EXPECT_EQ(node.wait_for_exit(10s), 0) << node.output();
}

TEST(CameraServerNode, GivenTheCalibrationFileRewrittenWhileRunningThenTheNewOneIsPublished) {
  // Given camera_server publishing a copy of the samples' calibration
  const std::string dir = sb::testing::temp_dir();
  const std::string file = dir + "/rig.yaml";
  auto original = sb::stereo::load_calibration(kCalibration);
  ASSERT_TRUE(original.ok()) << original.error();
  ASSERT_TRUE(sb::stereo::save_calibration(file, *original));
  const std::string partition = sb::testing::unique_partition();
  Process node = start_node(
      write_config("source: files\nleft_glob: " + kSamples + "/left*.jpg\nright_glob: " + kSamples +
                   "/right*.jpg\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\n" +
                   "calibration_file: " + file + "\n"),
      partition);
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_StereoCalibration> calib(participant,
                                                              sb::topics::kStereoCalibration);
  const auto wait_for_t0 = [&](double t0) {
    bool got = false;
    sb::testing::eventually(
        [&] {
          for (auto& c : calib.take()) got |= std::abs(c->t[0] - t0) < 1e-9;
          return got;
        },
        10s);
    return got;
  };
  ASSERT_TRUE(wait_for_t0(original->t[0])) << node.output();
  // When a new calibration replaces the file (as stereoball calibrate live writes it)
  auto changed = *original;
  changed.t *= 1.1;
  changed.p2(0, 3) *= 1.1;
  // (stamped a second after the file it replaces, so that even a file system that keeps whole
  // seconds gives it a later modification time, without waiting for one)
  const auto later_than = [&](const std::string& replacement) {
    std::filesystem::last_write_time(replacement, std::filesystem::last_write_time(file) + 1s);
  };
  ASSERT_TRUE(sb::stereo::save_calibration(dir + "/new.yaml", changed));
  later_than(dir + "/new.yaml");
  std::filesystem::rename(dir + "/new.yaml", file);
  // Then camera_server publishes it without a restart
  EXPECT_TRUE(wait_for_t0(changed.t[0])) << node.output();
  EXPECT_TRUE(node.wait_for_output("calibration reloaded from " + file, 5s)) << node.output();
  // When the file is replaced by one that is not a calibration
  std::ofstream(dir + "/bad.yaml") << "not: a calibration\n";
  later_than(dir + "/bad.yaml");
  std::filesystem::rename(dir + "/bad.yaml", file);
  // Then that is reported once, the node keeps running and publishes nothing new
  EXPECT_TRUE(node.wait_for_output("calibration file changed but not used", 10s)) << node.output();
  EXPECT_TRUE(node.running());
  EXPECT_TRUE(calib.take().empty());
  node.signal(SIGINT);
  EXPECT_EQ(node.wait_for_exit(10s), 0) << node.output();
}

TEST(CameraServerNode, GivenRectifyWhenPlayedThenFramesEqualTheRectifierOutput) {
  auto calib = sb::stereo::load_calibration(kCalibration);
  ASSERT_TRUE(calib.ok()) << calib.error();
  auto rectifier = sb::stereo::Rectifier::create(calib.value());
  ASSERT_TRUE(rectifier.ok()) << rectifier.error();
  const cv::Mat left = cv::imread(kSamples + "/left01.jpg", cv::IMREAD_UNCHANGED);
  const cv::Mat right = cv::imread(kSamples + "/right01.jpg", cv::IMREAD_UNCHANGED);
  cv::Mat left_rect, right_rect;
  ASSERT_TRUE(rectifier->rectify(left, right, left_rect, right_rect).ok());

  const std::string partition = sb::testing::unique_partition();
  const std::string config = write_config(
      "source: files\nleft_glob: " + kSamples + "/left01.jpg\nright_glob: " + kSamples +
      "/right01.jpg\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\ncalibration_file: " +
      kCalibration + "\nrectify: true\n");
  Process node = start_node(config, partition);
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame);
  ASSERT_TRUE(frames.wait_for_writers(1, 10'000'000'000)) << node.output();
  bool got = false;
  sb::testing::eventually(
      [&] {
        for (auto& s : frames.take()) {
          got = true;
          EXPECT_TRUE(s->rectified);
          EXPECT_TRUE(same_pixels(s->left, left_rect));
          EXPECT_TRUE(same_pixels(s->right, right_rect));
          EXPECT_FALSE(same_pixels(s->left, left));  // rectification changed the image
        }
        return got;
      },
      10s);
  EXPECT_TRUE(got) << node.output();
  node.signal(SIGINT);
  EXPECT_EQ(node.wait_for_exit(10s), 0) << node.output();
}

TEST(CameraServerNode, GivenCalibrationForAnotherSizeWhenStartedThenOneLineAndFailure) {
  const auto [code, out] = run_node(files_config(kSamples + "/aloeL.jpg", kSamples + "/aloeR.jpg"));
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("is for 640x480 images but the capture size is"), std::string::npos) << out;
}

TEST(CameraServerNode, GivenCalibrationOfSwappedCamerasWhenStartedThenRefusedSayingHowToFix) {
  // Given a calibration file of the sample rig with its cameras exchanged (negative baseline)
  auto calib = sb::stereo::load_calibration(kCalibration);
  ASSERT_TRUE(calib.ok()) << calib.error();
  const std::string swapped = sb::testing::temp_dir() + "/swapped_calibration.yaml";
  ASSERT_TRUE(sb::stereo::save_calibration(swapped, sb::stereo::swapped_cameras(*calib)).ok());
  // When camera_server starts with it
  const auto [code, out] = run_node(write_config(
      "source: files\nleft_glob: " + kSamples + "/left0*.jpg\nright_glob: " + kSamples +
      "/right0*.jpg\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\ncalibration_file: " + swapped +
      "\n"));
  // Then it refuses with one line naming the problem and the fix
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("negative baseline"), std::string::npos) << out;
  EXPECT_NE(out.find("swap left_device and right_device"), std::string::npos) << out;
}

TEST(CameraServerNode, GivenImagesInTheWrongOrderWhenPlayedThenSwapReportedAndStillPublished) {
  // Given the sample rig's calibration but the right images given as left and vice versa
  const std::string partition = sb::testing::unique_partition();
  Process node =
      start_node(files_config(kSamples + "/right0*.jpg", kSamples + "/left0*.jpg"), partition);
  // When it plays them, Then it says the images look swapped and how to fix it
  EXPECT_TRUE(node.wait_for_output("look swapped", 30s)) << node.output();
  EXPECT_NE(node.output().find("swap left_device and right_device"), std::string::npos)
      << node.output();
  // and keeps running (it cannot know which camera is which; the user fixes the config)
  EXPECT_TRUE(node.running());
  node.signal(SIGINT);
  EXPECT_EQ(node.wait_for_exit(10s), 0) << node.output();
}

TEST(CameraServerNode, GivenImagesInOrderWhenPlayedThenNoSwapReported) {
  const std::string partition = sb::testing::unique_partition();
  Process node =
      start_node(files_config(kSamples + "/left0*.jpg", kSamples + "/right0*.jpg"), partition);
  // The check of the first frame is done when the second pair is being played
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame);
  ASSERT_TRUE(frames.wait_for_writers(1, 10'000'000'000)) << node.output();
  bool second = false;
  sb::testing::eventually(
      [&] {
        for (auto& f : frames.take()) second = second || f->seq >= 1;
        return second;
      },
      20s);
  ASSERT_TRUE(second) << node.output();
  EXPECT_EQ(node.output().find("look swapped"), std::string::npos) << node.output();
  node.signal(SIGINT);
  EXPECT_EQ(node.wait_for_exit(10s), 0) << node.output();
}

TEST(CameraServerNode, GivenMissingCameraWhenStartedThenOneLineNamingDevice) {
  const auto [code, out] = run_node(write_config(
      "source: v4l2\nleft_device: /dev/video_missing_7\nright_device: /dev/video_missing_8\n"
      "width_px: 640\nheight_px: 480\nrate_hz: 30\n"));
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("left camera: /dev/video_missing_7: open failed: no such device"),
            std::string::npos)
      << out;
}

TEST(CameraServerNode, GivenSameDeviceTwiceOrBadFileWhenStartedThenClearError) {
  auto [code, out] =
      run_node(write_config("source: v4l2\nleft_device: /dev/video0\nright_device: /dev/video0\n"
                            "width_px: 640\nheight_px: 480\nrate_hz: 30\n"));
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("same device"), std::string::npos) << out;
  std::tie(code, out) = run_node(files_config("/nonexistent/l*.png", "/nonexistent/r*.png"));
  EXPECT_NE(code, 0);
  EXPECT_NE(out.find("matched no files"), std::string::npos) << out;
}

// Takes frames until n distinct ones arrived; compressed eyes are decoded as ball_detector does
// (cv::imdecode) and compared with the file images they came from.
struct DecodedFrames {
  int count = 0;
  double worst_mean_abs_diff = 0;  // decoded eye vs its file image, DN
  size_t max_pair_bytes = 0;
  bool contract_ok = true;  // encoding, step 0, decoded size as announced
};

DecodedFrames receive_decoded(const std::string& encoding, int n, const std::vector<cv::Mat>& left,
                              const std::vector<cv::Mat>& right, Process& node,
                              const std::string& partition) {
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame);
  EXPECT_TRUE(frames.wait_for_writers(1, 10'000'000'000)) << node.output();
  DecodedFrames r;
  auto check_eye = [&](const stereoball_msg_EyeImage& eye, const cv::Mat& ref) {
    const cv::Mat bytes(1, static_cast<int>(eye.data._length), CV_8U, eye.data._buffer);
    const cv::Mat img = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
    r.contract_ok = r.contract_ok && eye.step_bytes == 0 && !img.empty() &&
                    img.cols == static_cast<int>(eye.width_px) &&
                    img.rows == static_cast<int>(eye.height_px) && img.size() == ref.size() &&
                    img.type() == ref.type();
    if (img.size() != ref.size() || img.type() != ref.type()) return;
    cv::Mat d;
    cv::absdiff(img, ref, d);
    r.worst_mean_abs_diff = std::max(r.worst_mean_abs_diff, cv::mean(d)[0]);
  };
  sb::testing::eventually(
      [&] {
        for (auto& s : frames.take()) {
          const size_t i = s->seq % left.size();
          r.contract_ok = r.contract_ok && encoding == s->encoding;
          check_eye(s->left, left[i]);
          check_eye(s->right, right[i]);
          r.max_pair_bytes =
              std::max<size_t>(r.max_pair_bytes, s->left.data._length + s->right.data._length);
          ++r.count;
        }
        return r.count >= n;
      },
      15s);
  return r;
}

TEST(CameraServerNode, GivenFrameEncodingJpegWhenPlayedThenEyesDecodeCloseToTheFilesAndSmaller) {
  std::vector<cv::Mat> left, right;
  for (const auto& f : sample_names("left")) left.push_back(cv::imread(f, cv::IMREAD_UNCHANGED));
  for (const auto& f : sample_names("right")) right.push_back(cv::imread(f, cv::IMREAD_UNCHANGED));
  // Given the 13 real pairs played with frame_encoding jpeg at quality 90
  const std::string partition = sb::testing::unique_partition();
  Process node = start_node(files_config(kSamples + "/left*.jpg", kSamples + "/right*.jpg"),
                            partition, {"--frame-encoding", "jpeg"});
  // When 15 frames arrive
  const DecodedFrames r = receive_decoded("jpeg", 15, left, right, node, partition);
  ASSERT_GE(r.count, 15) << node.output();
  // Then each follows the contract, decodes to its own file's pixels within JPEG error, and a
  // pair is a fraction of the raw mono8 pair (2 x 640 x 480 bytes)
  EXPECT_TRUE(r.contract_ok);
  EXPECT_LT(r.worst_mean_abs_diff, 3.0);
  EXPECT_LT(r.max_pair_bytes, 2u * 640 * 480 / 2);
  std::printf(
      "jpeg q90 file frames: largest pair %zu bytes (raw mono8 %u), worst mean |diff| "
      "%.2f DN\n",
      r.max_pair_bytes, 2u * 640 * 480, r.worst_mean_abs_diff);
  node.signal(SIGINT);
  EXPECT_EQ(node.wait_for_exit(10s), 0) << node.output();
}

TEST(CameraServerNode, GivenFrameEncodingPngInTheConfigWhenPlayedThenEyesAreLossless) {
  const cv::Mat left = cv::imread(kSamples + "/left03.jpg", cv::IMREAD_UNCHANGED);
  const cv::Mat right = cv::imread(kSamples + "/right03.jpg", cv::IMREAD_UNCHANGED);
  // Given one pair played with frame_encoding png from the config file
  const std::string partition = sb::testing::unique_partition();
  const std::string config = write_config(
      "source: files\nleft_glob: " + kSamples + "/left03.jpg\nright_glob: " + kSamples +
      "/right03.jpg\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\nframe_encoding: png\n");
  Process node = start_node(config, partition);
  // When frames arrive, then they decode to exactly the file's pixels
  const DecodedFrames r = receive_decoded("png", 3, {left}, {right}, node, partition);
  ASSERT_GE(r.count, 3) << node.output();
  EXPECT_TRUE(r.contract_ok);
  EXPECT_EQ(r.worst_mean_abs_diff, 0.0);
}

TEST(CameraServerNode, GivenBadFrameEncodingOrQualityWhenStartedThenOneLineNamingFileAndKey) {
  const std::string files = "source: files\nleft_glob: " + kSamples +
                            "/left01.jpg\nright_glob: " + kSamples +
                            "/right01.jpg\nwidth_px: 640\nheight_px: 480\nrate_hz: 30\n";
  for (const std::string bad : {"frame_encoding: h264\n", "jpeg_quality: 0\n"}) {
    const std::string config = write_config(files + bad);
    const auto [code, out] = run_node(config);
    EXPECT_EQ(code, 2) << out;
    EXPECT_NE(out.find(config), std::string::npos) << out;
    EXPECT_NE(out.find(bad.substr(0, bad.find(':'))), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  }
  // And a bad override flag is refused too
  const auto [code, out] =
      run_node_with(files_config(kSamples + "/left01.jpg", kSamples + "/right01.jpg"),
                    {"--frame-encoding", "gif"});
  EXPECT_NE(code, 0) << out;
  EXPECT_NE(out.find("--frame-encoding"), std::string::npos) << out;
}

}  // namespace

namespace {

// Two real pairs of the 2304x1296 basketball rig, grey, with its calibration.
std::string rig_config(const std::string& extra) {
  return write_config(
      "source: files\nleft_glob: " + kRig + "/left/left_0[12].jpg\nright_glob: " + kRig +
      "/right/right_0[12].jpg\nfile_encoding: mono8\nwidth_px: 2304\n" +
      "height_px: 1296\nrate_hz: 10\ncalibration_file: " + kRigCalibration + "\n" + extra);
}

// The latest value of a counter in camera_server's heartbeat, once it is at least min.
std::optional<uint64_t> camera_counter(sb::dds::DataReader<stereoball_msg_ComponentStatus>& status,
                                       const std::string& name, uint64_t min) {
  std::optional<uint64_t> value;
  sb::testing::eventually(
      [&] {
        for (auto& s : status.take()) {
          if (!s->component || std::string(s->component) != "camera_server") continue;
          for (uint32_t i = 0; i < s->counters._length; ++i) {
            const auto& c = s->counters._buffer[i];
            if (c.name && name == c.name) value = c.value;
          }
        }
        return value && *value >= min;
      },
      10s);
  return value;
}

TEST(CameraServerPublishWidth, GivenTheRealRigAtHalfWidthThenFramesAndCalibrationAreScaled) {
  // Given the real rig's pairs (2304x1296) played with publish_width_px: 1152
  auto full = sb::stereo::load_calibration(kRigCalibration);
  ASSERT_TRUE(full.ok()) << full.error();
  const cv::Mat left = cv::imread(kRig + "/left/left_01.jpg", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(left.empty());
  cv::Mat left_half;
  cv::resize(left, left_half, {1152, 648}, 0, 0, cv::INTER_AREA);
  const std::string partition = sb::testing::unique_partition();
  Process node = start_node(rig_config("publish_width_px: 1152\n"), partition);
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame);
  sb::dds::DataReader<stereoball_msg_StereoCalibration> calib(participant,
                                                              sb::topics::kStereoCalibration);
  // When frames arrive, Then both eyes are 1152x648 and the left one is the area-scaled file
  int checked = 0;
  sb::testing::eventually(
      [&] {
        for (auto& f : frames.take()) {
          EXPECT_STREQ(f->encoding, "mono8");
          for (const auto* eye : {&f->left, &f->right}) {
            EXPECT_EQ(eye->width_px, 1152u);
            EXPECT_EQ(eye->height_px, 648u);
            EXPECT_EQ(eye->step_bytes, 1152u);
            EXPECT_EQ(eye->data._length, 1152u * 648u);
          }
          if (f->seq % 2 == 0 && f->left.data._length == 1152u * 648u) {
            EXPECT_TRUE(same_pixels(f->left, left_half)) << "seq " << f->seq;
          }
          ++checked;
        }
        return checked >= 4;
      },
      30s);
  ASSERT_GE(checked, 4) << node.output();
  // And the calibration is the rig's scaled by one half (pixel centres kept: c' = c/2 - 1/4)
  bool got = false;
  sb::testing::eventually(
      [&] {
        for (auto& c : calib.take()) {
          got = true;
          EXPECT_EQ(c->width_px, 1152u);
          EXPECT_EQ(c->height_px, 648u);
          EXPECT_NEAR(c->k1[0], 0.5 * full->k1(0, 0), 1e-9);
          EXPECT_NEAR(c->k1[2], 0.5 * full->k1(0, 2) - 0.25, 1e-9);
          EXPECT_NEAR(c->k2[4], 0.5 * full->k2(1, 1), 1e-9);
          EXPECT_NEAR(c->p1[0], 0.5 * full->p1(0, 0), 1e-9);
          EXPECT_NEAR(c->p2[3], 0.5 * full->p2(0, 3), 1e-9);  // -f*B: the baseline is kept
          EXPECT_NEAR(c->p2[6], 0.5 * full->p2(1, 2) - 0.25, 1e-9);
          EXPECT_NEAR(c->q[11], 0.5 * full->q(2, 3), 1e-9);  // the focal length in Q
          EXPECT_DOUBLE_EQ(c->q[14], full->q(3, 2));         // -1/Tx
          EXPECT_EQ(c->d1._length, full->d1.size());
          for (uint32_t i = 0; i < c->d1._length && i < full->d1.size(); ++i) {
            EXPECT_EQ(c->d1._buffer[i], full->d1[i]);
          }
          EXPECT_DOUBLE_EQ(c->t[0], full->t[0]);
          EXPECT_DOUBLE_EQ(c->r1[1], full->r1(0, 1));
          EXPECT_NE(std::string(c->source).find("scaled to 1152x648"), std::string::npos);
        }
        return got;
      },
      10s);
  EXPECT_TRUE(got) << node.output();
  node.signal(SIGINT);
  EXPECT_EQ(node.wait_for_exit(10s), 0) << node.output();
}

TEST(CameraServerPublishWidth, GivenRectifyThenTheScaledEyesAreRectifiedWithTheScaledCalibration) {
  // Given the rig's first pair at half width with rectify: true, and what that should give:
  // the area-scaled eyes rectified with the calibration scaled to 1152x648
  auto full = sb::stereo::load_calibration(kRigCalibration);
  ASSERT_TRUE(full.ok()) << full.error();
  const auto half = sb::stereo::scale_calibration(*full, {1152, 648});
  ASSERT_TRUE(half.ok()) << half.error();
  const auto rectifier = sb::stereo::Rectifier::create(*half);
  ASSERT_TRUE(rectifier.ok()) << rectifier.error();
  cv::Mat eyes[2], expected[2];
  for (int e = 0; e < 2; ++e) {
    const std::string name = e == 0 ? "/left/left_01.jpg" : "/right/right_01.jpg";
    cv::resize(cv::imread(kRig + name, cv::IMREAD_GRAYSCALE), eyes[e], {1152, 648}, 0, 0,
               cv::INTER_AREA);
  }
  ASSERT_TRUE(rectifier->rectify(eyes[0], eyes[1], expected[0], expected[1]).ok());
  const std::string partition = sb::testing::unique_partition();
  const std::string config =
      write_config("source: files\nleft_glob: " + kRig + "/left/left_01.jpg\nright_glob: " + kRig +
                   "/right/right_01.jpg\nfile_encoding: mono8\nwidth_px: 2304\nheight_px: 1296\n" +
                   "rate_hz: 10\ncalibration_file: " + kRigCalibration +
                   "\npublish_width_px: 1152\nrectify: true\n");
  Process node = start_node(config, partition);
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame);
  // When a frame arrives, Then it is rectified, 1152x648, exactly the expected eyes
  bool got = false;
  sb::testing::eventually(
      [&] {
        for (auto& f : frames.take()) {
          got = true;
          EXPECT_TRUE(f->rectified);
          EXPECT_TRUE(same_pixels(f->left, expected[0]));
          EXPECT_TRUE(same_pixels(f->right, expected[1]));
          EXPECT_FALSE(same_pixels(f->left, eyes[0]));  // rectification changed the image
        }
        return got;
      },
      30s);
  EXPECT_TRUE(got) << node.output();
  node.signal(SIGINT);
  EXPECT_EQ(node.wait_for_exit(10s), 0) << node.output();
}

TEST(CameraServerPublishWidth, GivenAWidthNotBelowTheImagesOrOddThenAnErrorNamingTheKey) {
  // Given an odd width: refused with the parameters, one line
  const auto [code, out] = run_node(rig_config("publish_width_px: 1151\n"));
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("key 'publish_width_px': 1151 must be even"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  // Given the images' own width (known once the files are read): the last line says why
  const auto [code2, out2] = run_node(rig_config("publish_width_px: 2304\n"));
  EXPECT_EQ(code2, 2) << out2;
  EXPECT_NE(out2.find("camera_server: key 'publish_width_px': 2304 must be smaller than the "
                      "captured width (2304x1296)"),
            std::string::npos)
      << out2;
}

TEST(CameraServerTransport, GivenRawFramesLargerThanTheReceiveBufferThenWarnedAtStartAndInHealth) {
  // Given raw 640x480 bgr8 frames (1.8 MB samples) and a deployment key, so that the node runs
  // on CYCLONEDDS_URI (a keyless node runs on its built-in configuration), whose socket receive
  // buffer request is 512 KiB (whatever the kernel's rmem_max, the buffer is at most that, so a
  // reader takes at most 1 MiB at once)
  const std::string key = sb::testing::make_key_file(sb::testing::temp_dir(), "deployment.key");
  const char* uri = std::getenv("CYCLONEDDS_URI");
  const std::string small_buffer = std::string(uri ? uri : "") + (uri ? "," : "") +
                                   "<Internal><SocketReceiveBufferSize max=\"512kB\"/></Internal>";
  const std::string partition = sb::testing::unique_partition();
  const std::string config = write_config(
      "source: files\nleft_glob: " + kSamples + "/left0*.jpg\nright_glob: " + kSamples +
      "/right0*.jpg\nfile_encoding: bgr8\nwidth_px: 640\n" + "height_px: 480\nrate_hz: 5\n");
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition, key});
  sb::dds::DataReader<stereoball_msg_ComponentStatus> status(participant,
                                                             sb::topics::kComponentStatus);
  // (the child inherits this process's environment: changed for the start only)
  const std::string saved = uri ? uri : "";
  ::setenv("CYCLONEDDS_URI", small_buffer.c_str(), 1);
  Process node = Process::start({sb::testing::bin("camera_server"), "--config", config, "--domain",
                                 std::to_string(sb::testing::test_domain()), "--partition",
                                 partition, "--key-file", key});
  if (uri) {
    ::setenv("CYCLONEDDS_URI", saved.c_str(), 1);
  } else {
    ::unsetenv("CYCLONEDDS_URI");
  }
  // When it starts, Then one warning names the sizes and the remedies
  EXPECT_TRUE(node.wait_for_output("most frames will be lost in transport", 20s)) << node.output();
  const std::string out = node.output();
  for (const char* part :
       {"raw 640x480 bgr8 frames", "1.8 MiB", "frame_encoding: jpeg", "publish_width_px", "shm.xml",
        "net.core.rmem_max", "90-stereoball-net.conf"}) {
    EXPECT_NE(out.find(part), std::string::npos) << part << " in:\n" << out;
  }
  // And the heartbeat carries it: the error counter, the sample and buffer sizes
  EXPECT_EQ(camera_counter(status, "frame_too_large", 1), 1u) << node.output();
  EXPECT_EQ(camera_counter(status, "frame_sample_bytes", 1), 2u * 640 * 480 * 3 + 1024);
  EXPECT_LE(camera_counter(status, "receive_buffer_bytes", 1).value_or(1u << 30), 512u << 10);
  node.signal(SIGINT);
  EXPECT_EQ(node.wait_for_exit(10s), 0) << node.output();
}

}  // namespace
