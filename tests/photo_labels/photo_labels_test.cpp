// The labelled real photographs of tests/data/circles (README.md there): every label file
// parses and names an image that loads, every circle lies inside its image and at or above the
// radius down to which the file says every circle was labelled (the benchmark searches from
// there), the set keeps at least 40 images and 300 circles, and the tune/report split of the
// images added for issue 38 follows the rule written down before any detector ran on them.

#include "ball_detector/core/circle_labels.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace stereoball::ball_detector {
namespace {

namespace fs = std::filesystem;

// Smallest labelled radius of a file without min_radius, as a share of the shorter side (the
// benchmark's default, tools/bench-detect/real_photos.hpp).
constexpr double kDefaultMinRadiusPerSide = 0.025;

// SHA-256 (FIPS 180-4) of a short string, as lower-case hex: the split rule hashes file names.
std::string sha256_hex(const std::string& message) {
  static constexpr std::array<uint32_t, 64> k = {
      0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4,
      0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe,
      0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f,
      0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7,
      0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc,
      0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b,
      0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116,
      0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
      0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7,
      0xc67178f2};
  std::array<uint32_t, 8> h = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                               0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  std::vector<uint8_t> data(message.begin(), message.end());
  const uint64_t bits = static_cast<uint64_t>(data.size()) * 8;
  data.push_back(0x80);
  while (data.size() % 64 != 56) data.push_back(0);
  for (int i = 7; i >= 0; --i) data.push_back(static_cast<uint8_t>(bits >> (8 * i)));
  const auto rotr = [](uint32_t x, int n) { return (x >> n) | (x << (32 - n)); };
  for (size_t block = 0; block < data.size(); block += 64) {
    std::array<uint32_t, 64> w{};
    for (int i = 0; i < 16; ++i)
      w[i] = (uint32_t{data[block + 4 * i]} << 24) | (uint32_t{data[block + 4 * i + 1]} << 16) |
             (uint32_t{data[block + 4 * i + 2]} << 8) | uint32_t{data[block + 4 * i + 3]};
    for (int i = 16; i < 64; ++i) {
      const uint32_t s0 = rotr(w[i - 15], 7) ^ rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
      const uint32_t s1 = rotr(w[i - 2], 17) ^ rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
      w[i] = w[i - 16] + s0 + w[i - 7] + s1;
    }
    auto v = h;
    for (int i = 0; i < 64; ++i) {
      const uint32_t s1 = rotr(v[4], 6) ^ rotr(v[4], 11) ^ rotr(v[4], 25);
      const uint32_t ch = (v[4] & v[5]) ^ (~v[4] & v[6]);
      const uint32_t t1 = v[7] + s1 + ch + k[i] + w[i];
      const uint32_t s0 = rotr(v[0], 2) ^ rotr(v[0], 13) ^ rotr(v[0], 22);
      const uint32_t maj = (v[0] & v[1]) ^ (v[0] & v[2]) ^ (v[1] & v[2]);
      const uint32_t t2 = s0 + maj;
      v = {t1 + t2, v[0], v[1], v[2], v[3] + t1, v[4], v[5], v[6]};
    }
    for (int i = 0; i < 8; ++i) h[i] += v[i];
  }
  std::string hex;
  static constexpr char digits[] = "0123456789abcdef";
  for (uint32_t word : h)
    for (int shift = 28; shift >= 0; shift -= 4) hex.push_back(digits[(word >> shift) & 0xf]);
  return hex;
}

struct LabelFile {
  fs::path path;
  CircleLabels labels;
};

std::vector<LabelFile> read_label_files(std::vector<std::string>& errors) {
  const fs::path dir = fs::path(SB_SOURCE_DIR) / "tests/data/circles";
  std::vector<fs::path> paths;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".circles") paths.push_back(e.path());
  std::sort(paths.begin(), paths.end());
  std::vector<LabelFile> out;
  for (const auto& p : paths) {
    std::ifstream in(p);
    std::stringstream text;
    text << in.rdbuf();
    auto parsed = parse_circle_labels(text.str(), p.filename().string());
    if (const auto* e = std::get_if<std::string>(&parsed))
      errors.push_back(*e);
    else
      out.push_back({p, std::get<CircleLabels>(parsed)});
  }
  return out;
}

TEST(PhotoLabels, GivenTheLabelFilesThenEachImageLoadsAndItsCirclesLieInsideAboveTheMinimum) {
  // Given every label file of the set
  std::vector<std::string> errors;
  const auto files = read_label_files(errors);
  EXPECT_TRUE(errors.empty()) << errors.front();
  std::map<LabelSplit, size_t> images, circles;
  for (const auto& f : files) {
    // When its image is read (paths are relative to the project root)
    const cv::Mat image =
        cv::imread((fs::path(SB_SOURCE_DIR) / f.labels.image_path).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << f.path.filename() << ": cannot read " << f.labels.image_path;
    // Then its circles are inside it and not below the radius the file was labelled down to
    const double min_radius = f.labels.min_radius_px.value_or(kDefaultMinRadiusPerSide *
                                                              std::min(image.cols, image.rows));
    for (const auto& c : f.labels.circles) {
      EXPECT_TRUE(c.x_px >= -0.5 && c.x_px < image.cols - 0.5 && c.y_px >= -0.5 &&
                  c.y_px < image.rows - 0.5)
          << f.path.filename() << ": centre " << c.x_px << "," << c.y_px << " outside the image";
      EXPECT_GE(c.radius_px, min_radius)
          << f.path.filename() << ": radius " << c.radius_px << " below the minimum " << min_radius
          << " the benchmark searches";
    }
    ++images[f.labels.split];
    circles[f.labels.split] += f.labels.circles.size();
  }
  // And the set keeps its size (issue 38: at least 40 images and 300 circles), both splits used
  EXPECT_GE(images[LabelSplit::tune] + images[LabelSplit::report], 40u);
  EXPECT_GE(circles[LabelSplit::tune] + circles[LabelSplit::report], 300u);
  EXPECT_GE(circles[LabelSplit::tune], 100u);
  EXPECT_GE(circles[LabelSplit::report], 100u);
}

TEST(PhotoLabels, GivenTheImagesAddedForIssue38ThenTheirSplitFollowsTheHashRule) {
  // Given the hash (checked on the FIPS 180-4 example)
  ASSERT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // And the images whose split was fixed by the rule before any detector ran on them
  const std::vector<std::string> by_rule = {"middlebury2005_moebius_view1.png",
                                            "rubberwhale1.png",
                                            "opencv-logo.png",
                                            "water_coins.jpg",
                                            "dualCircles.jpg",
                                            "astra_color.jpg",
                                            "middlebury2005_laundry_view1.jpg",
                                            "middlebury2005_reindeer_view1.jpg",
                                            "middlebury2006_aloe_view1.jpg",
                                            "middlebury2006_bowling1_view1.jpg",
                                            "middlebury2006_flowerpots_view1.jpg",
                                            "middlebury2014q_jadeplant.jpg",
                                            "middlebury2014q_motorcycle.jpg",
                                            "middlebury2014q_piano.jpg",
                                            "middlebury2014q_pipes.jpg",
                                            "middlebury2014q_playroom.jpg",
                                            "middlebury2014q_recycle.jpg",
                                            "middlebury2014q_shelves.jpg",
                                            "pas_legionary_denarius_legiv.jpg",
                                            "pas_legionary_denarius_legix.jpg",
                                            "pas_legionary_denarius_legxv.jpg",
                                            "pas_legionary_denarius_legxvi.jpg",
                                            "skimage_cell.jpg",
                                            "skimage_chelsea.jpg",
                                            "skimage_tutorials_hand_coin.jpg",
                                            "skimage_tutorials_mm.jpg",
                                            "skimage_tutorials_round_pill.jpg",
                                            "theophilus_solidus_athens.jpg",
                                            "vincmazet_bip_coins1.png",
                                            "vincmazet_bip_coins2.png",
                                            "vincmazet_bip_pollen_sem.jpg"};
  std::vector<std::string> errors;
  const auto files = read_label_files(errors);
  for (const auto& name : by_rule) {
    const auto it = std::find_if(files.begin(), files.end(), [&](const LabelFile& f) {
      return fs::path(f.labels.image_path).filename() == name;
    });
    ASSERT_NE(it, files.end()) << "no label file for " << name;
    // Then the first hex digit of SHA-256(file name) below 8 means tune, else report
    const char first = sha256_hex(name).front();
    const LabelSplit rule = first < '8' ? LabelSplit::tune : LabelSplit::report;
    EXPECT_EQ(it->labels.split, rule) << name << ": hash starts with " << first;
  }
}

}  // namespace
}  // namespace stereoball::ball_detector
