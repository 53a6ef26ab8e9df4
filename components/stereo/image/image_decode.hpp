#pragma once
// Bounded decoding of compressed images (frames on the wire, image files): the size is read
// from the header first (JPEG through libjpeg's jpeg_read_header, PNG from its IHDR chunk), so
// an image too large for the caller is refused before any pixel memory is allocated; a
// truncated or corrupt stream is an error, never an image (libjpeg's warnings, such as
// "Premature end of JPEG file", are treated as errors).

#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "common/util/result.hpp"

namespace stereoball::stereo {

/// Compressed formats decode_bgr understands.
enum class ImageCodec { kJpeg, kPng };

/// "jpeg" or "png".
const char* codec_name(ImageCodec codec);

/// What an image header says, read without decoding any pixel.
struct ImageHeader {
  ImageCodec codec = ImageCodec::kJpeg;
  int width_px = 0;
  int height_px = 0;
};

/// The codec of bytes from its signature (JPEG SOI, PNG magic), or nullopt.
std::optional<ImageCodec> sniff_codec(std::span<const std::uint8_t> bytes);

/// Reads the header of a JPEG or PNG stream; errors name the problem (not an image, bad header).
Result<ImageHeader> read_image_header(std::span<const std::uint8_t> bytes);

/// Success when header fits max_size, else an error saying which size is too large.
Status check_within(const ImageHeader& header, cv::Size max_size);

/// Decodes a complete JPEG/PNG stream whose header was read by read_image_header (and checked
/// by the caller) into 8-bit BGR, reusing out's buffer. An error names the problem
/// ("jpeg data is corrupt: Premature end of JPEG file"); out is then empty.
Status decode_bgr(std::span<const std::uint8_t> bytes, const ImageHeader& header, cv::Mat& out);

/// Whether decode_bgr_reduced can decode an image of header's codec and size reduced by
/// reduction: JPEG (libjpeg's scaled inverse DCT), reduction 2, 4 or 8 dividing both sides.
bool decodes_reduced(const ImageHeader& header, int reduction);

/// decode_bgr at 1/reduction of the header's size (decodes_reduced must hold): the JPEG's
/// blocks transformed back at that scale, a fraction of a full decode's work (each output
/// pixel about the mean of its reduction x reduction block). Errors as decode_bgr's.
Status decode_bgr_reduced(std::span<const std::uint8_t> bytes, const ImageHeader& header,
                          int reduction, cv::Mat& out);

}  // namespace stereoball::stereo
