#pragma once
// A captured image exactly as the driver delivered it, and a stereo pair of them.

#include <cstdint>
#include <vector>

#include "camera_server/core/stereo_pairer.hpp"

namespace stereoball::camera_server {

/// Raw bytes of one captured frame with the format they are in.
struct RawImage {
  std::vector<uint8_t> bytes;
  uint32_t fourcc = 0;  ///< V4L2 pixel format (YUYV, MJPG)
  uint32_t width_px = 0;
  uint32_t height_px = 0;
  uint32_t step_bytes = 0;  ///< bytes per row; 0 for compressed formats
  uint32_t sequence = 0;    ///< driver frame counter
};

/// A synchronized pair of raw images; stamps in ns since the Unix epoch.
using RawStereoPair = StereoPair<RawImage>;

}  // namespace stereoball::camera_server
