#pragma once
// Chooses a pixel format, frame size and rate from what a device offers, or explains what it
// offers when the request cannot be met.

#include <cstdint>
#include <string>
#include <vector>

#include "camera_server/core/status.hpp"

namespace stereoball::camera_server {

/// V4L2 four-character code of a pixel format.
constexpr uint32_t fourcc(char a, char b, char c, char d) {
  return static_cast<uint32_t>(static_cast<uint8_t>(a)) |
         (static_cast<uint32_t>(static_cast<uint8_t>(b)) << 8) |
         (static_cast<uint32_t>(static_cast<uint8_t>(c)) << 16) |
         (static_cast<uint32_t>(static_cast<uint8_t>(d)) << 24);
}
inline constexpr uint32_t kFourccYuyv = fourcc('Y', 'U', 'Y', 'V');
inline constexpr uint32_t kFourccMjpeg = fourcc('M', 'J', 'P', 'G');

/// Printable form of a four-character code ("YUYV").
std::string fourcc_text(uint32_t code);

/// Frame sizes a device offers for one format: discrete (min == max) or a stepwise range.
struct SizeOffer {
  uint32_t min_width_px = 0, max_width_px = 0, step_width_px = 1;
  uint32_t min_height_px = 0, max_height_px = 0, step_height_px = 1;
  std::vector<double> rates_hz;  ///< discrete frame rates for this size (empty = not reported)
};

/// One pixel format a device offers.
struct FormatOffer {
  uint32_t fourcc = 0;
  std::string description;  ///< driver's name, e.g. "YUYV 4:2:2"
  std::vector<SizeOffer> sizes;
};

/// What the configuration asks for.
struct FormatRequest {
  std::string pixel_format = "any";  ///< "yuyv", "mjpeg" or "any" (YUYV preferred)
  uint32_t width_px = 640;
  uint32_t height_px = 480;
  double rate_hz = 30.0;
};

/// The format to configure.
struct FormatChoice {
  uint32_t fourcc = 0;
  uint32_t width_px = 0;
  uint32_t height_px = 0;
  double rate_hz = 0.0;  ///< rate to request with S_PARM
};

/// Picks a supported format/size/rate; the error line names the device and lists its offers.
Result<FormatChoice> negotiate_format(const std::vector<FormatOffer>& offers,
                                      const FormatRequest& request, const std::string& device);

/// Human-readable list of the offers, e.g. "YUYV 640x480@30,15 320x240@30; MJPG 1280x720@30".
std::string describe_offers(const std::vector<FormatOffer>& offers);

}  // namespace stereoball::camera_server
