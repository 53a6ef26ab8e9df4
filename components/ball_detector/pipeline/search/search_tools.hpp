#pragma once
// The equipment the searches of a frame share and the pipeline reuses from frame to frame:
// the calibration, the detectors (whose last edge maps and votes later searches read), the
// rectified images and the followed ball's appearance; and the steps several searches take.

#include <opencv2/core.hpp>

#include <functional>
#include <optional>
#include <vector>

#include "ball_detector/core/appearance_model.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/detector_params.hpp"
#include "ball_detector/pipeline/pairing.hpp"
#include "ball_detector/pipeline/search/coarse_search.hpp"
#include "ball_detector/pipeline/search/search_strategy.hpp"
#include "stereo/core/rectifier.hpp"
#include "stereo/core/row_source.hpp"
#include "stereo/core/triangulation.hpp"

namespace stereoball::ball_detector {

/// Runs task(0) .. task(n - 1), possibly at the same time, and returns once all are done. Each
/// task touches only its own state. The pipeline owns no threads: its caller (the node) may
/// give it a runner that spreads the tasks over cores.
using RunTasks = TaskRunner;
/// Runs the tasks one after the other (the pipeline's default).
void run_tasks_in_turn(int n, const std::function<void(int)>& task);

/// Told before (started true) and after (false) each search of a frame, and around the radius
/// bands a whole-frame search runs beside it, on the thread that runs it: for a caller that
/// times them (the pipeline has no clock). Nested calls mean the inner search's time is its own.
using SearchObserver = std::function<void(SearchPath path, bool started)>;

/// The frame's right eye made as far as the searches read it (a lazily decoded JPEG eye): every
/// read of the right eye goes through rectify_box, rectify_whole or the pipeline's
/// rectified_region, which make the raw rows they read first.
struct RightRows {
  stereo::RowSource* source = nullptr;  ///< nullptr: the right detector input is whole
  /// Makes the raw rows box (rectified px) reads: through the rectification's look-up, or box's
  /// own rows when the eye is rectified already.
  void make_for(const stereo::Rectifier& rectifier, bool rectified, const cv::Rect& box) const;
  /// make_for each of boxes, the topmost rows first (boxes read in any order after it).
  void make_for(const stereo::Rectifier& rectifier, bool rectified,
                const std::vector<cv::Rect>& boxes) const;
  /// Makes every row.
  void make_all() const;
  /// Whether making rows met corrupt data (the frame is then a bad one).
  bool failed() const { return source != nullptr && !source->status(); }
};

/// The pipeline's equipment; one per StereoPipeline, used by one frame at a time.
struct SearchTools {
  /// params must pass validate().
  explicit SearchTools(const BallDetectorParams& params);

  BallDetectorParams params;           ///< p2p scaled to the calibration's width
  PixelToPixelParams configured_p2p;   ///< p2p as configured
  PixelToPixelDetector left_detector;  ///< the left eye's searches (its edges/votes are read on)
  PixelToPixelDetector right_detector;
  std::vector<PixelToPixelDetector> band_detectors;  ///< one per radius band of the left eye
  PixelToPixelDetector seed_detector;  ///< the brightness-free searches' left detector
  CoarseSearch coarse;  ///< the whole-frame and band searches' reduced left eye (wide frames)
  RunTasks run_tasks = run_tasks_in_turn;
  int task_threads = 1;     ///< how many tasks run_tasks runs at once (1: in turn)
  SearchObserver observer;  ///< empty: nobody times the searches
  std::optional<stereo::Rectifier> rectifier;
  RightRows right_rows;  ///< the frame's right eye, made as far as read (step() sets it)
  std::optional<stereo::Triangulator> triangulator;
  cv::Matx33d ray_from_pixel;     ///< rectified left pixel -> ray in the raw left camera
  cv::Mat rect_left, rect_right;  ///< rectified detector input (whole, or searched boxes only)
  cv::Mat brightness_free_right;  ///< the right box with its brightness removed (scratch)
  EdgeMap partner_edges;          ///< right-eye edges around one predicted partner (scratch)
  cv::Rect right_edges_box;       ///< the box of the right detector's last edge map, px
  std::optional<EdgeThresholds> left_thresholds;           ///< of the last whole left frame
  AppearanceModel appearance;                              ///< the followed ball's colour
  std::vector<cv::Point3d> rays;                           ///< raw_left_px's scratch
  std::vector<cv::Point2d> colour_rect_px, colour_raw_px;  ///< colour_of's scratch
  std::vector<cv::Vec3b> colour_px;                        ///< colour_of's scratch

  /// observer(path, started) if there is one.
  void observe(SearchPath path, bool started) const {
    if (observer) observer(path, started);
  }
  /// How the whole left eye's votes are cast: split over run_tasks when it runs tasks at once.
  VoteTasks left_vote_tasks() const {
    return task_threads > 1 ? VoteTasks{run_tasks, task_threads} : VoteTasks{};
  }
  /// The calibration's image size, px (0x0 without one).
  cv::Size image_size() const;
  /// The rectified left camera (nullopt without calibration).
  std::optional<stereo::PinholeCamera> left_camera() const;
  /// Window half size plus the smoothing box: arcs closer to a box edge cannot vote, px.
  int window_margin_px() const;
  /// channel (raw, or rectified when rectified) rectified whole into out.
  void rectify_whole(const cv::Mat& channel, stereo::Eye eye, bool rectified, cv::Mat& out) const;
  /// rectify_whole() in row bands, one per task of run_tasks when it runs tasks at once (each
  /// pixel is its own: the same image).
  void rectify_whole_in_tasks(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                              cv::Mat& out) const;
  /// out: a zero image of the calibration's size and channel's type.
  void clear_rectified(const cv::Mat& channel, cv::Mat& out) const;
  /// box (rectified px) of channel rectified into out.
  void rectify_box(const cv::Mat& channel, stereo::Eye eye, bool rectified, const cv::Rect& box,
                   cv::Mat& out) const;
  /// The right-eye boxes where partners of left can lie (overlapping ones merged), px.
  std::vector<cv::Rect> partner_boxes(const PairingContext& ctx,
                                      const std::vector<Circle>& left) const;
  /// The right eye searched in left's partner boxes (the left edge thresholds), best first.
  std::vector<Circle> detect_right_in_boxes(const FrameState& frame,
                                            const std::vector<Circle>& left, bool near_prior);
  /// How much of a predicted right outline must be in view: near a track's prior the predicted
  /// partner's own fraction, elsewhere also the detector's border rule.
  double partner_min_inside_fraction(bool near_prior) const;
  /// How a right outline predicted from a left circle is scored: no clutter rings, the right
  /// camera's perspective.
  RefineParams partner_scoring(double min_inside_fraction) const;
  /// The right outline of left's ball along its epipolar line, scored on edges whose pixel
  /// (0, 0) is origin in the rectified right image; p2p.min_score to pass.
  std::optional<Circle> partner_on_edges(const PairingContext& ctx, const Circle& left,
                                         const EdgeMap& edges, cv::Point origin,
                                         const RefineParams& scoring) const;
  /// The rectified pixels' places in the raw left image (lens model), px.
  void raw_left_px(const std::vector<cv::Point2d>& rectified_px, std::vector<cv::Point2d>& raw_px);
  /// The colours inside left (a rectified circle) in the frame's raw left image; nullopt for
  /// grey frames or too few pixels in view.
  std::optional<ColourHistogram> colour_of(const FrameState& frame, const Circle& left);
  /// Drops the left circles the followed ball's appearance rejects and ranks the rest by
  /// colour; returns how many it dropped.
  int apply_appearance(const FrameState& frame, std::vector<Circle>& left);
};

}  // namespace stereoball::ball_detector
