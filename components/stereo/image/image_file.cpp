#include "stereo/image/image_file.hpp"

#include <opencv2/imgcodecs.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

#include "stereo/image/image_decode.hpp"

namespace stereoball::stereo {
namespace {

// A compressed file is rarely larger than its raw pixels; twice that plus slack for
// metadata bounds the bytes read before the header is even looked at.
std::uintmax_t max_file_bytes(cv::Size max_size) {
  return 2 * std::uintmax_t{3} * static_cast<std::uintmax_t>(max_size.area()) + (1u << 20);
}

// OpenCV checks this limit after reading a header and before allocating (imgcodecs
// validateInputImageSize); it reads the variable once, at its first image.
void limit_opencv_pixels(cv::Size max_size) {
  static const bool set = [&] {
    const std::string pixels = std::to_string(static_cast<long long>(max_size.area()));
    return setenv("OPENCV_IO_MAX_IMAGE_PIXELS", pixels.c_str(), 1) == 0;
  }();
  (void)set;
}

}  // namespace

Result<cv::Mat> read_image_file(const std::string& path, cv::Size max_size) {
  std::error_code ec;
  const auto file_bytes = std::filesystem::file_size(path, ec);
  if (ec) return Error{"cannot read image '" + path + "': " + ec.message()};
  if (file_bytes > max_file_bytes(max_size))
    return Error{"'" + path + "' has " + std::to_string(file_bytes) +
                 " bytes, too many for an image within " + std::to_string(max_size.width) + "x" +
                 std::to_string(max_size.height)};
  std::vector<std::uint8_t> bytes(file_bytes);
  std::ifstream in(path, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(file_bytes)))
    return Error{"cannot read image '" + path + "'"};
  cv::Mat image;
  if (!sniff_codec(bytes)) {
    limit_opencv_pixels(max_size);
    try {
      image = cv::imdecode(bytes, cv::IMREAD_COLOR);
    } catch (const cv::Exception&) {
      image.release();
    }
    if (image.empty())
      return Error{"cannot read image '" + path + "' (not an image, corrupt, or larger than " +
                   std::to_string(max_size.area()) + " pixels)"};
    if (image.cols > max_size.width || image.rows > max_size.height)
      return Error{"'" + path + "' is larger than the limit"};
    return image;
  }
  const auto header = read_image_header(bytes);
  if (!header) return Error{"'" + path + "': " + header.error()};
  if (auto st = check_within(*header, max_size); !st) return Error{"'" + path + "': " + st.error()};
  if (auto st = decode_bgr(bytes, *header, image); !st)
    return Error{"'" + path + "': " + st.error()};
  return image;
}

}  // namespace stereoball::stereo
