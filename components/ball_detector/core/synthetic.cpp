#include "ball_detector/core/synthetic.hpp"

#include "common/util/enum_names.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace stereoball::ball_detector {
namespace {

double grey_of(const cv::Scalar& c) {
  return 0.114 * c[0] + 0.587 * c[1] + 0.299 * c[2];
}

// A colour whose grey level differs from background_grey by at least min_contrast, both at
// full brightness and darkened by shading (a ball's rim must stay visible).
cv::Scalar contrasting_colour(SceneRng& rng, double background_grey, double min_contrast,
                              double shading = 0.0) {
  for (int attempt = 0; attempt < 256; ++attempt) {
    const cv::Scalar c(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255));
    const double g = grey_of(c);
    if (std::abs(g - background_grey) >= min_contrast &&
        std::abs(g * (1.0 - shading) - background_grey) >= min_contrast)
      return c;
  }
  return background_grey > 128 ? cv::Scalar(20, 20, 20) : cv::Scalar(235, 235, 235);
}

void fill_background(cv::Mat& img, SceneRng& rng, cv::Scalar& base) {
  base = cv::Scalar(rng.uniform(60, 190), rng.uniform(60, 190), rng.uniform(60, 190));
  img.setTo(base);
}

void draw_clutter(cv::Mat& img, SceneRng& rng, int lines, int corners, int rects) {
  const int w = img.cols, h = img.rows;
  const int thick_max = std::max(1, std::min(w, h) / 150);
  for (int i = 0; i < rects; ++i) {
    const cv::Scalar c(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255));
    const int x = rng.integer(0, w - 1), y = rng.integer(0, h - 1);
    const int rw = rng.integer(w / 20, w / 4), rh = rng.integer(h / 20, h / 4);
    cv::rectangle(img, cv::Rect(x, y, rw, rh), c, cv::FILLED, cv::LINE_AA);
  }
  for (int i = 0; i < lines; ++i) {
    const cv::Scalar c(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255));
    cv::line(img, {rng.integer(0, w - 1), rng.integer(0, h - 1)},
             {rng.integer(0, w - 1), rng.integer(0, h - 1)}, c, rng.integer(1, thick_max),
             cv::LINE_AA);
  }
  for (int i = 0; i < corners; ++i) {
    const cv::Scalar c(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255));
    const cv::Point apex(rng.integer(w / 10, w - w / 10), rng.integer(h / 10, h - h / 10));
    const double a = rng.uniform(0, 2 * std::numbers::pi);
    const double open = rng.uniform(0.3, 2.2);
    const double len = rng.uniform(0.05, 0.25) * std::min(w, h);
    const cv::Point p1 =
        apex + cv::Point(static_cast<int>(len * std::cos(a)), static_cast<int>(len * std::sin(a)));
    const cv::Point p2 = apex + cv::Point(static_cast<int>(len * std::cos(a + open)),
                                          static_cast<int>(len * std::sin(a + open)));
    const int t = rng.integer(1, thick_max);
    cv::line(img, apex, p1, c, t, cv::LINE_AA);
    cv::line(img, apex, p2, c, t, cv::LINE_AA);
  }
}

BallSpec random_ball(SceneRng& rng, cv::Size size, double background_grey,
                     const std::vector<Circle>& avoid) {
  const double s = std::min(size.width, size.height);
  BallSpec b;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const double r = rng.uniform(0.035, 0.17) * s;
    b.circle = {rng.uniform(r + 2, size.width - r - 2), rng.uniform(r + 2, size.height - r - 2), r,
                1.0};
    const bool clear = std::none_of(avoid.begin(), avoid.end(), [&](const Circle& o) {
      return std::hypot(o.x_px - b.circle.x_px, o.y_px - b.circle.y_px) < o.radius_px + r + 6.0;
    });
    if (clear) break;
  }
  b.shading = rng.uniform(0.05, 0.3);
  b.colour = contrasting_colour(rng, background_grey, 50.0, b.shading);
  b.colour2 = contrasting_colour(rng, background_grey, 50.0, b.shading);
  b.seam_angle_rad = rng.uniform(0, 2 * std::numbers::pi);
  return b;
}

void apply_lighting(cv::Mat& img, SceneRng& rng) {
  const double gx = rng.uniform(-0.45, 0.45), gy = rng.uniform(-0.45, 0.45);
  for (int y = 0; y < img.rows; ++y) {
    auto* p = img.ptr<cv::Vec3b>(y);
    for (int x = 0; x < img.cols; ++x) {
      const double f = 1.0 + gx * (2.0 * x / img.cols - 1.0) + gy * (2.0 * y / img.rows - 1.0);
      for (int c = 0; c < 3; ++c) p[x][c] = cv::saturate_cast<uchar>(p[x][c] * f);
    }
  }
}

void add_noise(cv::Mat& img, SceneRng& rng, double sigma) {
  for (int y = 0; y < img.rows; ++y) {
    auto* p = img.ptr<cv::Vec3b>(y);
    for (int x = 0; x < img.cols; ++x)
      for (int c = 0; c < 3; ++c) p[x][c] = cv::saturate_cast<uchar>(p[x][c] + rng.normal(sigma));
  }
}

void occlude(cv::Mat& img, SceneRng& rng, const Circle& c) {
  // A box covering 20-35% of the diameter from a random side.
  const double cover = rng.uniform(0.2, 0.35) * 2.0 * c.radius_px;
  const int side = rng.integer(0, 3);
  const double r = c.radius_px;
  cv::Rect2d box;
  if (side == 0) box = {c.x_px - r - 30, c.y_px - r - 30, cover + 30, 2 * r + 60};
  if (side == 1) box = {c.x_px + r - cover, c.y_px - r - 30, cover + 30, 2 * r + 60};
  if (side == 2) box = {c.x_px - r - 30, c.y_px - r - 30, 2 * r + 60, cover + 30};
  if (side == 3) box = {c.x_px - r - 30, c.y_px + r - cover, 2 * r + 60, cover + 30};
  const cv::Scalar colour(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255));
  cv::rectangle(img, cv::Rect(box), colour, cv::FILLED);
}

}  // namespace

SceneRng::SceneRng(std::uint32_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 1) {}

std::uint32_t SceneRng::next() {
  // splitmix64: fully specified arithmetic, identical on every platform.
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return static_cast<std::uint32_t>((z ^ (z >> 31)) >> 32);
}

double SceneRng::uniform(double lo, double hi) {
  return lo + (hi - lo) * (next() / 4294967296.0);
}

double SceneRng::normal(double sigma) {
  const double u1 = (next() + 1.0) / 4294967297.0;
  const double u2 = next() / 4294967296.0;
  return sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

int SceneRng::integer(int lo, int hi) {
  if (hi <= lo) return lo;
  return lo + static_cast<int>(next() % static_cast<std::uint32_t>(hi - lo + 1));
}

void render_ball(cv::Mat& bgr, const BallSpec& ball) {
  const Circle& c = ball.circle;
  const int x0 = std::max(0, static_cast<int>(std::floor(c.x_px - c.radius_px - 1)));
  const int x1 = std::min(bgr.cols - 1, static_cast<int>(std::ceil(c.x_px + c.radius_px + 1)));
  const int y0 = std::max(0, static_cast<int>(std::floor(c.y_px - c.radius_px - 1)));
  const int y1 = std::min(bgr.rows - 1, static_cast<int>(std::ceil(c.y_px + c.radius_px + 1)));
  const double r2 = c.radius_px * c.radius_px;
  const double ca = std::cos(ball.seam_angle_rad), sa = std::sin(ball.seam_angle_rad);
  constexpr int kSub = 4;
  for (int y = y0; y <= y1; ++y) {
    auto* row = bgr.ptr<cv::Vec3b>(y);
    for (int x = x0; x <= x1; ++x) {
      cv::Vec3d acc(0, 0, 0);
      int inside = 0;
      for (int sy = 0; sy < kSub; ++sy)
        for (int sx = 0; sx < kSub; ++sx) {
          // Pixel (x, y) covers [x - 0.5, x + 0.5): centres on integers, as in OpenCV.
          const double dx = x - 0.5 + (sx + 0.5) / kSub - c.x_px;
          const double dy = y - 0.5 + (sy + 0.5) / kSub - c.y_px;
          const double d2 = dx * dx + dy * dy;
          if (d2 > r2) continue;
          ++inside;
          const double u = dx * ca + dy * sa, v = -dx * sa + dy * ca;
          const bool second =
              ball.two_colour && u > 0.35 * c.radius_px * std::sin(2.5 * v / c.radius_px);
          const cv::Scalar& col = second ? ball.colour2 : ball.colour;
          const double shade = 1.0 - ball.shading * d2 / r2;
          for (int ch = 0; ch < 3; ++ch) acc[ch] += col[ch] * shade;
        }
      if (inside == 0) continue;
      const double f = static_cast<double>(inside) / (kSub * kSub);
      for (int ch = 0; ch < 3; ++ch)
        row[x][ch] = cv::saturate_cast<uchar>(acc[ch] / (kSub * kSub) + (1.0 - f) * row[x][ch]);
    }
  }
}

namespace {

constexpr util::EnumName<SceneKind> kSceneKindNames[] = {
    {SceneKind::kPlain, "plain"},       {SceneKind::kTwoColour, "two-colour"},
    {SceneKind::kLighting, "lighting"}, {SceneKind::kNoise, "noise"},
    {SceneKind::kBlur, "blur"},         {SceneKind::kOcclusion, "occlusion"},
    {SceneKind::kClutter, "clutter"},   {SceneKind::kMultiple, "multiple"},
    {SceneKind::kNoBall, "no-ball"},    {SceneKind::kLinesOnly, "lines-only"}};

}  // namespace

std::string scene_kind_name(SceneKind kind) {
  return std::string(util::name_of(kSceneKindNames, kind, "?"));
}

SyntheticScene make_scene(SceneKind kind, cv::Size size, std::uint32_t seed) {
  SceneRng rng(seed * 131u + static_cast<std::uint32_t>(kind) * 7919u + size.width);
  SyntheticScene scene;
  scene.kind = kind;
  scene.image.create(size, CV_8UC3);
  cv::Scalar base;
  fill_background(scene.image, rng, base);
  const double bg = grey_of(base);
  const bool cluttered = kind == SceneKind::kClutter || kind == SceneKind::kNoBall;
  if (cluttered) draw_clutter(scene.image, rng, 4, 3, 4);
  if (kind == SceneKind::kLinesOnly) draw_clutter(scene.image, rng, 8, 6, 0);
  const bool has_ball = kind != SceneKind::kNoBall && kind != SceneKind::kLinesOnly;
  const int balls = kind == SceneKind::kMultiple ? rng.integer(2, 3) : (has_ball ? 1 : 0);
  for (int i = 0; i < balls; ++i) {
    BallSpec b = random_ball(rng, size, bg, scene.truth);
    b.two_colour = kind == SceneKind::kTwoColour || (kind == SceneKind::kClutter && i == 0) ||
                   (kind == SceneKind::kMultiple && i == 1);
    render_ball(scene.image, b);
    scene.truth.push_back(b.circle);
  }
  if (kind == SceneKind::kOcclusion) occlude(scene.image, rng, scene.truth.front());
  if (kind == SceneKind::kLighting) apply_lighting(scene.image, rng);
  if (kind == SceneKind::kBlur) {
    const double sigma = rng.uniform(1.2, 2.2) * std::min(size.width, size.height) / 288.0;
    cv::GaussianBlur(scene.image, scene.image, cv::Size(0, 0), sigma);
  }
  add_noise(scene.image, rng, kind == SceneKind::kNoise ? rng.uniform(8.0, 14.0) : 2.0);
  return scene;
}

std::vector<SyntheticScene> make_suite(cv::Size size, int per_kind, std::uint32_t seed) {
  std::vector<SyntheticScene> suite;
  for (int k = 0; k <= static_cast<int>(SceneKind::kLinesOnly); ++k)
    for (int i = 0; i < per_kind; ++i)
      suite.push_back(make_scene(static_cast<SceneKind>(k), size,
                                 seed + static_cast<std::uint32_t>(i) * 1000003u));
  return suite;
}

cv::Mat spotted_disc_image(cv::Size size, cv::Point centre_px, int radius_px, int spot_offset_px,
                           int spot_radius_px) {
  constexpr int kSub = 16;  // drawing shift of 4 bits
  cv::Mat img(size, CV_8UC3, cv::Scalar(120, 120, 120));
  cv::circle(img, centre_px * kSub, radius_px * kSub, cv::Scalar(30, 90, 230), cv::FILLED,
             cv::LINE_AA, 4);
  for (const double a : {-1.57, 0.5, 2.6}) {
    const cv::Point spot(static_cast<int>(kSub * (centre_px.x + spot_offset_px * std::cos(a))),
                         static_cast<int>(kSub * (centre_px.y + spot_offset_px * std::sin(a))));
    cv::circle(img, spot, spot_radius_px * kSub, cv::Scalar(250, 250, 250), cv::FILLED, cv::LINE_AA,
               4);
  }
  return img;
}

cv::Mat with_sensor_noise(const cv::Mat& img, int seed, double sigma) {
  cv::Mat noise(img.size(), CV_16SC3);
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
  cv::Mat noisy;
  cv::add(img, noise, noisy, cv::noArray(), CV_8UC3);
  return noisy;
}

}  // namespace stereoball::ball_detector
