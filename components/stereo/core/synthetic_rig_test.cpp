// Synthetic acceptance (issue 4): known rig, 0.1 px pixel noise, point
// rectification and triangulation; the depth error must sit at the
// noise-limited bound dZ = Z^2 * d_disparity / (f * B) within 20 %.

#include "stereo/core/synthetic_rig.hpp"

#include <gtest/gtest.h>

namespace stereoball::stereo {
namespace {

TEST(SyntheticAcceptance, GivenNoisyPixelsAt1mAnd2mWhenTriangulatedThenDepthErrorAtNoiseBound) {
  for (double z : {1.0, 2.0}) {
    // Given 2000 points at depth z seen with 0.1 px noise, When rectified and triangulated
    const DepthErrorFigures f = measure_depth_error(default_synthetic_rig(), z, 0.1, 2000, 1234);
    // Then the RMS depth error is the noise-limited bound within 20 %
    EXPECT_EQ(f.failures, 0);
    EXPECT_LE(f.rms_error_m, 1.2 * f.bound_m) << "z=" << z;
    EXPECT_GE(f.rms_error_m, 0.8 * f.bound_m) << "z=" << z;
  }
}

TEST(SyntheticAcceptance, GivenNoNoiseWhenTriangulatedThenDepthExact) {
  const DepthErrorFigures f = measure_depth_error(default_synthetic_rig(), 2.0, 0.0, 200, 1);
  EXPECT_LT(f.rms_error_m, 1e-6);
}

TEST(SyntheticAcceptance, GivenMoreNoiseWhenTriangulatedThenErrorScalesWithIt) {
  // The error follows the noise: ten times the pixel noise gives about ten times the error.
  const auto small = measure_depth_error(default_synthetic_rig(), 1.0, 0.1, 2000, 7);
  const auto large = measure_depth_error(default_synthetic_rig(), 1.0, 1.0, 2000, 7);
  EXPECT_NEAR(large.rms_error_m / small.rms_error_m, 10.0, 1.5);
}

}  // namespace
}  // namespace stereoball::stereo
