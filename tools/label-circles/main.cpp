// stereoball-label-circles: helps label circles in real photographs to about 1 px.
//   refine IMAGE X Y R [X Y R ...]   snaps rough circles to the outline: along 720 rays from
//                                    the rough centre, the sub-pixel maximum of the radial
//                                    derivative (strongest colour channel, Gaussian sigma 1)
//                                    within +-max(3, 0.15 R) px of R; circle fit; points more
//                                    than 1.5 px off dropped (a shadow, a neighbour), refit.
//                                    Prints "circle x y r" plus the inlier share and RMS.
//   overlay LABELS OUT_DIR           draws a label file's circles on its image (whole image and
//                                    a 4x zoom of each circle) as PNG files to look at.
// Run from the project root (label files name images relative to it).

#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/circle_labels.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace bd = stereoball::ball_detector;
namespace fs = std::filesystem;

namespace {

// Per-channel float images smoothed with sigma 1.
std::vector<cv::Mat> smoothed_channels(const cv::Mat& image) {
  cv::Mat f;
  image.convertTo(f, CV_32F);
  cv::GaussianBlur(f, f, cv::Size(0, 0), 1.0);
  std::vector<cv::Mat> ch;
  cv::split(f, ch);
  return ch;
}

float sample(const cv::Mat& m, double x, double y) {
  cv::Mat patch;
  cv::getRectSubPix(m, cv::Size(1, 1), cv::Point2f(static_cast<float>(x), static_cast<float>(y)),
                    patch);
  return patch.at<float>(0, 0);
}

// Radial derivative magnitude (largest over channels) at distance d along direction (ux, uy).
double radial_strength(const std::vector<cv::Mat>& ch, double cx, double cy, double ux, double uy,
                       double d) {
  double best = 0.0;
  for (const auto& c : ch) {
    const double a = sample(c, cx + ux * (d + 0.5), cy + uy * (d + 0.5));
    const double b = sample(c, cx + ux * (d - 0.5), cy + uy * (d - 0.5));
    best = std::max(best, std::abs(a - b));
  }
  return best;
}

struct Refined {
  bd::Circle circle;
  double inlier_share = 0.0;
  double rms_px = 0.0;
};

std::vector<cv::Point2d> outline_points(const std::vector<cv::Mat>& ch, const bd::Circle& rough) {
  const double reach = std::max(3.0, 0.15 * rough.radius_px);
  std::vector<cv::Point2d> pts;
  for (int i = 0; i < 720; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 720.0;
    const double ux = std::cos(a), uy = std::sin(a);
    std::vector<double> s;
    for (double d = rough.radius_px - reach; d <= rough.radius_px + reach; d += 0.25)
      s.push_back(radial_strength(ch, rough.x_px, rough.y_px, ux, uy, d));
    size_t m = 1;
    for (size_t j = 1; j + 1 < s.size(); ++j)
      if (s[j] > s[m]) m = j;
    if (m == 0 || m + 1 >= s.size() || s[m] < 4.0) continue;  // no step of >= 4 levels
    const double den = s[m - 1] - 2.0 * s[m] + s[m + 1];
    const double off = den < 0.0 ? 0.5 * (s[m - 1] - s[m + 1]) / den : 0.0;
    const double d = rough.radius_px - reach + 0.25 * (static_cast<double>(m) + off);
    const double px = rough.x_px + ux * d, py = rough.y_px + uy * d;
    if (px < 1 || py < 1 || px > ch[0].cols - 2 || py > ch[0].rows - 2) continue;
    pts.emplace_back(px, py);
  }
  return pts;
}

std::optional<Refined> refine(const std::vector<cv::Mat>& ch, const bd::Circle& rough) {
  bd::Circle c = rough;
  std::vector<cv::Point2d> kept;
  size_t total = 0;
  for (int round = 0; round < 3; ++round) {
    const auto pts = outline_points(ch, c);
    total = pts.size();
    auto fit = bd::fit_circle(pts);
    if (!fit) return std::nullopt;
    kept.clear();
    for (const auto& p : pts)
      if (std::abs(std::hypot(p.x - fit->x_px, p.y - fit->y_px) - fit->radius_px) < 1.5)
        kept.push_back(p);
    fit = bd::fit_circle(kept);
    if (!fit) return std::nullopt;
    c = *fit;
  }
  double ss = 0.0;
  for (const auto& p : kept) {
    const double e = std::hypot(p.x - c.x_px, p.y - c.y_px) - c.radius_px;
    ss += e * e;
  }
  return Refined{c, total ? static_cast<double>(kept.size()) / 720.0 : 0.0,
                 kept.empty() ? 0.0 : std::sqrt(ss / kept.size())};
}

void draw(cv::Mat& img, const bd::Circle& c, int scale, const cv::Point2d& origin) {
  const double x = (c.x_px - origin.x + 0.5) * scale - 0.5,
               y = (c.y_px - origin.y + 0.5) * scale - 0.5;
  cv::circle(img, cv::Point(cvRound(x * 16), cvRound(y * 16)), cvRound(c.radius_px * scale * 16),
             cv::Scalar(0, 0, 255), 1, cv::LINE_AA, 4);
  cv::drawMarker(img, cv::Point(cvRound(x), cvRound(y)), cv::Scalar(0, 0, 255), cv::MARKER_CROSS,
                 2 * scale + 1);
}

int overlay(const std::string& label_path, const fs::path& out_dir) {
  std::ifstream in(label_path);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) {
    std::fprintf(stderr, "cannot read '%s'\n", label_path.c_str());
    return 1;
  }
  const auto parsed = bd::parse_circle_labels(text.str(), label_path);
  if (const auto* e = std::get_if<std::string>(&parsed)) {
    std::fprintf(stderr, "%s\n", e->c_str());
    return 1;
  }
  const auto& labels = std::get<bd::CircleLabels>(parsed);
  const cv::Mat image = cv::imread(labels.image_path, cv::IMREAD_COLOR);
  if (image.empty()) {
    std::fprintf(stderr, "cannot read image '%s'\n", labels.image_path.c_str());
    return 1;
  }
  fs::create_directories(out_dir);
  const std::string stem = fs::path(label_path).stem().string();
  cv::Mat whole = image.clone();
  for (size_t i = 0; i < labels.circles.size(); ++i) {
    draw(whole, labels.circles[i], 1, {0, 0});
    cv::putText(whole, std::to_string(i),
                cv::Point(cvRound(labels.circles[i].x_px), cvRound(labels.circles[i].y_px)),
                cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(255, 0, 255));
  }
  cv::imwrite((out_dir / (stem + ".png")).string(), whole);
  for (size_t i = 0; i < labels.circles.size(); ++i) {
    const auto& c = labels.circles[i];
    const int half = static_cast<int>(std::ceil(c.radius_px)) + 4;
    const int scale = std::max(1, std::min(4, 400 / (2 * half)));
    cv::Rect box(cvRound(c.x_px) - half, cvRound(c.y_px) - half, 2 * half + 1, 2 * half + 1);
    box &= cv::Rect(0, 0, image.cols, image.rows);
    cv::Mat zoom;
    cv::resize(image(box), zoom, cv::Size(), scale, scale, cv::INTER_NEAREST);
    draw(zoom, c, scale, {static_cast<double>(box.x), static_cast<double>(box.y)});
    cv::imwrite((out_dir / cv::format("%s_%02zu.png", stem.c_str(), i)).string(), zoom);
  }
  std::printf("%zu circles drawn in %s\n", labels.circles.size(), out_dir.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage =
      "usage: stereoball-label-circles refine IMAGE X Y R [X Y R ...]\n"
      "       stereoball-label-circles overlay LABELS OUT_DIR\n";
  if (argc >= 2 && std::string(argv[1]) == "overlay" && argc == 4) return overlay(argv[2], argv[3]);
  if (argc < 6 || std::string(argv[1]) != "refine" || (argc - 3) % 3 != 0) {
    std::fprintf(stderr, "%s", usage.c_str());
    return 2;
  }
  const cv::Mat image = cv::imread(argv[2], cv::IMREAD_COLOR);
  if (image.empty()) {
    std::fprintf(stderr, "cannot read image '%s'\n", argv[2]);
    return 1;
  }
  const auto ch = smoothed_channels(image);
  for (int i = 3; i + 2 < argc; i += 3) {
    const bd::Circle rough{std::atof(argv[i]), std::atof(argv[i + 1]), std::atof(argv[i + 2]), 1};
    const auto r = refine(ch, rough);
    if (!r) {
      std::printf("# %s %s %s: no outline found\n", argv[i], argv[i + 1], argv[i + 2]);
      continue;
    }
    std::printf("circle %.2f %.2f %.2f   # from %s %s %s; inliers %.0f%%, rms %.2f px\n",
                r->circle.x_px, r->circle.y_px, r->circle.radius_px, argv[i], argv[i + 1],
                argv[i + 2], 100.0 * r->inlier_share, r->rms_px);
  }
  return 0;
}
