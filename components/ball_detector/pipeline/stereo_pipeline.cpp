#include "ball_detector/pipeline/stereo_pipeline.hpp"

#include "common/util/enum_names.hpp"
#include "stereo/core/calibration_scaling.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace stereoball::ball_detector {
namespace {

constexpr int kPatchHalf = kPatchSide / 2;

Status check_pixels(const char* eye, const cv::Mat& m) {
  if (m.empty()) return Error{std::string(eye) + " image is empty"};
  if (m.depth() != CV_8U || (m.channels() != 1 && m.channels() != 3))
    return Error{std::string(eye) + " image must be 8-bit grey or BGR (got " +
                 std::to_string(m.channels()) + " channels, depth " + std::to_string(m.depth()) +
                 ")"};
  return {};
}

// The answer of a stream's frame whose searches near the prior paired nothing within its gate
// (the whole frame is searched on the next frame): the last near search's outcome, unless it
// paired outside the gate.
SearchOutcome missed_near_prior(std::optional<SearchOutcome> missed) {
  if (missed && !missed->found()) return std::move(*missed);
  SearchOutcome out;
  out.path = missed ? missed->path : SearchPath::kExpectedOutlines;
  out.pairing.status = PairingStatus::kNoCandidate;
  out.pairing.reason =
      "nothing paired within the track prior's gate (the whole frame is searched on the next "
      "frame)";
  return out;
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

// The rows are string literals: a name's data() ends in a NUL.
constexpr util::EnumName<SearchPath> kSearchPathNames[] = {
    {SearchPath::kExpectedOutlines, "expected_outlines"},
    {SearchPath::kPriorWindow, "prior_window"},
    {SearchPath::kWholeFrame, "whole_frame"},
    {SearchPath::kRadiusBands, "radius_bands"},
    {SearchPath::kBrightnessFree, "brightness_free"}};

constexpr util::EnumName<DetectionStatus> kDetectionStatusNames[] = {
    {DetectionStatus::kFound, "found"},
    {DetectionStatus::kNoCandidate, "no_candidate"},
    {DetectionStatus::kEpipolarMismatch, "epipolar_mismatch"},
    {DetectionStatus::kSizeInconsistent, "size_inconsistent"},
    {DetectionStatus::kNoCalibration, "no_calibration"},
    {DetectionStatus::kBadFrame, "bad_frame"},
    {DetectionStatus::kOffFloor, "off_floor"},
    {DetectionStatus::kInteriorMismatch, "interior_mismatch"}};

const char* to_string(SearchPath path) {
  return util::name_of(kSearchPathNames, path, "?").data();
}

const char* to_string(DetectionStatus status) {
  return util::name_of(kDetectionStatusNames, status).data();
}

StereoPipeline::StereoPipeline(const BallDetectorParams& params)
    : tools_(params),
      epipolar_(stereo::EpipolarParams{params.epipolar_tolerance_px}),
      size_{params.ball_diameter_m, params.size_max_relative_error} {
  patch_raw_px_.reserve(kPatchSide * kPatchSide);
  patch_map_.create(kPatchSide, kPatchSide, CV_32FC2);
}

namespace {

// The calibration frames are searched with: input shrunk by the smallest whole factor that
// brings it to working_width_px (input itself when it is no wider, or the width is 0).
Result<stereo::StereoCalibration> working_calibration(const stereo::StereoCalibration& input,
                                                      int working_width_px) {
  const int width = input.image_size.width;
  if (working_width_px <= 0 || width <= working_width_px) return input;
  const int factor = (width + working_width_px - 1) / working_width_px;
  const int work_width = static_cast<int>(std::lround(static_cast<double>(width) / factor));
  return stereo::scale_calibration(input, stereo::scaled_size(input.image_size, work_width));
}

}  // namespace

Status StereoPipeline::set_calibration(const stereo::StereoCalibration& input) {
  if (auto e = stereo::validate_calibration(input); !e) return e;
  if (auto swapped = stereo::check_camera_order(input); !swapped)
    return Error{swapped.error() + "; " + kHowToSwapCameras + " and calibrate again"};
  auto working = working_calibration(input, tools_.params.working_width_px);
  if (!working) return Error{"working_width_px: " + working.error()};
  const stereo::StereoCalibration& calib = *working;
  auto rectifier = stereo::Rectifier::create(calib);
  if (!rectifier) return Error{rectifier.error()};
  auto triangulator = stereo::Triangulator::create(calib);
  if (!triangulator) return Error{triangulator.error()};
  SearchTools& t = tools_;
  t.rectifier.emplace(std::move(rectifier).value());
  t.triangulator.emplace(std::move(triangulator).value());
  const PixelToPixelParams p2p =
      scaled_to_width(t.configured_p2p, t.params.p2p_reference_width_px, calib.image_size.width);
  if (p2p.k_values != t.params.p2p.k_values || p2p.min_radius_px != t.params.p2p.min_radius_px) {
    t.params.p2p = p2p;
    t.left_detector = PixelToPixelDetector(t.params.detector_params());
    t.right_detector = PixelToPixelDetector(t.params.detector_params());
    t.seed_detector = PixelToPixelDetector(t.params.detector_params());
    t.band_detectors.clear();
    t.left_thresholds.reset();
  }
  if (t.params.perspective_outline) {
    t.left_detector.set_camera(left_camera());
    t.right_detector.set_camera(right_camera());
  }
  for (PixelToPixelDetector& d : t.band_detectors)
    d.set_camera(t.params.perspective_outline ? left_camera() : std::nullopt);
  const cv::Matx33d p(calib.p1(0, 0), calib.p1(0, 1), calib.p1(0, 2), calib.p1(1, 0),
                      calib.p1(1, 1), calib.p1(1, 2), calib.p1(2, 0), calib.p1(2, 1),
                      calib.p1(2, 2));
  t.ray_from_pixel = calib.r1.t() * p.inv();
  floor_ = floor_model(t.params, calib);
  t.coarse.set_up(t.params, calib.image_size.width, left_camera());
  input_calibration_ = input;
  work_scale_ =
      static_cast<double>(calib.image_size.width) / static_cast<double>(input.image_size.width);
  return {};
}

std::optional<stereo::PinholeCamera> StereoPipeline::left_camera() const {
  return tools_.left_camera();
}

std::optional<stereo::PinholeCamera> StereoPipeline::right_camera() const {
  if (!tools_.triangulator) return std::nullopt;
  return stereo::PinholeCamera{tools_.triangulator->focal_px(),
                               tools_.triangulator->principal_right_px()};
}

cv::Size StereoPipeline::image_size() const {
  return input_calibration_ ? input_calibration_->image_size : cv::Size();
}

bool StereoPipeline::at_working_size(cv::Size left, cv::Size right) const {
  return work_scale_ < 1.0 && left == working_size() && right == working_size();
}

int StereoPipeline::working_reduction() const {
  if (!input_calibration_ || !(work_scale_ < 1.0)) return 1;
  const cv::Size input = input_calibration_->image_size, work = working_size();
  for (const int r : {2, 4, 8})
    if (input.width == r * work.width && input.height == r * work.height) return r;
  return 1;
}

Status StereoPipeline::check_input(const cv::Mat& left, const cv::Mat& right) const {
  if (auto e = check_pixels("left", left); !e) return e;
  if (auto e = check_pixels("right", right); !e) return e;
  if (left.type() != right.type()) return Error{"left and right images differ in type"};
  // Frames a source decoded reduced (working_reduction) are searched as they are.
  if (at_working_size(left.size(), right.size())) return {};
  return stereo::check_image_size(*input_calibration_, left.size(), right.size());
}

std::pair<const cv::Mat*, const cv::Mat*> StereoPipeline::working_frames(const cv::Mat& left,
                                                                         const cv::Mat& right) {
  if (!(work_scale_ < 1.0) || at_working_size(left.size(), right.size())) return {&left, &right};
  // As camera_server's publish_width_px shrinks frames: the same pixels at either place.
  cv::resize(left, work_left_, tools_.image_size(), 0, 0, cv::INTER_AREA);
  cv::resize(right, work_right_, tools_.image_size(), 0, 0, cv::INTER_AREA);
  return {&work_left_, &work_right_};
}

void StereoPipeline::to_input_pixels(StereoDetection& out) const {
  if (!(work_scale_ < 1.0)) return;
  // scale_calibration's pixel map, inverted: u_work = s (u + 0.5) - 0.5.
  const double s = work_scale_;
  for (Circle* c : {&out.left, &out.right}) {
    if (!(c->radius_px > 0.0)) continue;
    c->x_px = (c->x_px + 0.5) / s - 0.5;
    c->y_px = (c->y_px + 0.5) / s - 0.5;
    c->radius_px /= s;
  }
  out.row_residual_px /= s;
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
  return detector_input_image(raw, tools_.params.input, grey);
}

const cv::Mat& StereoPipeline::rectified_region(const cv::Mat& channel, stereo::Eye eye,
                                                bool rectified, const cv::Rect& region) {
  // The edge step on a crop reads one pixel of its parent around it (edge_map.cpp): that ring
  // is rectified too, never left as unset or stale scratch.
  const cv::Rect read =
      (region - cv::Point(1, 1) + cv::Size(2, 2)) & cv::Rect(cv::Point(), tools_.image_size());
  if (eye == stereo::Eye::kRight) tools_.right_rows.make_for(*tools_.rectifier, rectified, read);
  if (rectified) return channel;
  // Only the region read, not the whole eye, into the eye's scratch image.
  cv::Mat& out = eye == stereo::Eye::kLeft ? region_left_ : region_right_;
  out.create(tools_.image_size(), channel.type());
  tools_.rectifier->rectify_eye_region(eye, channel, read, out);
  return out;
}

double StereoPipeline::motion_radii(std::optional<std::int64_t> eye_skew_ns,
                                    const std::optional<PositionPrior>& prior) const {
  const BallDetectorParams& params = tools_.params;
  double speed = params.epipolar_ball_speed_mps;
  if (!(speed > 0.0)) return 0.0;
  const std::int64_t skew_ns =
      params.epipolar_skew_ns >= 0 ? params.epipolar_skew_ns : eye_skew_ns.value_or(0);
  if (prior) speed = std::min(speed, cv::norm(prior->velocity_mps) + kTrackSpeedSlackMps);
  return speed * 1e-9 * static_cast<double>(std::abs(skew_ns)) / (0.5 * params.ball_diameter_m);
}

StereoDetection StereoPipeline::step(const cv::Mat& left, const cv::Mat& right, bool rectified,
                                     const std::optional<PositionPrior>& prior,
                                     std::int64_t stamp_ns,
                                     std::optional<std::int64_t> eye_skew_ns) {
  stereo::WholeImageRows whole(right);
  return step(left, whole, rectified, prior, stamp_ns, eye_skew_ns);
}

bool StereoPipeline::reads_right_whole(const cv::Mat& left, const cv::Mat& right) const {
  // Shrunk to the working size, or converted to another detector input: all of it, now.
  const bool shrunk = work_scale_ < 1.0 && !at_working_size(left.size(), right.size());
  return shrunk || (right.channels() == 3 && tools_.params.input != DetectorInput::kColour);
}

StereoDetection StereoPipeline::step(const cv::Mat& left, stereo::RowSource& right_rows,
                                     bool rectified, const std::optional<PositionPrior>& prior,
                                     std::int64_t stamp_ns,
                                     std::optional<std::int64_t> eye_skew_ns) {
  StereoDetection out;
  left_candidates_.clear();
  right_candidates_.clear();
  tools_.appearance.tick(stamp_ns);
  if (!tools_.rectifier) {
    out.status = DetectionStatus::kNoCalibration;
    out.reason = "no stereo calibration received yet";
    return out;
  }
  const cv::Mat& right = right_rows.image();
  if (auto e = check_input(left, right); !e) {
    out.status = DetectionStatus::kBadFrame;
    out.reason = e.error();
    return out;
  }
  // The right eye's rows are made as the searches read them, unless it is read whole here.
  tools_.right_rows.source = &right_rows;
  if (reads_right_whole(left, right)) {
    right_rows.make_all();
    tools_.right_rows.source = nullptr;
    if (auto e = right_rows.status(); !e) return bad_right_eye(e.error());
  }
  const auto [work_left, work_right] = working_frames(left, right);
  const FrameState frame{
      *work_left,
      detector_channel(*work_left, grey_left_),
      detector_channel(*work_right, grey_right_),
      rectified,
      prior,
      stamp_ns,
      PairingContext{epipolar_, *tools_.triangulator, size_, floor_,
                     motion_radii(eye_skew_ns, prior), tools_.params.dominance_margin}};
  if (refresh_due_) refresh_thresholds(frame.left_channel, rectified);  // finish_frame not called
  SearchOutcome answer = search(frame);
  report(frame, answer, out);
  tools_.right_rows.source = nullptr;
  // Corrupt data met in the rows read: what was searched on the zero rows is no answer.
  if (auto e = right_rows.status(); !e) return bad_right_eye(e.error());
  to_input_pixels(out);
  left_candidates_ = std::move(answer.left);
  right_candidates_ = std::move(answer.right);
  return out;
}

StereoDetection StereoPipeline::bad_right_eye(const std::string& problem) {
  tools_.right_rows.source = nullptr;
  StereoDetection out;
  out.status = DetectionStatus::kBadFrame;
  out.reason = problem;
  return out;
}

SearchOutcome StereoPipeline::search(const FrameState& frame) {
  FrameScratch scratch;
  int rejected = 0;  // by the appearance, over every search whose outcome the frame saw
  const auto tried = [&](const SearchStrategy& s, SearchPath path) {
    tools_.observe(path, true);
    std::optional<SearchOutcome> outcome = s.run(frame, scratch, tools_);
    tools_.observe(path, false);
    if (outcome) rejected += outcome->rejected_by_colour;
    return outcome;
  };
  const auto answer = [&](SearchOutcome outcome) {
    outcome.rejected_by_colour = rejected;
    return outcome;
  };
  // A stream: frames less than kBandSearchEveryNs apart (stills, and frames without stamps,
  // are not one).
  const bool stream = last_stamp_ns_ && frame.stamp_ns > *last_stamp_ns_ &&
                      frame.stamp_ns - *last_stamp_ns_ <= kBandSearchEveryNs;
  last_stamp_ns_ = frame.stamp_ns;
  // Near the track's prior, the first pair within its gate is the answer (a pair elsewhere
  // would not win over it): the whole frame is not searched in the frame's time, only its
  // thresholds measured again now and then, after the answer (finish_frame).
  if (frame.prior && tools_.params.prior_window && tools_.left_thresholds &&
      prepare_prior_box(frame, scratch, tools_)) {
    ++frames_since_full_search_;
    // Once the ball has been missing for a frame, a stream's frame whose prior box is large
    // (voting there costs about as much as over the whole frame) runs one of the two voting
    // searches, the prior window or the whole frame, in turn (README: searches).
    const cv::Size size = tools_.image_size();
    const bool in_turn = stream && static_cast<double>(scratch.prior_box.area()) >
                                       kLargePriorBoxShare * static_cast<double>(size.area());
    const bool window_turn = !(in_turn && window_only_last_frame_);
    const std::pair<const SearchStrategy*, SearchPath> near_prior[] = {
        {&expected_outlines_, SearchPath::kExpectedOutlines},
        {&prior_window_, SearchPath::kPriorWindow},
        {&expected_without_brightness_, SearchPath::kBrightnessFree}};
    std::optional<SearchOutcome> missed;  // the last near search's outcome, when none pairs
    for (const auto& [s, path] : near_prior) {
      if (path == SearchPath::kPriorWindow && !window_turn) continue;
      std::optional<SearchOutcome> near = tried(*s, path);
      if (!near) continue;
      if (!near->found_near(*frame.prior)) {
        missed = std::move(near);
        continue;
      }
      if (frames_since_full_search_ >= kFullSearchEveryFrames) refresh_due_ = true;
      window_only_last_frame_ = false;
      missed_last_frame_ = false;
      return answer(std::move(*near));
    }
    if (in_turn && window_turn && missed_last_frame_) {
      window_only_last_frame_ = true;  // the whole frame's turn is next
      return answer(missed_near_prior(std::move(missed)));
    }
  }
  window_only_last_frame_ = false;
  missed_last_frame_ = true;  // until a search below pairs
  // The whole frame; after it pairs nothing, radius bands (one a frame in a stream: all of them
  // cost several whole-frame searches' peaks, and made the slowest frames), and the colour
  // seeds' outlines without brightness. Each later search answers only if it pairs.
  // Coarse to fine, the whole frame's first try has searched every radius band on the reduced
  // eye already (coarse_left_circles), so the full-width fallback votes once over the whole
  // range and leaves the bands out (README: coarse to fine on wide frames). By radius, the bands
  // stay at full width: the reduced eye's lose white balls on a chessboard (README: by radius).
  const bool full_width_bands = !tools_.coarse.on() || tools_.coarse.by_radius;
  scratch.bands_due = full_width_bands;
  // Every band on stills and on a stream's first frame; then one band a frame, in turn.
  const bool every_band = !stream;
  scratch.band = every_band ? -1 : next_band_;
  SearchOutcome whole = *tried(whole_frame_, SearchPath::kWholeFrame);
  frames_since_full_search_ = 0;
  if (whole.found()) {
    missed_last_frame_ = false;
    return answer(std::move(whole));
  }
  if (full_width_bands) {
    whole.path = SearchPath::kRadiusBands;  // the last search the frame needed
    std::optional<SearchOutcome> bands = tried(radius_bands_, SearchPath::kRadiusBands);
    // A band that pairs what the whole range missed is searched again first next time.
    if (bands && bands->found()) {
      missed_last_frame_ = false;
      return answer(std::move(*bands));
    }
    if (!every_band) next_band_ = (next_band_ + 1) % std::max(1, radius_band_count(tools_));
  }
  std::optional<SearchOutcome> hue = tried(seeds_without_brightness_, SearchPath::kBrightnessFree);
  if (hue && hue->found()) {
    missed_last_frame_ = false;
    return answer(std::move(*hue));
  }
  return answer(std::move(whole));
}

void StereoPipeline::report(const FrameState& frame, const SearchOutcome& answer,
                            StereoDetection& out) {
  out.search = answer.path;
  out.candidates_left = static_cast<int>(answer.left.size());
  out.candidates_right = static_cast<int>(answer.right.size());
  fill_result(answer, out);
  if (out.status == DetectionStatus::kFound && tools_.params.interior_depth.enabled)
    check_interior(frame, out);
  if (out.status == DetectionStatus::kFound && tools_.params.outline_refit.enabled)
    refit_outlines(frame, out);
  if (out.status == DetectionStatus::kFound && tools_.params.balance_radii)
    balance_radii(frame, out);
  // On the pair as first paired: the refits above may have hidden its outlines' disagreement.
  if (out.status == DetectionStatus::kFound && answer.pairing.best)
    check_moved_pair(frame, *answer.pairing.best, out);
  if (out.status == DetectionStatus::kFound && answer.pairing.best)
    check_interior_motion(frame, *answer.pairing.best, out);
  out.rejected_by_colour = answer.rejected_by_colour;
  if (tools_.params.right_eye_partner_boxes && answer.left.empty())
    out.reason =
        answer.rejected_by_colour > 0
            ? "every left circle differs in colour from the followed ball"
            : "no circle in the left eye (the right eye is searched only near left circles)";
  // A right eye found corrupt makes the frame a bad one: nothing is learnt from it.
  if (out.status != DetectionStatus::kFound || tools_.right_rows.failed()) return;
  cut_patch(frame.left_raw, frame.rectified, out);
  // Where the following tracker expects the ball: this is the ball it follows.
  if (frame.prior && cv::norm(out.position_m - frame.prior->position_m) <= frame.prior->gate_m) {
    if (auto h = tools_.colour_of(frame, out.left)) tools_.appearance.learn(*h, frame.stamp_ns);
  }
}

void StereoPipeline::refresh_thresholds(const cv::Mat& left_channel, bool rectified) {
  tools_.rectify_whole(left_channel, stereo::Eye::kLeft, rectified, refresh_left_);
  tools_.left_thresholds =
      measure_edge_thresholds(refresh_left_, tools_.params.detector_params().edge, refresh_edges_);
  frames_since_full_search_ = 0;
  refresh_due_ = false;
}

bool StereoPipeline::finish_frame(const cv::Mat& left, bool rectified) {
  if (!refresh_due_ || !tools_.rectifier || !check_pixels("left", left).ok()) return false;
  if (at_working_size(left.size(), left.size())) {
    refresh_thresholds(detector_channel(left, grey_left_), rectified);
    return true;
  }
  if (!stereo::check_image_size(*input_calibration_, left.size(), left.size()).ok()) return false;
  if (work_scale_ < 1.0) {
    cv::resize(left, work_left_, tools_.image_size(), 0, 0, cv::INTER_AREA);
    refresh_thresholds(detector_channel(work_left_, grey_left_), rectified);
    return true;
  }
  refresh_thresholds(detector_channel(left, grey_left_), rectified);
  return true;
}

void StereoPipeline::fill_result(const SearchOutcome& answer, StereoDetection& out) const {
  const PairingResult& pairing = answer.pairing;
  out.status = from_pairing(pairing.status);
  out.reason = pairing.reason;
  if (pairing.best) {
    const StereoPair& p = *pairing.best;
    out.left = p.left;
    out.right = p.right;
    out.row_residual_px = p.row_residual_px;
    out.position_m = p.position_m;
    out.depth_from_size_m = p.depth_from_size_m;
  } else if (!answer.left.empty()) {
    out.left = answer.left.front();  // best single-eye circle, for display
  }
}

ShiftWindow StereoPipeline::shift_window(const StereoDetection& found, double motion_radii) const {
  const stereo::Triangulator& tri = *tools_.triangulator;
  const double depth_m = found.position_m[2];
  const double radius_m = 0.5 * tools_.params.ball_diameter_m;
  const double measured_px = found.left.x_px - found.right.x_px;
  ShiftWindow w;
  w.ball_lo_px = std::min(measured_px, tri.disparity_for_depth_px(depth_m));
  // The nearest surface (the front of the ball) is one radius closer than the centre.
  w.ball_hi_px = std::max(measured_px,
                          tri.disparity_for_depth_px(std::max(depth_m - radius_m, 0.5 * depth_m)));
  // Unsynchronised eyes: what lies inside the outline (the ball's seams, the hands holding it)
  // moved between the exposures by as much as the outline may have.
  const double moved_px = motion_radii * 0.5 * (found.left.radius_px + found.right.radius_px);
  w.ball_lo_px = std::max(0.0, w.ball_lo_px - moved_px);
  w.ball_hi_px += moved_px;
  // Everything from far away (the principal points' offset, or 0) up to well in front of the
  // ball: what the texture may belong to.
  w.search_lo_px = std::min(tri.principal_left_px().x - tri.principal_right_px().x, 0.0);
  w.search_hi_px = 1.5 * w.ball_hi_px + 8.0;
  return w;
}

void StereoPipeline::check_interior(const FrameState& frame, StereoDetection& found) {
  const cv::Size size = tools_.image_size();
  const ShiftWindow window = shift_window(found, frame.ctx.motion_radii);
  const cv::Rect left_region = interior_rows_region(found.left, size);
  const cv::Rect right_region = interior_search_region(left_region, window, size);
  if (left_region.empty() || right_region.empty()) return;
  const cv::Mat& left =
      rectified_region(frame.left_channel, stereo::Eye::kLeft, frame.rectified, left_region);
  const cv::Mat& right =
      rectified_region(frame.right_channel, stereo::Eye::kRight, frame.rectified, right_region);
  const InteriorDepth d =
      interior_depth(left, right, found.left, window, tools_.params.interior_depth);
  if (!d.contradicts) return;
  // Disparities as x_left - x_right, as the pairing's reasons give them.
  char where[32] = "far away";
  if (const auto depth_m = tools_.triangulator->depth_from_disparity_m(d.best_shift_px))
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

void StereoPipeline::balance_radii(const FrameState& frame, StereoDetection& found) {
  // A ball cut by the border shows each eye a different part: its fits may differ in radius.
  const cv::Size size = tools_.image_size();
  if (!circle_inside(found.left, size) || !circle_inside(found.right, size)) return;
  const double ball_radius_m = 0.5 * tools_.params.ball_diameter_m;
  const auto balance =
      radius_balance(*tools_.triangulator, found.left, found.right, found.position_m, ball_radius_m,
                     kBalanceMinPx, kBalanceFraction);
  if (!balance) return;
  const stereo::Eye eye = balance->right_eye ? stereo::Eye::kRight : stereo::Eye::kLeft;
  Circle& pulled = balance->right_eye ? found.right : found.left;
  const auto refit = refit_at_radius(balance->right_eye ? frame.right_channel : frame.left_channel,
                                     eye, frame.rectified, pulled, balance->radius_px);
  if (!refit) return;
  Circle left = found.left, right = found.right;
  (balance->right_eye ? right : left) = *refit;
  const auto centre = tools_.triangulator->sphere_centre_m({left.x_px, left.y_px},
                                                           {right.x_px, right.y_px}, ball_radius_m);
  if (!centre || !((*centre)[2] > 0.0)) return;
  pulled = *refit;
  found.position_m = *centre;
  found.reason += balance->right_eye ? "; right outline refitted at the left's radius"
                                     : "; left outline refitted at the right's radius";
}

std::optional<cv::Rect> StereoPipeline::edges_around(const cv::Mat& channel, stereo::Eye eye,
                                                     bool rectified, const Circle& circle,
                                                     int margin_px) {
  const cv::Rect region =
      cv::Rect(static_cast<int>(circle.x_px) - margin_px, static_cast<int>(circle.y_px) - margin_px,
               2 * margin_px + 1, 2 * margin_px + 1) &
      cv::Rect(cv::Point(), tools_.image_size());
  if (region.width < 8 || region.height < 8) return std::nullopt;
  const cv::Mat& image = rectified_region(channel, eye, rectified, region);
  const EdgeThresholds thresholds = tools_.left_thresholds
                                        ? *tools_.left_thresholds
                                        : thresholds_of(tools_.left_detector.edge_map());
  compute_edge_map(image(region), tools_.params.detector_params().edge, thresholds.canny,
                   thresholds.denoise, balance_edges_);
  return region;
}

std::optional<Circle> StereoPipeline::refit_at_radius(const cv::Mat& channel, stereo::Eye eye,
                                                      bool rectified, const Circle& circle,
                                                      double radius_px) {
  // The outline and the first refinement band around it.
  const int margin =
      static_cast<int>(std::ceil(radius_px + PixelToPixelParams::kPolishFirstBandPx)) + 2;
  const std::optional<cv::Rect> found_region =
      edges_around(channel, eye, rectified, circle, margin);
  if (!found_region) return std::nullopt;
  const cv::Rect region = *found_region;
  const PixelToPixelParams p2p = tools_.params.detector_params();
  RefineParams refine = p2p.refine_params;
  refine.hold_radius = true;
  refine.first_band_px = PixelToPixelParams::kPolishFirstBandPx;
  refine.robust_fit_floor_px = PixelToPixelParams::kPolishRobustFloorPx;
  if (tools_.params.perspective_outline)
    refine.camera = stereo::PinholeCamera{tools_.triangulator->focal_px(),
                                          eye == stereo::Eye::kLeft
                                              ? tools_.triangulator->principal_left_px()
                                              : tools_.triangulator->principal_right_px()};
  const Circle seed{circle.x_px - region.x, circle.y_px - region.y, radius_px, 0.0};
  auto refit = refine_circle(balance_edges_, seed, refine);
  // The refit must stand as an outline on its own, near where the free fit put it.
  if (!refit || refit->score < p2p.min_score ||
      std::hypot(refit->x_px - seed.x_px, refit->y_px - seed.y_px) >
          std::abs(radius_px - circle.radius_px) + 1.0)
    return std::nullopt;
  return shifted(*refit, region.tl());
}

void StereoPipeline::cut_patch(const cv::Mat& left_raw, bool rectified, StereoDetection& out) {
  if (rectified) {
    extract_patch(left_raw, out.left.x_px, out.left.y_px, out.patch_rgb);
    out.patch_valid = true;
    return;
  }
  const cv::Size size = left_raw.size();
  const int cx = static_cast<int>(std::lround(out.left.x_px));
  const int cy = static_cast<int>(std::lround(out.left.y_px));
  auto clamp_x = [&](int x) { return std::clamp(x, 0, size.width - 1); };
  auto clamp_y = [&](int y) { return std::clamp(y, 0, size.height - 1); };
  // Only 441 rectified pixels are needed: map them through the lens model instead of
  // rectifying the whole colour image.
  std::vector<cv::Point2d>& rect_px = tools_.colour_rect_px;
  rect_px.clear();
  for (int r = 0; r < kPatchSide; ++r)
    for (int c = 0; c < kPatchSide; ++c)
      rect_px.emplace_back(clamp_x(cx - kPatchHalf + c), clamp_y(cy - kPatchHalf + r));
  tools_.raw_left_px(rect_px, patch_raw_px_);
  for (int r = 0; r < kPatchSide; ++r)
    for (int c = 0; c < kPatchSide; ++c) {
      const cv::Point2d& p = patch_raw_px_[static_cast<std::size_t>(r * kPatchSide + c)];
      patch_map_.at<cv::Vec2f>(r, c) = cv::Vec2f(static_cast<float>(p.x), static_cast<float>(p.y));
    }
  cv::remap(left_raw, patch_bgr_, patch_map_, cv::noArray(), cv::INTER_LINEAR,
            cv::BORDER_REPLICATE);
  std::uint8_t* dst = out.patch_rgb.data();
  for (int r = 0; r < kPatchSide; ++r)
    for (int c = 0; c < kPatchSide; ++c, dst += 3) put_rgb(patch_bgr_, c, r, dst);
  out.patch_valid = true;
}

}  // namespace stereoball::ball_detector
