#include "ball_detector/pipeline/search/radius_bands.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::ball_detector {
std::vector<SearchHints> radius_bands(double min_radius_px, double max_radius_px, int image_rows) {
  const double top = std::min(max_radius_px, image_rows / 3.0);
  std::vector<SearchHints> bands;
  for (double low = min_radius_px; low < top; low *= kRadiusBandRatio) {
    bands.push_back(
        SearchHints{RadiusRange{low / 1.1, std::min(top, low * kRadiusBandRatio * 1.1)}});
    // This band reaches the top already: a next one would lie inside it.
    if (bands.back().radii.max_px >= top) break;
  }
  return bands;
}

std::vector<Circle> best_of_each_place(const std::vector<Circle>& found, double separation_px) {
  std::vector<Circle> kept;
  for (const Circle& c : found) {
    const bool seen = std::any_of(kept.begin(), kept.end(), [&](const Circle& k) {
      return std::hypot(k.x_px - c.x_px, k.y_px - c.y_px) < separation_px &&
             std::abs(k.radius_px - c.radius_px) < 0.2 * std::max(k.radius_px, c.radius_px);
    });
    if (!seen) kept.push_back(c);
  }
  return kept;
}

namespace {

// The left eye's bands (its radii, the rectified image's height).
std::vector<SearchHints> left_radius_bands(const SearchTools& tools) {
  return radius_bands(tools.params.p2p.min_radius_px, tools.params.p2p.max_radius_px,
                      tools.rect_left.rows);
}

}  // namespace

int radius_band_count(const SearchTools& tools) {
  return static_cast<int>(left_radius_bands(tools).size());
}

namespace {

// The bands searched (only >= 0: that one alone), with a detector each in tools.
std::vector<SearchHints> bands_with_detectors(SearchTools& tools, int only) {
  std::vector<SearchHints> bands = left_radius_bands(tools);
  if (only >= 0 && !bands.empty()) bands = {bands[static_cast<std::size_t>(only) % bands.size()]};
  while (tools.band_detectors.size() < bands.size()) {
    tools.band_detectors.emplace_back(tools.params.detector_params());
    tools.band_detectors.back().set_camera(tools.params.perspective_outline ? tools.left_camera()
                                                                            : std::nullopt);
  }
  return bands;
}

// The bands' circles, band by band, best first and one per place.
std::vector<Circle> merged_bands(const std::vector<std::vector<Circle>>& per_band,
                                 const SearchTools& tools) {
  std::vector<Circle> found;
  for (const auto& circles : per_band) found.insert(found.end(), circles.begin(), circles.end());
  std::stable_sort(found.begin(), found.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  // Neighbouring bands find the same circle.
  return best_of_each_place(found, tools.params.p2p.min_separation_px);
}

}  // namespace

std::vector<Circle> detect_left_in_bands(SearchTools& tools, const std::atomic<bool>* stop,
                                         int only) {
  // The left detector holds this image's edge map, made with these very thresholds, and the
  // lines its points voted along: each band plots them again over its radii instead of redoing
  // the edge step and the window rules. The bands are independent tasks, each on a detector of
  // its own (the left one is only read).
  const std::vector<SearchHints> bands = bands_with_detectors(tools, only);
  std::vector<std::vector<Circle>> per_band(bands.size());
  tools.run_tasks(static_cast<int>(bands.size()), [&](int task) {
    const auto b = static_cast<std::size_t>(task);
    if (stop && *stop) return;  // the result is not wanted any more
    per_band[b] = tools.band_detectors[b].redetect_from(tools.left_detector, bands[b]);
  });
  return merged_bands(per_band, tools);
}

LeftBandParts::LeftBandParts(SearchTools& tools, int only)
    : tools_(tools),
      bands_(bands_with_detectors(tools, only)),
      peaks_(bands_.size()),
      refined_(bands_.size()) {}

void LeftBandParts::vote(int b) {
  const auto i = static_cast<std::size_t>(b);
  peaks_[i] = tools_.band_detectors[i].peaks_from(tools_.left_detector, bands_[i]);
}

int LeftBandParts::peaks() {
  tasks_.clear();
  for (std::size_t b = 0; b < bands_.size(); ++b) {
    const int n = peaks_[b].value_or(0);
    refined_[b].assign(static_cast<std::size_t>(n), {});
    for (int i = 0; i < n; ++i) tasks_.emplace_back(static_cast<int>(b), i);
  }
  return static_cast<int>(tasks_.size());
}

void LeftBandParts::refine(int i) {
  const auto [b, peak] = tasks_[static_cast<std::size_t>(i)];
  const auto band = static_cast<std::size_t>(b);
  refined_[band][static_cast<std::size_t>(peak)] = tools_.band_detectors[band].refine_peak(peak);
}

std::vector<Circle> LeftBandParts::circles() const {
  std::vector<std::vector<Circle>> per_band(bands_.size());
  for (std::size_t b = 0; b < bands_.size(); ++b)
    if (peaks_[b]) per_band[b] = tools_.band_detectors[b].select_circles(refined_[b]);
  return merged_bands(per_band, tools_);
}

std::optional<SearchOutcome> RadiusBandSearch::run(const FrameState& frame, FrameScratch& scratch,
                                                   SearchTools& tools) const {
  if (!scratch.band_left) scratch.band_left = detect_left_in_bands(tools, nullptr, scratch.band);
  std::vector<Circle> left = std::move(*scratch.band_left);
  scratch.band_left.reset();
  // The right eye with the whole left frame's thresholds, each left circle's partner box with
  // only the radii its partner can have: one box searched for the union of every candidate's
  // radii is crowded out by clutter just like the left eye.
  const EdgeThresholds thresholds = *tools.left_thresholds;
  const cv::Size size = tools.image_size();
  tools.clear_rectified(frame.right_channel, tools.rect_right);
  std::vector<Circle> right;
  for (const Circle& c : left) {
    const cv::Rect box = partner_search_box(frame.ctx, c, size, tools.window_margin_px());
    if (box.width < 8 || box.height < 8) continue;
    tools.rectify_box(frame.right_channel, stereo::Eye::kRight, frame.rectified, box,
                      tools.rect_right);
    tools.right_edges_box = box;
    const SearchHints hints{partner_radius_range(frame.ctx, {c})};
    for (const Circle& r : tools.right_detector.detect(tools.rect_right(box), thresholds, hints))
      right.push_back(shifted(r, box.tl()));
  }
  SearchOutcome out = pairing_.pair(frame, tools, std::move(left), std::move(right), false);
  out.path = SearchPath::kRadiusBands;
  return out;
}

}  // namespace stereoball::ball_detector
