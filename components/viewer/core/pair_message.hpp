#pragma once
// The page's binary image message: one stereo pair as two JPEGs behind a fixed header that the
// page reads with a DataView (little-endian). Besides the frame number and capture time it
// carries the size of the image the detections refer to (an eye may be shown scaled down) and
// when the viewer took and encoded the frame, so clients can split the latency by stage.
//
//   offset  type  field
//        0  u32   type (2; type 1 was a 24-byte header without sizes and stages)
//        4  u32   bytes of the left JPEG
//        8  f64   frame sequence number
//       16  f64   capture time, ms since the epoch
//       24  u32   source width, px (detection coordinates are in this image)
//       28  u32   source height, px
//       32  f64   viewer took the frame from DDS, ms since the epoch
//       40  f64   viewer finished encoding the pair, ms since the epoch
//       48        left JPEG, then right JPEG

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace stereoball::viewer {

inline constexpr uint32_t kPairMessageType = 2;
inline constexpr size_t kPairHeaderBytes = 48;

/// What the header of a pair message says.
struct PairHeader {
  uint64_t frame_seq = 0;
  /// Stamps, ms since the epoch: capture, the viewer took the frame, the viewer encoded it.
  double capture_ms = 0, received_ms = 0, encoded_ms = 0;
  /// Size of the eyes the detections refer to (before any scaling down).
  uint32_t source_width_px = 0, source_height_px = 0;
  uint32_t left_bytes = 0;  ///< filled in by pair_message from the left JPEG
};

/// The whole message: header, then both JPEGs.
std::string pair_message(const PairHeader& header, std::span<const uint8_t> left_jpeg,
                         std::span<const uint8_t> right_jpeg);

/// The header of a message; nullopt when it is not a (type 2) pair message or is shorter than its
/// header and left JPEG claim.
std::optional<PairHeader> parse_pair_header(std::span<const uint8_t> message);

}  // namespace stereoball::viewer
