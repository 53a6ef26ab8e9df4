#pragma once
// Test-only helpers: synthetic ball / clutter detections for the tracker tests.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "tracker/core/types.hpp"

namespace stereoball::tracker::testing {

inline constexpr std::int64_t kFramePeriodNs = 33'333'333;  // 30 fps
inline constexpr double kFocalPx = 500.0;
inline constexpr std::uint32_t kWidthPx = 640;

/// A ball-like block: a disc of colour (r, g, b) on grey, brightness scaled by gain.
inline Patch ball_patch(double r, double g, double b, double gain = 1.0, int radius_px = 9) {
  Patch p{};
  for (int y = 0; y < kBlockSidePx; ++y) {
    for (int x = 0; x < kBlockSidePx; ++x) {
      const int dx = x - kBlockHalfSizePx;
      const int dy = y - kBlockHalfSizePx;
      const bool inside = dx * dx + dy * dy <= radius_px * radius_px;
      // Shading toward the rim makes the block depend on the ball size.
      const double shade = inside ? 1.0 - 0.3 * std::sqrt(dx * dx + dy * dy) / radius_px : 0.0;
      const double c[3] = {inside ? r * shade : 110.0, inside ? g * shade : 110.0,
                           inside ? b * shade : 110.0};
      for (int ch = 0; ch < 3; ++ch) {
        const double v = std::clamp(c[ch] * gain, 0.0, 255.0);
        p[static_cast<std::size_t>((y * kBlockSidePx + x) * 3 + ch)] =
            static_cast<std::uint8_t>(std::lround(v));
      }
    }
  }
  return p;
}

/// Adds uniform noise in [-amplitude, amplitude] to every byte.
inline Patch noisy(Patch p, std::mt19937& rng, int amplitude) {
  std::uniform_int_distribution<int> u(-amplitude, amplitude);
  for (auto& v : p) v = static_cast<std::uint8_t>(std::clamp(static_cast<int>(v) + u(rng), 0, 255));
  return p;
}

/// A random textured block, as clutter would give.
inline Patch clutter_patch(std::mt19937& rng) {
  std::uniform_int_distribution<int> u(0, 255);
  Patch p{};
  const int base[3] = {u(rng), u(rng), u(rng)};
  for (std::size_t i = 0; i < kPatchBytes; ++i) {
    p[i] = static_cast<std::uint8_t>(std::clamp(base[i % 3] + u(rng) / 4 - 32, 0, 255));
  }
  return p;
}

/// A detection at position with the left-image column projected by a pinhole camera.
inline Detection detection_at(const Eigen::Vector3d& position_m, const Patch& patch) {
  Detection d;
  d.found = true;
  d.position_m = position_m;
  d.left_x_px = kWidthPx / 2.0 + kFocalPx * position_m.x() / position_m.z();
  d.image_width_px = kWidthPx;
  d.patch_valid = true;
  d.patch_rgb = patch;
  return d;
}

/// Stereo-like measurement noise: small lateral, depth growing with distance.
inline Eigen::Vector3d measured(const Eigen::Vector3d& truth, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return truth + Eigen::Vector3d(0.002 * n(rng), 0.002 * n(rng), 0.003 * truth.z() * n(rng));
}

/// A uniformly random clutter position in front of the camera.
inline Eigen::Vector3d clutter_position(std::mt19937& rng) {
  std::uniform_real_distribution<double> x(-2.0, 2.0);
  std::uniform_real_distribution<double> y(-0.5, 0.8);
  std::uniform_real_distribution<double> z(0.4, 5.0);
  return {x(rng), y(rng), z(rng)};
}

}  // namespace stereoball::tracker::testing
