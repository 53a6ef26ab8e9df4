#pragma once
// A calibration for the same rig at another image size: what a camera server publishes next to
// frames it scaled before publishing (camera_server `publish_width_px`). Pure.

#include <opencv2/core.hpp>

#include "common/util/result.hpp"
#include "stereo/core/calibration.hpp"

namespace stereoball::stereo {

/// The size a frame of `size` gets when scaled to `width_px` wide with its aspect ratio kept:
/// the height is rounded to the nearest pixel (at least 1).
cv::Size scaled_size(cv::Size size, int width_px);

/// The calibration of the same rig for images resized (cv::resize) from calib.image_size to
/// `size`. Pixel centres are kept where the resize puts them: a pixel coordinate u becomes
/// s * (u + 0.5) - 0.5 with s = new / old size per axis, so K1, K2, P1 and P2 are multiplied
/// on the left by that map (focal lengths and the P2 baseline term by s, the principal points
/// by s plus (s - 1) / 2) and Q is rewritten to give the same 3D point for the scaled pixel
/// and disparity. Distortion, R, T, R1, R2 and the RMS figures are unchanged (the RMS stays in
/// the original pixels). An error names the problem (empty size, invalid calibration).
Result<StereoCalibration> scale_calibration(const StereoCalibration& calib, cv::Size size);

}  // namespace stereoball::stereo
