#pragma once
// The per-frame work of the ball detector, pure: rectify both eyes through the LUT, run
// Pixel-to-Pixel on each, pair candidates across eyes, triangulate, size check, and cut the
// 21x21 RGB patch around the left centre. Buffers are reused from frame to frame.

#include <opencv2/core.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "ball_detector/core/appearance_model.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/detector_params.hpp"
#include "ball_detector/pipeline/interior_depth.hpp"
#include "ball_detector/pipeline/interior_motion.hpp"
#include "ball_detector/pipeline/pairing.hpp"
#include "ball_detector/pipeline/search/brightness_free.hpp"
#include "ball_detector/pipeline/search/expected_outlines.hpp"
#include "ball_detector/pipeline/search/prior_window.hpp"
#include "ball_detector/pipeline/search/radius_bands.hpp"
#include "ball_detector/pipeline/search/search_strategy.hpp"
#include "ball_detector/pipeline/search/search_tools.hpp"
#include "ball_detector/pipeline/search/whole_frame.hpp"
#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"
#include "stereo/core/epipolar.hpp"
#include "stereo/core/rectifier.hpp"
#include "stereo/core/row_source.hpp"
#include "stereo/core/triangulation.hpp"

namespace stereoball::ball_detector {

/// Chroma of a CV_8UC3 image: max(B,G,R) - min(B,G,R) per pixel into a CV_8UC1 (reused).
void saturation(const cv::Mat& bgr, cv::Mat& out);

/// Brightest channel of a CV_8UC3 image: max(B,G,R) per pixel into a CV_8UC1 (reused).
void value(const cv::Mat& bgr, cv::Mat& out);

/// The image the detector runs on for input (a BGR image converted into scratch, or image
/// itself: colour input, or a single-channel image).
const cv::Mat& detector_input_image(const cv::Mat& image, DetectorInput input, cv::Mat& scratch);

/// The floor as the left rectified camera sees it (params' camera height and pitch, rotated
/// by the rectification), or nullopt when params.floor_tolerance_m is 0.
std::optional<FloorModel> floor_model(const BallDetectorParams& params,
                                      const stereo::StereoCalibration& calib);

/// What a user does about cameras in the wrong order (they are swapped at the source).
inline constexpr const char* kHowToSwapCameras =
    "swap the cameras at the source (camera_server: left_device and right_device, file source: "
    "left_glob and right_glob)";

/// Outcome of one stereo frame (mirrors the ball/detection statuses).
enum class DetectionStatus {
  kFound,
  kNoCandidate,
  kEpipolarMismatch,
  kSizeInconsistent,
  kNoCalibration,
  kBadFrame,
  kOffFloor,
  /// A ball-sized pair on the floor whose inside is textured and matches between the eyes at
  /// another depth than its outline: a round pattern on a surface (interior_depth.hpp).
  kInteriorMismatch
};

/// Short name of a status ("found", "no_candidate", ...).
const char* to_string(DetectionStatus status);

/// With a prior, the whole left frame's edge thresholds are measured again at least this often
/// (README: searches), frames.
constexpr int kFullSearchEveryFrames = 15;

/// Frames this close in capture time are a stream (README: searches): after its first frame,
/// each frame the whole frame pairs nothing on gets one radius band, the bands in turn (a band
/// that paired first again), and once the ball has been missing for a frame the frames with a
/// large prior box (kLargePriorBoxShare) vote in it and over the whole frame in turn; stills and
/// slower frames search every band, and the whole frame after the prior, on every frame, ns.
constexpr std::int64_t kBandSearchEveryNs = 200'000'000;

/// A prior box larger than this share of the image is a large one (kBandSearchEveryNs): voting
/// in it costs about a whole-frame search (boxes of a coasting track, or of a near ball).
constexpr double kLargePriorBoxShare = 0.25;

/// With a following track, the ball's speed allowed between the two eyes' exposures is the
/// track's plus this (its velocity lags a hand's push), m/s, when lower than the configured.
constexpr double kTrackSpeedSlackMps = 1.0;

/// Side of the colour block around the left centre, pixels (paper: 21x21, k = 10).
constexpr int kPatchSide = 21;
/// Bytes of the colour block (R, G, B per pixel, row-major).
constexpr int kPatchBytes = kPatchSide * kPatchSide * 3;

/// The 21x21 block centred on the pixel nearest (x_px, y_px) of a CV_8UC3 (BGR) or CV_8UC1
/// image, as R,G,B row-major; pixels outside the image repeat the nearest border pixel.
void extract_patch(const cv::Mat& image, double x_px, double y_px,
                   std::array<std::uint8_t, kPatchBytes>& out);

/// What the pipeline found in one stereo frame.
struct StereoDetection {
  DetectionStatus status = DetectionStatus::kNoCandidate;
  std::string reason;              ///< human-readable detail of status
  Circle left;                     ///< best left circle, rectified pixels (score 0 if none)
  Circle right;                    ///< matched right circle, rectified pixels
  double row_residual_px = 0.0;    ///< |y_left - y_right|, rectified pixels
  cv::Vec3d position_m;            ///< ball centre, left rectified camera frame, metres
  double depth_from_size_m = 0.0;  ///< depth implied by the radii, metres (0 if unknown)
  int candidates_left = 0;         ///< circles found in the left eye
  int candidates_right = 0;        ///< circles found in the right eye
  int rejected_by_colour = 0;      ///< left circles the followed ball's appearance rejected
  SearchPath search = SearchPath::kWholeFrame;  ///< the last search the frame needed
  bool patch_valid = false;  ///< patch_rgb holds the block around the left centre
  std::array<std::uint8_t, kPatchBytes> patch_rgb{};  ///< 21x21 R,G,B row-major, borders clamped
};

/// Rectification, detection and pairing of stereo frames for one calibration at a time.
class StereoPipeline {
 public:
  /// params must pass validate() (invalid detector values are clamped by the detector).
  explicit StereoPipeline(const BallDetectorParams& params);

  /// How independent parts of a frame's work are run (same detections with any runner);
  /// threads: how many tasks it runs at once (more than 1 lets work be split for it).
  void set_task_runner(RunTasks run, int threads = 1) {
    tools_.run_tasks = std::move(run);
    tools_.task_threads = std::max(1, threads);
  }
  /// Who is told when each search starts and ends (SearchObserver; empty = nobody).
  void set_search_observer(SearchObserver observer) { tools_.observer = std::move(observer); }

  /// Validates calib and builds the LUTs and triangulator; on error the previous one stays.
  Status set_calibration(const stereo::StereoCalibration& calib);
  /// Whether a calibration has been set.
  bool has_calibration() const { return tools_.rectifier.has_value(); }
  /// The frames the last step(left, right, ...) searched: left and right themselves, or their
  /// copies shrunk to working_size() (valid until the next step() or finish_frame()).
  std::pair<const cv::Mat*, const cv::Mat*> searched_frames(const cv::Mat& left,
                                                            const cv::Mat& right) const {
    if (!(work_scale_ < 1.0) || left.size() == working_size()) return {&left, &right};
    return {&work_left_, &work_right_};
  }
  /// The whole factor (2, 4 or 8) frames of image_size() are shrunk by to working_size() when
  /// it divides both sides, else 1: a source that can decode its frames reduced by it (JPEG,
  /// stereo::FrameDecoder::set_reduction) may give step() the reduced frames.
  int working_reduction() const;
  /// The rectifier of the working-size calibration (working_size()), nullopt without one.
  const std::optional<stereo::Rectifier>& rectifier() const { return tools_.rectifier; }
  /// Image size frames must have, or 0x0 without calibration.
  cv::Size image_size() const;
  /// Size frames are searched at (image_size() shrunk to BallDetectorParams::working_width_px),
  /// or 0x0 without calibration; rectified_left(), the candidates and the cameras are in it.
  cv::Size working_size() const { return tools_.image_size(); }

  /// One pair of BGR or grey frames of the calibration's size, or already shrunk to
  /// working_size() when that is smaller (rectified: no LUT), the prior
  /// (metres), capture stamp_ns and left-minus-right eye_skew_ns (README: step); never throws.
  StereoDetection step(const cv::Mat& left, const cv::Mat& right, bool rectified,
                       const std::optional<PositionPrior>& prior = std::nullopt,
                       std::int64_t stamp_ns = 0,
                       std::optional<std::int64_t> eye_skew_ns = std::nullopt);

  /// As step(left, right, ...), the right eye's rows made only as the searches read them
  /// (stereo::RowSource: a lazily decoded JPEG eye), all of them when the frame is shrunk or
  /// converted first. Corrupt data met in the rows read makes the frame kBadFrame with the
  /// source's reason (the searches' measurements on its left eye are kept).
  StereoDetection step(const cv::Mat& left, stereo::RowSource& right, bool rectified,
                       const std::optional<PositionPrior>& prior = std::nullopt,
                       std::int64_t stamp_ns = 0,
                       std::optional<std::int64_t> eye_skew_ns = std::nullopt);

  /// How far the ball can move between the two exposures for this skew and prior, radii.
  double motion_radii(std::optional<std::int64_t> eye_skew_ns,
                      const std::optional<PositionPrior>& prior) const;

  /// The work step() left for after its answer (README: step), on the same left frame;
  /// whether it did any.
  bool finish_frame(const cv::Mat& left, bool rectified);

  /// The followed ball's learnt appearance (for tests and diagnostics).
  const AppearanceModel& appearance() const { return tools_.appearance; }

  /// Rectified detector input of the last frame (right: the searched boxes only, zero elsewhere).
  const cv::Mat& rectified_left() const { return tools_.rect_left; }
  const cv::Mat& rectified_right() const { return tools_.rect_right; }
  /// Candidates of the last processed frame, rectified pixels, best first.
  const std::vector<Circle>& left_candidates() const { return left_candidates_; }
  const std::vector<Circle>& right_candidates() const { return right_candidates_; }
  /// The left detector's last edge map (whole eye or last crop: its frame_px), diagnostics.
  const EdgeMap& left_edges() const { return tools_.left_detector.edge_map(); }
  /// The rectified cameras of the calibration in use (nullopt without one).
  std::optional<stereo::PinholeCamera> left_camera() const;
  std::optional<stereo::PinholeCamera> right_camera() const;

 private:
  Status check_input(const cv::Mat& left, const cv::Mat& right) const;
  /// Whether step() reads the whole right eye before searching (shrinking, converting it).
  bool reads_right_whole(const cv::Mat& left, const cv::Mat& right) const;
  /// The answer for a frame whose right eye turned out corrupt.
  StereoDetection bad_right_eye(const std::string& problem);
  /// Whether frames of these sizes were shrunk to the working size already (by their source).
  bool at_working_size(cv::Size left, cv::Size right) const;
  /// The frames shrunk to the working size (the frames themselves at full size).
  std::pair<const cv::Mat*, const cv::Mat*> working_frames(const cv::Mat& left,
                                                           const cv::Mat& right);
  /// A detection's circles from working to input rectified pixels.
  void to_input_pixels(StereoDetection& out) const;
  void refresh_thresholds(const cv::Mat& left_channel, bool rectified);
  const cv::Mat& detector_channel(const cv::Mat& raw, cv::Mat& grey) const;
  /// The frame's searches in order (the driver): the answer, its candidates and path.
  SearchOutcome search(const FrameState& frame);
  /// The answer's checks, patch and colour learning into out.
  void report(const FrameState& frame, const SearchOutcome& answer, StereoDetection& out);
  void fill_result(const SearchOutcome& answer, StereoDetection& out) const;
  ShiftWindow shift_window(const StereoDetection& found, double motion_radii) const;
  /// channel (a raw eye, or rectified already) rectified at least over region: channel itself
  /// when rectified, else the eye's scratch image with region rectified into it.
  const cv::Mat& rectified_region(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                  const cv::Rect& region);
  void check_interior(const FrameState& frame, StereoDetection& found);
  void balance_radii(const FrameState& frame, StereoDetection& found);
  /// A found pair's outlines refitted to the arcs that agree (stereo_pipeline_outline_refit.cpp).
  void refit_outlines(const FrameState& frame, StereoDetection& found);
  /// A found pair that needs the motion allowance (unsynchronised eyes) withdrawn when its
  /// outlines are not one ball's (outline_refit.hpp moved_radii) and neither eye's is found again
  /// where the other's puts the ball unmoved (stereo_pipeline_outline_refit.cpp).
  void check_moved_pair(const FrameState& frame, const StereoPair& paired, StereoDetection& found);
  /// A found pair that needs the motion allowance withdrawn when the inside of its outlines,
  /// matched between the eyes, moved by other rows than its outlines did (interior_motion.hpp).
  void check_interior_motion(const FrameState& frame, const StereoPair& paired,
                             StereoDetection& found);
  std::optional<Circle> robust_outline_in(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                          const Circle& circle);
  /// The edges of channel (rectified over the region) within margin_px of circle's centre into
  /// balance_edges_; the region (rectified px), or nullopt when too little of it is in view.
  std::optional<cv::Rect> edges_around(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                       const Circle& circle, int margin_px);
  std::optional<Circle> refit_at_radius(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                        const Circle& circle, double radius_px);
  void cut_patch(const cv::Mat& left_raw, bool rectified, StereoDetection& out);

  SearchTools tools_;  // calibration, detectors, rectified images, appearance (frame to frame)
  // The calibration frames arrive with; tools_ holds it shrunk to the working width.
  std::optional<stereo::StereoCalibration> input_calibration_;
  double work_scale_ = 1.0;         // working / input width
  cv::Mat work_left_, work_right_;  // the frames shrunk (work_scale_ < 1)
  // The searches, in the order search() runs them.
  ExpectedOutlinesSearch expected_outlines_;
  PriorWindowSearch prior_window_;
  BrightnessFreeSearch expected_without_brightness_{BrightnessFreeSeeds::kExpectedOutline};
  WholeFrameSearch whole_frame_;
  RadiusBandSearch radius_bands_;
  BrightnessFreeSearch seeds_without_brightness_{BrightnessFreeSeeds::kColourSeeds};
  stereo::EpipolarCheck epipolar_;
  stereo::SizeCheckParams size_;
  std::optional<FloorModel> floor_;  // none when the floor check is off
  cv::Mat grey_left_, grey_right_;
  cv::Mat region_left_, region_right_;  // rectified_region's scratch images, one per eye
  EdgeMap balance_edges_;               // the edges of the region balance_radii refits
  cv::Mat patch_map_, patch_bgr_;
  std::vector<cv::Point2d> patch_raw_px_;
  std::vector<Circle> left_candidates_, right_candidates_;  // the last frame's answer's
  int frames_since_full_search_ = 0;
  bool refresh_due_ = false;        // the left thresholds are to be measured again (finish_frame)
  cv::Mat refresh_left_;            // the whole rectified left eye the refresh measures
  EdgeMap refresh_edges_;           // its gradients (scratch)
  int next_band_ = 0;               // the radius band the next frame without a pair searches
  bool missed_last_frame_ = false;  // the last frame's searches paired nothing
  // The last frame searched near the prior only (and paired nothing): the whole frame's turn.
  bool window_only_last_frame_ = false;
  std::optional<std::int64_t> last_stamp_ns_;  // capture stamp of the last frame searched
};

}  // namespace stereoball::ball_detector
