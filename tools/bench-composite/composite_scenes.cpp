#include "composite_scenes.hpp"

#include "stereo/core/rectifier.hpp"
#include "stereo/core/sphere_outline.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <random>

namespace stereoball::composite {
namespace {

constexpr int kSamples = 4;  // per pixel side

// Nearest hit of the ray origin + s * dir (dir not normalised) on the sphere, or -1.
double hit(const cv::Vec3d& origin, const cv::Vec3d& dir, const cv::Vec3d& centre, double r) {
  const cv::Vec3d oc = origin - centre;
  const double a = dir.dot(dir), b = 2.0 * oc.dot(dir), c = oc.dot(oc) - r * r;
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return -1.0;
  return (-b - std::sqrt(disc)) / (2.0 * a);
}

// Draws the sphere seen from a camera at eye_x_m on the x axis (rectified frame) into image.
void draw(cv::Mat& image, const Background& bg, double eye_x_m, const Ball& ball) {
  const stereo::PinholeCamera cam{bg.focal_px, bg.principal_px};
  const cv::Vec3d centre = ball.centre_m - cv::Vec3d(eye_x_m, 0, 0);
  const auto outline = stereo::sphere_outline(cam, centre, ball.radius_m);
  if (!outline) return;
  const double reach = outline->semi_major_px + 2.0;
  const cv::Rect box = cv::Rect(static_cast<int>(outline->centre_px.x - reach),
                                static_cast<int>(outline->centre_px.y - reach),
                                static_cast<int>(2 * reach) + 2, static_cast<int>(2 * reach) + 2) &
                       cv::Rect(0, 0, image.cols, image.rows);
  const cv::Vec3d light = cv::normalize(cv::Vec3d(-0.4, -0.6, -0.7));
  for (int v = box.y; v < box.y + box.height; ++v) {
    for (int u = box.x; u < box.x + box.width; ++u) {
      double cover = 0.0;
      cv::Vec3d colour(0, 0, 0);
      for (int sy = 0; sy < kSamples; ++sy) {
        for (int sx = 0; sx < kSamples; ++sx) {
          const double x = u + (sx + 0.5) / kSamples - 0.5, y = v + (sy + 0.5) / kSamples - 0.5;
          const cv::Vec3d dir((x - cam.principal_px.x) / cam.focal_px,
                              (y - cam.principal_px.y) / cam.focal_px, 1.0);
          const double s = hit(cv::Vec3d(0, 0, 0), dir, centre, ball.radius_m);
          if (s <= 0.0) continue;
          const cv::Vec3d normal = (s * dir - centre) / ball.radius_m;
          const double shade = 0.35 + 0.65 * std::max(0.0, normal.dot(light));
          cover += 1.0;
          for (int c = 0; c < 3; ++c) colour[c] += std::min(255.0, shade * ball.bgr[c]);
        }
      }
      if (cover == 0.0) continue;
      const double a = cover / (kSamples * kSamples);
      cv::Vec3b& px = image.at<cv::Vec3b>(v, u);
      for (int c = 0; c < 3; ++c)
        px[c] = cv::saturate_cast<uchar>((1.0 - a) * px[c] + colour[c] / (kSamples * kSamples));
    }
  }
}

bool inside(const Background& bg, double eye_x_m, const cv::Vec3d& centre_m, double radius_m,
            double margin_px) {
  const stereo::PinholeCamera cam{bg.focal_px, bg.principal_px};
  const auto o = stereo::sphere_outline(cam, centre_m - cv::Vec3d(eye_x_m, 0, 0), radius_m);
  if (!o) return false;
  const double r = o->semi_major_px + margin_px;
  return o->centre_px.x - r >= 0 && o->centre_px.y - r >= 0 &&
         o->centre_px.x + r <= bg.left.cols - 1 && o->centre_px.y + r <= bg.left.rows - 1;
}

Result<cv::Mat> read_bgr(const std::string& path) {
  cv::Mat m = cv::imread(path, cv::IMREAD_COLOR);
  if (m.empty()) return Error{path + ": cannot read"};
  return m;
}

}  // namespace

stereo::StereoCalibration rectified_rig_calibration(const Background& bg) {
  const cv::Matx33d k(bg.focal_px, 0, bg.principal_px.x, 0, bg.focal_px, bg.principal_px.y, 0, 0,
                      1);
  stereo::StereoCalibration c;
  c.image_size = bg.left.size();
  c.k1 = c.k2 = k;
  c.r = c.r1 = c.r2 = cv::Matx33d::eye();
  c.t = cv::Vec3d(-bg.baseline_m, 0, 0);
  c.p1 = cv::Matx34d(bg.focal_px, 0, bg.principal_px.x, 0, 0, bg.focal_px, bg.principal_px.y, 0, 0,
                     0, 1, 0);
  c.p2 = c.p1;
  c.p2(0, 3) = -bg.focal_px * bg.baseline_m;
  c.q = cv::Matx44d(1, 0, 0, -bg.principal_px.x, 0, 1, 0, -bg.principal_px.y, 0, 0, 0, bg.focal_px,
                    0, 0, 1.0 / bg.baseline_m, 0);
  return c;
}

Result<std::vector<Background>> load_real_backgrounds(
    const std::string& data_dir, const stereo::StereoCalibration& calibration) {
  auto rectifier = stereo::Rectifier::create(calibration);
  if (!rectifier) return Error{rectifier.error()};
  std::vector<Background> out;
  for (int id : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14}) {
    const std::string n = (id < 10 ? "0" : "") + std::to_string(id) + ".jpg";
    auto l = read_bgr(data_dir + "/left" + n);
    if (!l) return Error{l.error()};
    auto r = read_bgr(data_dir + "/right" + n);
    if (!r) return Error{r.error()};
    Background bg;
    bg.name = "chessboard" + n.substr(0, 2);
    if (auto e = rectifier->rectify(*l, *r, bg.left, bg.right); !e) return Error{e.error()};
    bg.focal_px = stereo::focal_px(calibration);
    bg.principal_px = {calibration.p1(0, 2), calibration.p1(1, 2)};
    bg.baseline_m = stereo::baseline_m(calibration);
    out.push_back(std::move(bg));
  }
  auto l = read_bgr(data_dir + "/aloeL.jpg");
  if (!l) return Error{l.error()};
  auto r = read_bgr(data_dir + "/aloeR.jpg");
  if (!r) return Error{r.error()};
  Background aloe;
  aloe.name = "aloe";
  cv::resize(*l, aloe.left, {}, 0.5, 0.5, cv::INTER_AREA);
  cv::resize(*r, aloe.right, {}, 0.5, 0.5, cv::INTER_AREA);
  aloe.focal_px = 1870.0;
  aloe.principal_px = {0.5 * (aloe.left.cols - 1), 0.5 * (aloe.left.rows - 1)};
  aloe.baseline_m = 0.16;
  out.push_back(std::move(aloe));
  return out;
}

const std::vector<std::pair<std::string, cv::Scalar>>& ball_colours() {
  static const std::vector<std::pair<std::string, cv::Scalar>> colours = {
      {"orange", cv::Scalar(30, 120, 250)},
      {"tennis", cv::Scalar(60, 235, 205)},
      {"blue", cv::Scalar(200, 90, 30)},
      {"white", cv::Scalar(235, 235, 235)}};
  return colours;
}

std::pair<cv::Mat, cv::Mat> composite(const Background& background, const Ball& ball) {
  std::pair<cv::Mat, cv::Mat> out{background.left.clone(), background.right.clone()};
  draw(out.first, background, 0.0, ball);
  draw(out.second, background, background.baseline_m, ball);
  return out;
}

std::vector<Ball> place_balls(const Background& bg, int count, double radius_m, double min_depth_m,
                              double max_depth_m, unsigned seed, double margin_px) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> depth(min_depth_m, max_depth_m), unit(-1.0, 1.0);
  std::vector<Ball> out;
  for (int i = 0; i < count; ++i) {
    for (int attempt = 0; attempt < 200; ++attempt) {
      const double z = depth(rng);
      // Across the view of the left camera at that depth, both ways.
      const double half_w = 0.5 * bg.left.cols / bg.focal_px * z;
      const double half_h = 0.5 * bg.left.rows / bg.focal_px * z;
      const cv::Vec3d c(unit(rng) * half_w + 0.5 * bg.baseline_m, unit(rng) * half_h, z);
      if (!inside(bg, 0.0, c, radius_m, margin_px) ||
          !inside(bg, bg.baseline_m, c, radius_m, margin_px))
        continue;
      const auto& [name, bgr] = ball_colours()[out.size() % ball_colours().size()];
      out.push_back(Ball{c, radius_m, bgr, name});
      break;
    }
  }
  return out;
}

}  // namespace stereoball::composite
