#pragma once
// The pixels of one raw eye of an outgoing frame as an 8-bit image, for the parts that look at
// the pixels before publishing (camera_server's eye-order check, the preview): bgr8 and mono8
// as they are, yuyv converted with the one conversion of the tree (stereo/image/yuyv_convert).

#include <opencv2/core.hpp>

#include <string>

#include "common/util/result.hpp"
#include "stereo/frame/frame_view.hpp"

namespace stereoball::stereo {

/// bgr8 (CV_8UC3) and mono8 (CV_8UC1) without a copy, yuyv converted to BGR into `converted`
/// (the result then points there); sizes checked against the bytes the view holds. Errors name
/// the problem: compressed or unknown encodings, truncated data, an odd yuyv width.
Result<cv::Mat> eye_pixels(const EyeView& eye, const std::string& encoding, cv::Mat& converted);

}  // namespace stereoball::stereo
