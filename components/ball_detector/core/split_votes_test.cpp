// Votes split into tasks (VoteTasks) against votes cast in one run: the same accumulator, voters,
// circles and radius-band searches, on real edge maps, whether the tasks run in turn or at once.

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/same_circles_test_support.hpp"

using namespace stereoball::ball_detector;

namespace {

// Photographs of tests/data/circles, the opencv samples and one real stereo pair at the width
// the real-stereo bench halves it to (both eyes), in a fixed order.
std::vector<cv::Mat> split_votes_images() {
  namespace fs = std::filesystem;
  std::vector<std::string> paths;
  for (const char* dir : {"/tests/data/circles", "/opencv-samples"}) {
    const fs::path root =
        fs::path(dir[1] == 't' ? SB_SOURCE_DIR : SB_SHARED_DATA_DIR) / fs::path(dir).filename();
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(root, ec))
      if (e.path().extension() == ".jpg" || e.path().extension() == ".png")
        paths.push_back(e.path().string());
  }
  std::sort(paths.begin(), paths.end());
  if (paths.size() > 14) paths.resize(14);
  const std::string pair = std::string(SB_SHARED_DATA_DIR) + "/real-stereo-basketball/";
  paths.push_back(pair + "left/left_03.jpg");
  paths.push_back(pair + "right/right_03.jpg");
  std::vector<cv::Mat> out;
  for (const std::string& p : paths) {
    cv::Mat m = cv::imread(p, cv::IMREAD_COLOR);
    if (m.empty()) continue;
    if (m.cols > 1152)
      cv::resize(m, m, cv::Size(1152, m.rows * 1152 / m.cols), 0, 0, cv::INTER_AREA);
    out.push_back(m);
  }
  return out;
}

// The in-turn runner, as a pipeline without a helper thread has it.
void split_votes_in_turn(int n, const std::function<void(int)>& task) {
  for (int i = 0; i < n; ++i) task(i);
}

// A runner that runs every task on a thread of its own at once (the node's has two).
void split_votes_at_once(int n, const std::function<void(int)>& task) {
  std::vector<std::thread> threads;
  for (int i = 1; i < n; ++i) threads.emplace_back([&task, i] { task(i); });
  task(0);
  for (auto& t : threads) t.join();
}

// A runner that runs the tasks last first: the shares' order must not matter.
void split_votes_reversed(int n, const std::function<void(int)>& task) {
  for (int i = n - 1; i >= 0; --i) task(i);
}

bool split_votes_same_voters(const std::vector<Voter>& a, const std::vector<Voter>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Voter)) == 0);
}

struct SplitCase {
  std::vector<int> k_values;
  VoteTasks tasks;
  const char* what;
};

}  // namespace

TEST(SplitVotes, GivenRealImagesWhenVotesAreSplitIntoTasksThenVotesAndCirclesAreTheSame) {
  // Given real photographs and a real stereo pair, and detectors voting in one run
  const auto images = split_votes_images();
  ASSERT_GE(images.size(), 10u) << "expected tests/data/circles, opencv-samples, a real pair";
  const std::vector<SplitCase> cases = {
      {{3, 5}, {split_votes_in_turn, 2}, "k 3,5 in turn"},
      {{3, 5}, {split_votes_at_once, 2}, "k 3,5 on two threads"},
      {{5}, {split_votes_at_once, 2}, "k 5 on two threads"},
      {{3, 5, 7}, {split_votes_reversed, 3}, "k 3,5,7 in three shares, last first"},
  };
  for (const SplitCase& c : cases) {
    PixelToPixelParams params;
    params.k_values = c.k_values;
    PixelToPixelDetector split(params), whole(params), band_of_split(params), band_of_whole(params);
    std::int64_t voters = 0;
    int circles = 0;
    for (const cv::Mat& image : images) {
      SCOPED_TRACE(std::string(c.what) + ", image " + std::to_string(image.cols) + "x" +
                   std::to_string(image.rows));
      // When one casts its votes split into tasks and the other in one run
      ASSERT_TRUE(split.cast_votes(image, c.tasks));
      ASSERT_TRUE(whole.cast_votes(image));
      // Then the accumulators are equal cell for cell and the voters come in the same order
      ASSERT_EQ(split.raw_accumulator().size(), whole.raw_accumulator().size());
      EXPECT_EQ(cv::norm(split.raw_accumulator(), whole.raw_accumulator(), cv::NORM_INF), 0.0);
      EXPECT_TRUE(split_votes_same_voters(split.voters(), whole.voters()));
      // And a radius band searched on each one's lines finds the same (the lines' order)
      const SearchHints band{RadiusRange{9, 40}};
      test::expect_same_circles(band_of_split.redetect_from(split, band),
                                band_of_whole.redetect_from(whole, band));
      // And the circles are the same, bit for bit
      const auto found = split.circles_of_votes();
      test::expect_same_circles(found, whole.circles_of_votes());
      voters += static_cast<std::int64_t>(whole.voters().size());
      circles += static_cast<int>(found.size());
    }
    EXPECT_GT(voters, 10000) << c.what;
    EXPECT_GT(circles, 0) << c.what;
  }
}

TEST(SplitVotes, GivenEdgesFoundFirstWhenTheirVotesAreSplitThenTheyEqualOneRun) {
  // Given a real image whose edges one detector found alone (as the coarse try does)
  const auto images = split_votes_images();
  ASSERT_FALSE(images.empty());
  PixelToPixelParams params;
  params.k_values = {3, 5};
  PixelToPixelDetector reused(params), whole(params);
  EXPECT_FALSE(reused.cast_votes_on_last_edges({split_votes_at_once, 2})) << "no edges yet";
  const cv::Mat& image = images.back();
  ASSERT_TRUE(reused.find_edges(image));
  // When it votes on them in two tasks at once, and the other casts its votes in one run
  ASSERT_TRUE(reused.cast_votes_on_last_edges({split_votes_at_once, 2}));
  ASSERT_TRUE(whole.cast_votes(image));
  // Then the votes and circles are the same
  EXPECT_EQ(cv::norm(reused.raw_accumulator(), whole.raw_accumulator(), cv::NORM_INF), 0.0);
  EXPECT_TRUE(split_votes_same_voters(reused.voters(), whole.voters()));
  test::expect_same_circles(reused.circles_of_votes(), whole.circles_of_votes());
  // And an invalid image casts no votes however they are split
  EXPECT_FALSE(reused.cast_votes(cv::Mat(), {split_votes_at_once, 2}));
  EXPECT_TRUE(reused.circles_of_votes().empty());
}

TEST(SplitVotes, GivenConcentricDiscsWhenVotesAreSplitThenTheirCrowdedCellsAreTheSame) {
  // Given concentric discs of a large image, dark and light in turn: rays of edge points from
  // both shares of every k cross around their common centre (a cell holding 0xFFFF cannot be
  // reached by an image of sensible size; the sum of the shares saturates as one map does)
  cv::Mat image(1400, 1400, CV_8UC1, cv::Scalar(0));
  for (int r = 688, i = 0; r >= 8; r -= 8, ++i)
    cv::circle(image, {700, 700}, r, cv::Scalar(i % 2 ? 0 : 255), cv::FILLED);
  PixelToPixelParams params;
  params.k_values = {3, 5};
  params.max_radius_px = 700.0;
  PixelToPixelDetector split(params), whole(params);
  // When one casts its votes in two tasks at once and the other in one run
  ASSERT_TRUE(split.cast_votes(image, {split_votes_at_once, 2}));
  ASSERT_TRUE(whole.cast_votes(image));
  // Then the centre collected a thousand votes and more, and the maps are equal cell for cell
  double whole_max = 0;
  cv::minMaxLoc(whole.raw_accumulator(), nullptr, &whole_max);
  EXPECT_GT(whole_max, 1000.0);
  EXPECT_EQ(cv::norm(split.raw_accumulator(), whole.raw_accumulator(), cv::NORM_INF), 0.0);
  EXPECT_TRUE(split_votes_same_voters(split.voters(), whole.voters()));
  // And so are the circles
  test::expect_same_circles(split.circles_of_votes(), whole.circles_of_votes());
}
