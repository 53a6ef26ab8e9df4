#include "camera_server/core/camera_controls.hpp"

#include <linux/videodev2.h>

#include <algorithm>

namespace stereoball::camera_server {

std::vector<ControlSetting> map_controls(const CameraControls& c) {
  std::vector<ControlSetting> out;
  // UVC cameras implement "aperture priority" as their automatic mode, not V4L2_EXPOSURE_AUTO.
  out.push_back({V4L2_CID_EXPOSURE_AUTO,
                 c.auto_exposure ? V4L2_EXPOSURE_APERTURE_PRIORITY : V4L2_EXPOSURE_MANUAL,
                 "exposure_auto"});
  if (!c.auto_exposure && c.exposure_us > 0) {
    // V4L2_CID_EXPOSURE_ABSOLUTE counts 100 us units; round to nearest, at least 1.
    const int32_t units = std::max<int32_t>(1, (c.exposure_us + 50) / 100);
    out.push_back({V4L2_CID_EXPOSURE_ABSOLUTE, units, "exposure_time_absolute"});
  }
  if (c.gain >= 0) out.push_back({V4L2_CID_GAIN, c.gain, "gain"});
  out.push_back(
      {V4L2_CID_AUTO_WHITE_BALANCE, c.auto_white_balance ? 1 : 0, "white_balance_automatic"});
  if (!c.auto_white_balance && c.white_balance_temperature_k > 0) {
    out.push_back({V4L2_CID_WHITE_BALANCE_TEMPERATURE, c.white_balance_temperature_k,
                   "white_balance_temperature"});
  }
  return out;
}

}  // namespace stereoball::camera_server
