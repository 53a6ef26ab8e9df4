#pragma once
// Arithmetic shared by the detector's sources, and the intrinsics header of their hand-written
// AVX2 kernels (included only where cpu_dispatch.hpp builds such kernels).

#include "ball_detector/core/cpu_dispatch.hpp"

#include <opencv2/core/matx.hpp>

#include <cmath>
#include <optional>

#if SB_HAVE_AVX2_KERNELS
#include <immintrin.h>
#endif

namespace stereoball::ball_detector {

/// sqrt(a * a + b * b): std::hypot guards against an overflow that cannot happen with pixel
/// coordinates and gradients, and is several times slower.
inline double fast_hypot(double a, double b) {
  return std::sqrt(a * a + b * b);
}

/// x with a x = b, or nullopt when det(a) is 0: the closed form (Cramer's rule) that
/// cv::solve(a, b, x, DECOMP_CHOLESKY) takes for a system this small, operation for operation
/// (same bits), without its Mat wrapping, which costs twenty times the arithmetic.
inline std::optional<cv::Vec3d> solve_3x3(const cv::Matx33d& a, const cv::Vec3d& b) {
  // Cofactors by rows of the adjugate, each a difference of two products.
  const double det = a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) -
                     a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
                     a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
  if (det == 0.0) return std::nullopt;
  const double inv = 1.0 / det;
  const double x0 = ((a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) * b[0] +
                     (a(0, 2) * a(2, 1) - a(0, 1) * a(2, 2)) * b[1] +
                     (a(0, 1) * a(1, 2) - a(0, 2) * a(1, 1)) * b[2]) *
                    inv;
  const double x1 = ((a(1, 2) * a(2, 0) - a(1, 0) * a(2, 2)) * b[0] +
                     (a(0, 0) * a(2, 2) - a(0, 2) * a(2, 0)) * b[1] +
                     (a(0, 2) * a(1, 0) - a(0, 0) * a(1, 2)) * b[2]) *
                    inv;
  const double x2 = ((a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0)) * b[0] +
                     (a(0, 1) * a(2, 0) - a(0, 0) * a(2, 1)) * b[1] +
                     (a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0)) * b[2]) *
                    inv;
  return cv::Vec3d(x0, x1, x2);
}

/// solve_3x3 for a 2 x 2 system (cv::solve's closed form there, same bits).
inline std::optional<cv::Vec2d> solve_2x2(const cv::Matx22d& a, const cv::Vec2d& b) {
  const double det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
  if (det == 0.0) return std::nullopt;
  const double inv = 1.0 / det;
  const double x0 = (b[0] * a(1, 1) - b[1] * a(0, 1)) * inv;
  const double x1 = (b[1] * a(0, 0) - b[0] * a(1, 0)) * inv;
  return cv::Vec2d(x0, x1);
}

}  // namespace stereoball::ball_detector
