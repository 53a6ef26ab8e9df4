#include "ball_detector/pipeline/interior_depth.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace bd = stereoball::ball_detector;

namespace {

constexpr int kWidth = 640, kHeight = 480;

// Blocky random texture (8x8 blocks, as a carpet), the same for every call with one seed.
cv::Mat texture(int seed, cv::Size size = {kWidth, kHeight}) {
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  cv::Mat small(size.height / 8 + 1, size.width / 8 + 1, CV_8UC3);
  rng.fill(small, cv::RNG::UNIFORM, cv::Scalar::all(30), cv::Scalar::all(200));
  cv::Mat big;
  cv::resize(small, big, cv::Size(small.cols * 8, small.rows * 8), 0, 0, cv::INTER_NEAREST);
  return big(cv::Rect(0, 0, size.width, size.height)).clone();
}

// The right eye of a fronto-parallel surface at this shift: right(x) = left(x + shift).
cv::Mat shifted(const cv::Mat& left, int shift_px) {
  cv::Mat right(left.size(), left.type(), cv::Scalar::all(0));
  left(cv::Rect(shift_px, 0, left.cols - shift_px, left.rows))
      .copyTo(right(cv::Rect(0, 0, left.cols - shift_px, left.rows)));
  return right;
}

bd::ShiftWindow ball_at(double lo, double hi) {
  return {lo, hi, 0.0, 1.5 * hi + 8.0};
}

// The verdict on texture that lies at shift_px instead of the ball's depth.
void expect_elsewhere(const bd::InteriorDepth& d, double shift_px) {
  EXPECT_TRUE(d.textured);
  EXPECT_NEAR(d.best_shift_px, shift_px, 0.5);
  EXPECT_TRUE(d.contradicts);
}

}  // namespace

TEST(InteriorDepth, CircleInTextureAtAnotherDepthContradicts) {
  // Carpet 20 px of disparity away; a chance circle paired at 60-70 px (a ball 3x closer).
  const cv::Mat left = texture(1);
  const cv::Mat right = shifted(left, 20);
  const bd::Circle circle{320.0, 300.0, 80.0, 0.9};
  const bd::InteriorDepth d = bd::interior_depth(left, right, circle, ball_at(60, 70), {});
  EXPECT_TRUE(d.textured);
  EXPECT_NEAR(d.best_shift_px, 20.0, 0.5);
  EXPECT_GT(d.best_match, 0.95);
  EXPECT_LT(d.ball_match, 0.5);
  EXPECT_TRUE(d.contradicts);
}

TEST(InteriorDepth, CircleOnASlantedFloorContradicts) {
  // A level rig sees the floor with one disparity per row, larger toward the bottom: each row
  // is matched on its own (a template of all rows matches nowhere).
  const cv::Mat left = texture(8);
  cv::Mat right(left.size(), left.type(), cv::Scalar::all(0));
  for (int y = 0; y < left.rows; ++y) {
    const int shift = 20 + (y * 60) / left.rows;  // 20 px at the top, 80 px at the bottom
    left(cv::Rect(shift, y, left.cols - shift, 1))
        .copyTo(right(cv::Rect(0, y, left.cols - shift, 1)));
  }
  const bd::Circle circle{400.0, 420.0, 180.0, 0.9};
  const bd::InteriorDepth d = bd::interior_depth(left, right, circle, ball_at(200, 260), {});
  EXPECT_TRUE(d.textured);
  EXPECT_GE(d.rows_textured, 3);
  EXPECT_GT(2 * d.rows_elsewhere, d.rows_textured);
  EXPECT_GT(d.best_shift_px, 50.0);
  EXPECT_LT(d.best_shift_px, 81.0);
  EXPECT_TRUE(d.contradicts);
}

TEST(InteriorDepth, TextureAtTheOutlinesDepthStands) {
  const cv::Mat left = texture(2);
  const cv::Mat right = shifted(left, 62);
  const bd::Circle circle{320.0, 240.0, 60.0, 0.9};
  const bd::InteriorDepth d = bd::interior_depth(left, right, circle, ball_at(60, 70), {});
  EXPECT_TRUE(d.textured);
  EXPECT_EQ(d.rows_elsewhere, 0);  // every row matches best at 62 px, inside the ball's shifts
  EXPECT_FALSE(d.contradicts);
}

TEST(InteriorDepth, TexturedBallBeforeTexturedFloorStands) {
  // Floor at 20 px, a two-colour-panel ball (its own texture) at 64 px in front of it.
  const cv::Mat floor_left = texture(3);
  const cv::Mat left = floor_left.clone();
  cv::Mat right = shifted(floor_left, 20);
  const cv::Mat ball = texture(4, {200, 200});
  const cv::Point centre(400, 240);
  const int r = 50;
  cv::Mat mask(200, 200, CV_8U, cv::Scalar(0));
  cv::circle(mask, {100, 100}, r, cv::Scalar(255), cv::FILLED);
  ball.copyTo(left(cv::Rect(centre.x - 100, centre.y - 100, 200, 200)), mask);
  ball.copyTo(right(cv::Rect(centre.x - 64 - 100, centre.y - 100, 200, 200)), mask);
  const bd::Circle circle{400.0, 240.0, 50.0, 0.9};
  const bd::InteriorDepth d = bd::interior_depth(left, right, circle, ball_at(64, 70), {});
  EXPECT_TRUE(d.textured);
  EXPECT_EQ(d.rows_elsewhere, 0);  // the ball's own panels match at its 64 px
  EXPECT_FALSE(d.contradicts);
}

TEST(InteriorDepth, PlainInsideIsNotMatched) {
  // A one-colour ball with soft shading over carpet: nothing inside to match, the pair stands.
  cv::Mat left = texture(5);
  cv::Mat right = shifted(left, 20);
  cv::circle(left, {320, 240}, 70, cv::Scalar(40, 40, 200), cv::FILLED);
  cv::circle(right, {320 - 65, 240}, 70, cv::Scalar(40, 40, 200), cv::FILLED);
  const bd::InteriorDepth d =
      bd::interior_depth(left, right, {320.0, 240.0, 70.0, 0.9}, ball_at(65, 72), {});
  EXPECT_FALSE(d.textured);
  EXPECT_FALSE(d.contradicts);
}

TEST(InteriorDepth, CircleMostlyBelowTheImageIsJudgedOnItsVisibleInside) {
  // The false pairs seen in the simulator: centre below the image, only its top arc in view.
  const cv::Mat left = texture(6);
  const cv::Mat right = shifted(left, 90);
  const bd::Circle circle{384.0, 520.0, 150.0, 0.9};
  const bd::InteriorDepth d = bd::interior_depth(left, right, circle, ball_at(150, 190), {});
  expect_elsewhere(d, 90.0);
}

TEST(InteriorDepth, CircleWhoseCentreIsFarBelowTheImageIsJudgedOnItsTopChords) {
  // Seen on development seed 202: centre 120 px below the image, radius 220 px, on carpet.
  const cv::Mat left = texture(9);
  const cv::Mat right = shifted(left, 90);
  const bd::Circle circle{370.0, 600.0, 220.0, 0.9};
  ASSERT_FALSE(bd::interior_rows_region(circle, left.size()).empty());
  const bd::InteriorDepth d = bd::interior_depth(left, right, circle, ball_at(220, 280), {});
  expect_elsewhere(d, 90.0);
}

TEST(InteriorDepth, NearTheLeftBorderTheRowsAreCutToWhatTheRightEyeSees) {
  // Seen on development seed 202: centre x 139, radius 188, partner 163 px to the left (mostly
  // outside the right image); the carpet under it is at 60 px.
  const cv::Mat left = texture(12);
  const cv::Mat right = shifted(left, 60);
  const bd::Circle circle{139.0, 300.0, 150.0, 0.9};
  const bd::InteriorDepth d = bd::interior_depth(left, right, circle, ball_at(163, 200), {});
  expect_elsewhere(d, 60.0);
  // The same place holding a textured ball at its own 163-200 px stands.
  const cv::Mat ball_right = shifted(left, 170);
  const bd::InteriorDepth ball =
      bd::interior_depth(left, ball_right, circle, ball_at(163, 200), {});
  EXPECT_FALSE(ball.contradicts);
}

TEST(InteriorDepth, WhereTheBallsOwnDepthIsOutOfViewOnlyAStrongMatchElsewhereCounts) {
  // The ball's shift would put its inside beyond the right image's left border: no match at
  // the ball's depth to compare with. An exact copy of the texture elsewhere still tells...
  const cv::Mat left = texture(10);
  const cv::Mat right = shifted(left, 20);
  const bd::Circle circle{120.0, 240.0, 60.0, 0.9};
  const bd::InteriorDepth exact = bd::interior_depth(left, right, circle, ball_at(200, 230), {});
  expect_elsewhere(exact, 20.0);
  // ... a weak resemblance (correlation about 0.6) does not.
  cv::Mat noise(right.size(), CV_16SC3);
  cv::RNG(11).fill(noise, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(45));
  cv::Mat noisy;
  cv::add(right, noise, noisy, cv::noArray(), CV_8UC3);
  const bd::InteriorDepth weak = bd::interior_depth(left, noisy, circle, ball_at(200, 230), {});
  EXPECT_TRUE(weak.textured);
  EXPECT_FALSE(weak.contradicts) << weak.best_match;
}

TEST(InteriorDepth, UnusableInputGivesNoVerdictInsteadOfACrash) {
  const cv::Mat left = texture(7);
  const bd::ShiftWindow w = ball_at(20, 30);
  const bd::Circle inside{320.0, 240.0, 50.0, 0.9};
  cv::Mat grey;
  cv::cvtColor(left, grey, cv::COLOR_BGR2GRAY);
  EXPECT_FALSE(bd::interior_depth(left, grey, inside, w, {}).textured);  // types differ
  EXPECT_FALSE(bd::interior_depth(left, left(cv::Rect(0, 0, 100, 100)), inside, w, {}).textured);
  EXPECT_FALSE(bd::interior_depth(left, left, {-500.0, 240.0, 50.0, 0.9}, w, {}).textured);
  EXPECT_FALSE(bd::interior_depth(left, left, {320.0, 240.0, 2.0, 0.9}, w, {}).textured);
  EXPECT_FALSE(bd::interior_depth(left, left, {NAN, 240.0, 50.0, 0.9}, w, {}).textured);
  EXPECT_TRUE(bd::interior_rows_region({-500.0, 240.0, 50.0, 0.9}, left.size()).empty());
  // Huge or infinite radii and far-off centres: bounded to the image, no overflow.
  EXPECT_FALSE(bd::interior_depth(left, left, {320.0, 240.0, INFINITY, 0.9}, w, {}).textured);
  EXPECT_LE(bd::interior_depth(left, left, {1e300, 240.0, 1e299, 0.9}, w, {}).rows_textured, 12);
  const cv::Rect huge = bd::interior_rows_region({320.0, 240.0, 1e200, 0.9}, left.size());
  EXPECT_TRUE((huge & cv::Rect(0, 0, 640, 480)) == huge);
}

TEST(InteriorDepth, SearchRegionCoversEveryShiftAndStaysInTheImage) {
  const cv::Rect left_region = bd::interior_rows_region({320.0, 240.0, 100.0, 0.9}, {640, 480});
  ASSERT_FALSE(left_region.empty());
  // Within the 0.8 r disc (columns 240..400), its widest sampled chord near the centre row.
  EXPECT_GE(left_region.x, 240);
  EXPECT_LE(left_region.br().x, 401);
  EXPECT_GE(left_region.width, 150);
  EXPECT_GE(left_region.y, 159);
  EXPECT_LE(left_region.br().y, 322);
  const cv::Rect r = bd::interior_search_region(left_region, {60, 70, 0, 113}, {640, 480});
  EXPECT_EQ(r.x, left_region.x - 113);
  EXPECT_EQ(r.br().x, left_region.br().x);
  EXPECT_EQ(r.y, left_region.y);
  EXPECT_EQ(r.height, left_region.height);
  const cv::Rect clipped = bd::interior_search_region(left_region, {60, 70, 0, 900}, {640, 480});
  EXPECT_EQ(clipped.x, 0);
}

TEST(RowTemplateCorrelation, GivenSmallOrLargeRows_ThenAsMatchTemplate) {
  cv::RNG rng(21);
  for (const int type : {CV_8UC1, CV_8UC3}) {
    for (const cv::Size strip : {cv::Size(90, 3), cv::Size(900, 3)}) {
      cv::Mat image(strip, type), templ(1, strip.width / 3, type);
      rng.fill(image, cv::RNG::UNIFORM, cv::Scalar::all(0), cv::Scalar::all(256));
      image(cv::Rect(0, 0, templ.cols, 1)).copyTo(templ);
      image(cv::Rect(strip.width / 2, 1, strip.width / 2, 1)).setTo(cv::Scalar::all(77));  // flat
      cv::Mat expected, got;
      cv::matchTemplate(image, templ, expected, cv::TM_CCOEFF_NORMED);
      bd::row_template_correlation(image, templ, got);
      ASSERT_EQ(got.size(), expected.size());
      EXPECT_NEAR(got.at<float>(0, 0), 1.0f, 1e-5);  // the template's own place
      double worst = 0.0;
      for (int r = 0; r < got.rows; ++r)
        for (int c = 0; c < got.cols; ++c)
          worst = std::max(worst, double{std::abs(got.at<float>(r, c) - expected.at<float>(r, c))});
      EXPECT_LT(worst, 1e-4) << "type " << type << " width " << strip.width;
    }
  }
}
