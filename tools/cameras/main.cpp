// stereoball-cameras: lists V4L2 devices with their names, formats, sizes and frame rates.

#include <glob.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>
#include "common/util/cli11.hpp"

#include "camera_server/io/v4l2_device.hpp"

namespace sc = stereoball::camera_server;

namespace {

// /dev/video2 before /dev/video10.
bool natural_less(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return a.size() < b.size();
  return a < b;
}

std::vector<std::string> video_nodes(const std::string& pattern) {
  std::vector<std::string> out;
  glob_t g{};
  if (::glob(pattern.c_str(), 0, nullptr, &g) == 0) {
    for (size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  }
  ::globfree(&g);
  std::sort(out.begin(), out.end(), natural_less);
  return out;
}

// Prints one device; returns false when it could not be queried.
bool describe(const std::string& node) {
  sc::V4l2Device dev;
  sc::DeviceCaps caps;
  std::vector<sc::FormatOffer> formats;
  sc::DeviceStatus s = dev.open(node);
  if (s.ok()) s = dev.query_caps(caps);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message.c_str());  // messages name the device
    return false;
  }
  std::printf("%s: %s (driver %s, %s)\n", node.c_str(), caps.card.c_str(), caps.driver.c_str(),
              caps.bus_info.c_str());
  if (!caps.video_capture) {
    std::printf("  not a video capture node (metadata or output); not usable as a camera\n");
    return true;
  }
  if (s = dev.enumerate_formats(formats); !s.ok()) {
    std::fprintf(stderr, "%s\n", s.message.c_str());
    return false;
  }
  if (formats.empty()) std::printf("  no capture formats\n");
  for (const auto& f : formats) {
    std::printf("  %s (%s):", sc::fourcc_text(f.fourcc).c_str(), f.description.c_str());
    // describe_offers prints "FMT size@rates ..."; drop the leading code, shown above.
    const std::string sizes = sc::describe_offers({f});
    std::printf("%s\n", sizes.substr(sc::fourcc_text(f.fourcc).size()).c_str());
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Lists V4L2 video devices with their names, pixel formats, frame sizes and frame rates "
      "(e.g. to choose left_device/right_device, width_px, height_px, rate_hz and pixel_format "
      "for the camera_server)."};
  std::vector<std::string> devices;
  std::string pattern = "/dev/video*";
  app.add_option("--device,-d", devices,
                 "device node(s) to describe (default: every match of --glob)");
  app.add_option("--glob", pattern, "pattern of device nodes to list")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const bool explicit_devices = !devices.empty();
  if (!explicit_devices) devices = video_nodes(pattern);
  if (devices.empty()) {
    std::printf(
        "No video devices found (%s matches nothing). Is a camera plugged in and its "
        "driver (e.g. uvcvideo) loaded?\n",
        pattern.c_str());
    return 0;
  }
  bool all_ok = true;
  for (const auto& node : devices) all_ok = describe(node) && all_ok;
  // Listing is best-effort; a device the user named explicitly must work.
  return explicit_devices && !all_ok ? 1 : 0;
}
