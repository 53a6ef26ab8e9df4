#pragma once
// Baselines behind the CircleDetector interface, for comparison with Pixel-to-Pixel:
// classic 3D CHT, gradient-direction line voting, OpenCV HoughCircles, EDCircles.

#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "common/util/result.hpp"

#include <optional>
#include <string>
#include <vector>

namespace stereoball::ball_detector {

/// Parameters of the gradient-direction line voting baseline (Kimme / Minor-Sklansky / Faez).
struct GradientVotingParams {
  EdgeParams edge;                  ///< same edge step as Pixel-to-Pixel
  int box_size_px = 5;              ///< accumulator smoothing (odd), pixels
  double min_radius_px = 4.0;       ///< votes start this far from the edge point, pixels
  double max_radius_px = 120.0;     ///< votes stop this far, pixels
  int max_circles = 5;              ///< most circles returned
  double min_separation_px = 10.0;  ///< closest two centres, pixels
  double min_score = 0.55;          ///< score threshold, [0, 1]
  double min_relative_peak = 0.15;  ///< peaks below this fraction of the strongest are ignored
  bool refine = true;               ///< same least-squares refinement as Pixel-to-Pixel
  RefineParams refine_params;

  /// Success, or an error naming the first bad field and its allowed range.
  Status validate() const;
};

/// Every edge point draws a line along its gradient, both ways (the ball may be darker or
/// brighter than the background), between min and max radius.
class GradientVotingDetector final : public CircleDetector {
 public:
  explicit GradientVotingDetector(const GradientVotingParams& params);
  std::vector<Circle> detect(const cv::Mat& bgr_or_grey) override;
  const DetectionDiagnostics* diagnostics() const override;
  std::string name() const override { return "gradient"; }

 private:
  GradientVotingParams params_;
  EdgeMap edges_;
  cv::Mat accumulator_;
  std::vector<Voter> voters_;
  mutable DetectionDiagnostics diag_;
  mutable bool peak_ratio_done_ = false;
};

/// Parameters of the classic circle Hough transform with an (x, y, r) accumulator.
struct ChtParams {
  EdgeParams edge;                  ///< same edge step as Pixel-to-Pixel
  double min_radius_px = 4.0;       ///< smallest radius, pixels
  double max_radius_px = 120.0;     ///< largest radius, pixels
  double radius_step_px = 1.0;      ///< radius sampling, pixels
  int max_circles = 5;              ///< most circles returned
  double min_separation_px = 10.0;  ///< closest two centres, pixels
  double min_score = 0.5;           ///< votes / circle length threshold, [0, 1]

  /// Success, or an error naming the first bad field and its allowed range.
  Status validate() const;
};

/// Classic CHT: each edge point votes a full circle for every radius; score = votes / circle
/// length.
class ChtDetector final : public CircleDetector {
 public:
  explicit ChtDetector(const ChtParams& params);
  std::vector<Circle> detect(const cv::Mat& bgr_or_grey) override;
  const DetectionDiagnostics* diagnostics() const override { return &diag_; }
  std::string name() const override { return "cht"; }

 private:
  ChtParams params_;
  EdgeMap edges_;
  std::vector<float> radii_;
  std::vector<std::vector<cv::Point>> offsets_;  // digital circle per radius
  std::vector<std::uint16_t> votes_;
  DetectionDiagnostics diag_;
};

/// Parameters of the OpenCV HoughCircles baseline.
struct OpenCvHoughParams {
  bool alt = false;                 ///< HOUGH_GRADIENT_ALT instead of HOUGH_GRADIENT
  double dp = 1.0;                  ///< accumulator resolution divisor
  double param1 = 100.0;            ///< Canny high threshold
  double param2 = 30.0;             ///< accumulator threshold (ALT: circle "perfectness" in (0, 1])
  double min_radius_px = 4.0;       ///< smallest radius, pixels
  double max_radius_px = 120.0;     ///< largest radius, pixels
  double min_separation_px = 10.0;  ///< OpenCV minDist, pixels
  int max_circles = 5;              ///< most circles returned
  int blur_ksize = 0;               ///< median blur before detection (0 = none, else odd)

  /// Success, or an error naming the first bad field and its allowed range.
  Status validate() const;
};

/// cv::HoughCircles; score = min(1, votes / circumference) when OpenCV reports votes.
class OpenCvHoughDetector final : public CircleDetector {
 public:
  explicit OpenCvHoughDetector(const OpenCvHoughParams& params);
  std::vector<Circle> detect(const cv::Mat& bgr_or_grey) override;
  std::string name() const override { return params_.alt ? "opencv-alt" : "opencv"; }

 private:
  OpenCvHoughParams params_;
};

/// Parameters of the EDCircles baseline (cv::ximgproc::EdgeDrawing, OpenCV contrib).
struct EdCirclesParams {
  int gradient_threshold = 20;      ///< Edge Drawing's gradient threshold (its default 20), >= 1
  int anchor_threshold = 0;         ///< anchor threshold (its default 0), >= 0
  double sigma = 1.0;               ///< Gaussian pre-blur sigma (its default 1), > 0
  bool parameter_free = false;      ///< EDPF: thresholds from the image (Helmholtz principle)
  double min_axis_ratio = 0.9;      ///< an ellipse counts as a circle above this minor/major
  double min_radius_px = 4.0;       ///< smallest radius kept, pixels
  double max_radius_px = 120.0;     ///< largest radius kept, pixels
  double min_separation_px = 10.0;  ///< closest two centres, pixels (the stronger is kept)
  int max_circles = 5;              ///< most circles returned

  /// Success, or an error naming the first bad field and its allowed range.
  Status validate() const;
};

/// EDCircles (Akinlar & Topal 2013): Edge Drawing's one-pixel edge chains, arcs fitted to
/// them, joined into circles and ellipses and validated by the number of false alarms.
/// Near-circular ellipses become circles (mean of the semi-axes); score = minor/major.
class EdCirclesDetector final : public CircleDetector {
 public:
  explicit EdCirclesDetector(const EdCirclesParams& params);
  ~EdCirclesDetector() override;
  std::vector<Circle> detect(const cv::Mat& bgr_or_grey) override;
  std::string name() const override { return "edcircles"; }

 private:
  struct Impl;
  EdCirclesParams params_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace stereoball::ball_detector
