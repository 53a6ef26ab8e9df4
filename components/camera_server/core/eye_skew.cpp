#include "camera_server/core/eye_skew.hpp"

#include <algorithm>

namespace stereoball::camera_server {

void EyeSkewStats::add(int64_t left_stamp_ns, int64_t right_stamp_ns) {
  const int64_t d = left_stamp_ns - right_stamp_ns;
  // The magnitude as unsigned: no overflow even for stamps of opposite extremes.
  const uint64_t skew = d >= 0 ? static_cast<uint64_t>(d) : 0 - static_cast<uint64_t>(d);
  skews_ns_.push_back(skew);
}

std::optional<EyeSkewSummary> EyeSkewStats::take() {
  if (skews_ns_.empty()) return std::nullopt;
  EyeSkewSummary s;
  s.pairs = skews_ns_.size();
  const auto mid = skews_ns_.begin() + static_cast<std::ptrdiff_t>(skews_ns_.size() / 2);
  std::nth_element(skews_ns_.begin(), mid, skews_ns_.end());
  s.p50_us = *mid / 1000;
  s.max_us = *std::max_element(skews_ns_.begin(), skews_ns_.end()) / 1000;
  skews_ns_.clear();
  return s;
}

}  // namespace stereoball::camera_server
