#include "ball_detector/core/baselines.hpp"

#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_drawing.hpp>

#include <algorithm>
#include <cmath>

namespace stereoball::ball_detector {

Status EdCirclesParams::validate() const {
  if (gradient_threshold < 1 || gradient_threshold > 255)
    return Error{"gradient_threshold must be in [1, 255]"};
  if (anchor_threshold < 0 || anchor_threshold > 255)
    return Error{"anchor_threshold must be in [0, 255]"};
  if (!(sigma > 0.0 && sigma <= 10.0)) return Error{"sigma must be in (0, 10]"};
  if (!(min_axis_ratio >= 0.0 && min_axis_ratio <= 1.0))
    return Error{"min_axis_ratio must be in [0, 1]"};
  if (!(min_radius_px >= 0.0)) return Error{"min_radius_px must be >= 0"};
  if (!(max_radius_px > min_radius_px)) return Error{"max_radius_px must be > min_radius_px"};
  if (!(min_separation_px >= 0.0)) return Error{"min_separation_px must be >= 0"};
  if (max_circles < 1 || max_circles > 100) return Error{"max_circles must be in [1, 100]"};
  return {};
}

struct EdCirclesDetector::Impl {
  cv::Ptr<cv::ximgproc::EdgeDrawing> ed = cv::ximgproc::createEdgeDrawing();
};

EdCirclesDetector::EdCirclesDetector(const EdCirclesParams& params)
    : params_(params), impl_(std::make_unique<Impl>()) {
  auto& p = impl_->ed->params;
  p.GradientThresholdValue = params_.gradient_threshold;
  p.AnchorThresholdValue = params_.anchor_threshold;
  p.Sigma = static_cast<float>(params_.sigma);
  p.PFmode = params_.parameter_free;
}

EdCirclesDetector::~EdCirclesDetector() = default;

std::vector<Circle> EdCirclesDetector::detect(const cv::Mat& bgr_or_grey) {
  if (!validate_image(bgr_or_grey).ok()) return {};
  impl_->ed->detectEdges(to_grey(bgr_or_grey));
  std::vector<cv::Vec6d> found;
  impl_->ed->detectEllipses(found);
  // Each entry: centre x, y; radius (circles) or 0; semi-axes a, b (ellipses) or 0; angle.
  std::vector<Circle> all;
  for (const auto& f : found) {
    double r = f[2], ratio = 1.0;
    if (r <= 0.0) {
      const double a = std::max(f[3], f[4]), b = std::min(f[3], f[4]);
      if (!(a > 0.0)) continue;
      ratio = b / a;
      if (ratio < params_.min_axis_ratio) continue;
      r = 0.5 * (a + b);
    }
    if (r < params_.min_radius_px || r > params_.max_radius_px) continue;
    all.push_back({f[0], f[1], r, ratio});
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  std::vector<Circle> out;
  for (const auto& c : all) {
    if (static_cast<int>(out.size()) >= params_.max_circles) break;
    const bool close = std::any_of(out.begin(), out.end(), [&](const Circle& o) {
      return std::hypot(o.x_px - c.x_px, o.y_px - c.y_px) < params_.min_separation_px;
    });
    if (!close) out.push_back(c);
  }
  return out;
}

}  // namespace stereoball::ball_detector
