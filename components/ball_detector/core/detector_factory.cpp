#include "ball_detector/core/baselines.hpp"
#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/p2p_detector.hpp"

namespace stereoball::ball_detector {
namespace {

// The options every method's params share.
template <class Params>
Params with_common_options(Params p, const DetectorOptions& o) {
  p.max_circles = o.max_circles;
  p.min_radius_px = o.min_radius_px;
  p.max_radius_px = o.max_radius_px;
  p.min_separation_px = o.min_separation_px;
  return p;
}

}  // namespace

Status validate_image(const cv::Mat& image) {
  if (image.empty()) return Error{"image is empty"};
  if (image.depth() != CV_8U) return Error{"image must have 8-bit pixels"};
  if (image.channels() != 1 && image.channels() != 3 && image.channels() != 4)
    return Error{"image must have 1, 3 or 4 channels"};
  if (image.cols < 8 || image.rows < 8) return Error{"image is smaller than 8x8 pixels"};
  return {};
}

std::vector<std::string> detector_names() {
  return {"p2p", "cht", "gradient", "opencv", "opencv-alt", "edcircles"};
}

std::unique_ptr<CircleDetector> make_detector(const std::string& method, const DetectorOptions& o,
                                              std::string* error) {
  auto fail = [error](std::string msg) -> std::unique_ptr<CircleDetector> {
    if (error) *error = std::move(msg);
    return nullptr;
  };
  if (method == "p2p") {
    auto p = with_common_options(PixelToPixelParams{}, o);
    p.k_values = o.k_values;
    p.min_score = o.min_score;
    p.coarse_to_fine = o.coarse_to_fine;
    if (auto e = p.validate(); !e) return fail("p2p: " + e.error());
    return std::make_unique<PixelToPixelDetector>(p);
  }
  if (method == "gradient") {
    auto p = with_common_options(GradientVotingParams{}, o);
    p.min_score = o.min_score;
    if (auto e = p.validate(); !e) return fail("gradient: " + e.error());
    return std::make_unique<GradientVotingDetector>(p);
  }
  if (method == "cht") {
    auto p = with_common_options(ChtParams{}, o);
    p.min_score = o.min_score;
    if (auto e = p.validate(); !e) return fail("cht: " + e.error());
    return std::make_unique<ChtDetector>(p);
  }
  if (method == "opencv" || method == "opencv-alt") {
    OpenCvHoughParams p;
    p.alt = method == "opencv-alt";
    if (p.alt) {
      p.dp = 1.5;
      p.param1 = 300.0;
      p.param2 = 0.8;
    }
    if (o.opencv_param2 > 0.0) p.param2 = o.opencv_param2;
    p.max_circles = o.max_circles;
    p.min_radius_px = o.min_radius_px;
    p.max_radius_px = o.max_radius_px;
    p.min_separation_px = std::max(1.0, o.min_separation_px);
    if (auto e = p.validate(); !e) return fail(method + ": " + e.error());
    return std::make_unique<OpenCvHoughDetector>(p);
  }
  if (method == "edcircles") {
    const auto p = with_common_options(EdCirclesParams{}, o);
    if (auto e = p.validate(); !e) return fail("edcircles: " + e.error());
    return std::make_unique<EdCirclesDetector>(p);
  }
  return fail("unknown method '" + method +
              "' (expected p2p, cht, gradient, opencv, opencv-alt or edcircles)");
}

}  // namespace stereoball::ball_detector
