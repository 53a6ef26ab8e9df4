#include "ball_detector/core/appearance_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace stereoball::ball_detector {
namespace {

// Hue in bins (0..kHueBins) and saturation of one pixel, or nullopt if achromatic.
struct HueSat {
  double hue_bins, saturation;
};
std::optional<HueSat> hue_sat(const cv::Vec3b& p) {
  const int b = p[0], g = p[1], r = p[2];
  const int mx = std::max({b, g, r}), mn = std::min({b, g, r});
  const double s = mx > 0 ? static_cast<double>(mx - mn) / mx : 0.0;
  if (mx < ColourHistogram::kMinValue || s < ColourHistogram::kMinSaturation) return std::nullopt;
  const double c = mx - mn;
  double h;  // sextants 0..6
  if (mx == r) {
    h = std::fmod((g - b) / c + 6.0, 6.0);
  } else if (mx == g) {
    h = (b - r) / c + 2.0;
  } else {
    h = (r - g) / c + 4.0;
  }
  return HueSat{h / 6.0 * ColourHistogram::kHueBins, s};
}

}  // namespace

Status AppearanceParams::validate() const {
  std::ostringstream s;
  if (!(min_similarity >= 0.0 && min_similarity <= 1.0)) {
    s << "appearance.min_similarity = " << min_similarity << " is out of range [0, 1]";
  } else if (!(learn_rate > 0.0 && learn_rate <= 1.0)) {
    s << "appearance.learn_rate = " << learn_rate << " is out of range (0, 1]";
  } else if (frames_to_learn < 1 || frames_to_learn > 1000) {
    s << "appearance.frames_to_learn = " << frames_to_learn << " is out of range [1, 1000]";
  } else if (forget_after_ns < 0) {
    s << "appearance.forget_after_ns = " << forget_after_ns << " must not be negative";
  } else if (min_pixels < 1 || min_pixels > 10000) {
    s << "appearance.min_pixels = " << min_pixels << " is out of range [1, 10000]";
  } else {
    return {};
  }
  return Error{s.str()};
}

std::optional<ColourHistogram> ColourHistogram::of(const std::vector<cv::Vec3b>& bgr,
                                                   int min_pixels) {
  if (static_cast<int>(bgr.size()) < std::max(min_pixels, 1)) return std::nullopt;
  ColourHistogram h;
  const double w = 1.0 / static_cast<double>(bgr.size());
  for (const cv::Vec3b& p : bgr) {
    const auto hs = hue_sat(p);
    if (!hs) {
      h.bins_[kBins - 1] += w;
      continue;
    }
    const int sat_bin = hs->saturation < 0.5 ? 0 : 1;
    // Soft binning between the two nearest hue bin centres: a hue on a bin edge does not flip.
    const double x = hs->hue_bins - 0.5;
    const double lo = std::floor(x), frac = x - lo;
    const int a = (static_cast<int>(lo) + kHueBins) % kHueBins, b = (a + 1) % kHueBins;
    h.bins_[static_cast<std::size_t>(a * kSatBins + sat_bin)] += w * (1.0 - frac);
    h.bins_[static_cast<std::size_t>(b * kSatBins + sat_bin)] += w * frac;
  }
  return h;
}

double ColourHistogram::similarity(const ColourHistogram& other) const {
  double bc = 0.0;
  for (std::size_t i = 0; i < bins_.size(); ++i) bc += std::sqrt(bins_[i] * other.bins_[i]);
  return std::min(bc, 1.0);
}

double ColourHistogram::contained_in(const ColourHistogram& model) const {
  double inside = 0.0;
  for (std::size_t i = 0; i < bins_.size(); ++i)
    inside += bins_[i] * std::min(1.0, model.bins_[i] / kSupportWeight);
  return std::min(inside, 1.0);
}

void ColourHistogram::blend(const ColourHistogram& other, double w) {
  for (std::size_t i = 0; i < bins_.size(); ++i)
    bins_[i] = (1.0 - w) * bins_[i] + w * other.bins_[i];
}

void AppearanceModel::learn(const ColourHistogram& ball, std::int64_t now_ns) {
  if (!params_.enabled) return;
  tick(now_ns);
  // The first samples are averaged equally, later ones blended at the learn rate.
  const double w = samples_ < params_.frames_to_learn ? 1.0 / (samples_ + 1) : params_.learn_rate;
  model_.blend(ball, w);
  ++samples_;
  last_sample_ns_ = now_ns;
}

void AppearanceModel::tick(std::int64_t now_ns) {
  if (samples_ > 0 && now_ns - last_sample_ns_ > params_.forget_after_ns) {
    model_ = ColourHistogram{};
    samples_ = 0;
  }
}

bool AppearanceModel::ready() const {
  return params_.enabled && samples_ >= params_.frames_to_learn;
}

std::optional<double> AppearanceModel::similarity(const ColourHistogram& candidate) const {
  if (!ready()) return std::nullopt;
  return model_.similarity(candidate);
}

std::optional<double> AppearanceModel::containment(const ColourHistogram& candidate) const {
  if (!ready()) return std::nullopt;
  return candidate.contained_in(model_);
}

bool AppearanceModel::rejects(const std::optional<ColourHistogram>& candidate) const {
  if (!candidate) return false;
  const auto s = containment(*candidate);
  return s && *s < params_.min_similarity;
}

}  // namespace stereoball::ball_detector
