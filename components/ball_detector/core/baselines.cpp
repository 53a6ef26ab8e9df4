#include "ball_detector/core/baselines.hpp"

#include "ball_detector/core/fast_math.hpp"
#include "ball_detector/core/p2p_rules.hpp"
#include "ball_detector/core/voting.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <utility>

namespace stereoball::ball_detector {
namespace {

Status check_radii(double min_r, double max_r) {
  if (!(min_r >= 0.0)) return Error{"min_radius_px must be >= 0"};
  if (!(max_r > min_r && max_r <= 4000.0))
    return Error{"max_radius_px must be in (min_radius_px, 4000]"};
  return {};
}

std::vector<cv::Point> digital_circle(double r) {
  std::set<std::pair<int, int>> unique;
  const int samples = std::max(16, static_cast<int>(8.0 * std::numbers::pi * r));
  for (int i = 0; i < samples; ++i) {
    const double a = 2.0 * std::numbers::pi * i / samples;
    unique.insert({static_cast<int>(std::lround(r * std::cos(a))),
                   static_cast<int>(std::lround(r * std::sin(a)))});
  }
  std::vector<cv::Point> pts;
  for (const auto& [x, y] : unique) pts.emplace_back(x, y);
  return pts;
}

}  // namespace

Status GradientVotingParams::validate() const {
  if (auto e = edge.validate(); !e) return Error{"edge." + e.error()};
  if (box_size_px < 1 || box_size_px > 31 || box_size_px % 2 == 0)
    return Error{"box_size_px must be odd and in [1, 31]"};
  if (auto e = check_radii(min_radius_px, max_radius_px); !e) return e;
  if (max_circles < 1 || max_circles > 100) return Error{"max_circles must be in [1, 100]"};
  if (!(min_score >= 0.0 && min_score <= 1.0)) return Error{"min_score must be in [0, 1]"};
  return {};
}

GradientVotingDetector::GradientVotingDetector(const GradientVotingParams& params)
    : params_(params) {
  params_.box_size_px = std::clamp(params_.box_size_px | 1, 1, 31);
}

std::vector<Circle> GradientVotingDetector::detect(const cv::Mat& bgr_or_grey) {
  diag_ = DetectionDiagnostics{};
  peak_ratio_done_ = false;
  voters_.clear();
  if (!validate_image(bgr_or_grey).ok()) return {};
  compute_edge_map(bgr_or_grey, params_.edge, edges_);
  accumulator_.create(edges_.edges.size(), CV_16UC1);
  accumulator_.setTo(0);
  const BitImage& bits = edges_.bits;
  for (int y = 0; y < bits.height(); ++y) {
    const short* gx = edges_.dx.ptr<short>(y);
    const short* gy = edges_.dy.ptr<short>(y);
    bits.for_each_set_in_row(y, [&](int x) {
      const double g = fast_hypot(gx[x], gy[x]);
      if (g <= 0.0) return;
      const float ux = static_cast<float>(gx[x] / g), uy = static_cast<float>(gy[x] / g);
      for (float s : {1.0f, -1.0f}) {
        diag_.increments += plot_ray(accumulator_, x, y, s * ux, s * uy, params_.min_radius_px,
                                     params_.max_radius_px);
        voters_.push_back({static_cast<float>(x), static_cast<float>(y), s * ux, s * uy});
      }
      ++diag_.voters;
    });
  }
  const cv::Mat smoothed = box_filter(accumulator_, params_.box_size_px);
  diag_.edges = edges_.edges;
  diag_.accumulator = smoothed;
  double max_v = 0.0;
  cv::minMaxLoc(smoothed, nullptr, &max_v);
  if (max_v <= 0.0) return {};
  const auto peaks = find_peaks(smoothed, static_cast<float>(params_.min_relative_peak * max_v),
                                params_.min_separation_px, 3 * params_.max_circles);
  return circles_from_votes(
      edges_, voters_, peaks,
      candidate_options_of(params_, RadiusRange{params_.min_radius_px, params_.max_radius_px}));
}

const DetectionDiagnostics* GradientVotingDetector::diagnostics() const {
  if (!peak_ratio_done_ && !diag_.accumulator.empty()) {
    diag_.peak_to_mean = peak_to_mean(diag_.accumulator);
    peak_ratio_done_ = true;
  }
  return &diag_;
}

Status ChtParams::validate() const {
  if (auto e = edge.validate(); !e) return Error{"edge." + e.error()};
  if (auto e = check_radii(min_radius_px, max_radius_px); !e) return e;
  if (!(radius_step_px >= 0.25 && radius_step_px <= 100.0))
    return Error{"radius_step_px must be in [0.25, 100]"};
  if (max_circles < 1 || max_circles > 100) return Error{"max_circles must be in [1, 100]"};
  if (!(min_score >= 0.0 && min_score <= 1.0)) return Error{"min_score must be in [0, 1]"};
  return {};
}

ChtDetector::ChtDetector(const ChtParams& params) : params_(params) {
  const double r0 = std::max(1.0, params_.min_radius_px);
  const double step = std::max(0.25, params_.radius_step_px);
  for (double r = r0; r <= params_.max_radius_px + 1e-9; r += step) {
    radii_.push_back(static_cast<float>(r));
    offsets_.push_back(digital_circle(r));
  }
}

std::vector<Circle> ChtDetector::detect(const cv::Mat& bgr_or_grey) {
  diag_ = DetectionDiagnostics{};
  if (!validate_image(bgr_or_grey).ok() || radii_.empty()) return {};
  compute_edge_map(bgr_or_grey, params_.edge, edges_);
  const int w = edges_.edges.cols, h = edges_.edges.rows;
  const size_t plane = static_cast<size_t>(w) * h;
  votes_.assign(plane * radii_.size(), 0);
  const BitImage& bits = edges_.bits;
  for (int y = 0; y < h; ++y) {
    bits.for_each_set_in_row(y, [&](int x) {
      ++diag_.voters;
      for (size_t ri = 0; ri < radii_.size(); ++ri) {
        std::uint16_t* acc = votes_.data() + ri * plane;
        for (const auto& o : offsets_[ri]) {
          const unsigned cx = static_cast<unsigned>(x + o.x), cy = static_cast<unsigned>(y + o.y);
          if (cx >= static_cast<unsigned>(w) || cy >= static_cast<unsigned>(h)) continue;
          std::uint16_t& cell = acc[cy * static_cast<size_t>(w) + cx];
          if (cell != 0xFFFF) ++cell;
          ++diag_.increments;
        }
      }
    });
  }
  // Best normalised support over r for each (x, y): votes / number of circle pixels.
  cv::Mat best(h, w, CV_32F, cv::Scalar(0));
  cv::Mat best_r(h, w, CV_32F, cv::Scalar(0));
  for (size_t ri = 0; ri < radii_.size(); ++ri) {
    const float inv = 1.0f / static_cast<float>(offsets_[ri].size());
    const std::uint16_t* acc = votes_.data() + ri * plane;
    auto* b = best.ptr<float>(0);
    auto* br = best_r.ptr<float>(0);
    for (size_t i = 0; i < plane; ++i) {
      const float v = acc[i] * inv;
      if (v > b[i]) {
        b[i] = v;
        br[i] = radii_[ri];
      }
    }
  }
  diag_.edges = edges_.edges;
  const auto peaks = find_peaks(best, static_cast<float>(params_.min_score),
                                params_.min_separation_px, params_.max_circles);
  std::vector<Circle> out;
  for (const auto& p : peaks)
    out.push_back({static_cast<double>(p.x), static_cast<double>(p.y),
                   static_cast<double>(best_r.at<float>(p.y, p.x)), std::min(1.0f, p.value)});
  return out;
}

Status OpenCvHoughParams::validate() const {
  if (!(dp >= 1.0 && dp <= 4.0)) return Error{"dp must be in [1, 4]"};
  if (!(param1 > 0.0)) return Error{"param1 must be > 0"};
  if (alt && !(param2 > 0.0 && param2 <= 1.0)) return Error{"param2 must be in (0, 1] for ALT"};
  if (!alt && !(param2 > 0.0)) return Error{"param2 must be > 0"};
  if (auto e = check_radii(min_radius_px, max_radius_px); !e) return e;
  if (!(min_separation_px > 0.0)) return Error{"min_separation_px must be > 0"};
  if (max_circles < 1 || max_circles > 100) return Error{"max_circles must be in [1, 100]"};
  if (blur_ksize != 0 && (blur_ksize < 3 || blur_ksize % 2 == 0))
    return Error{"blur_ksize must be 0 or odd >= 3"};
  return {};
}

OpenCvHoughDetector::OpenCvHoughDetector(const OpenCvHoughParams& params) : params_(params) {}

std::vector<Circle> OpenCvHoughDetector::detect(const cv::Mat& bgr_or_grey) {
  if (!validate_image(bgr_or_grey).ok()) return {};
  cv::Mat grey = to_grey(bgr_or_grey);
  if (params_.blur_ksize >= 3) cv::medianBlur(grey, grey, params_.blur_ksize);
  std::vector<cv::Vec4f> found;
  cv::HoughCircles(grey, found, params_.alt ? cv::HOUGH_GRADIENT_ALT : cv::HOUGH_GRADIENT,
                   params_.dp, params_.min_separation_px, params_.param1, params_.param2,
                   static_cast<int>(std::floor(params_.min_radius_px)),
                   static_cast<int>(std::ceil(params_.max_radius_px)));
  std::vector<Circle> out;
  for (const auto& f : found) {
    if (static_cast<int>(out.size()) >= params_.max_circles) break;
    const double circumference = 2.0 * std::numbers::pi * std::max(1.0f, f[2]);
    const double score = f[3] > 0.0f ? std::min(1.0, f[3] / circumference) : 1.0;
    out.push_back({f[0], f[1], f[2], score});
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  return out;
}

}  // namespace stereoball::ball_detector
