#include "simulator/core/renderer.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "simulator/core/ground_truth.hpp"

namespace stereoball::simulator {
namespace {

// A plain grey room with a uniformly lit red ball: the ball is the only red thing.
Scenario plain_scene(double bx, double by) {
  Scenario s;
  s.room.plain = true;
  s.room.floor_a = {120, 120, 120};
  s.room.wall = {140, 140, 140};
  s.room.ceiling = {160, 160, 160};
  s.ball = BallSpec{};
  s.ball->x_m = bx, s.ball->y_m = by;
  s.ball->color_a = {220, 30, 30};
  s.ball->color_b = {220, 30, 30};
  s.lighting = {{0.0, 1.0, 0.0, 1.0}};
  return s;
}

BallState ball_at(const Scenario& s) {
  BallState b;
  b.present = true;
  b.radius_m = s.ball->radius_m;
  b.position_m = {s.ball->x_m, s.ball->y_m, s.ball->radius_m};
  return b;
}

cv::Mat rectify(const cv::Mat& raw, const stereo::StereoCalibration& c, bool left) {
  cv::Mat m1, m2, out;
  cv::initUndistortRectifyMap(left ? c.k1 : c.k2, left ? c.d1 : c.d2, left ? c.r1 : c.r2,
                              left ? c.p1 : c.p2, c.image_size, CV_32FC1, m1, m2);
  cv::remap(raw, out, m1, m2, cv::INTER_LINEAR);
  return out;
}

// Centroid of red pixels (the ball mask).
std::optional<cv::Point2d> red_centroid(const cv::Mat& bgr) {
  double sx = 0, sy = 0, n = 0;
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      if (p[2] > 2 * p[1] + 20) sx += x, sy += y, n += 1;
    }
  }
  if (n < 10) return std::nullopt;
  return cv::Point2d(sx / n, sy / n);
}

// Centre of the ellipse a sphere projects to in a pinhole image: the sphere's centre
// projection pushed outward by perspective (exact for the rectified camera).
cv::Point2d ellipse_centre(const Vec3d& c, double r, const cv::Matx34d& p) {
  const double f = p(0, 0), cx = p(0, 2), cy = p(1, 2);
  const double d = c.norm(), lateral = std::hypot(c.x, c.y);
  if (lateral < 1e-9) return {cx, cy};
  const double alpha = std::atan2(lateral, c.z), rho = std::asin(r / d);
  const double rc = 0.5 * f * (std::tan(alpha + rho) + std::tan(alpha - rho));
  return {cx + c.x / lateral * rc, cy + c.y / lateral * rc};
}

struct Placement {
  double x_m, y_m;
};

class BallProjection : public ::testing::TestWithParam<Placement> {};

TEST_P(BallProjection, RenderedBallCentreMatchesGroundTruthWithinHalfPixel) {
  // Given a ball against a plain background in front of the default rig
  const SimParams params;
  const StereoRig rig(params);
  const Scenario s = plain_scene(GetParam().x_m, GetParam().y_m);
  Renderer r(rig, s, 1.0, 1.0);
  const RobotState robot;
  const BallState ball = ball_at(s);
  const GroundTruth g = make_ground_truth(rig, robot, ball, 0, 0);
  ASSERT_TRUE(g.ball_visible_left && g.ball_visible_right);
  // When both eyes are rendered, rectified with the true calibration and the ball masked
  cv::Mat left, right;
  r.render(Eye::kLeft, robot, ball, s.lighting[0], left);
  r.render(Eye::kRight, robot, ball, s.lighting[0], right);
  const auto cl = red_centroid(rectify(left, rig.calibration(), true));
  const auto cr = red_centroid(rectify(right, rig.calibration(), false));
  ASSERT_TRUE(cl && cr);
  // Then the mask centres match the ground truth within 0.5 px (after the exact perspective
  // offset between a sphere's centre and its image ellipse's centre)
  const auto& c = rig.calibration();
  const cv::Point2d el = ellipse_centre(g.ball_camera_m, ball.radius_m, c.p1);
  const Vec3d in_right = g.ball_camera_m - Vec3d{-c.p2(0, 3) / c.p2(0, 0), 0, 0};
  cv::Point2d er = ellipse_centre(in_right, ball.radius_m, c.p1);
  er.x += c.p2(0, 2) - c.p1(0, 2);
  EXPECT_NEAR(cl->x, el.x, 0.5);
  EXPECT_NEAR(cl->y, el.y, 0.5);
  EXPECT_NEAR(cr->x, er.x, 0.5);
  EXPECT_NEAR(cr->y, er.y, 0.5);
  // And the ground-truth centre projection is off by no more than that perspective offset
  const double offset = std::hypot(el.x - g.ball_left_px.x, el.y - g.ball_left_px.y);
  EXPECT_LT(offset, 2.0);
  EXPECT_LE(std::hypot(cl->x - g.ball_left_px.x, cl->y - g.ball_left_px.y), offset + 0.5);
  EXPECT_NEAR(cl->y, cr->y, 0.5);  // same rectified row in both eyes
}

INSTANTIATE_TEST_SUITE_P(Placements, BallProjection,
                         ::testing::Values(Placement{1.5, 0.0}, Placement{2.0, 0.4},
                                           Placement{1.2, -0.3}, Placement{3.0, 0.6},
                                           Placement{0.9, 0.1}));

TEST(Renderer, NearAxisBallCentreMatchesGroundTruthProjectionDirectly) {
  // Given a ball placed on the left camera's rectified optical axis height-wise and laterally
  const SimParams params;
  const StereoRig rig(params);
  Scenario s = plain_scene(2.0, 0.06);
  Renderer r(rig, s, 1.0, 1.0);
  const RobotState robot;
  const BallState ball = ball_at(s);
  const GroundTruth g = make_ground_truth(rig, robot, ball, 0, 0);
  cv::Mat left;
  r.render(Eye::kLeft, robot, ball, s.lighting[0], left);
  const auto cl = red_centroid(rectify(left, rig.calibration(), true));
  ASSERT_TRUE(cl);
  // Then the mask centre equals the ground-truth projection within 0.5 px
  EXPECT_NEAR(cl->x, g.ball_left_px.x, 0.5);
  EXPECT_NEAR(cl->y, g.ball_left_px.y, 0.5);
}

TEST(Renderer, BallOnTheLeftOfTheRobotAppearsInTheLeftHalf) {
  // Given a ball 2 m ahead and 0.6 m to the robot's left (+y)
  const SimParams params;
  const StereoRig rig(params);
  const Scenario s = plain_scene(2.0, 0.6);
  Renderer r(rig, s, 1.0, 1.0);
  cv::Mat left;
  r.render(Eye::kLeft, RobotState{}, ball_at(s), s.lighting[0], left);
  const auto c = red_centroid(left);
  // Then it is in the left half of the image, below the horizon (the rig looks down)
  ASSERT_TRUE(c);
  EXPECT_LT(c->x, params.width_px / 2.0 - 50);
}

TEST(Renderer, BallCastsAShadowOnTheFloor) {
  // Given a lit scene with the light from the robot's left so the shadow falls to the right
  const SimParams params;
  const StereoRig rig(params);
  Scenario s = plain_scene(1.5, 0.0);
  s.sun_azimuth_rad = M_PI / 2;  // light comes from +y
  s.sun_elevation_rad = 0.5;
  s.lighting = {{0.0, 0.3, 0.9, 1.0}};
  Renderer r(rig, s, 1.0, 1.0);
  const BallState ball = ball_at(s);
  cv::Mat img;
  r.render(Eye::kLeft, RobotState{}, ball, s.lighting[0], img);
  // When we look at the floor point straight down-light from the ball centre
  const Vec3d sun{0.0, std::cos(0.5), std::sin(0.5)};
  const Vec3d shadow = ball.position_m - sun * (ball.position_m.z / sun.z);
  const Vec3d lit = shadow + Vec3d{0.0, -0.5, 0.0};
  auto pixel = [&](const Vec3d& w) {
    const Point2 p =
        project_raw(rig.intrinsics(Eye::kLeft), world_to_camera(rig, Eye::kLeft, RobotState{}, w));
    return img.at<cv::Vec3b>(static_cast<int>(std::lround(p.y)),
                             static_cast<int>(std::lround(p.x)));
  };
  // Then that point is darker than open floor beside it (ambient only there)
  const cv::Vec3b in = pixel(shadow);
  const cv::Vec3b out = pixel(lit);
  EXPECT_LT(in[1] + 20, out[1]);
}

TEST(Renderer, BoxHidesTheBallBehindIt) {
  // Given a tall box between the robot and the ball
  const SimParams params;
  const StereoRig rig(params);
  Scenario s = plain_scene(3.0, 0.0);
  s.boxes.push_back({1.5, 0.0, 0.5, 0.8, 0.6, 0.0, {40, 40, 200}});
  Renderer r(rig, s, 1.0, 1.0);
  cv::Mat img;
  r.render(Eye::kLeft, RobotState{}, ball_at(s), s.lighting[0], img);
  // Then no red ball pixels are visible, and the ground truth says the ball is hidden
  EXPECT_FALSE(red_centroid(img).has_value());
  const GroundTruth g = make_ground_truth(rig, RobotState{}, ball_at(s), 0, 0, occluders_of(s));
  EXPECT_FALSE(g.ball_visible_left);
  EXPECT_FALSE(g.ball_visible_right);
  // While without the occluders it would project inside both images
  EXPECT_TRUE(make_ground_truth(rig, RobotState{}, ball_at(s), 0, 0).ball_visible_left);
}

}  // namespace
}  // namespace stereoball::simulator

namespace stereoball::simulator {
namespace {

// Pixels of the left image (raw) inside radius_px of the ball's projected centre that are
// closer to colour a than to colour b, and the other way round.
std::pair<int, int> ball_colour_counts(const cv::Mat& img, const cv::Point2d& c, double radius_px,
                                       const Rgb& a, const Rgb& b) {
  int na = 0, nb = 0;
  auto dist = [](const cv::Vec3b& p, const Rgb& q) {
    // Hue direction only: shading scales all three channels.
    const cv::Vec3d v(p[2], p[1], p[0]), w(q.r, q.g, q.b);
    return 1.0 - v.dot(w) / (cv::norm(v) * cv::norm(w) + 1e-9);
  };
  for (int y = static_cast<int>(c.y - radius_px); y <= c.y + radius_px; ++y)
    for (int x = static_cast<int>(c.x - radius_px); x <= c.x + radius_px; ++x) {
      if (x < 0 || y < 0 || x >= img.cols || y >= img.rows) continue;
      if (std::hypot(x - c.x, y - c.y) > radius_px) continue;
      const cv::Vec3b p = img.at<cv::Vec3b>(y, x);
      (dist(p, a) < dist(p, b) ? na : nb)++;
    }
  return {na, nb};
}

class BallPatterns : public ::testing::TestWithParam<BallPattern> {};

TEST_P(BallPatterns, OneColourBallShowsOnlyColourA_TwoColourPatternsShowBoth) {
  // Given a red/blue ball of the pattern, 1.5 m ahead of the rig, lit evenly
  const SimParams params;
  const StereoRig rig(params);
  Scenario s = plain_scene(1.5, 0.0);
  s.ball->color_a = {220, 30, 30};
  s.ball->color_b = {30, 30, 220};
  s.ball->pattern = GetParam();
  Renderer r(rig, s, 1.0, 1.0);
  const BallState ball = ball_at(s);
  const GroundTruth g = make_ground_truth(rig, RobotState{}, ball, 0, 0);
  cv::Mat left;
  r.render(Eye::kLeft, RobotState{}, ball, s.lighting[0], left);
  const cv::Mat rect = rectify(left, rig.calibration(), true);
  const double radius_px = 0.8 * rig.calibration().p1(0, 0) * ball.radius_m / g.ball_camera_m.z;
  const auto [na, nb] = ball_colour_counts(rect, {g.ball_left_px.x, g.ball_left_px.y}, radius_px,
                                           s.ball->color_a, s.ball->color_b);
  // Then a solid ball has no second colour, the others show both in a good share
  if (GetParam() == BallPattern::kSolid) {
    EXPECT_EQ(nb, 0);
    EXPECT_GT(na, 500);
  } else {
    EXPECT_GT(na, (na + nb) / 5) << na << " / " << nb;
    EXPECT_GT(nb, (na + nb) / 10) << na << " / " << nb;
  }
}

INSTANTIATE_TEST_SUITE_P(All, BallPatterns,
                         ::testing::Values(BallPattern::kSolid, BallPattern::kPanels,
                                           BallPattern::kStripes, BallPattern::kFootball));

// Standard deviation of the grey level in the rectified left image's lower middle (floor).
double floor_texture(const Scenario& s) {
  const SimParams params;
  const StereoRig rig(params);
  Renderer r(rig, s, 1.0, 1.0);
  cv::Mat left, grey;
  r.render(Eye::kLeft, RobotState{}, BallState{}, s.lighting[0], left);
  cv::cvtColor(left(cv::Rect(200, 380, 240, 90)), grey, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, sd;
  cv::meanStdDev(grey, mean, sd);
  return sd[0];
}

TEST(Renderer, FloorPatternsAreTexturedAndPlainIsNot) {
  // Given the same two floor colours with each pattern
  Scenario s = plain_scene(1.5, 0.0);
  s.ball.reset();
  s.room.plain = false;
  s.room.floor_a = {150, 120, 90};
  s.room.floor_b = {90, 70, 50};
  s.room.tile_m = 0.6;
  const double plain = [&] {
    Scenario p = s;
    p.room.plain = true;
    return floor_texture(p);
  }();
  EXPECT_LT(plain, 2.0);
  // Then each pattern varies the floor's grey level
  for (FloorPattern f : {FloorPattern::kTiles, FloorPattern::kPlanks, FloorPattern::kCarpet}) {
    s.room.floor_pattern = f;
    EXPECT_GT(floor_texture(s), 5.0) << static_cast<int>(f);
  }
}

TEST(Renderer, DistractorSphereIsDrawnInItsColourAndHidesTheWall) {
  // Given a blue sphere 2 m ahead on the floor and no ball
  const SimParams params;
  const StereoRig rig(params);
  Scenario s = plain_scene(1.5, 0.0);
  s.ball.reset();
  s.spheres.push_back({{2.0, 0.0, 0.12}, 0.12, {30, 40, 220}});
  ASSERT_TRUE(s.validate().ok());
  Renderer r(rig, s, 1.0, 1.0);
  cv::Mat left;
  r.render(Eye::kLeft, RobotState{}, BallState{}, s.lighting[0], left);
  // Then its projected centre is blue
  BallState at;
  at.present = true;
  at.radius_m = 0.12;
  at.position_m = {2.0, 0.0, 0.12};
  const GroundTruth g = make_ground_truth(rig, RobotState{}, at, 0, 0);
  const cv::Vec3b p =
      rectify(left, rig.calibration(), true)
          .at<cv::Vec3b>(static_cast<int>(g.ball_left_px.y), static_cast<int>(g.ball_left_px.x));
  EXPECT_GT(p[0], 2 * p[2]) << p;
}

// A ball of 0.11 m radius on the floor 2 m straight ahead of the robot at the origin.
BallState ball_2m_ahead() {
  BallState ball;
  ball.present = true;
  ball.radius_m = 0.11;
  ball.position_m = {2.0, 0.0, 0.11};
  return ball;
}

TEST(GroundTruth, FullyVisibleOnlyWhenTheWholeBallIsInViewAndUnblocked) {
  const SimParams params;
  const StereoRig rig(params);
  // A ball 2 m ahead is fully visible
  BallState ball = ball_2m_ahead();
  GroundTruth g = make_ground_truth(rig, RobotState{}, ball, 0, 0);
  EXPECT_TRUE(g.ball_fully_visible_left && g.ball_fully_visible_right);
  // Its centre in view but its outline across the left border: visible, not fully
  ball.position_m = {1.0, 0.0, 0.11};
  for (double y = 0.3; y < 1.0; y += 0.01) {
    ball.position_m.y = y;
    g = make_ground_truth(rig, RobotState{}, ball, 0, 0);
    if (g.ball_left_px.x < 0.5 * 0.11 * rig.calibration().p1(0, 0)) break;
  }
  EXPECT_TRUE(g.ball_visible_left);
  EXPECT_FALSE(g.ball_fully_visible_left);
  // A box hiding part of the ball (not its centre): visible, not fully
  ball.position_m = {2.0, 0.0, 0.11};
  const std::vector<SolidBox> half{{{1.0, 0.06, 0.0}, {1.1, 0.5, 0.5}, {}}};
  g = make_ground_truth(rig, RobotState{}, ball, 0, 0, {half, {}});
  EXPECT_TRUE(g.ball_visible_left);
  EXPECT_FALSE(g.ball_fully_visible_left);
}

TEST(GroundTruth, AnotherBallInFrontHidesPartOfTheBallAndOneBehindItHidesNothing) {
  const SimParams params;
  const StereoRig rig(params);
  const BallState ball = ball_2m_ahead();
  const Vec3d eye = rig.pose(Eye::kLeft).position_m;  // robot at the origin: world = robot frame
  // Given a small sphere halfway along the left eye's line of sight to the ball's left rim
  SphereSpec in_front;
  in_front.center_m = eye + (ball.position_m + Vec3d{0.0, ball.radius_m, 0.0} - eye) * 0.5;
  in_front.radius_m = 0.03;
  GroundTruth g = make_ground_truth(rig, RobotState{}, ball, 0, 0, {{}, {in_front}});
  // Then the ball's centre is in view but not the whole ball
  EXPECT_TRUE(g.ball_visible_left);
  EXPECT_FALSE(g.ball_fully_visible_left);
  // Given a large sphere just behind the ball instead, the whole ball is in view
  SphereSpec behind;
  behind.center_m = ball.position_m + (ball.position_m - eye).normalized() * 0.3;
  behind.radius_m = 0.15;
  g = make_ground_truth(rig, RobotState{}, ball, 0, 0, {{}, {behind}});
  EXPECT_TRUE(g.ball_fully_visible_left && g.ball_fully_visible_right);
  // And a sphere on the line of sight to the centre hides the ball
  SphereSpec on_axis;
  on_axis.center_m = eye + (ball.position_m - eye) * 0.5;
  on_axis.radius_m = 0.05;
  g = make_ground_truth(rig, RobotState{}, ball, 0, 0, {{}, {on_axis}});
  EXPECT_FALSE(g.ball_visible_left);
}

}  // namespace
}  // namespace stereoball::simulator
