#pragma once
// Reads an image file into 8-bit BGR with its size bounded before decoding: JPEG and PNG
// through decode_bgr (header checked first, truncated or corrupt data refused), other formats
// through OpenCV with its own pixel limit (OPENCV_IO_MAX_IMAGE_PIXELS) set to max_size.

#include <opencv2/core.hpp>

#include <string>

#include "common/util/result.hpp"

namespace stereoball::stereo {

/// The image in path as BGR; errors name the file and the problem (missing, larger than
/// max_size, corrupt). Files larger than what a max_size image can take are not read.
Result<cv::Mat> read_image_file(const std::string& path, cv::Size max_size);

}  // namespace stereoball::stereo
