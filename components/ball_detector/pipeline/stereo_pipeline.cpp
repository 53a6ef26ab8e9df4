#include "ball_detector/pipeline/stereo_pipeline.hpp"

#include "ball_detector/core/colour_seeds.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>

namespace stereoball::ball_detector {
namespace {

constexpr int kPatchHalf = kPatchSide / 2;
// Where a circle's colour is sampled: rings at these fractions of its radius, kColourAngles
// points each, and the centre (inside the ball, clear of its outline and the background).
constexpr double kColourRings[] = {0.2, 0.4, 0.55, 0.7};
constexpr int kColourAngles = 12;

Status check_pixels(const char* eye, const cv::Mat& m) {
  if (m.empty()) return Error{std::string(eye) + " image is empty"};
  if (m.depth() != CV_8U || (m.channels() != 1 && m.channels() != 3))
    return Error{std::string(eye) + " image must be 8-bit grey or BGR (got " +
                 std::to_string(m.channels()) + " channels, depth " + std::to_string(m.depth()) +
                 ")"};
  return {};
}

DetectionStatus from_pairing(PairingStatus s) {
  switch (s) {
    case PairingStatus::kFound:
      return DetectionStatus::kFound;
    case PairingStatus::kNoCandidate:
      return DetectionStatus::kNoCandidate;
    case PairingStatus::kEpipolarMismatch:
      return DetectionStatus::kEpipolarMismatch;
    case PairingStatus::kSizeInconsistent:
      return DetectionStatus::kSizeInconsistent;
    case PairingStatus::kOffFloor:
      return DetectionStatus::kOffFloor;
  }
  return DetectionStatus::kNoCandidate;
}

// Writes pixel (b, g, r) or grey v of an 8-bit image at (x, y) into the patch as R, G, B.
void put_rgb(const cv::Mat& image, int x, int y, std::uint8_t* dst) {
  if (image.channels() == 3) {
    const auto& p = image.at<cv::Vec3b>(y, x);
    dst[0] = p[2];
    dst[1] = p[1];
    dst[2] = p[0];
  } else {
    dst[0] = dst[1] = dst[2] = image.at<std::uint8_t>(y, x);
  }
}

}  // namespace

// Per-thread planes reused from call to call: split + SIMD min/max is ~20x faster than a
// per-pixel loop over interleaved BGR.
struct Planes {
  cv::Mat ch[3];
  cv::Mat tmp;
};

Planes& planes() {
  thread_local Planes p;
  return p;
}

void saturation(const cv::Mat& bgr, cv::Mat& out) {
  Planes& p = planes();
  cv::split(bgr, p.ch);
  cv::min(p.ch[0], p.ch[1], p.tmp);
  cv::min(p.tmp, p.ch[2], p.tmp);
  cv::max(p.ch[0], p.ch[1], out);
  cv::max(out, p.ch[2], out);
  cv::subtract(out, p.tmp, out);
}

void value(const cv::Mat& bgr, cv::Mat& out) {
  Planes& p = planes();
  cv::split(bgr, p.ch);
  cv::max(p.ch[0], p.ch[1], out);
  cv::max(out, p.ch[2], out);
}

void extract_patch(const cv::Mat& image, double x_px, double y_px,
                   std::array<std::uint8_t, kPatchBytes>& out) {
  const int cx = static_cast<int>(std::lround(x_px));
  const int cy = static_cast<int>(std::lround(y_px));
  std::uint8_t* dst = out.data();
  for (int r = 0; r < kPatchSide; ++r) {
    const int y = std::clamp(cy - kPatchHalf + r, 0, image.rows - 1);
    for (int c = 0; c < kPatchSide; ++c, dst += 3)
      put_rgb(image, std::clamp(cx - kPatchHalf + c, 0, image.cols - 1), y, dst);
  }
}

std::optional<FloorModel> floor_model(const BallDetectorParams& params,
                                      const stereo::StereoCalibration& calib) {
  if (!(params.floor_tolerance_m > 0.0)) return std::nullopt;
  // Up in the raw left camera (x right, y down, z forward) pitched down by phi about x.
  const double phi = params.floor_camera_pitch_rad;
  const cv::Vec3d up_raw(0.0, -std::cos(phi), -std::sin(phi));
  FloorModel floor;
  floor.up = calib.r1 * up_raw;  // r1 takes raw left camera coordinates to rectified ones
  floor.camera_height_m = params.floor_camera_height_m;
  floor.tolerance_m = params.floor_tolerance_m;
  return floor;
}

void run_tasks_in_turn(int n, const std::function<void(int)>& task) {
  for (int i = 0; i < n; ++i) task(i);
}

const char* to_string(SearchPath path) {
  switch (path) {
    case SearchPath::kExpectedOutlines:
      return "expected_outlines";
    case SearchPath::kPriorWindow:
      return "prior_window";
    case SearchPath::kWholeFrame:
      return "whole_frame";
    case SearchPath::kRadiusBands:
      return "radius_bands";
    case SearchPath::kBrightnessFree:
      return "brightness_free";
  }
  return "?";
}

const char* to_string(DetectionStatus status) {
  switch (status) {
    case DetectionStatus::kFound:
      return "found";
    case DetectionStatus::kNoCandidate:
      return "no_candidate";
    case DetectionStatus::kEpipolarMismatch:
      return "epipolar_mismatch";
    case DetectionStatus::kSizeInconsistent:
      return "size_inconsistent";
    case DetectionStatus::kNoCalibration:
      return "no_calibration";
    case DetectionStatus::kBadFrame:
      return "bad_frame";
    case DetectionStatus::kOffFloor:
      return "off_floor";
    case DetectionStatus::kInteriorMismatch:
      return "interior_mismatch";
  }
  return "unknown";
}

StereoPipeline::StereoPipeline(const BallDetectorParams& params)
    : params_(params),
      configured_p2p_(params.p2p),
      left_detector_(params.detector_params()),
      right_detector_(params.detector_params()),
      seed_detector_(params.detector_params()),
      epipolar_(stereo::EpipolarParams{params.epipolar_tolerance_px}),
      size_{params.ball_diameter_m, params.size_max_relative_error},
      appearance_(params.appearance) {
  patch_rays_.resize(kPatchSide * kPatchSide);
  patch_raw_px_.reserve(kPatchSide * kPatchSide);
  patch_map_.create(kPatchSide, kPatchSide, CV_32FC2);
  left_candidates_.reserve(static_cast<std::size_t>(params.max_candidates_per_eye));
  right_candidates_.reserve(static_cast<std::size_t>(params.max_candidates_per_eye));
}

Status StereoPipeline::set_calibration(const stereo::StereoCalibration& calib) {
  if (auto e = stereo::validate_calibration(calib); !e) return e;
  if (auto swapped = stereo::check_camera_order(calib); !swapped)
    return Error{swapped.error() + "; " + kHowToSwapCameras + " and calibrate again"};
  auto rectifier = stereo::Rectifier::create(calib);
  if (!rectifier) return Error{rectifier.error()};
  auto triangulator = stereo::Triangulator::create(calib);
  if (!triangulator) return Error{triangulator.error()};
  rectifier_.emplace(std::move(rectifier).value());
  triangulator_.emplace(std::move(triangulator).value());
  const PixelToPixelParams p2p =
      scaled_to_width(configured_p2p_, params_.p2p_reference_width_px, calib.image_size.width);
  if (p2p.k_values != params_.p2p.k_values || p2p.min_radius_px != params_.p2p.min_radius_px) {
    params_.p2p = p2p;
    left_detector_ = PixelToPixelDetector(params_.detector_params());
    right_detector_ = PixelToPixelDetector(params_.detector_params());
    seed_detector_ = PixelToPixelDetector(params_.detector_params());
    band_detectors_.clear();
    left_thresholds_.reset();
  }
  if (params_.perspective_outline) {
    left_detector_.set_camera(
        stereo::PinholeCamera{triangulator_->focal_px(), triangulator_->principal_left_px()});
    right_detector_.set_camera(
        stereo::PinholeCamera{triangulator_->focal_px(), triangulator_->principal_right_px()});
  }
  for (PixelToPixelDetector& d : band_detectors_)
    d.set_camera(params_.perspective_outline ? left_camera() : std::nullopt);
  const cv::Matx33d p(calib.p1(0, 0), calib.p1(0, 1), calib.p1(0, 2), calib.p1(1, 0),
                      calib.p1(1, 1), calib.p1(1, 2), calib.p1(2, 0), calib.p1(2, 1),
                      calib.p1(2, 2));
  patch_ray_from_pixel_ = calib.r1.t() * p.inv();
  floor_ = floor_model(params_, calib);
  return {};
}

std::optional<stereo::PinholeCamera> StereoPipeline::left_camera() const {
  if (!triangulator_) return std::nullopt;
  return stereo::PinholeCamera{triangulator_->focal_px(), triangulator_->principal_left_px()};
}

std::optional<stereo::PinholeCamera> StereoPipeline::right_camera() const {
  if (!triangulator_) return std::nullopt;
  return stereo::PinholeCamera{triangulator_->focal_px(), triangulator_->principal_right_px()};
}

cv::Size StereoPipeline::image_size() const {
  return rectifier_ ? rectifier_->calibration().image_size : cv::Size();
}

Status StereoPipeline::check_input(const cv::Mat& left, const cv::Mat& right) const {
  if (auto e = check_pixels("left", left); !e) return e;
  if (auto e = check_pixels("right", right); !e) return e;
  if (left.type() != right.type()) return Error{"left and right images differ in type"};
  return stereo::check_image_size(rectifier_->calibration(), left.size(), right.size());
}

const cv::Mat& detector_input_image(const cv::Mat& image, DetectorInput input, cv::Mat& scratch) {
  // One channel first (remapping one channel is cheaper), unless edges come from colour.
  if (image.channels() != 3 || input == DetectorInput::kColour) return image;
  switch (input) {
    case DetectorInput::kGrey:
      cv::cvtColor(image, scratch, cv::COLOR_BGR2GRAY);
      break;
    case DetectorInput::kSaturation:
      saturation(image, scratch);
      break;
    case DetectorInput::kValue:
      value(image, scratch);
      break;
    case DetectorInput::kRed:
      cv::extractChannel(image, scratch, 2);
      break;
    case DetectorInput::kGreen:
      cv::extractChannel(image, scratch, 1);
      break;
    case DetectorInput::kBlue:
      cv::extractChannel(image, scratch, 0);
      break;
    case DetectorInput::kColour:
      return image;
  }
  return scratch;
}

const cv::Mat& StereoPipeline::detector_channel(const cv::Mat& raw, cv::Mat& grey) const {
  return detector_input_image(raw, params_.input, grey);
}

void StereoPipeline::rectify_whole(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                   cv::Mat& out) const {
  if (rectified) {
    channel.copyTo(out);
  } else {
    rectifier_->rectify_eye(eye, channel, out);
  }
}

void StereoPipeline::clear_rectified(const cv::Mat& channel, cv::Mat& out) const {
  out.create(rectifier_->calibration().image_size, channel.type());
  out.setTo(0);
}

void StereoPipeline::rectify_box(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                 const cv::Rect& box, cv::Mat& out) const {
  if (rectified) {
    channel(box).copyTo(out(box));
  } else {
    rectifier_->rectify_eye_region(eye, channel, box, out);
  }
}

const cv::Mat& StereoPipeline::rectified_region(const cv::Mat& channel, stereo::Eye eye,
                                                bool rectified, const cv::Rect& region) {
  if (rectified) return channel;
  // Only the region read, not the whole eye, into the eye's scratch image.
  cv::Mat& out = eye == stereo::Eye::kLeft ? region_left_ : region_right_;
  out.create(rectifier_->calibration().image_size, channel.type());
  rectifier_->rectify_eye_region(eye, channel, region, out);
  return out;
}

double StereoPipeline::motion_radii(std::optional<std::int64_t> eye_skew_ns,
                                    const std::optional<PositionPrior>& prior) const {
  double speed = params_.epipolar_ball_speed_mps;
  if (!(speed > 0.0)) return 0.0;
  const std::int64_t skew_ns =
      params_.epipolar_skew_ns >= 0 ? params_.epipolar_skew_ns : eye_skew_ns.value_or(0);
  if (prior) speed = std::min(speed, cv::norm(prior->velocity_mps) + kTrackSpeedSlackMps);
  return speed * 1e-9 * static_cast<double>(std::abs(skew_ns)) / (0.5 * params_.ball_diameter_m);
}

StereoDetection StereoPipeline::step(const cv::Mat& left, const cv::Mat& right, bool rectified,
                                     const std::optional<PositionPrior>& prior,
                                     std::int64_t stamp_ns,
                                     std::optional<std::int64_t> eye_skew_ns) {
  StereoDetection out;
  left_candidates_.clear();
  right_candidates_.clear();
  colour_seeds_.clear();
  appearance_.tick(stamp_ns);
  frame_left_ = &left;
  frame_rectified_ = rectified;
  rejected_by_colour_ = 0;
  if (!rectifier_) {
    out.status = DetectionStatus::kNoCalibration;
    out.reason = "no stereo calibration received yet";
    return out;
  }
  if (auto e = check_input(left, right); !e) {
    out.status = DetectionStatus::kBadFrame;
    out.reason = e.error();
    return out;
  }
  frame_motion_radii_ = motion_radii(eye_skew_ns, prior);
  const PairingContext ctx{epipolar_, *triangulator_,      size_,
                           floor_,    frame_motion_radii_, params_.dominance_margin};
  const cv::Mat& left_channel = detector_channel(left, grey_left_);
  const cv::Mat& right_channel = detector_channel(right, grey_right_);
  if (refresh_due_) refresh_thresholds(left_channel, rectified);  // finish_frame was not called
  std::optional<PairingResult> pairing;
  if (prior && params_.prior_window && left_thresholds_) {
    pairing = search_near_prior(ctx, left_channel, right_channel, rectified, *prior);
    // Found where the track expects it: that is the answer (a pair elsewhere would not win over
    // it, see pair_candidates), so the whole frame is not searched in the frame's time; only its
    // thresholds are measured again now and then, after the answer (finish_frame).
    if (pairing && frames_since_full_search_ >= kFullSearchEveryFrames) refresh_due_ = true;
    if (pairing) out.search = near_prior_path_;
  }
  bool whole_frame = false;
  std::optional<std::vector<Circle>> band_left;  // the left eye's radius bands, when due
  // Every kBandSearchEveryFrames frames without a pair, and at low frame rates (stills, a slow
  // source) whenever kBandSearchEveryNs have passed since the last band search.
  const bool bands_due =
      frames_without_pair_ % kBandSearchEveryFrames == 0 ||
      (last_band_search_ns_ && stamp_ns - *last_band_search_ns_ > kBandSearchEveryNs);
  if (!pairing) {
    pairing = search_whole_frame(ctx, left_channel, right_channel, rectified, prior,
                                 bands_due ? &band_left : nullptr);
    whole_frame = true;
  }
  // A later search after nothing paired: its pair if it finds one; otherwise the report keeps
  // the earlier searches' candidates.
  const auto fall_back_to = [&](const auto& search) {
    auto earlier_left = left_candidates_, earlier_right = right_candidates_;
    PairingResult later = search();
    if (later.status == PairingStatus::kFound) {
      pairing = std::move(later);
      return true;
    }
    left_candidates_ = std::move(earlier_left);
    right_candidates_ = std::move(earlier_right);
    return false;
  };
  // Nothing paired over the whole frame: the left eye again radius band by radius band, each
  // circle's right box with its own radii (kBandSearchEveryFrames: costly, so not every frame).
  if (pairing->status == PairingStatus::kFound) frames_without_pair_ = 0;
  if (whole_frame && pairing->status != PairingStatus::kFound &&
      (++frames_without_pair_, bands_due)) {
    out.search = SearchPath::kRadiusBands;
    last_band_search_ns_ = stamp_ns;
    // The bands paired what the whole range missed (a ball that clutter outscores in one
    // accumulator): the next frame without a pair tries them again at once, not
    // kBandSearchEveryFrames later.
    if (fall_back_to([&] {
          if (!band_left) band_left = detect_left_in_bands(nullptr);
          return search_radius_bands(ctx, std::move(*band_left), right_channel, rectified, prior);
        }))
      frames_without_pair_ = 0;
  }
  // Still nothing: the colour seeds' outlines without brightness (a hue-only rim).
  if (whole_frame && pairing->status != PairingStatus::kFound && !colour_seeds_.empty() &&
      params_.colour_seeds.chroma_outlines && fall_back_to([&] {
        return pair_seeds_without_brightness(ctx, left_channel, right_channel, rectified, prior,
                                             colour_seeds_);
      }))
    out.search = SearchPath::kBrightnessFree;
  out.candidates_left = static_cast<int>(left_candidates_.size());
  out.candidates_right = static_cast<int>(right_candidates_.size());

  fill_result(*pairing, out);
  if (out.status == DetectionStatus::kFound && params_.interior_depth.enabled)
    check_interior(left_channel, right_channel, rectified, out);
  if (out.status == DetectionStatus::kFound && params_.outline_refit.enabled)
    refit_outlines(ctx, left_channel, right_channel, rectified, out);
  if (out.status == DetectionStatus::kFound && params_.balance_radii)
    balance_radii(left_channel, right_channel, rectified, out);
  out.rejected_by_colour = rejected_by_colour_;
  if (params_.right_eye_partner_boxes && left_candidates_.empty())
    out.reason =
        rejected_by_colour_ > 0
            ? "every left circle differs in colour from the followed ball"
            : "no circle in the left eye (the right eye is searched only near left circles)";
  if (out.status == DetectionStatus::kFound) {
    cut_patch(left, rectified, out);
    // Where the following tracker expects the ball: this is the ball it follows.
    if (prior && cv::norm(out.position_m - prior->position_m) <= prior->gate_m) {
      if (auto h = colour_of(out.left)) appearance_.learn(*h, stamp_ns);
    }
  }
  frame_left_ = nullptr;
  return out;
}

void StereoPipeline::refresh_thresholds(const cv::Mat& left_channel, bool rectified) {
  rectify_whole(left_channel, stereo::Eye::kLeft, rectified, refresh_left_);
  left_thresholds_ =
      measure_edge_thresholds(refresh_left_, params_.detector_params().edge, refresh_edges_);
  frames_since_full_search_ = 0;
  refresh_due_ = false;
}

bool StereoPipeline::finish_frame(const cv::Mat& left, bool rectified) {
  if (!refresh_due_ || !rectifier_ || !check_pixels("left", left).ok() ||
      !stereo::check_image_size(rectifier_->calibration(), left.size(), left.size()).ok())
    return false;
  refresh_thresholds(detector_channel(left, grey_left_), rectified);
  return true;
}

std::optional<PairingResult> StereoPipeline::search_near_prior(const PairingContext& ctx,
                                                               const cv::Mat& left_channel,
                                                               const cv::Mat& right_channel,
                                                               bool rectified,
                                                               const PositionPrior& prior) {
  const cv::Size size = rectifier_->calibration().image_size;
  const cv::Rect box = prior_search_box(ctx, prior, size, window_margin_px());
  if (box.width < 8 || box.height < 8) return std::nullopt;
  clear_rectified(left_channel, rect_left_);
  rectify_box(left_channel, stereo::Eye::kLeft, rectified, box, rect_left_);
  left_candidates_.clear();
  // The tracker expects the ball here: a ball it follows out of the view is still scored on
  // what is left of it in the image.
  SearchHints hints{prior_radius_range(ctx, prior), params_.prior_min_inside_fraction};
  // A ball the tracker follows out of the view may have its centre outside the image.
  hints.centre_margin_px = prior_centre_margin_px(ctx, prior, size);
  if (params_.prior_seeded) {
    const int rejected_before = rejected_by_colour_;
    auto seeded = pair_at_expected_outlines(ctx, right_channel, rectified, prior, box, hints);
    if (seeded) {
      ++frames_since_full_search_;
      near_prior_path_ = SearchPath::kExpectedOutlines;
      return seeded;
    }
    left_candidates_.clear();  // the box is searched as if that had not been tried
    rejected_by_colour_ = rejected_before;
  }
  for (const Circle& c : left_detector_.detect(rect_left_(box), *left_thresholds_, hints))
    left_candidates_.push_back(shifted(c, box.tl()));
  right_candidates_ = detect_right_in_boxes(ctx, right_channel, rectified, true);
  PairingResult pairing = pair_with_predicted_partners(ctx, prior, true);
  ++frames_since_full_search_;
  near_prior_path_ = SearchPath::kPriorWindow;
  // Only a ball where the track expects it ends the search; anything else needs the frame.
  if (pairing.status == PairingStatus::kFound &&
      cv::norm(pairing.best->position_m - prior.position_m) <= prior.gate_m)
    return pairing;
  // The expected outline once more without brightness (a hue-only rim), before the frame.
  if (params_.colour_seeds.chroma_outlines) {
    auto seeded =
        pair_expected_without_brightness(ctx, left_channel, right_channel, rectified, prior);
    if (seeded) {
      near_prior_path_ = SearchPath::kBrightnessFree;
      return seeded;
    }
  }
  return std::nullopt;
}

std::optional<PairingResult> StereoPipeline::pair_at_expected_outlines(
    const PairingContext& ctx, const cv::Mat& right_channel, bool rectified,
    const PositionPrior& prior, const cv::Rect& left_box, const SearchHints& left_hints) {
  const auto expected = prior_outlines(ctx, prior);
  if (!expected) return std::nullopt;
  const Circle left_seed = shifted(expected->left, -left_box.tl());
  left_candidates_.clear();
  for (const Circle& c : left_detector_.detect_at_seeds(rect_left_(left_box), *left_thresholds_,
                                                        left_hints, {&left_seed, 1}))
    left_candidates_.push_back(shifted(c, left_box.tl()));
  if (left_candidates_.empty()) return std::nullopt;
  // The prediction errs alike in both eyes: the right seed is the left circle found, moved as
  // the expected outline moves from eye to eye.
  const Circle& left = left_candidates_.front();
  const Circle right_seed{left.x_px + expected->right.x_px - expected->left.x_px,
                          left.y_px + expected->right.y_px - expected->left.y_px,
                          left.radius_px * expected->right.radius_px / expected->left.radius_px,
                          0.0};
  const cv::Size size = rectifier_->calibration().image_size;
  const cv::Rect box = seed_box(right_seed, ctx.size.max_relative_error, size);
  if (box.width < 8 || box.height < 8) return std::nullopt;
  clear_rectified(right_channel, rect_right_);
  rectify_box(right_channel, stereo::Eye::kRight, rectified, box, rect_right_);
  right_edges_box_ = box;
  SearchHints right_hints{partner_radius_range(ctx, left_candidates_),
                          params_.prior_min_inside_fraction};
  const Circle seed_in_box = shifted(right_seed, -box.tl());
  right_candidates_.clear();
  for (const Circle& c : right_detector_.detect_at_seeds(rect_right_(box), *left_thresholds_,
                                                         right_hints, {&seed_in_box, 1}))
    right_candidates_.push_back(shifted(c, box.tl()));
  PairingResult pairing = pair_with_predicted_partners(ctx, prior, true);
  if (pairing.status == PairingStatus::kFound &&
      cv::norm(pairing.best->position_m - prior.position_m) <= prior.gate_m)
    return pairing;
  return std::nullopt;
}

PairingResult StereoPipeline::search_whole_frame(const PairingContext& ctx,
                                                 const cv::Mat& left_channel,
                                                 const cv::Mat& right_channel, bool rectified,
                                                 const std::optional<PositionPrior>& prior,
                                                 std::optional<std::vector<Circle>>* band_left) {
  rectify_whole(left_channel, stereo::Eye::kLeft, rectified, rect_left_);
  const bool voted = left_detector_.cast_votes(rect_left_);
  // Task 0 finishes the search (peaks, right eye, pairing). When a band search is due, the
  // other tasks search the left eye's radius bands on the same votes meanwhile, in case it
  // pairs nothing: on another core this takes the bands out of the frame's time, and the work
  // is dropped (stopped between bands) if it pairs. Run in turn, task 0 goes first and the
  // bands run only if it paired nothing. Task 0 does not touch what the band tasks read (the
  // left detector's edges and lines), nor they anything it touches.
  PairingResult pairing;
  std::atomic<bool> paired{false};
  std::vector<Circle> bands;
  run_tasks_(band_left ? 2 : 1, [&](int task) {
    if (task == 1) {
      if (!paired) bands = detect_left_in_bands(&paired);
      return;
    }
    left_candidates_ = voted ? left_circles_of_votes(!band_left) : std::vector<Circle>{};
    if (voted && params_.colour_seeds.enabled) add_colour_seeded_candidates();
    left_thresholds_ = thresholds_of(left_detector_.edge_map());
    frames_since_full_search_ = 0;
    if (params_.right_eye_partner_boxes) {
      right_candidates_ = detect_right_in_boxes(ctx, right_channel, rectified, false);
    } else {
      rectify_whole(right_channel, stereo::Eye::kRight, rectified, rect_right_);
      right_candidates_ = right_detector_.detect(rect_right_);
      right_edges_box_ = cv::Rect(cv::Point(0, 0), rect_right_.size());
    }
    pairing = pair_with_predicted_partners(ctx, prior, false);
    paired = pairing.status == PairingStatus::kFound;
  });
  if (band_left && !paired) *band_left = std::move(bands);
  return pairing;
}

void StereoPipeline::add_colour_seeded_candidates() {
  if (rect_left_.type() != CV_8UC3) return;
  const RadiusRange radii = left_detector_.radius_range();
  colour_seeds_ = colour_blob_seeds(rect_left_, radii.min_px, radii.max_px, params_.colour_seeds);
  for (const Circle& c : left_detector_.refine_seeds(colour_seeds_)) {
    const bool known =
        std::any_of(left_candidates_.begin(), left_candidates_.end(), [&](const Circle& k) {
          return std::hypot(k.x_px - c.x_px, k.y_px - c.y_px) <
                 0.5 * std::max(k.radius_px, c.radius_px);
        });
    if (!known) left_candidates_.push_back(c);
  }
}

std::vector<Circle> StereoPipeline::left_circles_of_votes(bool peaks_at_once) {
  // Refining and scoring the peaks is most of a whole-frame search (~40 %), and each peak is
  // independent. When the band search runs beside it, it has the other core to itself.
  if (!peaks_at_once) return left_detector_.circles_of_votes();
  const int n = left_detector_.find_peaks_of_votes();
  std::vector<PeakCircles> per_peak(static_cast<std::size_t>(n));
  run_tasks_(n,
             [&](int i) { per_peak[static_cast<std::size_t>(i)] = left_detector_.refine_peak(i); });
  return left_detector_.select_circles(per_peak);
}

std::vector<Circle> StereoPipeline::detect_left_in_bands(const std::atomic<bool>* stop) {
  // Up to a third of the image height: an outline larger than that is the largest structure in
  // view and wins the whole-range accumulator already, while in a band of its own clutter
  // scatters enough edge points along a 200 px circle to pass min_score (phantom pairs).
  const double top = std::min(params_.p2p.max_radius_px, rect_left_.rows / 3.0);
  std::vector<SearchHints> bands;
  for (double low = params_.p2p.min_radius_px; low < top; low *= kRadiusBandRatio) {
    // Bands overlap by 10 %: a circle on a boundary is whole in one of them.
    bands.push_back(
        SearchHints{RadiusRange{low / 1.1, std::min(top, low * kRadiusBandRatio * 1.1)}});
    // This band reaches the top already: a next one would lie inside it (it cost 3 ms).
    if (bands.back().radii.max_px >= top) break;
  }
  // The left detector holds this image's edge map, made with these very thresholds, and the
  // lines its points voted along: each band plots them again over its radii instead of redoing
  // the edge step and the window rules. The bands are independent tasks, each on a detector of
  // its own (the left one is only read).
  while (band_detectors_.size() < bands.size()) {
    band_detectors_.emplace_back(params_.detector_params());
    band_detectors_.back().set_camera(params_.perspective_outline ? left_camera() : std::nullopt);
  }
  std::vector<std::vector<Circle>> per_band(bands.size());
  run_tasks_(static_cast<int>(bands.size()), [&](int task) {
    const auto b = static_cast<std::size_t>(task);
    if (stop && *stop) return;  // the result is not wanted any more
    per_band[b] = band_detectors_[b].redetect_from(left_detector_, bands[b]);
  });
  std::vector<Circle> found;
  for (const auto& circles : per_band) found.insert(found.end(), circles.begin(), circles.end());
  std::stable_sort(found.begin(), found.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  // Neighbouring bands find the same circle: keep the best of each place and size.
  std::vector<Circle> kept;
  for (const Circle& c : found) {
    const bool seen = std::any_of(kept.begin(), kept.end(), [&](const Circle& k) {
      return std::hypot(k.x_px - c.x_px, k.y_px - c.y_px) < params_.p2p.min_separation_px &&
             std::abs(k.radius_px - c.radius_px) < 0.2 * std::max(k.radius_px, c.radius_px);
    });
    if (!seen) kept.push_back(c);
  }
  return kept;
}

PairingResult StereoPipeline::search_radius_bands(const PairingContext& ctx,
                                                  std::vector<Circle> band_left,
                                                  const cv::Mat& right_channel, bool rectified,
                                                  const std::optional<PositionPrior>& prior) {
  // band_left: the left eye's circles band by band (detect_left_in_bands); the right eye is
  // searched with the whole left frame's thresholds.
  const EdgeThresholds thresholds = *left_thresholds_;
  left_candidates_ = std::move(band_left);
  // Each left circle's partner box with only the radii its partner can have: one box searched
  // for the union of every candidate's radii is crowded out by clutter just like the left eye.
  const cv::Size size = rectifier_->calibration().image_size;
  clear_rectified(right_channel, rect_right_);
  right_candidates_.clear();
  for (const Circle& left : left_candidates_) {
    const cv::Rect box = partner_search_box(ctx, left, size, window_margin_px());
    if (box.width < 8 || box.height < 8) continue;
    rectify_box(right_channel, stereo::Eye::kRight, rectified, box, rect_right_);
    right_edges_box_ = box;
    const SearchHints hints{partner_radius_range(ctx, {left})};
    for (const Circle& c : right_detector_.detect(rect_right_(box), thresholds, hints))
      right_candidates_.push_back(shifted(c, box.tl()));
  }
  PairingResult pairing = pair_with_predicted_partners(ctx, prior, false);
  return pairing;
}

PairingResult StereoPipeline::pair_with_predicted_partners(
    const PairingContext& ctx, const std::optional<PositionPrior>& prior, bool near_prior) {
  rejected_by_colour_ += apply_appearance();
  PairingResult pairing = pair_candidates(ctx, left_candidates_, right_candidates_, prior);
  if (!params_.predicted_partner || pairing.status == PairingStatus::kFound) return pairing;
  // The left circle passed its own border rule; the right eye sees the ball shifted by the
  // disparity, often farther out of the image, and its outline has one free parameter left:
  // a smaller part in view suffices.
  // Only where the track expects the ball: elsewhere (a new track starts there) the right outline
  // needs the detector's own border rule, for a left circle at the left border whose partner is
  // mostly outside the right image has too little of it in view to tell a ball from a chance
  // circle in dense texture (development seed 202: most of the carpet circles still followed).
  const auto predicted = predicted_partners(ctx, partner_min_inside_fraction(near_prior));
  if (predicted.empty()) return pairing;
  right_candidates_.insert(right_candidates_.end(), predicted.begin(), predicted.end());
  return pair_candidates(ctx, left_candidates_, right_candidates_, prior);
}

int StereoPipeline::window_margin_px() const {
  const auto& ks = params_.p2p.k_values;
  // Window half size plus the smoothing box: arcs closer to a box edge cannot vote.
  return (ks.empty() ? 5 : *std::max_element(ks.begin(), ks.end())) + 4;
}

std::vector<cv::Rect> StereoPipeline::partner_boxes(const PairingContext& ctx) const {
  const cv::Size size = rectifier_->calibration().image_size;
  const int margin = window_margin_px();
  std::vector<cv::Rect> boxes;
  for (const Circle& c : left_candidates_) {
    cv::Rect box = partner_search_box(ctx, c, size, margin);
    if (box.width < 8 || box.height < 8) continue;
    // Overlapping boxes are searched once, as their union.
    for (bool merged = true; merged;) {
      merged = false;
      for (auto it = boxes.begin(); it != boxes.end(); ++it) {
        if ((*it & box).empty()) continue;
        box |= *it;
        boxes.erase(it);
        merged = true;
        break;
      }
    }
    boxes.push_back(box);
  }
  return boxes;
}

std::vector<Circle> StereoPipeline::detect_right_in_boxes(const PairingContext& ctx,
                                                          const cv::Mat& right_channel,
                                                          bool rectified, bool near_prior) {
  clear_rectified(right_channel, rect_right_);
  right_edges_box_ = {};
  std::vector<Circle> found;
  SearchHints hints{partner_radius_range(ctx, left_candidates_)};
  if (near_prior) {
    hints.min_inside_fraction = params_.prior_min_inside_fraction;
    hints.centre_margin_px =
        partner_centre_margin_px(ctx, left_candidates_, rectifier_->calibration().image_size);
  }
  for (const cv::Rect& box : partner_boxes(ctx)) {
    rectify_box(right_channel, stereo::Eye::kRight, rectified, box, rect_right_);
    right_edges_box_ = box;
    // The left image's thresholds: the box's own statistics depend on what it holds.
    for (const Circle& c :
         right_detector_.detect(rect_right_(box), thresholds_of(left_detector_.edge_map()), hints))
      found.push_back(shifted(c, box.tl()));
  }
  std::stable_sort(found.begin(), found.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  return found;
}

double StereoPipeline::partner_min_inside_fraction(bool near_prior) const {
  return near_prior ? params_.predicted_partner_min_inside_fraction
                    : std::max(params_.predicted_partner_min_inside_fraction,
                               params_.p2p.refine_params.min_inside_fraction);
}

std::optional<Circle> StereoPipeline::partner_on_edges(const PairingContext& ctx,
                                                       const Circle& left, const EdgeMap& edges,
                                                       cv::Point origin,
                                                       const RefineParams& scoring) const {
  const auto score = [&](const Circle& c) {
    return score_circle(edges, shifted(c, -origin), scoring);
  };
  return predicted_partner(ctx, left, score, params_.p2p.min_score);
}

RefineParams StereoPipeline::partner_scoring(double min_inside_fraction) const {
  RefineParams scoring = params_.detector_params().refine_params;
  scoring.min_inside_fraction = min_inside_fraction;
  // The outline is scored where its left circle, already past the clutter rings, predicts it:
  // not a chance circle found in texture. The rings there cost balls on textured floors.
  scoring.clutter_ring_per_radius = 0.0;
  if (params_.perspective_outline)
    scoring.camera =
        stereo::PinholeCamera{triangulator_->focal_px(), triangulator_->principal_right_px()};
  return scoring;
}

std::vector<Circle> StereoPipeline::predicted_partners(const PairingContext& ctx,
                                                       double min_inside_fraction) {
  const cv::Size size = rectifier_->calibration().image_size;
  const EdgeThresholds thresholds = thresholds_of(left_detector_.edge_map());
  const PixelToPixelParams p2p = params_.detector_params();
  const RefineParams scoring = partner_scoring(min_inside_fraction);
  std::vector<Circle> found;
  for (const Circle& left : left_candidates_) {
    const cv::Rect box = partner_search_box(ctx, left, size, window_margin_px());
    if (box.width < 8 || box.height < 8) continue;
    // detect_right_in_boxes rectified this box already (it searched the union of these), and
    // the right detector still holds the edges of the last box it searched.
    const EdgeMap* edges = &right_detector_.edge_map();
    cv::Point origin = right_edges_box_.tl();
    if ((box & right_edges_box_) != box) {
      compute_edge_map(rect_right_(box), p2p.edge, thresholds.canny, thresholds.denoise,
                       partner_edges_);
      edges = &partner_edges_;
      origin = box.tl();
    }
    if (auto partner = partner_on_edges(ctx, left, *edges, origin, scoring))
      found.push_back(*partner);
  }
  return found;
}

void StereoPipeline::fill_result(const PairingResult& pairing, StereoDetection& out) const {
  out.status = from_pairing(pairing.status);
  out.reason = pairing.reason;
  if (pairing.best) {
    const StereoPair& p = *pairing.best;
    out.left = p.left;
    out.right = p.right;
    out.row_residual_px = p.row_residual_px;
    out.position_m = p.position_m;
    out.depth_from_size_m = p.depth_from_size_m;
  } else if (!left_candidates_.empty()) {
    out.left = left_candidates_.front();  // best single-eye circle, for display
  }
}

ShiftWindow StereoPipeline::shift_window(const StereoDetection& found) const {
  const stereo::Triangulator& tri = *triangulator_;
  const double depth_m = found.position_m[2];
  const double radius_m = 0.5 * params_.ball_diameter_m;
  const double measured_px = found.left.x_px - found.right.x_px;
  ShiftWindow w;
  w.ball_lo_px = std::min(measured_px, tri.disparity_for_depth_px(depth_m));
  // The nearest surface (the front of the ball) is one radius closer than the centre.
  w.ball_hi_px = std::max(measured_px,
                          tri.disparity_for_depth_px(std::max(depth_m - radius_m, 0.5 * depth_m)));
  // Unsynchronised eyes: what lies inside the outline (the ball's seams, the hands holding it)
  // moved between the exposures by as much as the outline may have.
  const double moved_px =
      frame_motion_radii_ * 0.5 * (found.left.radius_px + found.right.radius_px);
  w.ball_lo_px = std::max(0.0, w.ball_lo_px - moved_px);
  w.ball_hi_px += moved_px;
  // Everything from far away (the principal points' offset, or 0) up to well in front of the
  // ball: what the texture may belong to.
  w.search_lo_px = std::min(tri.principal_left_px().x - tri.principal_right_px().x, 0.0);
  w.search_hi_px = 1.5 * w.ball_hi_px + 8.0;
  return w;
}

void StereoPipeline::check_interior(const cv::Mat& left_channel, const cv::Mat& right_channel,
                                    bool rectified, StereoDetection& found) {
  const cv::Size size = rectifier_->calibration().image_size;
  const ShiftWindow window = shift_window(found);
  const cv::Rect left_region = interior_rows_region(found.left, size);
  const cv::Rect right_region = interior_search_region(left_region, window, size);
  if (left_region.empty() || right_region.empty()) return;
  const cv::Mat& left = rectified_region(left_channel, stereo::Eye::kLeft, rectified, left_region);
  const cv::Mat& right =
      rectified_region(right_channel, stereo::Eye::kRight, rectified, right_region);
  const InteriorDepth d = interior_depth(left, right, found.left, window, params_.interior_depth);
  if (!d.contradicts) return;
  // Disparities as x_left - x_right, as the pairing's reasons give them.
  char where[32] = "far away";
  if (const auto depth_m = triangulator_->depth_from_disparity_m(d.best_shift_px))
    std::snprintf(where, sizeof where, "%.2f m", *depth_m);
  char text[256];
  std::snprintf(text, sizeof text,
                "texture inside the circle matches at disparity %.0f px (%s), not at the "
                "outline's %.0f px (%.2f m; correlation %.2f vs %.2f): a round pattern on a "
                "surface, not a ball",
                d.best_shift_px, where, found.left.x_px - found.right.x_px, found.position_m[2],
                d.best_match, d.ball_match);
  found.status = DetectionStatus::kInteriorMismatch;
  found.reason = text;
}

namespace {

// Whether all of c lies in an image of size.
bool circle_inside(const Circle& c, cv::Size size) {
  return c.x_px - c.radius_px >= 0.0 && c.y_px - c.radius_px >= 0.0 &&
         c.x_px + c.radius_px <= size.width - 1.0 && c.y_px + c.radius_px <= size.height - 1.0;
}

// Radii that differ by less than this (or kBalanceFraction of the radius) are fit noise.
constexpr double kBalanceMinPx = 0.3;
constexpr double kBalanceFraction = 0.02;

}  // namespace

void StereoPipeline::balance_radii(const cv::Mat& left_channel, const cv::Mat& right_channel,
                                   bool rectified, StereoDetection& found) {
  // A ball cut by the border shows each eye a different part: its fits may differ in radius.
  const cv::Size size = rectifier_->calibration().image_size;
  if (!circle_inside(found.left, size) || !circle_inside(found.right, size)) return;
  const double ball_radius_m = 0.5 * params_.ball_diameter_m;
  const auto balance = radius_balance(*triangulator_, found.left, found.right, found.position_m,
                                      ball_radius_m, kBalanceMinPx, kBalanceFraction);
  if (!balance) return;
  const stereo::Eye eye = balance->right_eye ? stereo::Eye::kRight : stereo::Eye::kLeft;
  Circle& pulled = balance->right_eye ? found.right : found.left;
  const auto refit = refit_at_radius(balance->right_eye ? right_channel : left_channel, eye,
                                     rectified, pulled, balance->radius_px);
  if (!refit) return;
  Circle left = found.left, right = found.right;
  (balance->right_eye ? right : left) = *refit;
  const auto centre = triangulator_->sphere_centre_m({left.x_px, left.y_px},
                                                     {right.x_px, right.y_px}, ball_radius_m);
  if (!centre || !((*centre)[2] > 0.0)) return;
  pulled = *refit;
  found.position_m = *centre;
  found.reason += balance->right_eye ? "; right outline refitted at the left's radius"
                                     : "; left outline refitted at the right's radius";
}

std::optional<Circle> StereoPipeline::refit_at_radius(const cv::Mat& channel, stereo::Eye eye,
                                                      bool rectified, const Circle& circle,
                                                      double radius_px) {
  const cv::Size size = rectifier_->calibration().image_size;
  // The outline and the first refinement band around it.
  const int margin =
      static_cast<int>(std::ceil(radius_px + PixelToPixelParams::kPolishFirstBandPx)) + 2;
  const cv::Rect region =
      cv::Rect(static_cast<int>(circle.x_px) - margin, static_cast<int>(circle.y_px) - margin,
               2 * margin + 1, 2 * margin + 1) &
      cv::Rect(cv::Point(), size);
  if (region.width < 8 || region.height < 8) return std::nullopt;
  const cv::Mat& image = rectified_region(channel, eye, rectified, region);
  const PixelToPixelParams p2p = params_.detector_params();
  const EdgeThresholds thresholds =
      left_thresholds_ ? *left_thresholds_ : thresholds_of(left_detector_.edge_map());
  compute_edge_map(image(region), p2p.edge, thresholds.canny, thresholds.denoise, balance_edges_);
  RefineParams refine = p2p.refine_params;
  refine.hold_radius = true;
  refine.first_band_px = PixelToPixelParams::kPolishFirstBandPx;
  refine.robust_fit_floor_px = PixelToPixelParams::kPolishRobustFloorPx;
  if (params_.perspective_outline)
    refine.camera = stereo::PinholeCamera{
        triangulator_->focal_px(), eye == stereo::Eye::kLeft ? triangulator_->principal_left_px()
                                                             : triangulator_->principal_right_px()};
  const Circle seed{circle.x_px - region.x, circle.y_px - region.y, radius_px, 0.0};
  auto refit = refine_circle(balance_edges_, seed, refine);
  // The refit must stand as an outline on its own, near where the free fit put it.
  if (!refit || refit->score < p2p.min_score ||
      std::hypot(refit->x_px - seed.x_px, refit->y_px - seed.y_px) >
          std::abs(radius_px - circle.radius_px) + 1.0)
    return std::nullopt;
  return shifted(*refit, region.tl());
}

void StereoPipeline::raw_left_px(const std::vector<cv::Point2d>& rectified_px,
                                 std::vector<cv::Point2d>& raw_px) {
  patch_rays_.resize(rectified_px.size());
  for (std::size_t i = 0; i < rectified_px.size(); ++i) {
    const cv::Vec3d ray =
        patch_ray_from_pixel_ * cv::Vec3d(rectified_px[i].x, rectified_px[i].y, 1.0);
    patch_rays_[i] = {ray[0], ray[1], ray[2]};
  }
  const stereo::StereoCalibration& calib = rectifier_->calibration();
  cv::projectPoints(patch_rays_, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Mat(calib.k1),
                    cv::Mat(calib.d1, true), raw_px);
}

void StereoPipeline::cut_patch(const cv::Mat& left_raw, bool rectified, StereoDetection& out) {
  const cv::Size size = left_raw.size();
  const int cx = static_cast<int>(std::lround(out.left.x_px));
  const int cy = static_cast<int>(std::lround(out.left.y_px));
  auto clamp_x = [&](int x) { return std::clamp(x, 0, size.width - 1); };
  auto clamp_y = [&](int y) { return std::clamp(y, 0, size.height - 1); };
  std::uint8_t* dst = out.patch_rgb.data();
  if (rectified) {
    extract_patch(left_raw, out.left.x_px, out.left.y_px, out.patch_rgb);
    out.patch_valid = true;
    return;
  }
  // Only 441 rectified pixels are needed: map them through the lens model instead of
  // rectifying the whole colour image.
  colour_rect_px_.clear();
  for (int r = 0; r < kPatchSide; ++r)
    for (int c = 0; c < kPatchSide; ++c)
      colour_rect_px_.emplace_back(clamp_x(cx - kPatchHalf + c), clamp_y(cy - kPatchHalf + r));
  raw_left_px(colour_rect_px_, patch_raw_px_);
  for (int r = 0; r < kPatchSide; ++r)
    for (int c = 0; c < kPatchSide; ++c) {
      const cv::Point2d& p = patch_raw_px_[static_cast<std::size_t>(r * kPatchSide + c)];
      patch_map_.at<cv::Vec2f>(r, c) = cv::Vec2f(static_cast<float>(p.x), static_cast<float>(p.y));
    }
  cv::remap(left_raw, patch_bgr_, patch_map_, cv::noArray(), cv::INTER_LINEAR,
            cv::BORDER_REPLICATE);
  for (int r = 0; r < kPatchSide; ++r)
    for (int c = 0; c < kPatchSide; ++c, dst += 3) put_rgb(patch_bgr_, c, r, dst);
  out.patch_valid = true;
}

std::optional<ColourHistogram> StereoPipeline::colour_of(const Circle& left) {
  if (!frame_left_ || frame_left_->channels() != 3) return std::nullopt;
  const cv::Mat& image = *frame_left_;
  colour_rect_px_.clear();
  colour_rect_px_.emplace_back(left.x_px, left.y_px);
  for (const double f : kColourRings)
    for (int a = 0; a < kColourAngles; ++a) {
      const double t = 2.0 * CV_PI * (a + 0.5 * f) / kColourAngles;
      colour_rect_px_.emplace_back(left.x_px + f * left.radius_px * std::cos(t),
                                   left.y_px + f * left.radius_px * std::sin(t));
    }
  if (frame_rectified_) {
    colour_raw_px_ = colour_rect_px_;
  } else {
    raw_left_px(colour_rect_px_, colour_raw_px_);
  }
  colour_px_.clear();
  for (const cv::Point2d& p : colour_raw_px_) {
    const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y));
    // A ball cut by the border is sampled where it is in view.
    if (x >= 0 && y >= 0 && x < image.cols && y < image.rows)
      colour_px_.push_back(image.at<cv::Vec3b>(y, x));
  }
  return ColourHistogram::of(colour_px_, appearance_.params().min_pixels);
}

int StereoPipeline::apply_appearance() {
  if (!appearance_.ready()) return 0;
  int rejected = 0;
  for (auto it = left_candidates_.begin(); it != left_candidates_.end();) {
    const auto h = colour_of(*it);
    if (appearance_.rejects(h)) {
      it = left_candidates_.erase(it);
      ++rejected;
      continue;
    }
    // Rank: a circle more of whose colours are the ball's keeps more of its outline score.
    if (h) it->score *= 0.5 + 0.5 * appearance_.containment(*h).value_or(1.0);
    ++it;
  }
  std::stable_sort(left_candidates_.begin(), left_candidates_.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  return rejected;
}

}  // namespace stereoball::ball_detector
