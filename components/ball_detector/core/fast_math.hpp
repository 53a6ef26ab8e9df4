#pragma once
// Arithmetic shared by the detector's sources, and the intrinsics header of their hand-written
// AVX2 kernels (included only where cpu_dispatch.hpp builds such kernels).

#include "ball_detector/core/cpu_dispatch.hpp"

#include <cmath>

#if SB_HAVE_AVX2_KERNELS
#include <immintrin.h>
#endif

namespace stereoball::ball_detector {

/// sqrt(a * a + b * b): std::hypot guards against an overflow that cannot happen with pixel
/// coordinates and gradients, and is several times slower.
inline double fast_hypot(double a, double b) {
  return std::sqrt(a * a + b * b);
}

}  // namespace stereoball::ball_detector
