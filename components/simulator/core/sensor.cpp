#include "simulator/core/sensor.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::simulator {

Sensor::Sensor(double sigma_dn, uint64_t seed) : rng_(seed), enabled_(sigma_dn > 0.0) {
  table_.resize(size_t{1} << kTableBits);
  SplitMix64 table_rng(seed ^ 0x5eed5eed5eedULL);
  for (size_t i = 0; i < table_.size(); i += 2) {
    // Box-Muller gives two independent normals per pair of uniforms.
    const double u1 = std::max(table_rng.uniform(), 1e-12), u2 = table_rng.uniform();
    const double r = std::sqrt(-2.0 * std::log(u1)) * sigma_dn * 16.0;
    table_[i] =
        static_cast<int16_t>(std::clamp(std::lround(r * std::cos(2 * M_PI * u2)), -32000L, 32000L));
    table_[i + 1] =
        static_cast<int16_t>(std::clamp(std::lround(r * std::sin(2 * M_PI * u2)), -32000L, 32000L));
  }
}

void Sensor::apply(cv::Mat& image) {
  if (!enabled_) return;
  const int n = image.cols * image.channels();
  // A random start per row, chosen so the row never wraps: the inner loop then vectorizes.
  const uint64_t span = table_.size() > static_cast<size_t>(n) ? table_.size() - n : 1;
  for (int y = 0; y < image.rows; ++y) {
    uint8_t* p = image.ptr<uint8_t>(y);
    const int16_t* noise =
        table_.data() + (table_.size() > static_cast<size_t>(n) ? rng_.next() % span : 0);
    const int m = std::min<int>(n, static_cast<int>(table_.size()));
    for (int i = 0; i < m; ++i) {
      const int v = p[i] * 16 + noise[i] + 8;
      p[i] = static_cast<uint8_t>(std::clamp(v >> 4, 0, 255));
    }
  }
}

}  // namespace stereoball::simulator
