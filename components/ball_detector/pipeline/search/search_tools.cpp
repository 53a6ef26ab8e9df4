#include "ball_detector/pipeline/search/search_tools.hpp"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>

namespace stereoball::ball_detector {
namespace {

// Where a circle's colour is sampled: rings at these fractions of its radius, kColourAngles
// points each, and the centre (inside the ball, clear of its outline and the background).
constexpr double kColourRings[] = {0.2, 0.4, 0.55, 0.7};
constexpr int kColourAngles = 12;

}  // namespace

void RightRows::make_for(const stereo::Rectifier& rectifier, bool rectified,
                         const cv::Rect& box) const {
  if (source == nullptr) return;
  if (rectified) {
    source->make_rows(box.y, box.y + box.height);
    return;
  }
  const cv::Range rows = rectifier.raw_rows(stereo::Eye::kRight, box);
  source->make_rows(rows.start, rows.end);
}

void RightRows::make_for(const stereo::Rectifier& rectifier, bool rectified,
                         const std::vector<cv::Rect>& boxes) const {
  if (source == nullptr) return;
  std::vector<cv::Range> rows;
  for (const cv::Rect& box : boxes)
    rows.push_back(rectified ? cv::Range(box.y, box.y + box.height)
                             : rectifier.raw_rows(stereo::Eye::kRight, box));
  source->make_rows_top_first(std::move(rows));
}

void RightRows::make_all() const {
  if (source != nullptr) source->make_all();
}

void run_tasks_in_turn(int n, const std::function<void(int)>& task) {
  for (int i = 0; i < n; ++i) task(i);
}

SearchTools::SearchTools(const BallDetectorParams& p)
    : params(p),
      configured_p2p(p.p2p),
      left_detector(p.detector_params()),
      right_detector(p.detector_params()),
      seed_detector(p.detector_params()),
      appearance(p.appearance) {}

cv::Size SearchTools::image_size() const {
  return rectifier ? rectifier->calibration().image_size : cv::Size();
}

std::optional<stereo::PinholeCamera> SearchTools::left_camera() const {
  if (!triangulator) return std::nullopt;
  return stereo::PinholeCamera{triangulator->focal_px(), triangulator->principal_left_px()};
}

int SearchTools::window_margin_px() const {
  const auto& ks = params.p2p.k_values;
  return (ks.empty() ? 5 : *std::max_element(ks.begin(), ks.end())) + 4;
}

void SearchTools::rectify_whole(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                cv::Mat& out) const {
  if (eye == stereo::Eye::kRight) right_rows.make_all();
  if (rectified) {
    channel.copyTo(out);
  } else {
    rectifier->rectify_eye(eye, channel, out);
  }
}

void SearchTools::rectify_whole_in_tasks(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                                         cv::Mat& out) const {
  if (task_threads <= 1 || rectified) return rectify_whole(channel, eye, rectified, out);
  const cv::Size size = image_size();
  out.create(size, channel.type());
  const int n = task_threads;
  run_tasks(n, [&](int i) {
    const int top = size.height * i / n, bottom = size.height * (i + 1) / n;
    rectifier->rectify_eye_region(eye, channel, cv::Rect(0, top, size.width, bottom - top), out);
  });
}

void SearchTools::clear_rectified(const cv::Mat& channel, cv::Mat& out) const {
  out.create(image_size(), channel.type());
  out.setTo(0);
}

void SearchTools::rectify_box(const cv::Mat& channel, stereo::Eye eye, bool rectified,
                              const cv::Rect& box, cv::Mat& out) const {
  if (eye == stereo::Eye::kRight) right_rows.make_for(*rectifier, rectified, box);
  if (rectified) {
    channel(box).copyTo(out(box));
  } else {
    rectifier->rectify_eye_region(eye, channel, box, out);
  }
}

std::vector<cv::Rect> SearchTools::partner_boxes(const PairingContext& ctx,
                                                 const std::vector<Circle>& left) const {
  const cv::Size size = image_size();
  const int margin = window_margin_px();
  std::vector<cv::Rect> boxes;
  for (const Circle& c : left) {
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

std::vector<Circle> SearchTools::detect_right_in_boxes(const FrameState& frame,
                                                       const std::vector<Circle>& left,
                                                       bool near_prior) {
  clear_rectified(frame.right_channel, rect_right);
  right_edges_box = {};
  std::vector<Circle> found;
  SearchHints hints{partner_radius_range(frame.ctx, left)};
  if (near_prior) {
    hints.min_inside_fraction = params.prior_min_inside_fraction;
    hints.centre_margin_px = partner_centre_margin_px(frame.ctx, left, image_size());
  }
  const std::vector<cv::Rect> boxes = partner_boxes(frame.ctx, left);
  // A lower box may come first (the boxes follow the left circles' scores): the rows of all of
  // them are made top first, so a lazily decoded eye never decodes again from the top for them.
  right_rows.make_for(*rectifier, frame.rectified, boxes);
  for (const cv::Rect& box : boxes) {
    rectify_box(frame.right_channel, stereo::Eye::kRight, frame.rectified, box, rect_right);
    right_edges_box = box;
    // The left image's thresholds: the box's own statistics depend on what it holds.
    for (const Circle& c :
         right_detector.detect(rect_right(box), thresholds_of(left_detector.edge_map()), hints))
      found.push_back(shifted(c, box.tl()));
  }
  std::stable_sort(found.begin(), found.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  return found;
}

double SearchTools::partner_min_inside_fraction(bool near_prior) const {
  return near_prior ? params.predicted_partner_min_inside_fraction
                    : std::max(params.predicted_partner_min_inside_fraction,
                               params.p2p.refine_params.min_inside_fraction);
}

RefineParams SearchTools::partner_scoring(double min_inside_fraction) const {
  RefineParams scoring = params.detector_params().refine_params;
  scoring.min_inside_fraction = min_inside_fraction;
  // The outline is scored where its left circle, already past the clutter rings, predicts it:
  // not a chance circle found in texture. The rings there cost balls on textured floors.
  scoring.clutter_ring_per_radius = 0.0;
  if (params.perspective_outline)
    scoring.camera =
        stereo::PinholeCamera{triangulator->focal_px(), triangulator->principal_right_px()};
  return scoring;
}

std::optional<Circle> SearchTools::partner_on_edges(const PairingContext& ctx, const Circle& left,
                                                    const EdgeMap& edges, cv::Point origin,
                                                    const RefineParams& scoring) const {
  const auto score = [&](const Circle& c) {
    return score_circle(edges, shifted(c, -origin), scoring);
  };
  return predicted_partner(ctx, left, score, params.p2p.min_score);
}

void SearchTools::raw_left_px(const std::vector<cv::Point2d>& rectified_px,
                              std::vector<cv::Point2d>& raw_px) {
  rays.resize(rectified_px.size());
  for (std::size_t i = 0; i < rectified_px.size(); ++i) {
    const cv::Vec3d ray = ray_from_pixel * cv::Vec3d(rectified_px[i].x, rectified_px[i].y, 1.0);
    rays[i] = {ray[0], ray[1], ray[2]};
  }
  const stereo::StereoCalibration& calib = rectifier->calibration();
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Mat(calib.k1),
                    cv::Mat(calib.d1, true), raw_px);
}

std::optional<ColourHistogram> SearchTools::colour_of(const FrameState& frame, const Circle& left) {
  if (frame.left_raw.channels() != 3) return std::nullopt;
  const cv::Mat& image = frame.left_raw;
  colour_rect_px.clear();
  colour_rect_px.emplace_back(left.x_px, left.y_px);
  for (const double f : kColourRings)
    for (int a = 0; a < kColourAngles; ++a) {
      const double t = 2.0 * CV_PI * (a + 0.5 * f) / kColourAngles;
      colour_rect_px.emplace_back(left.x_px + f * left.radius_px * std::cos(t),
                                  left.y_px + f * left.radius_px * std::sin(t));
    }
  if (frame.rectified) {
    colour_raw_px = colour_rect_px;
  } else {
    raw_left_px(colour_rect_px, colour_raw_px);
  }
  colour_px.clear();
  for (const cv::Point2d& p : colour_raw_px) {
    const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y));
    // A ball cut by the border is sampled where it is in view.
    if (x >= 0 && y >= 0 && x < image.cols && y < image.rows)
      colour_px.push_back(image.at<cv::Vec3b>(y, x));
  }
  return ColourHistogram::of(colour_px, appearance.params().min_pixels);
}

int SearchTools::apply_appearance(const FrameState& frame, std::vector<Circle>& left) {
  if (!appearance.ready()) return 0;
  int rejected = 0;
  for (auto it = left.begin(); it != left.end();) {
    const auto h = colour_of(frame, *it);
    if (appearance.rejects(h)) {
      it = left.erase(it);
      ++rejected;
      continue;
    }
    // Rank: a circle more of whose colours are the ball's keeps more of its outline score.
    if (h) it->score *= 0.5 + 0.5 * appearance.containment(*h).value_or(1.0);
    ++it;
  }
  std::stable_sort(left.begin(), left.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  return rejected;
}

}  // namespace stereoball::ball_detector
