#pragma once
// Seeded, deterministic sensor read noise added to rendered images.

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace stereoball::simulator {

/// SplitMix64: small, fast, fully specified generator (same sequence on every platform).
class SplitMix64 {
 public:
  /// Generator seeded with seed.
  explicit SplitMix64(uint64_t seed) : s_(seed) {}
  /// Next 64 random bits.
  uint64_t next() {
    uint64_t z = (s_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform double in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  uint64_t s_;
};

/// Adds Gaussian read noise (sigma in digital numbers) from a precomputed table;
/// each row of each frame starts at a fresh random table offset.
class Sensor {
 public:
  /// Noise of standard deviation sigma_dn; the sequence is fixed by seed.
  Sensor(double sigma_dn, uint64_t seed);
  /// Adds noise in place to an 8-bit image (any channel count); no-op for sigma 0.
  void apply(cv::Mat& image);

 private:
  static constexpr int kTableBits = 16;
  std::vector<int16_t> table_;  // noise in 1/16 DN, so rounding stays unbiased
  SplitMix64 rng_;
  bool enabled_;
};

}  // namespace stereoball::simulator
