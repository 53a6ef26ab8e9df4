#pragma once
// Real stereo backgrounds with a composited ball: rectified real pairs (OpenCV's 13 chessboard
// pairs through their calibration, the rectified Middlebury Aloe pair) with a shaded sphere
// drawn into both eyes at a known 3D position. Ground truth for the stereo pipeline on real
// clutter (hands, hair, chessboards, leaves) that no simulator scene has.

#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace stereoball::composite {

/// A rectified real pair and the rectified rig it was taken with.
struct Background {
  std::string name;
  cv::Mat left, right;       ///< rectified, BGR (grey sources converted)
  double focal_px = 0;       ///< rectified focal length, pixels
  cv::Point2d principal_px;  ///< shared principal point of both rectified eyes
  double baseline_m = 0;     ///< right camera this far along +x of the left one, metres
};

/// The calibration of an already rectified rig: no distortion, no rotation, the right camera
/// baseline_m to the right; rectifying with it leaves images unchanged.
stereo::StereoCalibration rectified_rig_calibration(const Background& background);

/// The 13 OpenCV chessboard pairs rectified with calibration, then the Aloe pair at half size
/// (Middlebury 2006: f = 3740 px and B = 160 mm at full size, so 1870 px here), from
/// data_dir (../shared/data/opencv-samples). Error names the missing file.
Result<std::vector<Background>> load_real_backgrounds(const std::string& data_dir,
                                                      const stereo::StereoCalibration& calibration);

/// One ball to draw: centre in the left rectified camera frame and colour.
struct Ball {
  cv::Vec3d centre_m;
  double radius_m = 0.11;
  cv::Scalar bgr;
  std::string colour;  ///< name for reports
};

/// Named colours the benches and tests cycle through (orange, tennis yellow-green, blue, white).
const std::vector<std::pair<std::string, cv::Scalar>>& ball_colours();

/// Draws ball into both eyes of background (copies): a Lambert-shaded sphere (light from the
/// upper left, ambient 0.35) traced per pixel with 4x4 samples, blended over the image by
/// coverage so the outline is anti-aliased like a camera's.
std::pair<cv::Mat, cv::Mat> composite(const Background& background, const Ball& ball);

/// count balls at depths drawn uniformly from [min_depth_m, max_depth_m] and positions where
/// the whole outline lies at least margin_px inside both images, colours cycling; the same
/// seed gives the same balls. Fewer when no position fits (tries 200 per ball).
std::vector<Ball> place_balls(const Background& background, int count, double radius_m,
                              double min_depth_m, double max_depth_m, unsigned seed,
                              double margin_px = 4.0);

}  // namespace stereoball::composite
