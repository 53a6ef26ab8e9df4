#include "stereo/core/pair_error.hpp"

#include "stereo/core/rectifier.hpp"

#include <opencv2/calib3d.hpp>

#include <cmath>

namespace stereoball::stereo {
namespace {

// Residuals of both eyes for a board pose (rvec, tvec) in the left camera: 4 per corner.
class JointPoseResiduals : public cv::LMSolver::Callback {
 public:
  JointPoseResiduals(const StereoCalibration& calib, const std::vector<cv::Point3f>& board_m,
                     const std::vector<cv::Point2f>& left_px,
                     const std::vector<cv::Point2f>& right_px)
      : calib_(calib), board_(board_m), left_(left_px), right_(right_px) {}

  bool compute(cv::InputArray param, cv::OutputArray err, cv::OutputArray jac) const override {
    const cv::Mat p = param.getMat();
    cv::Mat e = residuals(p);
    if (jac.needed()) {
      // Central differences: 6 parameters, two small projections each; cheap and exact enough.
      jac.create(e.rows, 6, CV_64F);
      cv::Mat j = jac.getMat();
      for (int k = 0; k < 6; ++k) {
        cv::Mat plus = p.clone(), minus = p.clone();
        const double h = k < 3 ? 1e-7 : 1e-7 * (1.0 + std::abs(p.at<double>(5)));
        plus.at<double>(k) += h;
        minus.at<double>(k) -= h;
        const cv::Mat d = (residuals(plus) - residuals(minus)) / (2.0 * h);
        d.copyTo(j.col(k));
      }
    }
    e.copyTo(err);
    return true;
  }

  // Projected minus observed corners, left then right, as one column of 4n values.
  cv::Mat residuals(const cv::Mat& p) const {
    const cv::Vec3d rvec(p.at<double>(0), p.at<double>(1), p.at<double>(2));
    const cv::Vec3d tvec(p.at<double>(3), p.at<double>(4), p.at<double>(5));
    cv::Vec3d rvec_r, tvec_r;
    cv::composeRT(rvec, tvec, rodrigues(calib_.r), cv::Vec3d(calib_.t), rvec_r, tvec_r);
    std::vector<cv::Point2f> pl, pr;  // float like the board points (projectPoints keeps the depth)
    cv::projectPoints(board_, rvec, tvec, cv::Mat(calib_.k1), cv::Mat(calib_.d1, true), pl);
    cv::projectPoints(board_, rvec_r, tvec_r, cv::Mat(calib_.k2), cv::Mat(calib_.d2, true), pr);
    cv::Mat e(static_cast<int>(4 * board_.size()), 1, CV_64F);
    for (std::size_t i = 0; i < board_.size(); ++i) {
      e.at<double>(static_cast<int>(2 * i)) = pl[i].x - left_[i].x;
      e.at<double>(static_cast<int>(2 * i + 1)) = pl[i].y - left_[i].y;
      const int o = static_cast<int>(2 * (board_.size() + i));
      e.at<double>(o) = pr[i].x - right_[i].x;
      e.at<double>(o + 1) = pr[i].y - right_[i].y;
    }
    return e;
  }

 private:
  static cv::Vec3d rodrigues(const cv::Matx33d& r) {
    cv::Vec3d v;
    cv::Rodrigues(r, v);
    return v;
  }
  const StereoCalibration& calib_;
  const std::vector<cv::Point3f>& board_;
  const std::vector<cv::Point2f>& left_;
  const std::vector<cv::Point2f>& right_;
};

double rms_of(const cv::Mat& e, int begin, int end) {
  double sum = 0.0;
  for (int i = begin; i < end; ++i) sum += e.at<double>(i) * e.at<double>(i);
  // Two residuals (x, y) per corner; RMS per corner, as OpenCV reports it.
  return end > begin ? std::sqrt(sum / (0.5 * (end - begin))) : 0.0;
}

double mean_row_error(const StereoCalibration& calib, const std::vector<cv::Point2f>& left_px,
                      const std::vector<cv::Point2f>& right_px) {
  auto rectifier = Rectifier::create(calib);
  if (!rectifier || left_px.empty()) return 0.0;
  const auto l = rectifier->rectify_points(
      Eye::kLeft, std::vector<cv::Point2d>(left_px.begin(), left_px.end()));
  const auto r = rectifier->rectify_points(
      Eye::kRight, std::vector<cv::Point2d>(right_px.begin(), right_px.end()));
  double sum = 0.0;
  for (std::size_t i = 0; i < l.size(); ++i) sum += std::abs(l[i].y - r[i].y);
  return sum / static_cast<double>(l.size());
}

}  // namespace

PairError stereo_pair_error(const StereoCalibration& calib, const std::vector<cv::Point3f>& board_m,
                            const std::vector<cv::Point2f>& left_px,
                            const std::vector<cv::Point2f>& right_px) {
  PairError out;
  if (board_m.size() < 4 || left_px.size() != board_m.size() || right_px.size() != board_m.size())
    return out;
  // The left eye alone gives the start; the joint fit then moves it to suit both eyes.
  cv::Vec3d rvec, tvec;
  cv::solvePnP(board_m, left_px, cv::Mat(calib.k1), cv::Mat(calib.d1, true), rvec, tvec);
  cv::Mat p = (cv::Mat_<double>(6, 1) << rvec[0], rvec[1], rvec[2], tvec[0], tvec[1], tvec[2]);
  const auto residuals = cv::makePtr<JointPoseResiduals>(calib, board_m, left_px, right_px);
  cv::LMSolver::create(residuals, 100)->run(p);
  const cv::Mat e = residuals->residuals(p);
  const int half = e.rows / 2;
  out.rms_px = rms_of(e, 0, e.rows);
  out.left_rms_px = rms_of(e, 0, half);
  out.right_rms_px = rms_of(e, half, e.rows);
  out.mean_row_error_px = mean_row_error(calib, left_px, right_px);
  return out;
}

}  // namespace stereoball::stereo
