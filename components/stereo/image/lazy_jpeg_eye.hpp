#pragma once
// A JPEG eye decoded only as far as its reader needs (stereo::RowSource): libjpeg decodes top
// to bottom and can stop after any row and go on later, so the rows a search reads are decoded
// when it first reads them, the same bytes a whole decode gives, and rows below the lowest one
// read are never decoded. Rows between those asked for are passed over (their data is still
// read, not turned into pixels); a later read above the decoder's place decodes again from the
// top, passing over the rows made already.

#include <opencv2/core.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "stereo/core/row_source.hpp"
#include "stereo/image/image_decode.hpp"

namespace stereoball::stereo {

/// One JPEG eye at a time, decoded row by row on demand; reused from frame to frame.
class LazyJpegEye final : public RowSource {
 public:
  LazyJpegEye();
  ~LazyJpegEye() override;
  LazyJpegEye(const LazyJpegEye&) = delete;
  LazyJpegEye& operator=(const LazyJpegEye&) = delete;

  /// Starts on bytes, a JPEG whose header read_image_header read and the caller checked, at
  /// 1/reduction of its size (1, or a factor decodes_reduced accepts); no row is decoded yet.
  /// bytes must stay valid while rows are made. A stream that does not end in its EOI marker
  /// (truncated) is decoded whole at once, so its error comes now, as decode_bgr's would.
  /// Errors name eye ("right jpeg data is corrupt: ...").
  Status start(const std::string& eye, std::span<const std::uint8_t> bytes,
               const ImageHeader& header, int reduction);
  /// Decodes the next rows in order until stop is set or every row is made: another core's
  /// share while the frame's other eye decodes (call before any make_rows). The error met, if any.
  Status decode_ahead(const std::atomic<bool>& stop);

  const cv::Mat& image() const override { return image_; }
  void make_rows(int begin_row, int end_row) override;
  Status status() const override;

  /// Whether row holds decoded pixels (for tests and measurements).
  bool row_made(int row) const { return row >= 0 && row < image_.rows && made_[row] != 0; }
  /// How many rows hold decoded pixels.
  int rows_made() const;

 private:
  struct Decoder;
  bool restart();
  /// Moves the decoder from its row to end_row, decoding the rows of [begin_row, end_row) not
  /// made yet and passing over the others.
  bool advance(int begin_row, int end_row);
  void fail();

  std::unique_ptr<Decoder> decoder_;
  std::span<const std::uint8_t> bytes_;
  ImageHeader header_;
  int reduction_ = 1;
  std::string eye_;
  cv::Mat image_;
  std::vector<std::uint8_t> made_;  // per row: holds decoded pixels
  std::optional<std::string> error_;
};

}  // namespace stereoball::stereo
