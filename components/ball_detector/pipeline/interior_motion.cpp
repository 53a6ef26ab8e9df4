#include "ball_detector/pipeline/interior_motion.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>

namespace stereoball::ball_detector {

InteriorOffset interior_offset(const cv::Mat& left_image, const cv::Mat& right_image,
                               const Circle& left, const Circle& right, double dx_reach_px,
                               double dy_reach_px, const InteriorOffsetParams& params) {
  InteriorOffset out;
  if (left_image.type() != right_image.type() || !(left.radius_px > 0.0)) return out;
  // The inner square, as far as it is in view (a ball cut by the border keeps its upper part).
  const int half =
      std::max(2, static_cast<int>(std::lround(params.inner_fraction * left.radius_px)));
  const cv::Rect square(static_cast<int>(std::lround(left.x_px)) - half,
                        static_cast<int>(std::lround(left.y_px)) - half, 2 * half + 1,
                        2 * half + 1);
  const cv::Rect templ_box = square & cv::Rect(cv::Point(), left_image.size());
  if (templ_box.area() < square.area() / 2 || templ_box.width < 8 || templ_box.height < 8)
    return out;
  // The same square where the right circle puts it, grown by the reaches, as far as in view.
  const int shift_x = static_cast<int>(std::lround(left.x_px - right.x_px));
  const int shift_y = static_cast<int>(std::lround(left.y_px - right.y_px));
  const int rx = static_cast<int>(std::ceil(dx_reach_px));
  const int ry = static_cast<int>(std::ceil(dy_reach_px));
  const cv::Rect search_box = cv::Rect(templ_box.x - shift_x - rx, templ_box.y - shift_y - ry,
                                       templ_box.width + 2 * rx, templ_box.height + 2 * ry) &
                              cv::Rect(cv::Point(), right_image.size());
  if (search_box.width < templ_box.width || search_box.height < templ_box.height) return out;
  const cv::Mat templ = left_image(templ_box);
  cv::Scalar mean, stddev;
  cv::meanStdDev(templ, mean, stddev);
  double texture = 0.0;
  for (int c = 0; c < templ.channels(); ++c) texture = std::max(texture, stddev[c]);
  if (texture < params.min_texture) return out;
  cv::Mat result;
  cv::matchTemplate(right_image(search_box), templ, result, cv::TM_CCOEFF_NORMED);
  double best = 0.0;
  cv::Point at;
  cv::minMaxLoc(result, nullptr, &best, nullptr, &at);
  if (!(best >= params.min_match)) return out;
  // The peak to a fraction of a pixel: the parabola through it and its two neighbours, per axis.
  const auto vertex = [](float before, float peak, float after) {
    const double curve = static_cast<double>(before) - 2.0 * peak + after;
    return curve < 0.0 ? 0.5 * (before - after) / curve : 0.0;
  };
  const float* row = result.ptr<float>(at.y);
  const double fx =
      at.x > 0 && at.x + 1 < result.cols ? vertex(row[at.x - 1], row[at.x], row[at.x + 1]) : 0.0;
  const double fy =
      at.y > 0 && at.y + 1 < result.rows
          ? vertex(result.at<float>(at.y - 1, at.x), row[at.x], result.at<float>(at.y + 1, at.x))
          : 0.0;
  // The match's top-left corner in the right image, against the template's in the left.
  out.measured = true;
  out.match = best;
  out.dx_px = templ_box.x - (search_box.x + at.x + fx);
  out.dy_px = templ_box.y - (search_box.y + at.y + fy);
  return out;
}

}  // namespace stereoball::ball_detector
