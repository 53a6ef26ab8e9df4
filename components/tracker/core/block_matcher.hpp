#pragma once
// Block matching of paper section IV: SSD between 21x21 RGB blocks of the left
// image against a stored reference block that is refreshed on every good match.

#include <cstdint>
#include <optional>

#include "tracker/core/types.hpp"

namespace stereoball::tracker {

/// Sum of squared differences over all pixels and channels (paper eq. 4); 0 iff equal.
std::int64_t block_ssd(const Patch& a, const Patch& b);

/// Holds the reference block and compares new blocks against it.
class BlockMatcher {
 public:
  /// threshold: a block matches when SSD < threshold (unitless).
  explicit BlockMatcher(double threshold) : threshold_(threshold) {}

  /// True once a reference block is stored.
  bool has_reference() const { return reference_.has_value(); }
  /// Replaces the reference with this block.
  void store(const Patch& block) { reference_ = block; }
  /// Forgets the reference.
  void clear() { reference_.reset(); }
  /// SSD of block against the reference; nullopt without a reference.
  std::optional<std::int64_t> ssd(const Patch& block) const;
  /// True when an SSD value counts as a match (strictly below the threshold).
  bool is_match(std::int64_t ssd) const { return static_cast<double>(ssd) < threshold_; }
  /// The threshold, unitless.
  double threshold() const { return threshold_; }

 private:
  double threshold_;
  std::optional<Patch> reference_;
};

}  // namespace stereoball::tracker
