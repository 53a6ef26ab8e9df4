#include "simulator/core/board_scene.hpp"

#include <algorithm>
#include <cmath>

#include "simulator/core/camera_model.hpp"
#include "simulator/core/range_check.hpp"
#include "simulator/core/sensor.hpp"

namespace stereoball::simulator {
namespace {

Mat3 rot_x(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3{{1, 0, 0, 0, c, -s, 0, s, c}};
}

Mat3 rot_y(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3{{c, 0, s, 0, 1, 0, -s, 0, c}};
}

// Left camera from board coordinates (x along rows, y down the columns, z into the board).
Mat3 cam_from_board(const BoardPose& p) {
  return Mat3::rot_z(p.roll_rad) * rot_y(p.tilt_y_rad) * rot_x(p.tilt_x_rad);
}

// The right eye's pose relative to the left: X_right = R X_left + T.
void right_from_left(const StereoRig& rig, Mat3& r, Vec3d& t) {
  const Mat3 rr_t = rig.pose(Eye::kRight).r_robot_from_cam.transposed();
  r = rr_t * rig.pose(Eye::kLeft).r_robot_from_cam;
  t = rr_t * (rig.pose(Eye::kLeft).position_m - rig.pose(Eye::kRight).position_m);
}

// Ease in and out: 0 -> 1 with zero speed at both ends.
double smooth(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

BoardPose mix(const BoardPose& a, const BoardPose& b, double s) {
  BoardPose p;
  p.centre_m = a.centre_m * (1.0 - s) + b.centre_m * s;
  p.tilt_x_rad = a.tilt_x_rad + (b.tilt_x_rad - a.tilt_x_rad) * s;
  p.tilt_y_rad = a.tilt_y_rad + (b.tilt_y_rad - a.tilt_y_rad) * s;
  p.roll_rad = a.roll_rad + (b.roll_rad - a.roll_rad) * s;
  return p;
}

// Box-filtered square wave (+1 / -1 alternating every unit of u) for a pixel footprint w units.
double filtered_wave(double u, double w) {
  const double f = std::floor(u);
  const double sign = (static_cast<int64_t>(f) % 2 == 0) ? 1.0 : -1.0;
  const double d = std::min(u - f, f + 1.0 - u);  // to the nearest edge
  return sign * std::min(1.0, 2.0 * d / std::max(w, 1e-9));
}

// Box-filtered coverage of the interval [lo, hi] at u for a footprint w.
double filtered_inside(double u, double lo, double hi, double w) {
  const double d = std::min(u - lo, hi - u);
  return std::clamp(0.5 + d / std::max(w, 1e-9), 0.0, 1.0);
}

}  // namespace

Status CalibrationScene::validate() const {
  if (board.cols < 3 || board.cols > 30)
    return Error{"calibration.board.inner_corners[0] = " + std::to_string(board.cols) +
                 " is out of range [3, 30]"};
  if (board.rows < 3 || board.rows > 30)
    return Error{"calibration.board.inner_corners[1] = " + std::to_string(board.rows) +
                 " is out of range [3, 30]"};
  if (board.cols == board.rows)
    return Error{
        "calibration.board.inner_corners: columns and rows must differ (a square "
        "grid has no defined orientation)"};
  if (auto e = check_range("calibration.board.square_m", board.square_m, 0.002, 1.0); !e) return e;
  if (auto e = check_range("calibration.board.margin_m", board.margin_m, board.square_m * 0.5, 2.0);
      !e)
    return e;
  if (auto e = check_range("calibration.board.black_dn", board.black_dn, 0, 255); !e) return e;
  if (auto e = check_range("calibration.board.white_dn", board.white_dn, board.black_dn + 20, 255);
      !e)
    return e;
  if (auto e = check_range("calibration.eye_skew_ms", eye_skew_s * 1e3, -1000, 1000); !e) return e;
  if (auto e = check_range("calibration.background_dn", background_dn, 0, 255); !e) return e;
  if (random_poses) {
    if (!holds.empty()) return Error{"calibration: give either poses or random_poses, not both"};
    if (auto e = random_poses->validate(); !e)
      return Error{"calibration.random_poses." + e.error()};
  } else if (holds.empty()) {
    return Error{"calibration.poses: needs at least one pose (or give random_poses)"};
  }
  for (std::size_t i = 0; i < holds.size(); ++i) {
    const std::string n = "calibration.poses[" + std::to_string(i) + "]";
    const BoardHold& h = holds[i];
    if (auto e = check_range(n + ".x_m", h.pose.centre_m.x, -20, 20); !e) return e;
    if (auto e = check_range(n + ".y_m", h.pose.centre_m.y, -20, 20); !e) return e;
    if (auto e = check_range(n + ".z_m", h.pose.centre_m.z, 0.1, 20); !e) return e;
    if (auto e = check_range(n + ".tilt_x_deg", h.pose.tilt_x_rad * 180 / M_PI, -75, 75); !e)
      return e;
    if (auto e = check_range(n + ".tilt_y_deg", h.pose.tilt_y_rad * 180 / M_PI, -75, 75); !e)
      return e;
    if (auto e = check_range(n + ".roll_deg", h.pose.roll_rad * 180 / M_PI, -180, 180); !e)
      return e;
    if (auto e = check_range(n + ".hold_s", h.hold_s, 0, 3600); !e) return e;
    if (auto e = check_range(n + ".move_s", h.move_s, 0, 3600); !e) return e;
  }
  return {};
}

double CalibrationScene::duration_s() const {
  if (random_poses && holds.empty())
    return random_poses->count * random_poses->hold_s +
           (random_poses->count - 1) * random_poses->move_s;
  double t = 0.0;
  for (std::size_t i = 0; i < holds.size(); ++i) {
    t += holds[i].hold_s;
    if (i + 1 < holds.size()) t += holds[i].move_s;
  }
  return t;
}

BoardPose board_pose_at(const CalibrationScene& scene, double t_s) {
  if (scene.holds.empty()) return {};
  double t0 = 0.0;
  for (std::size_t i = 0; i + 1 < scene.holds.size(); ++i) {
    const BoardHold& h = scene.holds[i];
    if (t_s <= t0 + h.hold_s) return h.pose;
    if (t_s < t0 + h.hold_s + h.move_s) {
      return mix(h.pose, scene.holds[i + 1].pose, smooth((t_s - t0 - h.hold_s) / h.move_s));
    }
    t0 += h.hold_s + h.move_s;
  }
  return scene.holds.back().pose;
}

int hold_index_at(const CalibrationScene& scene, double t_s) {
  double t0 = 0.0;
  for (std::size_t i = 0; i < scene.holds.size(); ++i) {
    const BoardHold& h = scene.holds[i];
    if (t_s <= t0 + h.hold_s || i + 1 == scene.holds.size()) return static_cast<int>(i);
    if (t_s < t0 + h.hold_s + h.move_s) return -1;
    t0 += h.hold_s + h.move_s;
  }
  return -1;
}

std::vector<Vec3d> board_corners_cam(const CalibrationBoard& board, const BoardPose& pose) {
  const Mat3 r = cam_from_board(pose);
  std::vector<Vec3d> out;
  out.reserve(static_cast<std::size_t>(board.cols * board.rows));
  for (int row = 0; row < board.rows; ++row) {
    for (int col = 0; col < board.cols; ++col) {
      const Vec3d b{(col - 0.5 * (board.cols - 1)) * board.square_m,
                    (row - 0.5 * (board.rows - 1)) * board.square_m, 0.0};
      out.push_back(pose.centre_m + r * b);
    }
  }
  return out;
}

Vec3d left_cam_to_eye(const StereoRig& rig, Eye eye, const Vec3d& p_left) {
  if (eye == Eye::kLeft) return p_left;
  Mat3 r;
  Vec3d t;
  right_from_left(rig, r, t);
  return r * p_left + t;
}

std::vector<cv::Point2d> board_corners_px(const StereoRig& rig, Eye eye,
                                          const CalibrationBoard& board, const BoardPose& pose) {
  std::vector<cv::Point2d> out;
  for (const Vec3d& p : board_corners_cam(board, pose)) {
    const Point2 px = project_raw(rig.intrinsics(eye), left_cam_to_eye(rig, eye, p));
    out.emplace_back(px.x, px.y);
  }
  return out;
}

bool board_in_view(const StereoRig& rig, const CalibrationBoard& board, const BoardPose& pose,
                   double margin_px) {
  const Mat3 r = cam_from_board(pose);
  const double hx = 0.5 * (board.cols + 1) * board.square_m + board.margin_m;
  const double hy = 0.5 * (board.rows + 1) * board.square_m + board.margin_m;
  for (Eye eye : {Eye::kLeft, Eye::kRight}) {
    // The border's outline, sampled along its edges (distortion bends straight edges).
    for (int i = 0; i <= 40; ++i) {
      const double s = -1.0 + i / 20.0;
      for (const Vec3d b : {Vec3d{s * hx, -hy, 0}, Vec3d{s * hx, hy, 0}, Vec3d{-hx, s * hy, 0},
                            Vec3d{hx, s * hy, 0}}) {
        const Vec3d p = left_cam_to_eye(rig, eye, pose.centre_m + r * b);
        if (p.z < 0.05) return false;
        const Point2 px = project_raw(rig.intrinsics(eye), p);
        if (px.x < margin_px || px.y < margin_px || px.x > rig.width_px() - 1 - margin_px ||
            px.y > rig.height_px() - 1 - margin_px) {
          return false;
        }
      }
    }
  }
  return true;
}

Status BoardPoseRanges::validate() const {
  if (count < 1 || count > 1000)
    return Error{"count = " + std::to_string(count) + " is out of range [1, 1000]"};
  if (auto e = check_range("near_m", near_m, 0.1, 20); !e) return e;
  if (auto e = check_range("far_m", far_m, near_m, 20); !e) return e;
  if (auto e = check_range("max_tilt_deg", max_tilt_rad * 180 / M_PI, 0, 70); !e) return e;
  if (auto e = check_range("max_roll_deg", max_roll_rad * 180 / M_PI, 0, 90); !e) return e;
  if (auto e = check_range("hold_s", hold_s, 0, 3600); !e) return e;
  return check_range("move_s", move_s, 0, 3600);
}

std::vector<BoardHold> draw_board_holds(const StereoRig& rig, const CalibrationBoard& board,
                                        const BoardPoseRanges& ranges, uint64_t seed) {
  SplitMix64 rng(seed * 0x9e3779b97f4a7c15ULL + 0x5eed);
  const auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * rng.uniform(); };
  const Intrinsics& k = rig.intrinsics(Eye::kLeft);
  // Where the board's centre goes in the image (3x3 cells, visited in a shuffled order), how
  // far (three depth bands) and how it is tilted (facing, then about each axis both ways):
  // the three cycles have coprime lengths, so the combinations vary.
  std::vector<int> cells{0, 1, 2, 3, 4, 5, 6, 7, 8};
  for (std::size_t i = cells.size() - 1; i > 0; --i)
    std::swap(cells[i], cells[static_cast<std::size_t>(rng.next() % (i + 1))]);
  // Tilts: facing, about either axis and about the diagonals (which skew the image's corner
  // angles most), both ways.
  const double d = std::sqrt(0.5);
  const double tilt_dir[7][2] = {{0, 0}, {d, d}, {1, 0}, {-d, d}, {0, 1}, {-d, -d}, {d, -d}};
  std::vector<BoardHold> out;
  for (int i = 0; i < ranges.count; ++i) {
    const int cell = cells[static_cast<std::size_t>(i % 9)];
    const int band = (i + i / 9) % 3;
    const double* dir = tilt_dir[i % 7];
    BoardHold h;
    h.hold_s = ranges.hold_s;
    h.move_s = ranges.move_s;
    bool found = false;
    for (int attempt = 0; attempt < 60 && !found; ++attempt) {
      // Failed attempts first pull the target toward the image centre, then push the board
      // farther: a near board fits both eyes only near the middle.
      const double pull = std::clamp((attempt - 10) / 20.0, 0.0, 1.0);
      const double push = std::clamp((attempt - 30) / 30.0, 0.0, 1.0);
      const double span = ranges.far_m - ranges.near_m;
      const double depth =
          uniform(ranges.near_m + span * band / 3.0, ranges.near_m + span * (band + 1) / 3.0) +
          push * span * (2 - band) / 3.0;
      const double u =
          rig.width_px() * ((cell % 3 + uniform(0.1, 0.9)) / 3.0 * (1.0 - pull) + 0.5 * pull);
      const double v =
          rig.height_px() * ((cell / 3 + uniform(0.1, 0.9)) / 3.0 * (1.0 - pull) + 0.5 * pull);
      const double tilt = uniform(0.6, 1.0) * ranges.max_tilt_rad;
      h.pose.centre_m = Vec3d{(u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0} * depth;
      h.pose.tilt_x_rad = dir[0] * tilt;
      h.pose.tilt_y_rad = dir[1] * tilt;
      h.pose.roll_rad = uniform(-1.0, 1.0) * ranges.max_roll_rad;
      found = board_in_view(rig, board, h.pose, 8.0);
    }
    if (!found) {
      // The board does not fit anywhere at this depth range: straight on, centred, far.
      h.pose = BoardPose{};
      h.pose.centre_m = Vec3d{0.0, 0.0, ranges.far_m};
    }
    out.push_back(h);
  }
  return out;
}

CalibrationScene with_drawn_holds(const CalibrationScene& scene, const StereoRig& rig) {
  if (!scene.random_poses) return scene;
  CalibrationScene out = scene;
  out.holds = draw_board_holds(rig, scene.board, *scene.random_poses, scene.random_poses->seed);
  out.random_poses.reset();
  return out;
}

BoardRenderer::BoardRenderer(const StereoRig& rig, const CalibrationScene& scene)
    : width_(rig.width_px()),
      height_(rig.height_px()),
      board_(scene.board),
      background_dn_(scene.background_dn) {
  right_from_left(rig, r_right_from_left_, t_right_from_left_);
  for (Eye eye : {Eye::kLeft, Eye::kRight}) {
    const int e = static_cast<int>(eye);
    k_[e] = rig.intrinsics(eye);
    rays_[e].resize(static_cast<std::size_t>(width_) * height_);
    for (int v = 0; v < height_; ++v) {
      for (int u = 0; u < width_; ++u) {
        const Point2 pd{(u - k_[e].cx) / k_[e].fx, (v - k_[e].cy) / k_[e].fy};
        const Point2 p = undistort_normalized(k_[e].dist, pd).value_or(pd);
        rays_[e][static_cast<std::size_t>(v) * width_ + u] = {p.x, p.y};
      }
    }
  }
}

void BoardRenderer::render(Eye eye, const BoardPose& pose, cv::Mat& out) const {
  const int e = static_cast<int>(eye);
  // The board's frame in this eye's camera frame.
  Mat3 r = cam_from_board(pose);
  Vec3d c = pose.centre_m;
  if (eye == Eye::kRight) {
    r = r_right_from_left_ * r;
    c = r_right_from_left_ * c + t_right_from_left_;
  }
  const Mat3 rt = r.transposed();
  const Vec3d n = r * Vec3d{0, 0, 1};
  const double nc = n.dot(c);
  // Board coordinates in squares, inner corners at integers 0..cols-1 / 0..rows-1.
  const double s = board_.square_m;
  const double ox = 0.5 * (board_.cols - 1), oy = 0.5 * (board_.rows - 1);
  const auto w = static_cast<std::size_t>(width_);
  std::vector<cv::Point2d> uv(w * static_cast<std::size_t>(height_));
  std::vector<uint8_t> hit(uv.size(), 0);
  for (std::size_t i = 0; i < uv.size(); ++i) {
    const Vec3d d{rays_[e][i].x, rays_[e][i].y, 1.0};
    const double nd = n.dot(d);
    if (std::abs(nd) < 1e-12) continue;
    const double t = nc / nd;
    if (t <= 0.0) continue;
    const Vec3d b = rt * (d * t - c);
    uv[i] = {b.x / s + ox, b.y / s + oy};
    hit[i] = 1;
  }
  const double mid = 0.5 * (board_.white_dn + board_.black_dn);
  const double amp = 0.5 * (board_.white_dn - board_.black_dn);
  const double m = board_.margin_m / s;
  out.create(height_, width_, CV_8UC3);
  for (int v = 0; v < height_; ++v) {
    auto* row = out.ptr<uint8_t>(v);
    for (int u = 0; u < width_; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + static_cast<std::size_t>(u);
      double value = background_dn_;
      if (hit[i]) {
        // The pixel's footprint on the board, from the neighbours' board coordinates.
        const std::size_t il = u > 0 && hit[i - 1] ? i - 1 : i;
        const std::size_t ir = u + 1 < width_ && hit[i + 1] ? i + 1 : i;
        const std::size_t iu = v > 0 && hit[i - w] ? i - w : i;
        const std::size_t id = v + 1 < height_ && hit[i + w] ? i + w : i;
        const double su = ir > il ? 1.0 / static_cast<double>(ir - il) : 0.0;
        const double sv = id > iu ? static_cast<double>(w) / static_cast<double>(id - iu) : 0.0;
        const cv::Point2d du = (uv[ir] - uv[il]) * su, dv = (uv[id] - uv[iu]) * sv;
        const double wx = std::abs(du.x) + std::abs(dv.x), wy = std::abs(du.y) + std::abs(dv.y);
        const double x = uv[i].x, y = uv[i].y;
        const double board_cov = filtered_inside(x, -1.0 - m, board_.cols + m, wx) *
                                 filtered_inside(y, -1.0 - m, board_.rows + m, wy);
        const double squares_cov =
            filtered_inside(x, -1.0, board_.cols, wx) * filtered_inside(y, -1.0, board_.rows, wy);
        // Dark where the two waves agree: the outer corner squares are dark.
        const double checker = mid - amp * filtered_wave(x, wx) * filtered_wave(y, wy);
        const double on_board = board_.white_dn * (1.0 - squares_cov) + checker * squares_cov;
        value = background_dn_ * (1.0 - board_cov) + on_board * board_cov;
      }
      const auto dn = static_cast<uint8_t>(std::clamp(std::lround(value), 0L, 255L));
      row[3 * u] = row[3 * u + 1] = row[3 * u + 2] = dn;
    }
  }
}

}  // namespace stereoball::simulator
