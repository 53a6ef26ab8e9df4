#include "plot.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace stereoball::demo {
namespace {

struct Range {
  double lo = 1e300, hi = -1e300;
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  void finish() {
    if (lo > hi) lo = 0, hi = 1;
    if (hi - lo < 1e-9) lo -= 0.5, hi += 0.5;
    const double pad = 0.05 * (hi - lo);
    lo -= pad;
    hi += pad;
  }
};

double nice_step(double span) {
  const double raw = span / 6;
  const double mag = std::pow(10, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * mag >= raw) return m * mag;
  }
  return 10 * mag;
}

std::string label(double v) {
  if (v == 0) v = 0;  // no "-0" for a tick at -0.0
  char buf[32];
  std::snprintf(buf, sizeof buf, std::abs(v) < 10 ? "%.2g" : "%.0f", v);
  return buf;
}

}  // namespace

cv::Mat render(const Chart& chart, cv::Size size) {
  cv::Mat img(size, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 70, right = 20, top = 35, bottom = 45;
  const cv::Rect area(left, top, size.width - left - right, size.height - top - bottom);
  Range xr, yr;
  for (const auto& s : chart.series) {
    for (const auto& p : s.points) xr.add(p.x), yr.add(p.y);
  }
  for (const auto& m : chart.markers) xr.add(m.x);
  if (!chart.y_tick_names.empty()) yr.add(0), yr.add(chart.y_tick_names.size() - 1.0);
  xr.finish();
  yr.finish();
  if (chart.equal_aspect) {
    // Same metres per pixel on both axes: widen the tighter range around its centre.
    const double sx = (xr.hi - xr.lo) / area.width, sy = (yr.hi - yr.lo) / area.height;
    const double s = std::max(sx, sy);
    const double cx = (xr.lo + xr.hi) / 2, cy = (yr.lo + yr.hi) / 2;
    xr.lo = cx - s * area.width / 2, xr.hi = cx + s * area.width / 2;
    yr.lo = cy - s * area.height / 2, yr.hi = cy + s * area.height / 2;
  }
  auto to_px = [&](cv::Point2d p) {
    return cv::Point(
        static_cast<int>(area.x + (p.x - xr.lo) / (xr.hi - xr.lo) * area.width),
        static_cast<int>(area.y + area.height - (p.y - yr.lo) / (yr.hi - yr.lo) * area.height));
  };
  const auto grey = cv::Scalar(220, 220, 220), black = cv::Scalar(0, 0, 0);
  const double xs = nice_step(xr.hi - xr.lo);
  for (double x = std::ceil(xr.lo / xs) * xs; x <= xr.hi; x += xs) {
    const int px = to_px({x, yr.lo}).x;
    cv::line(img, {px, area.y}, {px, area.y + area.height}, grey, 1);
    cv::putText(img, label(x), {px - 10, area.y + area.height + 16}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
                black, 1, cv::LINE_AA);
  }
  if (chart.y_tick_names.empty()) {
    const double ys = nice_step(yr.hi - yr.lo);
    for (double y = std::ceil(yr.lo / ys) * ys; y <= yr.hi; y += ys) {
      const int py = to_px({xr.lo, y}).y;
      cv::line(img, {area.x, py}, {area.x + area.width, py}, grey, 1);
      cv::putText(img, label(y), {5, py + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
    }
  } else {
    for (size_t i = 0; i < chart.y_tick_names.size(); ++i) {
      const int py = to_px({xr.lo, static_cast<double>(i)}).y;
      cv::line(img, {area.x, py}, {area.x + area.width, py}, grey, 1);
      cv::putText(img, chart.y_tick_names[i], {3, py + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.35, black, 1,
                  cv::LINE_AA);
    }
  }
  cv::rectangle(img, area, black, 1);
  // Event lines (dashed) under the series, their labels above them.
  for (const auto& m : chart.markers) {
    const int px = to_px({m.x, yr.lo}).x;
    for (int y = area.y; y < area.y + area.height; y += 10)
      cv::line(img, {px, y}, {px, std::min(y + 6, area.y + area.height)}, m.colour, 2);
  }
  for (const auto& s : chart.series) {
    std::vector<cv::Point> pts;
    for (size_t i = 0; i < s.points.size(); ++i) {
      if (s.step && i > 0) pts.push_back(to_px({s.points[i].x, s.points[i - 1].y}));
      pts.push_back(to_px(s.points[i]));
    }
    if (s.dots) {
      for (const auto& p : pts) cv::circle(img, p, 6, s.colour, cv::FILLED);
      continue;
    }
    if (pts.size() == 1) cv::circle(img, pts[0], 4, s.colour, cv::FILLED);
    if (pts.size() > 1) cv::polylines(img, pts, false, s.colour, 2, cv::LINE_AA);
  }
  // Marker labels: each in the highest row where it overlaps no label placed before it.
  std::vector<std::vector<std::pair<int, int>>> rows;  // per row, the [x0, x1] spans taken
  for (const auto& m : chart.markers) {
    const int px = to_px({m.x, yr.lo}).x;
    const int width = cv::getTextSize(m.label, cv::FONT_HERSHEY_SIMPLEX, 0.4, 1, nullptr).width;
    // Right of the line, or left of it near the right edge.
    const int tx = px + 4 + width > area.x + area.width ? px - 4 - width : px + 4;
    size_t row = 0;
    for (; row < rows.size(); ++row) {
      bool free = true;
      for (const auto& [x0, x1] : rows[row]) free = free && (tx + width + 6 < x0 || tx > x1 + 6);
      if (free) break;
    }
    if (row == rows.size()) rows.emplace_back();
    rows[row].emplace_back(tx, tx + width);
    const int ty = area.y + 32 + 14 * static_cast<int>(row);
    cv::rectangle(img, {tx - 1, ty - 11}, {tx + width + 1, ty + 3}, cv::Scalar(255, 255, 255),
                  cv::FILLED);
    cv::putText(img, m.label, {tx, ty}, cv::FONT_HERSHEY_SIMPLEX, 0.4, m.colour, 1, cv::LINE_AA);
  }
  int lx = area.x + 10;
  for (const auto& s : chart.series) {
    cv::line(img, {lx, area.y + 12}, {lx + 20, area.y + 12}, s.colour, 3);
    cv::putText(img, s.label, {lx + 25, area.y + 16}, cv::FONT_HERSHEY_SIMPLEX, 0.45, black, 1,
                cv::LINE_AA);
    lx += 40 + static_cast<int>(s.label.size()) * 9;
  }
  cv::putText(img, chart.title, {left, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, black, 1, cv::LINE_AA);
  cv::putText(img, chart.x_label, {area.x + area.width / 2 - 30, size.height - 8},
              cv::FONT_HERSHEY_SIMPLEX, 0.45, black, 1, cv::LINE_AA);
  if (!chart.y_label.empty()) {
    cv::putText(img, chart.y_label, {left, area.y + area.height - 6}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
                cv::Scalar(90, 90, 90), 1, cv::LINE_AA);
  }
  return img;
}

cv::Mat render_stack(const std::vector<Chart>& charts, cv::Size each) {
  std::vector<cv::Mat> parts;
  for (const auto& c : charts) parts.push_back(render(c, each));
  cv::Mat out;
  cv::vconcat(parts, out);
  return out;
}

}  // namespace stereoball::demo
