#include "stereo/core/rectifier.hpp"

#include "stereo/core/synthetic_rig.hpp"
#include "stereo/core/triangulation.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace stereoball::stereo {
namespace {

class RectifierTest : public ::testing::Test {
 protected:
  SyntheticRig rig_ = default_synthetic_rig();
  StereoCalibration calib_ = rig_.calibration();
  Rectifier rect_ = Rectifier::create(calib_).value();
};

TEST_F(RectifierTest, GivenPointsWhenProjectedRectifiedTriangulatedThenRecovered) {
  // Given 3D points spread over the field of view at 0.5 .. 3 m
  const Triangulator tri = Triangulator::create(calib_).value();
  for (double z : {0.5, 1.0, 2.0, 3.0}) {
    for (double u : {-0.3, 0.0, 0.25}) {
      const cv::Point3d p(u * z, -0.6 * u * z, z);
      // When projected into the distorted images, point-rectified and triangulated
      const cv::Point2d l = rect_.rectify_point(Eye::kLeft, rig_.project_left(p));
      const cv::Point2d r = rect_.rectify_point(Eye::kRight, rig_.project_right(p));
      const auto x = tri.point_m(l.x, r.x, 0.5 * (l.y + r.y));
      // Then the point comes back in the left rectified frame (R1 * p) to micrometres
      ASSERT_TRUE(x.has_value());
      const cv::Vec3d expected = calib_.r1 * cv::Vec3d(p.x, p.y, p.z);
      EXPECT_LT(cv::norm(*x - expected), 1e-5 * z) << "z=" << z << " u=" << u;
      EXPECT_NEAR(l.y, r.y, 1e-4);
    }
  }
}

TEST_F(RectifierTest, GivenRectifiedPointWhenUnrectifiedThenBackToRawPixel) {
  // Given a raw pixel near the image corner (strong distortion)
  for (Eye eye : {Eye::kLeft, Eye::kRight}) {
    const cv::Point2d raw(40.0, 455.0);
    // When rectified and mapped back
    const cv::Point2d back = rect_.unrectify_point(eye, rect_.rectify_point(eye, raw));
    // Then it lands on the same raw pixel
    EXPECT_NEAR(back.x, raw.x, 1e-3);
    EXPECT_NEAR(back.y, raw.y, 1e-3);
  }
}

// Centroid of a bright blob, pixels.
cv::Point2d centroid(const cv::Mat& img) {
  const cv::Moments m = cv::moments(img);
  return {m.m10 / m.m00, m.m01 / m.m00};
}

TEST_F(RectifierTest, GivenBlobImageWhenLutRectifiedThenBlobWherePointRectifierSaysIt) {
  // Given a raw left image with a small blob at a distorted off-centre position
  const cv::Point2d raw(150.3, 120.7);
  cv::Mat img(rig_.size, CV_32F, cv::Scalar(0));
  cv::circle(img, cv::Point(cvRound(raw.x * 16), cvRound(raw.y * 16)), 3 * 16, cv::Scalar(1.0),
             cv::FILLED, cv::LINE_AA, 4);
  cv::GaussianBlur(img, img, cv::Size(0, 0), 1.5);
  const cv::Point2d raw_c = centroid(img);
  // When the whole image goes through the fixed-point LUT
  cv::Mat out;
  ASSERT_TRUE(rect_.rectify_eye(Eye::kLeft, img, out).ok());
  // Then the blob's centroid is where the cheap point path puts it (sub-pixel)
  const cv::Point2d expected = rect_.rectify_point(Eye::kLeft, raw_c);
  const cv::Point2d got = centroid(out);
  EXPECT_NEAR(got.x, expected.x, 0.1);
  EXPECT_NEAR(got.y, expected.y, 0.1);
  EXPECT_EQ(out.size(), rig_.size);
}

TEST_F(RectifierTest, GivenWrongSizeFrameWhenRectifiedThenClearErrorAndOutputsUntouched) {
  // Given a correctly sized left frame and a half-size right frame
  const cv::Mat left(rig_.size, CV_8UC3, cv::Scalar(10, 20, 30));
  const cv::Mat right(cv::Size(320, 240), CV_8UC3, cv::Scalar(1, 2, 3));
  cv::Mat left_out, right_out;
  // When rectified
  const auto error = rect_.rectify(left, right, left_out, right_out);
  // Then the error names the eye and both sizes, and nothing was written
  ASSERT_FALSE(error.ok());
  EXPECT_NE(error.error().find("right image is 320x240"), std::string::npos) << error.error();
  EXPECT_NE(error.error().find("640x480"), std::string::npos) << error.error();
  EXPECT_TRUE(left_out.empty());
  EXPECT_TRUE(right_out.empty());
}

TEST_F(RectifierTest, GivenEmptyFrameWhenRectifiedThenErrorSaysEmpty) {
  cv::Mat out;
  const auto error = rect_.rectify_eye(Eye::kLeft, cv::Mat(), out);
  ASSERT_FALSE(error.ok());
  EXPECT_NE(error.error().find("left image is empty"), std::string::npos);
}

TEST_F(RectifierTest, GivenGoodFramesWhenRectifiedThenSameSizeAndType) {
  const cv::Mat frame(rig_.size, CV_8UC3, cv::Scalar(100, 150, 200));
  cv::Mat l, r;
  ASSERT_TRUE(rect_.rectify(frame, frame, l, r).ok());
  EXPECT_EQ(l.size(), rig_.size);
  EXPECT_EQ(r.type(), CV_8UC3);
  // Centre pixels map from inside the image, so they keep the colour.
  EXPECT_EQ(l.at<cv::Vec3b>(240, 320), cv::Vec3b(100, 150, 200));
}

// Given a noisy frame, when only a region is rectified, then that region equals the same
// region of the full rectification, pixels outside it are untouched, and a region hanging over
// the border is clipped.
TEST_F(RectifierTest, GivenRegionWhenRectifiedThenEqualsThatPartOfTheFullRectification) {
  cv::Mat raw(rig_.size, CV_8UC1);
  cv::randu(raw, 0, 256);
  cv::Mat full;
  ASSERT_TRUE(rect_.rectify_eye(Eye::kRight, raw, full).ok());
  cv::Mat part(rig_.size, CV_8UC1, cv::Scalar(7));
  const cv::Rect roi(100, 50, 120, 90);
  ASSERT_TRUE(rect_.rectify_eye_region(Eye::kRight, raw, roi, part).ok());
  EXPECT_EQ(cv::norm(full(roi), part(roi), cv::NORM_INF), 0.0);
  EXPECT_EQ(part.at<uchar>(10, 10), 7);
  EXPECT_EQ(part.at<uchar>(200, 300), 7);
  const cv::Rect over(rig_.size.width - 30, rig_.size.height - 20, 100, 100);
  ASSERT_TRUE(rect_.rectify_eye_region(Eye::kRight, raw, over, part).ok());
  const cv::Rect inside = over & cv::Rect(cv::Point(0, 0), rig_.size);
  EXPECT_EQ(cv::norm(full(inside), part(inside), cv::NORM_INF), 0.0);
  cv::Mat wrong(10, 10, CV_8UC1);
  const auto error = rect_.rectify_eye_region(Eye::kRight, raw, roi, wrong);
  ASSERT_FALSE(error.ok());
  EXPECT_NE(error.error().find("output"), std::string::npos) << error.error();
}

TEST_F(RectifierTest, GivenRegionsWhenRawRowsAskedThenRectifyingReadsNoOtherRow) {
  // Given a noisy colour frame and boxes over the distorted corners, the middle, a thin strip,
  // one hanging over the border and an empty one
  cv::Mat raw(rig_.size, CV_8UC3);
  cv::randu(raw, 0, 256);
  const int w = rig_.size.width, h = rig_.size.height;
  const cv::Rect boxes[] = {{0, 0, 90, 60},   {w - 90, h - 60, 90, 60},   {200, 150, 160, 120},
                            {0, h / 2, w, 3}, {w - 30, h - 20, 100, 100}, {5, 5, 0, 0}};
  for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
    for (const cv::Rect& box : boxes) {
      // When the raw rows the region reads are asked for, and every other row is scribbled over
      const cv::Range rows = rect_.raw_rows(eye, box);
      if ((box & cv::Rect(0, 0, w, h)).empty()) {
        EXPECT_TRUE(rows.empty());
        continue;
      }
      ASSERT_GE(rows.start, 0);
      ASSERT_LE(rows.end, h);
      ASSERT_LT(rows.start, rows.end);
      cv::Mat scribbled(rig_.size, CV_8UC3, cv::Scalar(13, 200, 77));
      raw.rowRange(rows).copyTo(scribbled.rowRange(rows));
      // Then the region rectified from either frame is the same, bit for bit
      cv::Mat clean_out(rig_.size, CV_8UC3, cv::Scalar(0)), scribbled_out = clean_out.clone();
      ASSERT_TRUE(rect_.rectify_eye_region(eye, raw, box, clean_out).ok());
      ASSERT_TRUE(rect_.rectify_eye_region(eye, scribbled, box, scribbled_out).ok());
      EXPECT_EQ(cv::norm(clean_out, scribbled_out, cv::NORM_INF), 0.0)
          << "box " << box << " rows " << rows.start << ".." << rows.end;
      // and a region away from the bottom needs no row near it
      if (box.y + box.height < h / 2) {
        EXPECT_LT(rows.end, h - 40) << "box " << box;
      }
    }
  }
}

TEST(RectifierCreate, GivenInvalidCalibrationWhenCreatedThenErrorNamesField) {
  StereoCalibration c = default_synthetic_rig().calibration();
  c.k2(1, 1) = -5;
  const auto r = Rectifier::create(c);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().rfind("K2:", 0), 0u) << r.error();
}

}  // namespace
}  // namespace stereoball::stereo
