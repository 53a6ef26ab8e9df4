#include "camera_server/io/file_source.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

namespace stereoball::camera_server {
namespace {

const std::string kSamples = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples";

bool identical(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  return cv::norm(a, b, cv::NORM_INF) == 0.0;
}

TEST(FileSource, GivenTheThirteenRealPairsByGlobWhenOpenedAsReadThenMono8ByteIdenticalToFiles) {
  auto src = FileSource::open({kSamples + "/left*.jpg", kSamples + "/right*.jpg", "", "as_read"});
  ASSERT_TRUE(src.ok()) << src.error();
  ASSERT_EQ(src->size(), 13u);
  EXPECT_EQ(src->encoding(), "mono8");
  EXPECT_EQ(src->image_size(), cv::Size(640, 480));
  for (size_t i = 0; i < src->size(); ++i) {
    const FilePair& p = src->pair(i);
    EXPECT_TRUE(identical(p.left, cv::imread(p.left_path, cv::IMREAD_UNCHANGED))) << p.left_path;
    EXPECT_TRUE(identical(p.right, cv::imread(p.right_path, cv::IMREAD_UNCHANGED))) << p.right_path;
    // left01 pairs with right01: the numbers after the prefix agree.
    EXPECT_EQ(p.left_path.substr(p.left_path.size() - 6),
              p.right_path.substr(p.right_path.size() - 6));
    EXPECT_TRUE(p.left.isContinuous());
  }
}

TEST(FileSource, GivenPairsDirWhenOpenedAsBgr8ThenSamePairsConvertedLikeImread) {
  auto src = FileSource::open({"", "", kSamples, "bgr8"});
  ASSERT_TRUE(src.ok()) << src.error();
  ASSERT_EQ(src->size(), 13u);  // aloeL/aloeR and single images are not left/right pairs
  EXPECT_EQ(src->encoding(), "bgr8");
  const FilePair& p = src->pair(4);
  EXPECT_EQ(p.left.type(), CV_8UC3);
  EXPECT_TRUE(identical(p.left, cv::imread(p.left_path, cv::IMREAD_COLOR)));
}

TEST(FileSource, GivenGlobsMatchingDifferentCountsWhenOpenedThenErrorNamesBothCounts) {
  auto src = FileSource::open({kSamples + "/left*.jpg", kSamples + "/right0*.jpg", "", "as_read"});
  ASSERT_FALSE(src.ok());
  EXPECT_NE(src.error().find("13"), std::string::npos) << src.error();
  EXPECT_NE(src.error().find("9"), std::string::npos) << src.error();
}

TEST(FileSource, GivenGlobMatchingNothingWhenOpenedThenErrorNamesGlob) {
  auto src = FileSource::open({"/nonexistent/left*.png", kSamples + "/right*.jpg", "", "as_read"});
  ASSERT_FALSE(src.ok());
  EXPECT_NE(src.error().find("/nonexistent/left*.png"), std::string::npos);
}

TEST(FileSource, GivenPairsOfDifferentSizesWhenOpenedThenErrorNamesFiles) {
  auto src = FileSource::open({kSamples + "/left01.jpg", kSamples + "/aloeR.jpg", "", "as_read"});
  ASSERT_FALSE(src.ok());
  EXPECT_NE(src.error().find("left01.jpg"), std::string::npos) << src.error();
  EXPECT_NE(src.error().find("aloeR.jpg"), std::string::npos) << src.error();
}

TEST(FileSource, GivenNonImageFileWhenOpenedThenErrorNamesFile) {
  const std::string xml = kSamples + "/stereo_calib.xml";
  auto src = FileSource::open({xml, xml, "", "as_read"});
  ASSERT_FALSE(src.ok());
  EXPECT_NE(src.error().find("stereo_calib.xml: cannot read"), std::string::npos) << src.error();
}

TEST(FileSource, GivenMissingFolderWhenOpenedThenErrorNamesFolder) {
  auto src = FileSource::open({"", "", "/nonexistent/pairs", "as_read"});
  ASSERT_FALSE(src.ok());
  EXPECT_NE(src.error().find("/nonexistent/pairs"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::camera_server
