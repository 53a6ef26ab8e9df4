#pragma once
// Step 1 of Pixel-to-Pixel: a thin binary edge map (colour or grey gradient, Canny with
// image-derived thresholds, removal of staircase pixels) plus a bit-packed copy for fast window
// counts.

#include "ball_detector/core/canny.hpp"
#include "common/util/result.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace stereoball::ball_detector {

/// Parameters of the edge step.
struct EdgeParams {
  double noise_factor = 4.0;  ///< high threshold >= this * median |dx|+|dy| (noise level), > 0
  double high_percentile =
      0.99;  ///< quantile of |dx|+|dy| giving the image's strong-edge level, (0, 1)
  double contrast_fraction = 0.15;  ///< high threshold >= this * that quantile, [0, 1]
  double low_ratio = 0.4;           ///< Canny low threshold = high * this, (0, 1]
  double min_high_threshold =
      24.0;  ///< floor of the high threshold (Sobel L1 units, 4 per grey level)
  double max_high_threshold = 1000.0;  ///< ceiling of the high threshold (Sobel L1 units)
  double denoise_median =
      20.0;          ///< Gaussian pre-blur when median |dx|+|dy| exceeds this (0 = never)
  bool thin = true;  ///< remove staircase pixels so edges are one pixel thick
  /// Colour images: at each pixel the Sobel gradient of the channel (B, G or R) that changes
  /// most, so an outline is found wherever the ball differs from its background in any
  /// channel, also where grey levels are equal (a red ball on a green floor of equal
  /// brightness). false = the grey image's gradient (the paper). Grey input: grey either way.
  bool colour = true;

  /// Success, or an error naming the first bad field and its allowed range.
  Status validate() const;
};

/// Binary image packed 64 pixels per word, rows padded by one word (safe two-word reads).
class BitImage {
 public:
  BitImage() = default;
  /// Packs a CV_8U image (non-zero = set); reuses storage when the size is unchanged.
  void assign(const cv::Mat& binary);
  /// Pointer to the words of row y (bit x%64 of word x/64 is pixel x).
  const std::uint64_t* row(int y) const { return words_.data() + static_cast<size_t>(y) * stride_; }
  /// Bits of pixels [x0, x0 + n) of row y in the low n bits; requires 0 <= x0, n <= 63.
  std::uint64_t bits(int y, int x0, int n) const {
    const std::uint64_t* r = row(y);
    const int w = x0 >> 6;
    const int o = x0 & 63;
    std::uint64_t v = r[w] >> o;
    if (o + n > 64) v |= r[w + 1] << (64 - o);
    return v & ((std::uint64_t{1} << n) - 1);
  }
  /// bits() for n <= 57 as one unaligned load: each row keeps a clear word past its width, so
  /// the 8 bytes from pixel x0's byte stay inside the row.
  std::uint64_t short_bits(int y, int x0, int n) const {
    if constexpr (std::endian::native == std::endian::little) {
      std::uint64_t v;
      std::memcpy(&v, reinterpret_cast<const unsigned char*>(row(y)) + (x0 >> 3), sizeof v);
      return (v >> (x0 & 7)) & ((std::uint64_t{1} << n) - 1);
    } else {
      return bits(y, x0, n);
    }
  }
  /// Writable words of row y (bits past the width must stay clear).
  std::uint64_t* mutable_row(int y) { return words_.data() + static_cast<size_t>(y) * stride_; }
  /// Whether pixel (x, y) is set; no bounds check.
  bool test(int x, int y) const { return (row(y)[x >> 6] >> (x & 63)) & 1u; }
  /// Calls f(x) for every set pixel x of row y, left to right (f must not change the image).
  template <typename F>
  void for_each_set_in_row(int y, F&& f) const {
    const std::uint64_t* r = row(y);
    for (int wi = 0; wi * 64 < width_; ++wi)
      for (std::uint64_t word = r[wi]; word != 0; word &= word - 1)
        f(wi * 64 + std::countr_zero(word));
  }
  /// Makes an all-clear image of that size; reuses storage when the size is unchanged.
  void reset(int width, int height);
  /// Sets pixel (x, y); no bounds check.
  void set(int x, int y) {
    words_[static_cast<size_t>(y) * stride_ + (x >> 6)] |= std::uint64_t{1} << (x & 63);
  }
  /// Clears pixel (x, y); no bounds check.
  void clear(int x, int y) {
    words_[static_cast<size_t>(y) * stride_ + (x >> 6)] &= ~(std::uint64_t{1} << (x & 63));
  }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  std::vector<std::uint64_t> words_;
  int width_ = 0;
  int height_ = 0;
  int stride_ = 0;
};

/// The edge pixels of a map listed in raster order, one array per field (loops over every
/// point of a region run as vector code), and where each row's points start.
struct EdgePoints {
  std::vector<int> x, y;             ///< pixel coordinates
  std::vector<std::int16_t> gx, gy;  ///< Sobel derivatives there (EdgeMap::dx, dy)
  std::vector<int> row_start;        ///< row y's points are [row_start[y], row_start[y + 1])
};

/// Lists the set pixels of bits with their derivatives from dx, dy (CV_16S, same size).
void list_edge_points(const BitImage& bits, const cv::Mat& dx, const cv::Mat& dy, EdgePoints& out);

/// The edge map of one image and the by-products other steps reuse.
struct EdgeMap {
  cv::Mat grey;                  ///< CV_8U image the gradient came from (grey input or colour off)
  cv::Mat colour;                ///< CV_8UC3 image the gradient came from (colour on), else empty
  cv::Mat dx, dy;                ///< CV_16S Sobel derivatives
  cv::Mat edges;                 ///< CV_8U, 255 on edge pixels, thin
  BitImage bits;                 ///< packed copy of edges
  EdgePoints points;             ///< the pixels of edges listed (made with bits)
  double low_threshold = 0.0;    ///< Canny low threshold used (Sobel L1 units)
  double high_threshold = 0.0;   ///< Canny high threshold used (Sobel L1 units)
  double median_gradient = 0.0;  ///< median |dx|+|dy| of the image (noise level), Sobel L1 units
  bool denoised = false;         ///< whether the pre-blur ran
  int removed_staircase = 0;     ///< pixels removed by thinning
  /// The whole camera image in this map's coordinates: the map itself, or, for a crop (a
  /// cv::Mat ROI view), its parent image (from cv::Mat::locateROI).
  cv::Rect2d frame_px;
  CannyWorkspace canny_work;             ///< scratch of the Canny step, reused image after image
  std::array<cv::Mat, 3> colour_planes;  ///< B, G, R planes with a border (colour), reused
};

/// The whole camera image in image's coordinates (EdgeMap::frame_px): image itself, or for a
/// crop (a cv::Mat ROI view) its parent image.
cv::Rect2d frame_of(const cv::Mat& image);

/// Converts a CV_8UC1/3/4 image to CV_8U grey (no copy for grey input).
cv::Mat to_grey(const cv::Mat& image);

/// Image-derived Canny thresholds and the gradient statistics they come from (Sobel L1 units).
struct CannyThresholds {
  double low = 0.0;
  double high = 0.0;
  double median_gradient = 0.0;  ///< noise level
};

/// Canny thresholds: high = max(noise_factor * median, contrast_fraction * high quantile) of
/// |dx|+|dy|, clamped to [min, max]; low = low_ratio * high.
CannyThresholds canny_thresholds(const cv::Mat& dx, const cv::Mat& dy, const EdgeParams& params);

/// Table over the 8-neighbour code (bit i = neighbour i, clockwise from east) saying whether
/// the centre is a staircase pixel: it joins two perpendicular 4-neighbours and removing it
/// keeps its neighbours 8-connected.
const std::array<bool, 256>& staircase_table();

/// staircase_table for 64 pixels at once: bit i of the result is the entry of the pixel whose
/// eight neighbours are bit i of the planes (e = east, se = south-east, ..., ne = north-east).
std::uint64_t staircase_bits(std::uint64_t e, std::uint64_t se, std::uint64_t s, std::uint64_t sw,
                             std::uint64_t w, std::uint64_t nw, std::uint64_t n, std::uint64_t ne);

/// 8-neighbour code of pixel (x, y) of a CV_8U image (1 <= x < cols-1, 1 <= y < rows-1).
int neighbour_code(const cv::Mat& binary, int x, int y);

/// Removes staircase pixels in place (one raster pass); returns how many were removed.
int thin_staircase(cv::Mat& binary);

/// The same pass on binary and its packed copy bits (bits.assign(binary) done by the caller):
/// the neighbour codes come from the packed rows, several times faster on textured images.
/// Both end as thin_staircase(binary) leaves binary.
int thin_staircase(cv::Mat& binary, BitImage& bits);

/// Whether every pixel of a CV_8UC3 image has B == G == R (a grey image read as colour, whose
/// gradient is one channel's). Row by row, so a colour image is told apart within its first rows.
bool channels_equal(const cv::Mat& bgr);

/// Per pixel of a CV_8UC3 image, the 3x3 Sobel (dx, dy) (CV_16S) of the channel (B, G or R;
/// the first on ties) with the largest |dx| + |dy|, in one pass; borders replicated, and a crop
/// (a cv::Mat ROI) reads its parent's pixels around it. Equal to three cv::Sobel passes and a
/// per-pixel select. planes: scratch reused from call to call.
void strongest_channel_gradient(const cv::Mat& bgr, cv::Mat& dx, cv::Mat& dy,
                                std::array<cv::Mat, 3>& planes);

/// Computes the whole edge step into out (buffers reused across calls of the same size).
void compute_edge_map(const cv::Mat& image, const EdgeParams& params, EdgeMap& out);

/// full's edge map halved, for voting on its image halved (half_image, e.g. halve_image's; its
/// source image in half): a pixel is an edge where any pixel of its 2 x 2 block of full is (a faint
/// outline the full-width thresholds keep survives, which an edge step on the halved image may
/// lose), with the block's summed derivatives (its gradient's direction; subpixel placement and
/// orientation read only ratios), thinned as the edge step thins when thin; an odd last row or
/// column of full is dropped. Thresholds are full's; half's buffers are reused.
void halve_edge_map(const EdgeMap& full, const cv::Mat& half_image, bool thin, EdgeMap& half);

/// The edge step's decisions for one image, to reuse on crops of it (or of its twin).
struct EdgeThresholds {
  CannyThresholds canny;
  bool denoise = false;
};

/// The thresholds and pre-blur decision an edge map was made with.
inline EdgeThresholds thresholds_of(const EdgeMap& e) {
  return {{e.low_threshold, e.high_threshold, e.median_gradient}, e.denoised};
}

/// The thresholds and pre-blur decision compute_edge_map(image, params, work) takes, without
/// its Canny and thinning steps (work keeps the gradients): a cheap refresh of the thresholds a
/// caller reuses on crops.
EdgeThresholds measure_edge_thresholds(const cv::Mat& image, const EdgeParams& params,
                                       EdgeMap& work);

/// Same with the thresholds and the pre-blur decision taken elsewhere (e.g. on the full image
/// when only a crop is searched: a crop's own statistics depend on whatever it holds).
void compute_edge_map(const cv::Mat& image, const EdgeParams& params, const CannyThresholds& fixed,
                      bool denoise, EdgeMap& out);

/// How much remove_brightness amplifies each channel's difference from the pixel's mean: a hue
/// step of a few grey levels (a dull lilac rim on grey carpet) clears the edge step's floor of
/// 6 grey levels, and a saturated colour clips only on the far side of 128.
constexpr int kBrightnessFreeGain = 2;

/// The colour image with its brightness taken out: each channel becomes 128 + gain * (channel -
/// mean of the pixel's three), clipped to [0, 255] (CV_8UC3, same size; out is reused). Grey of
/// any brightness maps to (128, 128, 128), so the brightness texture of a grey or evenly
/// tinted floor vanishes while a hue step keeps its edge.
void remove_brightness(const cv::Mat& bgr, cv::Mat& out);

/// compute_edge_map() of bgr (CV_8UC3, may be a crop of a camera image) with its brightness
/// removed (into scratch, reused): only hue steps leave edges. frame_px is bgr's, as if bgr
/// itself had been mapped (scratch is an image of its own, not a crop: its frame would be the
/// box, which puts a crop's border rule and its camera's perspective in the wrong place).
/// Thresholds measured on that image.
void compute_brightness_free_edge_map(const cv::Mat& bgr, const EdgeParams& params,
                                      cv::Mat& scratch, EdgeMap& out);
/// Same with the thresholds and the pre-blur decision taken elsewhere.
void compute_brightness_free_edge_map(const cv::Mat& bgr, const EdgeParams& params,
                                      const CannyThresholds& fixed, bool denoise, cv::Mat& scratch,
                                      EdgeMap& out);

}  // namespace stereoball::ball_detector
