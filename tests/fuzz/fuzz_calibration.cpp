// libFuzzer target: calibration files (config/calibration/*.yaml, OpenCV FileStorage) on
// arbitrary text, and the rectifier built from whatever passes validation.

#include <cstddef>
#include <cstdint>
#include <string>

#include "stereo/core/rectifier.hpp"
#include "stereo/io/calibration_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto calib = stereoball::stereo::parse_calibration(text);
  // Rectification tables grow with the image: only sizes a deployment would accept.
  if (calib && calib->image_size.area() <= 640 * 480) {
    (void)stereoball::stereo::Rectifier::create(*calib);
  }
  return 0;
}
