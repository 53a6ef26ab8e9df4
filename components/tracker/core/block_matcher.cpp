#include "tracker/core/block_matcher.hpp"

namespace stereoball::tracker {

std::int64_t block_ssd(const Patch& a, const Patch& b) {
  // Max total is 1323 * 255^2 = 86,028,075: int32 would do, int64 keeps it obvious.
  std::int64_t sum = 0;
  for (std::size_t i = 0; i < kPatchBytes; ++i) {
    const int d = static_cast<int>(a[i]) - static_cast<int>(b[i]);
    sum += d * d;
  }
  return sum;
}

std::optional<std::int64_t> BlockMatcher::ssd(const Patch& block) const {
  if (!reference_) return std::nullopt;
  return block_ssd(*reference_, block);
}

}  // namespace stereoball::tracker
