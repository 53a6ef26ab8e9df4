// The voting windows' rules against plain references: connected_rows vs a breadth-first flood
// fill and its rows-at-once growth vs row by row, chord ends from row masks vs find_chord_ends,
// the packed and wide windows' component and chord ends vs those of the row masks (and their
// one-load row reads vs BitImage::bits), the detector's wide-window lines vs the row masks' on
// real images.

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <iterator>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "ball_detector/core/canny.hpp"
#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/fast_math.hpp"
#include "ball_detector/core/fast_paths_test_support.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/p2p_rules.hpp"
#include "ball_detector/core/same_circles_test_support.hpp"
#include "ball_detector/core/synthetic.hpp"
#include "ball_detector/core/voting.hpp"

namespace stereoball::ball_detector {
namespace {

// A height x width bit image, each pixel set or not at random (OpenCV's generator).
BitImage random_bit_image(int height, int width) {
  cv::Mat binary(height, width, CV_8UC1);
  cv::randu(binary, 0, 2);
  BitImage bits;
  bits.assign(binary);
  return bits;
}

// Reference: 8-connected component of the window centre by breadth-first search.
int bfs_component(const std::array<std::uint64_t, 64>& window, int n, int k) {
  auto set = [&](int r, int c) { return (window[static_cast<size_t>(r)] >> c) & 1u; };
  if (!set(k, k)) return 0;
  std::vector<char> seen(static_cast<size_t>(n * n), 0);
  std::deque<std::pair<int, int>> queue{{k, k}};
  seen[static_cast<size_t>(k * n + k)] = 1;
  int count = 0;
  while (!queue.empty()) {
    const auto [r, c] = queue.front();
    queue.pop_front();
    ++count;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const int rr = r + dr, cc = c + dc;
        if (rr < 0 || cc < 0 || rr >= n || cc >= n || !set(rr, cc)) continue;
        char& s = seen[static_cast<size_t>(rr * n + cc)];
        if (!s) s = 1, queue.emplace_back(rr, cc);
      }
  }
  return count;
}

TEST(ConnectedRows, GivenRandomWindowsThenTheComponentEqualsABreadthFirstFloodFill) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20000; ++trial) {
    // Given a random window (densities from sparse to dense, several k) with its centre set
    const int k = std::array{2, 5, 8, 15, 31}[static_cast<size_t>(trial) % 5];
    const int n = 2 * k + 1;
    const unsigned density = 5 + static_cast<unsigned>(trial) % 50;
    std::array<std::uint64_t, 64> window{};
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c)
        if (rng() % 100 < density) window[static_cast<size_t>(r)] |= std::uint64_t{1} << c;
    window[static_cast<size_t>(k)] |= std::uint64_t{1} << k;
    // When its component is grown (no early stop)
    std::array<std::uint64_t, 64> rows{};
    const int count = connected_rows(std::span<const std::uint64_t>(window.data(), n), k, rows);
    // Then the count equals the reference, and the masks hold exactly that many window pixels
    const int expected = bfs_component(window, n, k);
    ASSERT_EQ(count, expected) << "trial " << trial << " k " << k;
    int in_masks = 0;
    for (int r = 0; r < n; ++r) {
      ASSERT_EQ(rows[static_cast<size_t>(r)] & ~window[static_cast<size_t>(r)], 0u);
      in_masks += std::popcount(rows[static_cast<size_t>(r)]);
    }
    ASSERT_EQ(in_masks, expected);
  }
}

TEST(ConnectedRows, GivenAMaskBufferHoldingOldBitsThenEveryMaskIsWrittenAfresh) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 6000; ++trial) {
    // Given a random window and a mask buffer full of set bits (a previous window's masks)
    const int k = std::array{2, 5, 8, 31}[static_cast<size_t>(trial) % 4];
    const int n = 2 * k + 1;
    const unsigned density = 5 + static_cast<unsigned>(trial) % 40;
    std::array<std::uint64_t, 64> window{};
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c)
        if (rng() % 100 < density) window[static_cast<size_t>(r)] |= std::uint64_t{1} << c;
    window[static_cast<size_t>(k)] |= std::uint64_t{1} << k;
    const int stop = trial % 2 == 0 ? n : 64 * 64;
    std::array<std::uint64_t, 64> reused;
    reused.fill(~std::uint64_t{0});
    std::array<std::uint64_t, 64> cleared{};
    // When grown into both buffers (with and without the rule's early stop)
    const auto span = std::span<const std::uint64_t>(window.data(), n);
    const int from_reused = connected_rows(span, k, reused, stop);
    const int from_cleared = connected_rows(span, k, cleared, stop);
    // Then the counts and all 2k+1 masks agree: no old bit survives
    ASSERT_EQ(from_reused, from_cleared) << "trial " << trial;
    for (int r = 0; r < n; ++r)
      ASSERT_EQ(reused[static_cast<size_t>(r)], cleared[static_cast<size_t>(r)])
          << "trial " << trial << " row " << r;
  }
}

TEST(ConnectedRows, GivenAUShapeThatReturnsOverItsRowsThenTheWorklistFindsAllOfIt) {
  // Given a U through the centre row whose right arm is reached only around its bottom
  const int k = 5, n = 11;
  std::array<std::uint64_t, 64> window{};
  for (int r = 5; r <= 9; ++r) window[static_cast<size_t>(r)] |= 1u << 2;  // left arm, from O
  window[9] |= 0b11111100u;                                                // bottom
  for (int r = 2; r <= 9; ++r) window[static_cast<size_t>(r)] |= 1u << 7;  // right arm, upward
  window[5] |= 1u << k;                                                    // O on the left arm
  window[5] |= 1u << 3 | 1u << 4;  // joins O to the left arm
  // When grown
  std::array<std::uint64_t, 64> rows{};
  const int count = connected_rows(std::span<const std::uint64_t>(window.data(), n), k, rows);
  // Then the right arm above the centre row is included too
  EXPECT_EQ(count, bfs_component(window, n, k));
  EXPECT_TRUE((rows[2] >> 7) & 1u);
}

TEST(ConnectedRows, GivenAStopThenTheCountExceedsItOnlyWhenTheComponentDoes) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 3000; ++trial) {
    const int k = 5, n = 11;
    std::array<std::uint64_t, 64> window{};
    for (int r = 0; r < n; ++r) window[static_cast<size_t>(r)] = rng() & ((1u << n) - 1);
    window[k] |= 1u << k;
    std::array<std::uint64_t, 64> rows{};
    const int stopped =
        connected_rows(std::span<const std::uint64_t>(window.data(), n), k, rows, n);
    const int full = bfs_component(window, n, k);
    // The rule needs exactly 2k+1: a stopped count must not look like one.
    if (full > n)
      EXPECT_GT(stopped, n);
    else
      EXPECT_EQ(stopped, full);
  }
}

TEST(ConnectedRows, GivenWindowsOfThirteenToThirtyOnePixelsThenAllRowsAtOnceEqualRowByRow) {
  std::mt19937 rng(73);
  int whole = 0, above = 0;
  for (int trial = 0; trial < 40000; ++trial) {
    // Given a random window of every k the rows-at-once growth takes (6 to 15: two to four
    // registers, the last one partly used), sparse to dense, O set (now and then not), in a
    // mask buffer holding old bits
    const int k = 6 + trial % 10;
    const int n = 2 * k + 1;
    const unsigned density = 3 + static_cast<unsigned>(trial) % 40;
    std::array<std::uint64_t, 64> window{};
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c)
        if (rng() % 100 < density) window[static_cast<size_t>(r)] |= std::uint64_t{1} << c;
    if (trial % 50 != 0) window[static_cast<size_t>(k)] |= std::uint64_t{1} << k;
    const auto span = std::span<const std::uint64_t>(window.data(), n);
    // When grown all rows at once (where AVX2 runs) and row by row, whole and stopped by the
    // count rule
    for (const int stop : {64 * 64, n}) {
      std::array<std::uint64_t, 64> fast;
      fast.fill(~std::uint64_t{0});
      std::array<std::uint64_t, 64> plain{};
      const int count = connected_rows(span, k, fast, stop);
      const int reference = connected_rows_plain(span, k, plain, stop);
      // Then the count is the same below, at or above the stop, and so are the masks when whole
      if (reference > stop) {
        ++above;
        ASSERT_GT(count, stop) << "trial " << trial;
        continue;
      }
      ++whole;
      ASSERT_EQ(count, reference) << "trial " << trial << " k " << k;
      for (int r = 0; r < n; ++r)
        ASSERT_EQ(fast[static_cast<size_t>(r)], plain[static_cast<size_t>(r)])
            << "trial " << trial << " k " << k << " row " << r;
    }
  }
  EXPECT_GT(whole, 20000);
  EXPECT_GT(above, 5000);
}

TEST(WindowRows, GivenRandomBitImagesThenEveryWindowEqualsItsRowsReadOneByOne) {
  std::mt19937 rng(31);
  for (const int width : {70, 130, 200}) {
    // Given a random bit image whose rows span one to four words
    const int height = 70;
    const BitImage bits = random_bit_image(height, width);
    for (int trial = 0; trial < 3000; ++trial) {
      // When a window of any k, at any x (every offset in a word), is read whole
      const int k = 1 + static_cast<int>(rng() % 31);
      if (2 * k + 1 > width || 2 * k + 1 > height) continue;
      const int x = k + static_cast<int>(rng() % static_cast<unsigned>(width - 2 * k));
      const int y = k + static_cast<int>(rng() % static_cast<unsigned>(height - 2 * k));
      std::array<std::uint64_t, 64> rows{};
      const int count = window_rows(bits, x, y, k, rows);
      // Then each row equals BitImage::bits of that row, and the count is the window's
      ASSERT_EQ(count, count_window_points(bits, x, y, k));
      for (int r = 0; r < 2 * k + 1; ++r)
        ASSERT_EQ(rows[static_cast<size_t>(r)], bits.bits(y - k + r, x - k, 2 * k + 1))
            << "width " << width << " x " << x << " y " << y << " k " << k << " row " << r;
    }
  }
}

TEST(ConnectedRows, GivenTheNarrowestWindowsThenTheComponentEqualsABreadthFirstFloodFill) {
  // The fill takes a number of doubling steps fixed by the window width: k = 1 (3 columns) and
  // k = 3 (7) are the narrowest of their step counts.
  std::mt19937 rng(23);
  for (int trial = 0; trial < 4000; ++trial) {
    // Given a random narrow window with its centre set
    const int k = trial % 2 == 0 ? 1 : 3;
    const int n = 2 * k + 1;
    std::array<std::uint64_t, 64> window{};
    for (int r = 0; r < n; ++r)
      window[static_cast<size_t>(r)] = rng() & ((std::uint64_t{1} << n) - 1);
    window[static_cast<size_t>(k)] |= std::uint64_t{1} << k;
    // When its component is grown
    std::array<std::uint64_t, 64> rows{};
    const int count = connected_rows(std::span<const std::uint64_t>(window.data(), n), k, rows);
    // Then it equals the reference
    ASSERT_EQ(count, bfs_component(window, n, k)) << "trial " << trial << " k " << k;
  }
}

TEST(ChordEndsOfRows, GivenRandomWindowsThenAAndBEqualFindChordEndsOnTheCollectedPoints) {
  std::mt19937 rng(13);
  int compared = 0, with_chord = 0;
  for (int trial = 0; trial < 50000; ++trial) {
    // Given a random window (sparse, so every kind of configuration and tie occurs), of every
    // k up to the widest a row holds, and now and then one of more rows than a row has bits
    // (k = 40: 81 rows of 64 columns)
    const int k = trial % 100 == 99 ? 40 : trial % 4 == 3 ? 9 + trial / 4 % 23 : 1 + trial % 8;
    const int n = 2 * k + 1;
    std::array<std::uint64_t, 96> rows{};
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < std::min(n, 64); ++c)
        if (rng() % 100 < 12) rows[static_cast<size_t>(r)] |= std::uint64_t{1} << c;
    const auto span = std::span<const std::uint64_t>(rows.data(), n);
    std::array<WindowPoint, 96 * 64> points{};
    const int got = collect_masked_points(span, k, points);
    // When the chord ends are read off the masks and found on the point list
    const auto from_rows = chord_ends_of_rows(span, k);
    const auto from_points = find_chord_ends(std::span<const WindowPoint>(points.data(), got));
    // Then both agree, including which point wins a tie
    ASSERT_EQ(from_rows.has_value(), from_points.has_value()) << "trial " << trial;
    ++compared;
    if (!from_rows) continue;
    ++with_chord;
    ASSERT_EQ(from_rows->a, from_points->a) << "trial " << trial;
    ASSERT_EQ(from_rows->b, from_points->b) << "trial " << trial;
    // and the whole analysis of a window holding exactly 2k+1 points agrees too
    if (got == n) {
      const auto a = analyse_window_rows(span, k);
      const auto b = analyse_window(std::span<const WindowPoint>(points.data(), got), k);
      ASSERT_EQ(a.has_value(), b.has_value());
      if (a) {
        ASSERT_TRUE(a->c2x == b->c2x && a->c2y == b->c2y && a->nx == b->nx && a->ny == b->ny);
      }
      // as does the detector's path, which has counted the points already
      const auto counted = vote_line_of_rows(span, k);
      ASSERT_EQ(counted.has_value(), a.has_value());
      if (a) {
        ASSERT_TRUE(counted->c2x == a->c2x && counted->c2y == a->c2y && counted->nx == a->nx &&
                    counted->ny == a->ny);
      }
    }
  }
  EXPECT_GT(with_chord, compared / 4);
}

// A random window of half size k <= kPackedMaxK as row masks and packed (the same pixels),
// about density percent of them set, O set when with_centre.
struct RandomWindow {
  std::array<std::uint64_t, 64> rows{};
  std::uint64_t packed = 0;
};
RandomWindow random_window(std::mt19937& rng, int k, unsigned density, bool with_centre) {
  RandomWindow w;
  const int n = 2 * k + 1;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      if (rng() % 100 < density || (with_centre && r == k && c == k)) {
        w.rows[static_cast<size_t>(r)] |= std::uint64_t{1} << c;
        w.packed |= std::uint64_t{1} << (8 * r + c);
      }
  return w;
}

TEST(PackedWindow, GivenRandomBitImagesThenEveryPackedWindowHoldsTheWindowsRows) {
  std::mt19937 rng(41);
  for (const int width : {20, 70, 130}) {
    // Given a random bit image whose rows span one to three words
    const BitImage bits = random_bit_image(40, width);
    for (int trial = 0; trial < 3000; ++trial) {
      // When a window of every packed k, at any x, is packed
      const int k = 1 + trial % kPackedMaxK;
      const int x = k + static_cast<int>(rng() % static_cast<unsigned>(width - 2 * k));
      const int y = k + static_cast<int>(rng() % static_cast<unsigned>(40 - 2 * k));
      const std::uint64_t packed = packed_window(bits, x, y, k);
      // Then byte r holds row r of the window and nothing else is set
      std::array<std::uint64_t, 64> rows{};
      window_rows(bits, x, y, k, rows);
      std::uint64_t expected = 0;
      for (int r = 0; r < 2 * k + 1; ++r) expected |= rows[static_cast<size_t>(r)] << (8 * r);
      ASSERT_EQ(packed, expected) << "width " << width << " x " << x << " y " << y << " k " << k;
    }
  }
}

TEST(ShortBits, GivenRandomBitImagesThenEveryReadEqualsBits) {
  for (const int width : {1, 9, 63, 64, 65, 130, 200}) {
    // Given a random bit image (a row of one word to four, and widths ending anywhere in one)
    const BitImage bits = random_bit_image(3, width);
    // When every run of pixels inside a row is read with one load
    for (int y = 0; y < 3; ++y)
      for (int x0 = 0; x0 < width; ++x0)
        for (int n = 1; n <= std::min(57, width - x0); ++n)
          // Then it holds the same bits as the two-word read
          ASSERT_EQ(bits.short_bits(y, x0, n), bits.bits(y, x0, n))
              << "width " << width << " y " << y << " x0 " << x0 << " n " << n;
  }
}

TEST(ConnectedPacked, GivenRandomWindowsThenCountAndComponentEqualConnectedRows) {
  std::mt19937 rng(43);
  for (int trial = 0; trial < 30000; ++trial) {
    // Given a random window of every packed k, sparse to dense, O set (now and then not)
    const int k = 1 + trial % kPackedMaxK;
    const int n = 2 * k + 1;
    const RandomWindow w =
        random_window(rng, k, 5 + static_cast<unsigned>(trial) % 60, trial % 50 != 0);
    // When its component through O is grown whole, and stopped as the count rule stops it
    const auto span = std::span<const std::uint64_t>(w.rows.data(), n);
    std::array<std::uint64_t, 64> rows{};
    const int full_rows = connected_rows(span, k, rows);
    std::uint64_t component = ~std::uint64_t{0};
    const int full = connected_packed(w.packed, k, component);
    std::array<std::uint64_t, 64> stopped_rows{};
    const int stopped_by_rows = connected_rows(span, k, stopped_rows, n);
    std::uint64_t stopped_component = 0;
    const int stopped = connected_packed(w.packed, k, stopped_component, n);
    // Then the whole component is connected_rows' own, bit for bit
    ASSERT_EQ(full, full_rows) << "trial " << trial;
    std::uint64_t expected = 0;
    for (int r = 0; r < n; ++r) expected |= rows[static_cast<size_t>(r)] << (8 * r);
    ASSERT_EQ(component, expected) << "trial " << trial;
    // and the stopped one is the same below, at or above the rule's 2k+1 points
    if (stopped_by_rows > n) {
      ASSERT_GT(stopped, n) << "trial " << trial;
    } else {
      ASSERT_EQ(stopped, stopped_by_rows) << "trial " << trial;
      ASSERT_EQ(stopped_component, expected) << "trial " << trial;
    }
  }
}

// How many windows of a random test had chord ends and a vote line.
struct ChordCounts {
  int with_chord = 0;
  int with_line = 0;
};

// chord and line (read off a packed or wide word) equal those read off the window's row masks,
// ties included; counts the windows that had each.
void expect_same_chord_and_line(const std::optional<ChordEnds>& chord,
                                const std::optional<VoteLine>& line,
                                std::span<const std::uint64_t> rows, int k, int trial,
                                ChordCounts& counts) {
  const auto chord_of_rows = chord_ends_of_rows(rows, k);
  ASSERT_EQ(chord.has_value(), chord_of_rows.has_value()) << "trial " << trial;
  if (chord) {
    ++counts.with_chord;
    ASSERT_EQ(chord->a, chord_of_rows->a) << "trial " << trial;
    ASSERT_EQ(chord->b, chord_of_rows->b) << "trial " << trial;
  }
  const auto line_of_rows = vote_line_of_rows(rows, k);
  ASSERT_EQ(line.has_value(), line_of_rows.has_value()) << "trial " << trial;
  if (line) {
    ++counts.with_line;
    ASSERT_TRUE(line->c2x == line_of_rows->c2x && line->c2y == line_of_rows->c2y &&
                line->nx == line_of_rows->nx && line->ny == line_of_rows->ny)
        << "trial " << trial;
  }
}

TEST(ChordEndsPacked, GivenRandomWindowsThenEndsAndVoteLineEqualThoseOfTheRowMasks) {
  std::mt19937 rng(47);
  ChordCounts counts;
  for (int trial = 0; trial < 60000; ++trial) {
    // Given a random window of every packed k (sparse: every configuration and tie occurs),
    // now and then an empty one
    const int k = 1 + trial % kPackedMaxK;
    const int n = 2 * k + 1;
    const RandomWindow w =
        random_window(rng, k, trial % 100 == 0 ? 0 : 5 + static_cast<unsigned>(trial) % 30, false);
    const auto span = std::span<const std::uint64_t>(w.rows.data(), n);
    // When the chord ends and vote line are read off the packed word and off the row masks
    // Then they agree, including which point wins a tie
    ASSERT_NO_FATAL_FAILURE(expect_same_chord_and_line(
        chord_ends_packed(w.packed, k), vote_line_packed(w.packed, k), span, k, trial, counts));
  }
  EXPECT_GT(counts.with_chord, 20000);
  EXPECT_GT(counts.with_line, 5000);
}

#if SB_WIDE_WINDOWS
// A random window of half size kPackedMaxK < k <= kWideMaxK as row masks and wide (the same
// pixels), about density percent of them set, O set when with_centre.
struct RandomWideWindow {
  std::array<std::uint64_t, 64> rows{};
  WideWindow wide = 0;
};
RandomWideWindow random_wide_window(std::mt19937& rng, int k, unsigned density, bool with_centre) {
  RandomWideWindow w;
  const int n = 2 * k + 1;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      if (rng() % 100 < density || (with_centre && r == k && c == k)) {
        w.rows[static_cast<size_t>(r)] |= std::uint64_t{1} << c;
        w.wide |= WideWindow{1} << (n * r + c);
      }
  return w;
}

// The wide word of row masks (row r at bit n r).
WideWindow wide_of_rows(std::span<const std::uint64_t> rows, int k) {
  const int n = 2 * k + 1;
  WideWindow w = 0;
  for (int r = 0; r < n; ++r) w |= static_cast<WideWindow>(rows[static_cast<size_t>(r)]) << (n * r);
  return w;
}

// connected_wide, chord_ends_wide and vote_line_wide for a k known only at run time.
int connected_wide_of(int k, WideWindow window, WideWindow& component, int stop_above = 128) {
  return k == 4 ? connected_wide<4>(window, component, stop_above)
                : connected_wide<5>(window, component, stop_above);
}
std::optional<ChordEnds> chord_ends_wide_of(int k, WideWindow window) {
  return k == 4 ? chord_ends_wide<4>(window) : chord_ends_wide<5>(window);
}
std::optional<VoteLine> vote_line_wide_of(int k, WideWindow window) {
  return k == 4 ? vote_line_wide<4>(window) : vote_line_wide<5>(window);
}

TEST(WideWindow, GivenRandomBitImagesThenEveryWideWindowHoldsTheWindowsRows) {
  std::mt19937 rng(61);
  for (const int width : {20, 70, 130}) {
    // Given a random bit image whose rows span one to three words
    const BitImage bits = random_bit_image(40, width);
    for (int trial = 0; trial < 3000; ++trial) {
      // When a window of every wide k, at any x, is packed
      const int k = kPackedMaxK + 1 + trial % (kWideMaxK - kPackedMaxK);
      const int x = k + static_cast<int>(rng() % static_cast<unsigned>(width - 2 * k));
      const int y = k + static_cast<int>(rng() % static_cast<unsigned>(40 - 2 * k));
      const WideWindow wide = k == 4 ? wide_window<4>(bits, x, y) : wide_window<5>(bits, x, y);
      // Then bits [n r, n r + n) hold row r of the window and nothing else is set
      std::array<std::uint64_t, 64> rows{};
      window_rows(bits, x, y, k, rows);
      ASSERT_TRUE(wide == wide_of_rows(rows, k))
          << "width " << width << " x " << x << " y " << y << " k " << k;
    }
  }
}

TEST(ConnectedWide, GivenRandomWindowsThenCountAndComponentEqualConnectedRows) {
  std::mt19937 rng(67);
  int whole = 0;
  for (int trial = 0; trial < 30000; ++trial) {
    // Given a random window of every wide k, sparse to dense, O set (now and then not), pixels
    // in the first and last columns (where a shift by one would wrap) as often as elsewhere
    const int k = kPackedMaxK + 1 + trial % (kWideMaxK - kPackedMaxK);
    const int n = 2 * k + 1;
    const RandomWideWindow w =
        random_wide_window(rng, k, 5 + static_cast<unsigned>(trial) % 60, trial % 50 != 0);
    // When its component through O is grown whole, and stopped as the count rule stops it
    const auto span = std::span<const std::uint64_t>(w.rows.data(), n);
    std::array<std::uint64_t, 64> rows{};
    const int full_rows = connected_rows(span, k, rows);
    WideWindow component = ~WideWindow{0};
    const int full = connected_wide_of(k, w.wide, component);
    std::array<std::uint64_t, 64> stopped_rows{};
    const int stopped_by_rows = connected_rows(span, k, stopped_rows, n);
    WideWindow stopped_component = 0;
    const int stopped = connected_wide_of(k, w.wide, stopped_component, n);
    // Then the whole component is connected_rows' own, bit for bit
    ASSERT_EQ(full, full_rows) << "trial " << trial;
    const WideWindow expected = wide_of_rows(rows, k);
    ASSERT_TRUE(component == expected) << "trial " << trial;
    // and the stopped one is the same below, at or above the rule's 2k+1 points
    if (stopped_by_rows > n) {
      ASSERT_GT(stopped, n) << "trial " << trial;
    } else {
      ++whole;
      ASSERT_EQ(stopped, stopped_by_rows) << "trial " << trial;
      ASSERT_TRUE(stopped_component == expected) << "trial " << trial;
    }
  }
  EXPECT_GT(whole, 5000);
}

TEST(ChordEndsWide, GivenRandomWindowsThenEndsAndVoteLineEqualThoseOfTheRowMasks) {
  std::mt19937 rng(71);
  ChordCounts counts;
  for (int trial = 0; trial < 60000; ++trial) {
    // Given a random window of every wide k (sparse: every configuration and tie occurs),
    // now and then an empty one
    const int k = kPackedMaxK + 1 + trial % (kWideMaxK - kPackedMaxK);
    const int n = 2 * k + 1;
    const RandomWideWindow w = random_wide_window(
        rng, k, trial % 100 == 0 ? 0 : 3 + static_cast<unsigned>(trial) % 20, false);
    const auto span = std::span<const std::uint64_t>(w.rows.data(), n);
    // When the chord ends and vote line are read off the wide word and off the row masks
    // Then they agree, including which point wins a tie
    ASSERT_NO_FATAL_FAILURE(expect_same_chord_and_line(
        chord_ends_wide_of(k, w.wide), vote_line_wide_of(k, w.wide), span, k, trial, counts));
  }
  EXPECT_GT(counts.with_chord, 20000);
  EXPECT_GT(counts.with_line, 5000);
}

// The vote lines of one k on an edge map as the row masks give them (the plain reference of the
// detector's window loop): count rule, component through O, orientation isolation.
std::vector<Voter> row_mask_voters(const EdgeMap& edges, int k, int isolate_max_points) {
  std::array<BitImage, kOrientationBins> near;
  near_orientation_planes(edges, near);
  const int n = 2 * k + 1;
  std::vector<Voter> out;
  const BitImage& bits = edges.bits;
  for (int y = k; y < bits.height() - k; ++y)
    for (int x = k; x < bits.width() - k; ++x) {
      if (!bits.test(x, y)) continue;
      std::array<std::uint64_t, 64> rows{}, mask{}, aligned{};
      const int count = window_rows(bits, x, y, k, rows);
      const auto window = std::span<const std::uint64_t>(rows.data(), n);
      std::optional<VoteLine> line;
      if (count == n) {
        line = vote_line_of_rows(window, k);
      } else if (count > n && count <= isolate_max_points) {
        int connected = connected_rows(window, k, mask, n);
        if (connected > n) {
          const BitImage& plane = near[static_cast<std::size_t>(
              orientation_bin(edges.dx.at<short>(y, x), edges.dy.at<short>(y, x)))];
          int kept = 0;
          bool dropped = false;
          for (int r = 0; r < n; ++r) {
            aligned[static_cast<size_t>(r)] =
                rows[static_cast<size_t>(r)] & plane.bits(y - k + r, x - k, n);
            kept += std::popcount(aligned[static_cast<size_t>(r)]);
            dropped = dropped || aligned[static_cast<size_t>(r)] != rows[static_cast<size_t>(r)];
          }
          if (kept >= n && dropped)
            connected =
                connected_rows(std::span<const std::uint64_t>(aligned.data(), n), k, mask, n);
        }
        if (connected == n)
          line = vote_line_of_rows(std::span<const std::uint64_t>(mask.data(), n), k);
      }
      if (!line) continue;
      const float norm = fast_hypot(static_cast<float>(line->nx), static_cast<float>(line->ny));
      out.push_back({static_cast<float>(x + 0.5 * line->c2x),
                     static_cast<float>(y + 0.5 * line->c2y), line->nx / norm, line->ny / norm});
    }
  return out;
}

TEST(WideWindowVotes, GivenRealImagesThenTheDetectorsLinesForKFourAndFiveAreThoseOfTheRowMasks) {
  // Given the real colour images and a detector voting with windows of k = 4 and 5 (the wide
  // words), isolation on
  const auto images = real_colours();
  ASSERT_GE(images.size(), 10u);
  PixelToPixelParams params;
  params.coarse_to_fine = false;
  params.k_values = {4, 5};
  params.isolate_arc = true;
  params.isolate_by_orientation = true;
  std::size_t compared = 0;
  for (const auto& image : images) {
    PixelToPixelDetector detector(params);
    // When it casts its votes
    ASSERT_TRUE(detector.cast_votes(image));
    // Then its voters are, in order, those the row masks give for k = 4, then for k = 5
    std::vector<Voter> expected;
    for (const int k : {4, 5}) {
      const int n = 2 * k + 1;
      const auto of_k = row_mask_voters(detector.edge_map(), k,
                                        static_cast<int>(params.isolate_max_points_factor * n));
      expected.insert(expected.end(), of_k.begin(), of_k.end());
    }
    const std::vector<Voter>& voters = detector.voters();
    ASSERT_EQ(voters.size(), expected.size());
    for (std::size_t i = 0; i < voters.size(); ++i)
      ASSERT_TRUE(voters[i].x == expected[i].x && voters[i].y == expected[i].y &&
                  voters[i].ux == expected[i].ux && voters[i].uy == expected[i].uy)
          << "voter " << i;
    compared += voters.size();
  }
  EXPECT_GT(compared, 10000u);
}
#endif

}  // namespace
}  // namespace stereoball::ball_detector
