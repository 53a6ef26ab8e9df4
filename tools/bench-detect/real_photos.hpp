#pragma once
// The real-photograph part of stereoball bench detect: labelled photographs (tests/data/circles),
// every method's settings chosen on the tune split, reported on the report split.

#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/circle_labels.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace stereoball::bench_detect {

/// One photograph and its labelled circles.
struct LabelledImage {
  std::string name;  ///< label file stem
  cv::Mat image;     ///< BGR
  std::vector<ball_detector::Circle> truth;
  ball_detector::LabelSplit split = ball_detector::LabelSplit::tune;
  /// Smallest radius every method searches: the label file's min_radius (every circle down to
  /// it is labelled) or kDefaultMinRadiusPerSide of the shorter side.
  double min_radius_px = 0.0;
};

/// Smallest labelled radius, as a share of the shorter image side, of a file without min_radius.
constexpr double kDefaultMinRadiusPerSide = 0.025;

/// Reads every *.circles file of dir (images relative to project_root); the first error
/// (unreadable file, malformed line, unreadable image) names the file.
std::variant<std::vector<LabelledImage>, std::string> load_labelled_images(
    const std::filesystem::path& dir, const std::filesystem::path& project_root);

/// One setting of one method: makes the detector for an image size and smallest radius.
struct Setting {
  std::string label;
  std::function<std::unique_ptr<ball_detector::CircleDetector>(cv::Size, double min_radius_px)>
      make;
};

/// A method and the settings tried for it on the tune split.
struct Family {
  std::string name;
  std::vector<Setting> settings;
};

/// Counts, centre errors and per-image median times of one setting on a set of images.
struct RealScore {
  int tp = 0, fp = 0, fn = 0;
  std::vector<double> errors_px;
  std::vector<double> image_ms;  ///< one median per image
  double f1() const;
};

/// Runs a setting on the images of one split; each image timed `repeats` times. explain: print
/// what was found on every image with a miss or a false positive.
RealScore score_setting(const Setting& setting, const std::vector<LabelledImage>& images,
                        ball_detector::LabelSplit split, int repeats, double min_iou, bool explain);

/// One family's chosen setting and its report-split figures.
struct RealRow {
  std::string family;
  std::string setting;
  double tune_f1 = 0.0;
  double report_f1 = 0.0;
  double report_ms = 0.0;       ///< median per image
  double tune_ms = 0.0;         ///< median per image on the tune split (one run each)
  double interleaved_ms = 0.0;  ///< median per image, timed interleaved with the other rows
};

/// Chooses each family's best setting on the tune split (F1, then time) and prints it with its
/// report-split figures, one row per family, then every row's setting timed interleaved on the
/// report split (interleaved_timing.hpp) and the time ratios of the first row (the detector
/// under test) to the others measured that way. print_detections: print_detections() of every
/// row.
/// time_cap_family (not empty): a second row for the first family, "<first> <= <cap>": its best
/// tune F1 among its settings whose median tune-split time is at most that of the cap family's
/// chosen setting in the same run (a time-aware choice, still on the tune split only).
/// breakdown: also print, for each family's chosen setting, its tune-split misses and false
/// positives by labelled radius and per image (never the report split's: it is not looked at
/// while settings are chosen).
std::vector<RealRow> run_real_photo_table(const std::vector<Family>& families,
                                          const std::vector<LabelledImage>& images, int repeats,
                                          double min_iou, bool verbose, bool breakdown = false,
                                          const std::string& time_cap_family = "",
                                          bool print_detections = false);

/// Every circle a setting finds on every image of both splits, one line per image (name, then
/// x y r score at 3 decimals): for diffing two builds of a detector ("same circles").
void print_detections(const std::string& row, const Setting& setting,
                      const std::vector<LabelledImage>& images);

/// Labelled radius bands of the breakdown, px: [kBreakdownBandsPx[i], kBreakdownBandsPx[i+1]).
inline constexpr std::array<double, 6> kBreakdownBandsPx = {0.0, 8.0, 12.0, 20.0, 40.0, 1e9};

/// One setting's tune-split figures by labelled radius band and by image.
struct Breakdown {
  std::array<int, 5> truth{}, found{};  ///< labelled and found circles per radius band
  struct Image {
    std::string name;
    int truth = 0, tp = 0, fp = 0;
    double min_truth_radius_px = 0.0;
  };
  std::vector<Image> images;
};

/// A labelled circle counts as found when a detection overlaps it by min_iou (not one-to-one:
/// a diagnosis, the F1 comes from match_circles).
Breakdown tune_breakdown(const Setting& setting, const std::vector<LabelledImage>& images,
                         double min_iou);

}  // namespace stereoball::bench_detect
