// Test-only fixture shared by the pairing and outline-check tests: the default synthetic rig,
// its triangulator and row check, and a pairing context for a 0.22 m ball.
#pragma once

#include <gtest/gtest.h>

#include <optional>

#include "ball_detector/pipeline/pairing.hpp"
#include "stereo/core/sphere_outline.hpp"
#include "stereo/core/synthetic_rig.hpp"

namespace stereoball::ball_detector::testing {

class SyntheticPairingTest : public ::testing::Test {
 protected:
  static constexpr double kBallRadiusM = 0.11;

  /// size_tolerance: the size check's accepted relative radius error.
  explicit SyntheticPairingTest(double size_tolerance)
      : calib_(stereo::default_synthetic_rig().calibration()),
        tri_(stereo::Triangulator::create(calib_).value()),
        epi_(stereo::EpipolarParams{2.0}),
        size_{2.0 * kBallRadiusM, size_tolerance},
        ctx_{epi_, tri_, size_, std::nullopt} {}

  /// The circle one eye sees of the ball centred at centre_m (left camera frame, m): the
  /// outline is an ellipse off the axis; a circle fit gives its centre and mean semi-axis.
  Circle outline_in_eye(const cv::Vec3d& centre_m, bool right, double score = 0.9,
                        double radius_scale = 1.0) const {
    const cv::Point2d principal = right ? tri_.principal_right_px() : tri_.principal_left_px();
    // The right camera sits baseline_m to the right of the left one.
    const cv::Vec3d in_eye = right ? centre_m - cv::Vec3d(tri_.baseline_m(), 0, 0) : centre_m;
    const auto o = stereo::sphere_outline({tri_.focal_px(), principal}, in_eye, kBallRadiusM);
    return Circle{o->centre_px.x, o->centre_px.y, radius_scale * o->mean_radius_px(), score};
  }

  stereo::StereoCalibration calib_;
  stereo::Triangulator tri_;
  stereo::EpipolarCheck epi_;
  stereo::SizeCheckParams size_;
  PairingContext ctx_;
};

}  // namespace stereoball::ball_detector::testing
