#pragma once
// Test support shared by the detector core's tests: two results that must agree bit for bit.

#include <gtest/gtest.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ball_detector/core/circle.hpp"

namespace stereoball::ball_detector::test {

/// Whether two doubles have the same bits (NaN payloads and signed zeros included).
inline bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

/// The same circles, bit for bit, in the same order.
inline void expect_same_circles(const std::vector<Circle>& a, const std::vector<Circle>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x_px, b[i].x_px) << i;
    EXPECT_EQ(a[i].y_px, b[i].y_px) << i;
    EXPECT_EQ(a[i].radius_px, b[i].radius_px) << i;
    EXPECT_EQ(a[i].score, b[i].score) << i;
  }
}

}  // namespace stereoball::ball_detector::test
