// The real processes on real backgrounds with a composited ball: camera_server plays
// composited rectified pairs from files (with the rectified rig's calibration file) and the
// real ball_detector finds the ball where it was drawn.

#include "common/dds/reader.hpp"
#include "composite_scenes.hpp"
#include "process.hpp"
#include "stereo/io/calibration_file.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <opencv2/imgcodecs.hpp>

#include <fstream>
#include <map>
#include <sstream>

namespace sb = stereoball;
using namespace std::chrono_literals;
using sb::testing::Process;

namespace {

std::string write_file(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

TEST(CompositeProcesses, GivenComposedRealPairsWhenPlayedByCameraServerThenDetectorFindsBalls) {
  // Given the Aloe background and chessboard pair 05 with one ball each, written as files with
  // the rectified rig's calibration
  const auto calib = sb::stereo::load_calibration(
      sb::testing::source_path("config/calibration/opencv_samples_stereo.yaml"));
  ASSERT_TRUE(calib.ok()) << calib.error();
  auto bgs = sb::composite::load_real_backgrounds(
      std::string(SB_SHARED_DATA_DIR) + "/opencv-samples", *calib);
  ASSERT_TRUE(bgs.ok()) << bgs.error();
  const sb::composite::Background& bg = (*bgs)[4];  // chessboard05: 640x480 like the others
  const std::string dir = sb::testing::temp_dir();
  std::vector<sb::composite::Ball> balls = sb::composite::place_balls(bg, 2, 0.11, 0.8, 3.0, 5);
  ASSERT_EQ(balls.size(), 2u);
  for (std::size_t i = 0; i < balls.size(); ++i) {
    const auto [l, r] = sb::composite::composite(bg, balls[i]);
    ASSERT_TRUE(cv::imwrite(dir + "/left_" + std::to_string(i) + ".png", l));
    ASSERT_TRUE(cv::imwrite(dir + "/right_" + std::to_string(i) + ".png", r));
  }
  const std::string calib_file = dir + "/rectified_rig.yaml";
  ASSERT_TRUE(
      sb::stereo::save_calibration(calib_file, sb::composite::rectified_rig_calibration(bg)).ok());
  const std::string camera_config =
      write_file(dir + "/camera_server.yaml",
                 "source: files\nleft_glob: " + dir + "/left_*.png\n" + "right_glob: " + dir +
                     "/right_*.png\nwidth_px: 640\n" +
                     "height_px: 480\nrate_hz: 5\ncalibration_file: " + calib_file + "\n");
  // The detector's own config with the floor check off: a composited ball floats.
  std::ifstream in(sb::testing::source_path("config/ball_detector.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string detector_yaml = text.str();
  const auto at = detector_yaml.find("tolerance_m: 0.10");
  ASSERT_NE(at, std::string::npos);
  detector_yaml.replace(at, 17, "tolerance_m: 0.0 ");
  const std::string detector_config = write_file(dir + "/ball_detector.yaml", detector_yaml);

  // When both processes run on a private partition
  const std::string partition = sb::testing::unique_partition();
  const std::string domain = std::to_string(sb::testing::test_domain());
  sb::dds::DomainParticipant participant({sb::testing::test_domain(), partition});
  sb::dds::DataReader<stereoball_msg_BallDetection> detections(participant,
                                                               sb::topics::kBallDetection);
  Process detector = Process::start({sb::testing::bin("ball_detector"), "--config", detector_config,
                                     "--domain", domain, "--partition", partition});
  Process camera = Process::start({sb::testing::bin("camera_server"), "--config", camera_config,
                                   "--domain", domain, "--partition", partition});

  // Then every ball is found where it was drawn (within 0.5 % of its depth)
  std::map<std::size_t, int> found;  // ball index -> FOUND detections
  sb::testing::eventually(
      [&] {
        for (auto& d : detections.take()) {
          const std::size_t i = d->frame_seq % balls.size();
          if (d->status != stereoball_msg_DETECTION_FOUND) continue;
          const cv::Vec3d p(d->position_m[0], d->position_m[1], d->position_m[2]);
          EXPECT_LT(cv::norm(p - balls[i].centre_m), 0.005 * balls[i].centre_m[2])
              << "ball " << i << " at z " << balls[i].centre_m[2];
          ++found[i];
        }
        return found.size() == balls.size();
      },
      60s);
  EXPECT_EQ(found.size(), balls.size()) << detector.output() << camera.output();
  camera.signal(SIGINT);
  detector.signal(SIGINT);
  EXPECT_EQ(camera.wait_for_exit(10s), 0) << camera.output();
  EXPECT_EQ(detector.wait_for_exit(10s), 0) << detector.output();
}

}  // namespace
