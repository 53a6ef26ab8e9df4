#pragma once
// The followed ball's appearance, learnt online (addition to the paper): a hue-saturation
// histogram of the pixels inside the ball once the tracker follows it, used to rank circle
// candidates and to reject round things of another colour. Hue and saturation barely change
// with shading (brightness), so one side of the ball in shadow still matches the lit side.
// Nothing about the ball's colour is configured. Pure: time is an argument.

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::ball_detector {

/// Settings of the appearance model.
struct AppearanceParams {
  bool enabled = true;
  /// Candidates whose colours lie in the learnt ones less than this (ColourHistogram::
  /// contained_in: 0 = none of its colours seen on the ball, 1 = all of them) are rejected.
  double min_similarity = 0.5;
  double learn_rate = 0.2;  ///< weight of each new sample in the running histogram
  int frames_to_learn = 3;  ///< samples before the model ranks and rejects anything
  std::int64_t forget_after_ns = 3'000'000'000;  ///< a loss longer than this forgets the model
  int min_pixels = 12;                           ///< fewer sampled pixels than this: no histogram

  /// Success, or the first invalid field with its allowed range.
  Status validate() const;
};

/// A normalised hue-saturation histogram: kHueBins x kSatBins chromatic bins (hue soft-binned
/// between neighbouring bins) plus one bin for grey, white, black and very dark pixels.
class ColourHistogram {
 public:
  static constexpr int kHueBins = 16;
  static constexpr int kSatBins = 2;
  static constexpr int kBins = kHueBins * kSatBins + 1;
  /// Pixels with saturation (chroma / max) below this, or max below kMinValue, are achromatic.
  static constexpr double kMinSaturation = 0.2;
  static constexpr int kMinValue = 24;

  /// Histogram of BGR pixels; nullopt if fewer than min_pixels.
  static std::optional<ColourHistogram> of(const std::vector<cv::Vec3b>& bgr, int min_pixels);

  /// Bhattacharyya coefficient sum(sqrt(p_i q_i)) in [0, 1].
  double similarity(const ColourHistogram& other) const;
  /// How much of this histogram lies in colours model holds, [0, 1]: the sum over bins of this
  /// bin's weight times min(1, model's weight / kSupportWeight). Unlike similarity, it does
  /// not change with the proportions of the colours: a ball with panels or stripes of two
  /// colours shows them in other proportions as it rolls (or a part of it in shadow), and
  /// still lies wholly in the colours learnt from it.
  double contained_in(const ColourHistogram& model) const;
  /// A bin holding at least this weight counts as a colour of the model in contained_in.
  static constexpr double kSupportWeight = 0.04;
  /// this = (1 - w) this + w other.
  void blend(const ColourHistogram& other, double w);
  /// Weight of bin i (sums to 1).
  double bin(int i) const { return bins_[static_cast<std::size_t>(i)]; }

 private:
  std::array<double, kBins> bins_{};
};

/// The learnt appearance of the followed ball and its clock.
class AppearanceModel {
 public:
  explicit AppearanceModel(const AppearanceParams& params) : params_(params) {}

  /// Adds a sample of the followed ball seen at now_ns.
  void learn(const ColourHistogram& ball, std::int64_t now_ns);
  /// Forgets the model once now_ns is more than forget_after_ns after the last sample.
  void tick(std::int64_t now_ns);
  /// Whether the model has enough samples to rank and reject.
  bool ready() const;
  /// Similarity of a candidate's histogram to the ball's, nullopt unless ready().
  std::optional<double> similarity(const ColourHistogram& candidate) const;
  /// How much of the candidate lies in the ball's colours (contained_in), nullopt unless ready().
  std::optional<double> containment(const ColourHistogram& candidate) const;
  /// True if ready() and the candidate's containment is below min_similarity (no histogram:
  /// false).
  bool rejects(const std::optional<ColourHistogram>& candidate) const;
  /// Samples learnt since the last forget.
  int samples() const { return samples_; }
  const AppearanceParams& params() const { return params_; }

 private:
  AppearanceParams params_;
  ColourHistogram model_;
  int samples_ = 0;
  std::int64_t last_sample_ns_ = 0;
};

}  // namespace stereoball::ball_detector
