#include "ball_detector/core/colour_seeds.hpp"

#include "ball_detector/core/cpu_dispatch.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace stereoball::ball_detector {
namespace {

// Chroma of one BGR row: max - min of the three channels per pixel.
SB_AVX2_CLONE void chroma_row(const std::uint8_t* __restrict bgr, std::uint8_t* __restrict out,
                              int n) {
  for (int x = 0; x < n; ++x) {
    const std::uint8_t b = bgr[3 * x], g = bgr[3 * x + 1], r = bgr[3 * x + 2];
    out[x] = static_cast<std::uint8_t>(std::max(std::max(b, g), r) - std::min(std::min(b, g), r));
  }
}

// Median and median absolute deviation of an 8-bit image, from its histogram.
std::pair<int, int> median_and_mad(const cv::Mat& u8) {
  std::array<int, 256> hist{};
  for (int y = 0; y < u8.rows; ++y) {
    const auto* row = u8.ptr<std::uint8_t>(y);
    for (int x = 0; x < u8.cols; ++x) ++hist[row[x]];
  }
  const long half = (static_cast<long>(u8.total()) + 1) / 2;
  auto median_of = [&](const std::array<int, 256>& h) {
    long seen = 0;
    for (int v = 0; v < 256; ++v)
      if ((seen += h[static_cast<std::size_t>(v)]) >= half) return v;
    return 255;
  };
  const int median = median_of(hist);
  std::array<int, 256> dev{};
  for (int v = 0; v < 256; ++v)
    dev[static_cast<std::size_t>(std::abs(v - median))] += hist[static_cast<std::size_t>(v)];
  return {median, median_of(dev)};
}

// Stripes of one colour with others between become one region under a closing with this.
const cv::Mat& close_kernel() {
  static const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5));
  return kernel;
}

// The most of the image the rare colours may cover together.
constexpr double kMaxRareCover = 0.1;

// A colour quantised to 8 levels per channel: one of 512 bins.
inline int colour_bin(const std::uint8_t* bgr) {
  return (bgr[0] >> 5) << 6 | (bgr[1] >> 5) << 3 | (bgr[2] >> 5);
}

// Pixels of chroma above min_chroma whose colour (colour_bin) covers less than rare_fraction of
// the image: a ball whose chroma the floor shares but not its colour.
cv::Mat rare_colour_mask(const cv::Mat& bgr, const cv::Mat& chroma, double min_chroma,
                         double rare_fraction) {
  // The colours' shares from every other pixel of every other row: a quarter of the image
  // measures a share of 1 % as well, at a quarter of the cost.
  std::array<int, 512> hist{};
  int samples = 0;
  for (int y = 0; y < bgr.rows; y += 2) {
    const auto* row = bgr.ptr<std::uint8_t>(y);
    for (int x = 0; x < bgr.cols; x += 2, ++samples) ++hist[colour_bin(row + 3 * x)];
  }
  const double rare_count = rare_fraction * samples;
  double rare_samples = 0.0;
  std::array<std::uint8_t, 512> rare{};
  for (std::size_t i = 0; i < hist.size(); ++i) {
    if (hist[i] >= rare_count) continue;
    rare[i] = 255;
    rare_samples += hist[i];
  }
  // Colours that are each rare but together cover much of the image (colourful texture) are
  // the image's own, not something standing out from it.
  cv::Mat mask(bgr.size(), CV_8U, cv::Scalar(0));
  if (rare_samples > kMaxRareCover * samples) return mask;
  const auto least = static_cast<int>(std::floor(min_chroma));  // chroma > min_chroma
  for (int y = 0; y < bgr.rows; ++y) {
    const auto* row = bgr.ptr<std::uint8_t>(y);
    const auto* c = chroma.ptr<std::uint8_t>(y);
    auto* out = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < bgr.cols; ++x)
      if (c[x] > least) out[x] = rare[colour_bin(row + 3 * x)];
  }
  return mask;
}

}  // namespace

cv::Mat colour_chroma(const cv::Mat& bgr) {
  CV_Assert(bgr.type() == CV_8UC3);
  // One pass: a split and four min/max passes cost three times as much.
  cv::Mat chroma(bgr.size(), CV_8UC1);
  for (int y = 0; y < bgr.rows; ++y)
    chroma_row(bgr.ptr<std::uint8_t>(y), chroma.ptr<std::uint8_t>(y), bgr.cols);
  return chroma;
}

std::vector<Circle> colour_blob_seeds(const cv::Mat& bgr, double min_radius_px,
                                      double max_radius_px, const ColourSeedParams& params) {
  if (bgr.empty() || bgr.type() != CV_8UC3 || bgr.cols < 4 || bgr.rows < 4) return {};
  cv::Mat half;
  cv::resize(bgr, half, cv::Size(bgr.cols / 2, bgr.rows / 2), 0, 0, cv::INTER_AREA);
  const cv::Mat chroma = colour_chroma(half);
  const auto [median, mad] = median_and_mad(chroma);
  const double threshold =
      std::max(params.min_chroma, median + params.spread_factor * 1.4826 * mad);
  cv::Mat mask = chroma > threshold;
  if (params.rare_fraction > 0.0) {
    // At least as colourful as the image's typical pixel: blends of a floor's colours along
    // its joints are rare too, and duller than the floor.
    const double least_chroma = std::max(params.min_chroma, static_cast<double>(median));
    cv::Mat rare = rare_colour_mask(half, chroma, least_chroma, params.rare_fraction);
    // Specks of a rare colour in texture or on edges are not regions. Closed first, so that a
    // small ball's thin stripes become one area, then opened: what does not hold a 3x3 square
    // goes (a ball of 4 px radius and more at full resolution stays).
    if (cv::countNonZero(rare) > 0) {
      cv::morphologyEx(rare, rare, cv::MORPH_CLOSE, close_kernel());
      cv::morphologyEx(rare, rare, cv::MORPH_OPEN, cv::Mat::ones(3, 3, CV_8U));
      mask |= rare;
    }
  }
  // Nothing stands out (a scene without an outstanding colour): no region, and labelling an
  // empty mask would cost more than everything above.
  if (cv::countNonZero(mask) == 0) return {};
  // Stripes of one colour with light ones between: one region.
  cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, close_kernel());
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  struct Region {
    Circle circle;
    int area = 0;
  };
  std::vector<Region> regions;
  for (int i = 1; i < n; ++i) {
    const int w = stats.at<int>(i, cv::CC_STAT_WIDTH), h = stats.at<int>(i, cv::CC_STAT_HEIGHT);
    const int area = stats.at<int>(i, cv::CC_STAT_AREA);
    const double radius = std::max(w, h);  // half-resolution diameter = full-resolution radius
    if (radius < min_radius_px || radius > max_radius_px) continue;
    if (std::max(w, h) > params.max_aspect * std::min(w, h)) continue;
    if (area < params.min_fill * w * h) continue;
    // Half-resolution pixel (x, y) covers full-resolution [2x, 2x + 2): its centre is 2x + 0.5.
    const double cx = 2.0 * (stats.at<int>(i, cv::CC_STAT_LEFT) + 0.5 * w) - 0.5;
    const double cy = 2.0 * (stats.at<int>(i, cv::CC_STAT_TOP) + 0.5 * h) - 0.5;
    regions.push_back({Circle{cx, cy, radius, 0.0}, area});
  }
  std::sort(regions.begin(), regions.end(),
            [](const Region& a, const Region& b) { return a.area > b.area; });
  std::vector<Circle> seeds;
  for (const Region& r : regions) {
    if (static_cast<int>(seeds.size()) >= params.max_seeds) break;
    seeds.push_back(r.circle);
  }
  return seeds;
}

}  // namespace stereoball::ball_detector
