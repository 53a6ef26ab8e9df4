#pragma once
// The per-frame work of the ball detector, pure: rectify both eyes through the LUT, run
// Pixel-to-Pixel on each, pair candidates across eyes, triangulate, size check, and cut the
// 21x21 RGB patch around the left centre. Buffers are reused from frame to frame.

#include <opencv2/core.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ball_detector/core/appearance_model.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/detector_params.hpp"
#include "ball_detector/pipeline/interior_depth.hpp"
#include "ball_detector/pipeline/pairing.hpp"
#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"
#include "stereo/core/epipolar.hpp"
#include "stereo/core/rectifier.hpp"
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

/// With a prior, the left eye's edge thresholds (which the searches near the prior reuse) are
/// measured again on the whole frame at least this often, frames.
constexpr int kFullSearchEveryFrames = 15;

/// When the whole-frame search pairs nothing, each eye is searched again in radius bands this
/// ratio wide (largest / smallest radius), each band with its own accumulator peaks: in real
/// clutter (chessboard squares, knuckles, hair) small structures fill every examined peak of
/// the one whole-range accumulator and a large ball outline is never scored.
constexpr double kRadiusBandRatio = 2.5;
/// The band search costs about 7 ms of CPU on a 640x480 frame (red input; 45 ms when each band
/// redid the edge step, 13 ms when it redid the window rules); frames after frames without a
/// pair get it on the first of them and then every this many (at 30 Hz a ball coming into
/// view is looked for band by band within 0.17 s). A band search that pairs starts the count
/// again: the next frame without a pair gets the bands at once.
constexpr int kBandSearchEveryFrames = 5;
/// ... or, at a low frame rate (stills, a slow source), when this much capture time has passed
/// since the last band search: the bands' cost is bounded in time, ns (above 5 frames at 30 Hz,
/// so a 30 Hz stream is searched as before).
constexpr std::int64_t kBandSearchEveryNs = 200'000'000;

/// Runs task(0) .. task(n - 1), possibly at the same time, and returns once all are done. Each
/// task touches only its own state. The pipeline owns no threads: its caller (the node) may
/// give it a runner that spreads the tasks over cores.
using RunTasks = std::function<void(int n, const std::function<void(int)>& task)>;
/// Runs the tasks one after the other (the pipeline's default).
void run_tasks_in_turn(int n, const std::function<void(int)>& task);

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

/// Which search of a frame gave its answer.
enum class SearchPath {
  kExpectedOutlines,  ///< the prior's predicted outlines refined in each eye (no voting)
  kPriorWindow,       ///< voting in the box around the prior
  kWholeFrame,        ///< voting over the whole left eye
  kRadiusBands,       ///< the whole left eye again, radius band by radius band
  /// the colour seeds' outlines, or near a prior its expected outline, on the images with
  /// their brightness removed, in both eyes
  kBrightnessFree,
};

/// Short name of a search path ("expected_outlines", ...).
const char* to_string(SearchPath path);

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

  /// How independent parts of a frame's work are run (run_tasks_in_turn until set): the
  /// detections are the same whichever runner it is.
  void set_task_runner(RunTasks run) { run_tasks_ = std::move(run); }

  /// Validates calib and builds the rectification LUTs and the triangulator; on error the
  /// previous calibration (if any) stays in use and the message names the problem.
  Status set_calibration(const stereo::StereoCalibration& calib);
  /// Whether a calibration has been set.
  bool has_calibration() const { return rectifier_.has_value(); }
  /// The calibration's rectifier, nullopt without calibration.
  const std::optional<stereo::Rectifier>& rectifier() const { return rectifier_; }
  /// Image size frames must have, or 0x0 without calibration.
  cv::Size image_size() const;

  /// Processes one pair of CV_8UC3 (BGR) or CV_8UC1 frames of the calibration's size;
  /// rectified = true skips the LUT (the source already rectified). Wrong input gives
  /// kBadFrame / kNoCalibration with the reason, never an exception. prior: where the tracker
  /// expects the ball (see pair_candidates); a pair found there teaches the appearance model
  /// the followed ball's colour (BGR frames only). stamp_ns: capture time, the model's clock.
  /// eye_skew_ns: left minus right capture stamp when the source measured both (the epipolar
  /// allowance of unsynchronised eyes, params' epipolar.skew_ns = -1); nullopt = unknown (0).
  StereoDetection step(const cv::Mat& left, const cv::Mat& right, bool rectified,
                       const std::optional<PositionPrior>& prior = std::nullopt,
                       std::int64_t stamp_ns = 0,
                       std::optional<std::int64_t> eye_skew_ns = std::nullopt);

  /// How far the ball can move between the two exposures, in radii of its outline
  /// (PairingContext::motion_radii), for a frame with this skew and prior.
  double motion_radii(std::optional<std::int64_t> eye_skew_ns,
                      const std::optional<PositionPrior>& prior) const;

  /// Work a frame leaves for after its answer: the periodic refresh of the whole left eye's
  /// edge thresholds while the ball is found where the track expects it (about 2 ms of CPU
  /// every kFullSearchEveryFrames frames). Call it after publishing the detection, with the
  /// same left frame, so the answer does not wait for it; if it is not called, the next step()
  /// does it first on its own frame. Returns whether it did anything (a frame that does not
  /// fit the calibration is left alone).
  bool finish_frame(const cv::Mat& left, bool rectified);

  /// The followed ball's learnt appearance (for tests and diagnostics).
  const AppearanceModel& appearance() const { return appearance_; }

  /// Rectified detector-input images of the last processed frame (for debugging and tests);
  /// with right_eye_partner_boxes the right one holds only the searched boxes (zero elsewhere).
  const cv::Mat& rectified_left() const { return rect_left_; }
  const cv::Mat& rectified_right() const { return rect_right_; }
  /// Candidates of the last processed frame, rectified pixels, best first.
  const std::vector<Circle>& left_candidates() const { return left_candidates_; }
  const std::vector<Circle>& right_candidates() const { return right_candidates_; }
  /// The left detector's last edge map (the whole eye, or the crop last searched: see its
  /// frame_px), for diagnostics.
  const EdgeMap& left_edges() const { return left_detector_.edge_map(); }
  /// The rectified cameras of the calibration in use (nullopt without one).
  std::optional<stereo::PinholeCamera> left_camera() const;
  std::optional<stereo::PinholeCamera> right_camera() const;

 private:
  Status check_input(const cv::Mat& left, const cv::Mat& right) const;
  void refresh_thresholds(const cv::Mat& left_channel, bool rectified);
  void rectify_whole(const cv::Mat& channel, stereo::Eye eye, bool rectified, cv::Mat& out) const;
  /// out: a zero image of the calibration's size and channel's type (boxes are then rectified
  /// into it with rectify_box; the rest stays zero).
  void clear_rectified(const cv::Mat& channel, cv::Mat& out) const;
  void rectify_box(const cv::Mat& channel, stereo::Eye eye, bool rectified, const cv::Rect& box,
                   cv::Mat& out) const;
  const cv::Mat& detector_channel(const cv::Mat& raw, cv::Mat& grey) const;
  std::vector<cv::Rect> partner_boxes(const PairingContext& ctx) const;
  std::optional<PairingResult> search_near_prior(const PairingContext& ctx,
                                                 const cv::Mat& left_channel,
                                                 const cv::Mat& right_channel, bool rectified,
                                                 const PositionPrior& prior);
  /// The pair at the prior's expected outlines refined (left in left_box, already rectified),
  /// or nullopt when that gives no pair within the gate.
  std::optional<PairingResult> pair_at_expected_outlines(const PairingContext& ctx,
                                                         const cv::Mat& right_channel,
                                                         bool rectified, const PositionPrior& prior,
                                                         const cv::Rect& left_box,
                                                         const SearchHints& left_hints);
  PairingResult search_whole_frame(const PairingContext& ctx, const cv::Mat& left_channel,
                                   const cv::Mat& right_channel, bool rectified,
                                   const std::optional<PositionPrior>& prior,
                                   std::optional<std::vector<Circle>>* band_left);
  PairingResult search_radius_bands(const PairingContext& ctx, std::vector<Circle> band_left,
                                    const cv::Mat& right_channel, bool rectified,
                                    const std::optional<PositionPrior>& prior);
  /// The left detector's last image (whole, its own thresholds) searched again band by band;
  /// stops early (result unused) once *stop is set.
  std::vector<Circle> detect_left_in_bands(const std::atomic<bool>* stop);
  /// The left detector's last votes turned into circles, each peak a task or all in turn.
  std::vector<Circle> left_circles_of_votes(bool peaks_at_once);
  // Left candidates refined from colour-region seeds (colour_seeds.hpp) that the votes missed;
  // the seeds are kept for pair_seeds_without_brightness.
  void add_colour_seeded_candidates();
  /// Seeds (left rectified px) refined on the left image with its brightness removed, each found
  /// circle's right outline looked for the same way, and the pairs checked as any are: a ball
  /// whose rim differs from the floor in hue, hardly in brightness, on a floor whose brightness
  /// texture sets the frame's edge thresholds (stereo_pipeline_brightness_free.cpp). Nothing
  /// for grey input.
  PairingResult pair_seeds_without_brightness(const PairingContext& ctx,
                                              const cv::Mat& left_channel,
                                              const cv::Mat& right_channel, bool rectified,
                                              const std::optional<PositionPrior>& prior,
                                              std::span<const Circle> seeds);
  /// The same from the prior's expected left outline; only a pair within the gate counts.
  std::optional<PairingResult> pair_expected_without_brightness(const PairingContext& ctx,
                                                                const cv::Mat& left_channel,
                                                                const cv::Mat& right_channel,
                                                                bool rectified,
                                                                const PositionPrior& prior);
  /// The right outline of left's ball along its epipolar line, scored on the right partner box
  /// with its brightness removed (edges at thresholds, the left box's).
  std::optional<Circle> right_outline_without_brightness(const PairingContext& ctx,
                                                         const cv::Mat& right_channel,
                                                         bool rectified, const Circle& left,
                                                         const EdgeThresholds& thresholds);
  /// How a right outline predicted from a left circle is scored (min_inside_fraction of it in
  /// view): no clutter rings, the right camera's perspective.
  RefineParams partner_scoring(double min_inside_fraction) const;
  /// How much of a predicted right outline must be in view: near a track's prior the predicted
  /// partner's own fraction, elsewhere also the detector's border rule.
  double partner_min_inside_fraction(bool near_prior) const;
  /// The right outline of left's ball along its epipolar line (predicted_partner), scored on
  /// edges whose pixel (0, 0) is origin in the rectified right image; p2p.min_score to pass.
  std::optional<Circle> partner_on_edges(const PairingContext& ctx, const Circle& left,
                                         const EdgeMap& edges, cv::Point origin,
                                         const RefineParams& scoring) const;
  int window_margin_px() const;
  std::vector<Circle> detect_right_in_boxes(const PairingContext& ctx, const cv::Mat& right_channel,
                                            bool rectified, bool near_prior);
  std::vector<Circle> predicted_partners(const PairingContext& ctx, double min_inside_fraction);
  PairingResult pair_with_predicted_partners(const PairingContext& ctx,
                                             const std::optional<PositionPrior>& prior,
                                             bool near_prior);
  void fill_result(const PairingResult& pairing, StereoDetection& out) const;
  ShiftWindow shift_window(const StereoDetection& found) const;
  /// channel (a raw eye, or rectified already) rectified at least over region: channel itself
  /// when rectified, else the eye's scratch image with region rectified into it.
  const cv::Mat& rectified_region(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                  const cv::Rect& region);
  void check_interior(const cv::Mat& left_channel, const cv::Mat& right_channel, bool rectified,
                      StereoDetection& found);
  void balance_radii(const cv::Mat& left_channel, const cv::Mat& right_channel, bool rectified,
                     StereoDetection& found);
  /// A found pair's outlines refitted to the arcs that agree (stereo_pipeline_outline_refit.cpp).
  void refit_outlines(const PairingContext& ctx, const cv::Mat& left_channel,
                      const cv::Mat& right_channel, bool rectified, StereoDetection& found);
  std::optional<Circle> robust_outline_in(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                          const Circle& circle);
  std::optional<Circle> refit_at_radius(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                        const Circle& circle, double radius_px);
  void cut_patch(const cv::Mat& left_raw, bool rectified, StereoDetection& out);
  void raw_left_px(const std::vector<cv::Point2d>& rectified_px, std::vector<cv::Point2d>& raw_px);
  std::optional<ColourHistogram> colour_of(const Circle& left);
  int apply_appearance();

  BallDetectorParams params_;          // p2p scaled to the calibration's width (set_calibration)
  PixelToPixelParams configured_p2p_;  // p2p as configured
  PixelToPixelDetector left_detector_;
  PixelToPixelDetector right_detector_;
  std::vector<PixelToPixelDetector> band_detectors_;  // one per radius band of the left eye
  PixelToPixelDetector seed_detector_;  // pair_seeds_without_brightness's left searches
  std::vector<Circle> colour_seeds_;    // the last whole-frame search's (left rectified px)
  cv::Mat brightness_free_right_;       // right_outline_without_brightness's image
  RunTasks run_tasks_ = run_tasks_in_turn;
  stereo::EpipolarCheck epipolar_;
  stereo::SizeCheckParams size_;
  std::optional<stereo::Rectifier> rectifier_;
  std::optional<stereo::Triangulator> triangulator_;
  cv::Matx33d patch_ray_from_pixel_;  // rectified pixel -> ray in the raw left camera
  cv::Mat grey_left_, grey_right_, rect_left_, rect_right_;
  cv::Mat region_left_, region_right_;  // rectified_region's scratch images, one per eye
  EdgeMap balance_edges_;               // the edges of the region balance_radii refits
  cv::Mat patch_map_, patch_bgr_;
  std::vector<cv::Point3d> patch_rays_;
  std::vector<cv::Point2d> patch_raw_px_;
  std::vector<Circle> left_candidates_, right_candidates_;
  EdgeMap partner_edges_;     // right-eye edges around one predicted partner
  cv::Rect right_edges_box_;  // the box of the right detector's last edge map
  // search_near_prior: which of its searches answered (kExpectedOutlines or kPriorWindow).
  SearchPath near_prior_path_ = SearchPath::kPriorWindow;
  std::optional<EdgeThresholds> left_thresholds_;  // of the last whole left frame
  std::optional<FloorModel> floor_;                // none when the floor check is off
  AppearanceModel appearance_;
  const cv::Mat* frame_left_ = nullptr;  // the raw left frame of the step in progress
  bool frame_rectified_ = false;
  double frame_motion_radii_ = 0.0;  // the frame's PairingContext::motion_radii
  int rejected_by_colour_ = 0;
  std::vector<cv::Point2d> colour_rect_px_, colour_raw_px_;
  std::vector<cv::Vec3b> colour_px_;
  int frames_since_full_search_ = 0;
  bool refresh_due_ = false;     // the left thresholds are to be measured again (finish_frame)
  cv::Mat refresh_left_;         // the whole rectified left eye the refresh measures
  EdgeMap refresh_edges_;        // its gradients (scratch)
  int frames_without_pair_ = 0;  // consecutive whole-frame searches that paired nothing
  std::optional<std::int64_t> last_band_search_ns_;  // capture stamp of the last band search
};

}  // namespace stereoball::ball_detector
