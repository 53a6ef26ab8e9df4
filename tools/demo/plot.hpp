#pragma once
// Small line-chart renderer (OpenCV) for the demo's report PNGs.

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace stereoball::demo {

struct Series {
  std::string label;
  std::vector<cv::Point2d> points;
  cv::Scalar colour;
  bool step = false;  ///< draw as a step function (states)
  bool dots = false;  ///< draw each point as a dot, unconnected (events on a path)
};

/// A vertical line across the plot area at x, labelled near its top (an event on a time axis).
struct Marker {
  double x = 0;
  std::string label;
  cv::Scalar colour;
};

struct Chart {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  bool equal_aspect = false;              ///< for top views (metres on both axes)
  std::vector<std::string> y_tick_names;  ///< names for integer y ticks (states), optional
  std::vector<Marker> markers;            ///< vertical event lines, optional
};

/// Renders chart into an image of the given size.
cv::Mat render(const Chart& chart, cv::Size size);
/// Renders charts stacked vertically into one image.
cv::Mat render_stack(const std::vector<Chart>& charts, cv::Size each);

}  // namespace stereoball::demo
