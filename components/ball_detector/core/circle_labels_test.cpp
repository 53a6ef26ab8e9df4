// Label files of real photographs: the format, and malformed lines named by file and line.

#include "ball_detector/core/circle_labels.hpp"

#include <gtest/gtest.h>

#include <string>

namespace stereoball::ball_detector {
namespace {

std::string error_of(const std::string& text) {
  const auto r = parse_circle_labels(text, "a.circles");
  const auto* e = std::get_if<std::string>(&r);
  return e ? *e : std::string("(parsed)");
}

TEST(CircleLabels, GivenAWellFormedFileThenImageSplitAndCirclesAreRead) {
  const auto r = parse_circle_labels(
      "# labels\nimage ../shared/x.png\n\nsplit report\ncircle 10.5 20 3.25  # coin\n"
      "circle 1 2 3\n",
      "a.circles");
  const auto* l = std::get_if<CircleLabels>(&r);
  ASSERT_NE(l, nullptr) << std::get<std::string>(r);
  EXPECT_EQ(l->image_path, "../shared/x.png");
  EXPECT_EQ(l->split, LabelSplit::report);
  ASSERT_EQ(l->circles.size(), 2u);
  EXPECT_DOUBLE_EQ(l->circles[0].x_px, 10.5);
  EXPECT_DOUBLE_EQ(l->circles[0].y_px, 20.0);
  EXPECT_DOUBLE_EQ(l->circles[0].radius_px, 3.25);
  EXPECT_DOUBLE_EQ(l->circles[1].radius_px, 3.0);
  EXPECT_FALSE(l->min_radius_px.has_value());
}

TEST(CircleLabels, GivenAMinRadiusLineThenItIsReadAndAMalformedOneIsNamed) {
  // Given a file stating the radius down to which every circle was labelled
  const auto r = parse_circle_labels("image x.png\nsplit tune\nmin_radius 6.5\n", "a.circles");
  // Then it is read
  const auto* l = std::get_if<CircleLabels>(&r);
  ASSERT_NE(l, nullptr) << std::get<std::string>(r);
  ASSERT_TRUE(l->min_radius_px.has_value());
  EXPECT_DOUBLE_EQ(*l->min_radius_px, 6.5);
  // And a malformed or repeated one is an error naming file and line
  const std::string head = "image x.png\nsplit tune\n";
  EXPECT_EQ(error_of(head + "min_radius 0\n").rfind("a.circles:3: ", 0), 0u);
  EXPECT_EQ(error_of(head + "min_radius\n").rfind("a.circles:3: ", 0), 0u);
  EXPECT_EQ(error_of(head + "min_radius 4 5\n").rfind("a.circles:3: ", 0), 0u);
  EXPECT_EQ(error_of(head + "min_radius 4\nmin_radius 5\n").rfind("a.circles:4: second", 0), 0u);
}

TEST(CircleLabels, GivenAMalformedLineThenTheErrorNamesFileAndLine) {
  const std::string head = "image x.png\nsplit tune\n";
  EXPECT_EQ(error_of(head + "circle 1 2\n").rfind("a.circles:3: ", 0), 0u);
  EXPECT_EQ(error_of(head + "\ncircle 1 2 x\n").rfind("a.circles:4: ", 0), 0u);
  EXPECT_EQ(error_of(head + "circle 1 2 -3\n").rfind("a.circles:3: ", 0), 0u);
  EXPECT_EQ(error_of(head + "circle 1 2 nan\n").rfind("a.circles:3: ", 0), 0u);
  EXPECT_EQ(error_of(head + "circle 1 2 3 4\n").rfind("a.circles:3: ", 0), 0u);
  EXPECT_EQ(error_of(head + "cirle 1 2 3\n").rfind("a.circles:3: unknown key 'cirle'", 0), 0u);
  EXPECT_EQ(error_of("image x.png\nsplit test\n").rfind("a.circles:2: ", 0), 0u);
  EXPECT_EQ(error_of(head + "image y.png\n").rfind("a.circles:3: second 'image'", 0), 0u);
}

TEST(CircleLabels, GivenAMissingImageOrSplitThenTheErrorSaysWhich) {
  EXPECT_EQ(error_of("split tune\ncircle 1 2 3\n"), "a.circles: no 'image' line");
  EXPECT_EQ(error_of("image x.png\n"), "a.circles: no 'split' line");
}

}  // namespace
}  // namespace stereoball::ball_detector
