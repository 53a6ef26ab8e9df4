#pragma once
// An image whose rows are made when first read: a JPEG eye is decoded top to bottom, and a
// reader that needs only some of its rows (the right eye searched in boxes) can leave the rest
// undecoded. The pixels of the rows made are the same bytes a whole decode gives.

#include <opencv2/core.hpp>

#include <algorithm>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::stereo {

/// An image of final size and type whose rows are made on demand; rows not made hold no
/// meaningful pixels.
class RowSource {
 public:
  virtual ~RowSource() = default;
  /// The image: size and type from the start, valid pixels in the rows made so far.
  virtual const cv::Mat& image() const = 0;
  /// Makes rows [begin_row, end_row) valid (clipped to the image). When the data turns out
  /// corrupt on the way, the rows not made are zero from then on and status() names the problem.
  virtual void make_rows(int begin_row, int end_row) = 0;
  /// Makes every row.
  void make_all() { make_rows(0, image().rows); }
  /// Makes several row ranges, the topmost first: an image decoded top to bottom then never
  /// has to go back up between them, whatever order they are read in.
  void make_rows_top_first(std::vector<cv::Range> ranges) {
    std::sort(ranges.begin(), ranges.end(),
              [](const cv::Range& a, const cv::Range& b) { return a.start < b.start; });
    for (const cv::Range& r : ranges) make_rows(r.start, r.end);
  }
  /// Success, or the problem met while making rows (the eye named).
  virtual Status status() const = 0;
};

/// A RowSource over an image that is whole already (raw frames, tests): nothing to make.
class WholeImageRows final : public RowSource {
 public:
  explicit WholeImageRows(cv::Mat image) : image_(std::move(image)) {}
  const cv::Mat& image() const override { return image_; }
  void make_rows(int, int) override {}
  Status status() const override { return {}; }

 private:
  cv::Mat image_;
};

}  // namespace stereoball::stereo
