// stereoball calibrate live (also `stereoball calibrate --live`): calibrates the running rig
// from stereo/frame. Shows the board to both cameras; a pose is taken only when the board has
// stood still in both eyes, the console shows coverage and what to do next, and the file is
// written only when the verdict passes.

#include <CLI/CLI.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>

#include "common/dds/reader.hpp"
#include "common/dds/waitset.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "live_calibration.hpp"
#include "stereo/frame/frame_decoder.hpp"
#include "stereo/io/calibration_file.hpp"

namespace {

namespace sb = stereoball;
namespace live = stereoball::calibrate_live;

struct Options {
  sb::node::CommonOptions common;
  std::string board = "9x6";
  double square_mm = 25.0;
  int poses = 15;
  double still_s = 0.3;
  double max_motion_px = 0.5;
  double max_rms_px = 0.5;
  double max_row_error_px = 0.3;
  double baseline_m = 0;
  double timeout_s = 600;
  double stall_s = 2.0;
  std::string output;
  std::string save_poses_dir;
};

volatile std::sig_atomic_t g_stop = 0;

void request_stop(int) {
  g_stop = 1;
}

int fail(const std::string& message, int code = 2) {
  std::fprintf(stderr, "stereoball calibrate live: %s\n", message.c_str());
  return code;
}

// Board corners in one eye: searched on a copy at most 800 px wide (fast on large sensors),
// refined to sub-pixel on the full image. Empty when the whole board is not seen.
std::vector<cv::Point2f> find_corners(const cv::Mat& eye,
                                      const sb::stereo::BoardCalibrationParams& p) {
  cv::Mat grey;
  if (eye.channels() == 3)
    cv::cvtColor(eye, grey, cv::COLOR_BGR2GRAY);
  else
    grey = eye;
  const double scale = std::min(1.0, 800.0 / grey.cols);
  cv::Mat small = grey;
  if (scale < 1.0) cv::resize(grey, small, {}, scale, scale, cv::INTER_AREA);
  std::vector<cv::Point2f> corners;
  const int flags =
      cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK;
  if (!cv::findChessboardCorners(small, p.inner_corners, corners, flags)) return {};
  for (auto& c : corners) c *= static_cast<float>(1.0 / scale);
  const int half = p.subpix_window_px / 2;
  cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 1e-3));
  return corners;
}

std::string bar(double fraction) {
  const int filled = static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * 10));
  return std::string(filled, '#') + std::string(10 - filled, '-');
}

void print_progress(const live::Progress& p) {
  std::printf("poses %d/%d  x %s  y %s  size %s  skew %s  depth %s  still L %.1f s R %.1f s | %s\n",
              p.poses, p.target_poses, bar(p.coverage[0]).c_str(), bar(p.coverage[1]).c_str(),
              bar(p.coverage[2]).c_str(), bar(p.coverage[3]).c_str(), bar(p.depth_coverage).c_str(),
              p.left.still_ns * 1e-9, p.right.still_ns * 1e-9, p.hint.c_str());
  std::fflush(stdout);
}

void print_verdict(const live::Verdict& v) {
  const auto& c = v.result.calibration;
  std::printf("\nper-pose stereo RMS:\n");
  for (const auto& e : v.per_pose) std::printf("  %-10s %.3f px\n", e.name.c_str(), e.rms_px);
  for (const auto& d : v.result.dropped)
    std::printf("  dropped %s: %s\n", d.name.c_str(), d.reason.c_str());
  std::printf(
      "stereo RMS %.3f px, mean rectified row error %.3f px (max %.3f px), baseline "
      "%.4f m, focal %.1f px\n",
      c.rms_px, v.result.mean_rectified_row_error_px, v.result.max_rectified_row_error_px,
      std::abs(c.t[0]), c.p1(0, 0));
  for (const auto& w : v.warnings) std::printf("warning: %s\n", w.c_str());
  for (const auto& f : v.failures) std::printf("FAIL: %s\n", f.c_str());
  std::printf("verdict: %s\n", v.pass ? "PASS" : "FAIL");
}

sb::Status save_pose_images(const std::string& dir, int index, const cv::Mat& left,
                            const cv::Mat& right) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return sb::Error{dir + ": cannot create (" + ec.message() + ")"};
  char name[32];
  std::snprintf(name, sizeof name, "%03d.png", index);
  if (!cv::imwrite(dir + "/left_" + name, left) || !cv::imwrite(dir + "/right_" + name, right))
    return sb::Error{dir + ": cannot write pose images"};
  return {};
}

int write_result(const Options& o, const live::LiveParams& params, const live::Verdict& v) {
  sb::stereo::CalibrationFileInfo info;
  info.mean_rectified_row_error_px = v.result.mean_rectified_row_error_px;
  info.square_size_m = params.board.square_m;
  info.board_inner_corners = params.board.inner_corners;
  info.pair_names = v.result.pair_names;
  info.note = "written by stereoball calibrate live";
  if (auto st = sb::stereo::save_calibration(o.output, v.result.calibration, info); !st)
    return fail(st.error(), 1);
  std::printf(
      "wrote %s; camera_server publishes it once its calibration_file names this file "
      "and it is restarted\n",
      o.output.c_str());
  return 0;
}

int run(const Options& o, const live::LiveParams& params) {
  sb::dds::DomainParticipant participant(
      {o.common.domain_id, o.common.partition, o.common.key_file});
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame);
  sb::dds::ReadCondition readable(frames.handle());
  sb::dds::WaitSet waitset(participant);
  waitset.attach(readable.handle(), 0);
  sb::stereo::FrameDecoder decoder;
  std::optional<live::LiveCalibration> session;
  cv::Size size;
  const int64_t start_ns = sb::node::monotonic_ns();
  int64_t last_frame_ns = start_ns, last_print_ns = 0;
  bool stall_reported = false;
  std::printf(
      "waiting for stereo/frame on domain %d%s; show the %s board to both cameras and "
      "hold it still at each place\n",
      o.common.domain_id,
      o.common.partition.empty() ? "" : (" partition " + o.common.partition).c_str(),
      o.board.c_str());
  while (!g_stop) {
    const int64_t now = sb::node::monotonic_ns();
    if (now - start_ns > static_cast<int64_t>(o.timeout_s * 1e9)) {
      std::printf("time is up (--timeout-s %.0f)\n", o.timeout_s);
      break;
    }
    if (!stall_reported && now - last_frame_ns > static_cast<int64_t>(o.stall_s * 1e9)) {
      std::printf(
          "no frames for %.1f s: is camera_server running on this domain and partition? "
          "(stereoball doctor)\n",
          (now - last_frame_ns) * 1e-9);
      stall_reported = true;
    }
    waitset.wait(100'000'000);
    auto sample = frames.take_latest();
    if (!sample) continue;
    const auto& msg = **sample;
    last_frame_ns = sb::node::monotonic_ns();
    stall_reported = false;
    if (msg.rectified)
      return fail(
          "frames are rectified: calibrate needs raw frames (set "
          "rectify: false in the camera_server config)",
          1);
    const cv::Size eye(static_cast<int>(msg.left.width_px), static_cast<int>(msg.left.height_px));
    if (!session) {
      size = eye;
      session.emplace(params, size);
      std::printf("frames of %dx%d from %s\n", size.width, size.height,
                  msg.source ? msg.source : "?");
    } else if (eye != size) {
      return fail("the frame size changed from " + std::to_string(size.width) + "x" +
                      std::to_string(size.height) + " to " + std::to_string(eye.width) + "x" +
                      std::to_string(eye.height) + " during calibration: nothing written",
                  1);
    }
    cv::Mat left, right;
    if (auto st = decoder.decode(msg, size, left, right); !st) {
      std::printf("frame %llu refused: %s\n", static_cast<unsigned long long>(msg.seq),
                  st.error().c_str());
      continue;
    }
    const int64_t ls = msg.left.capture_stamp_ns ? msg.left.capture_stamp_ns : msg.stamp_ns;
    const int64_t rs = msg.right.capture_stamp_ns ? msg.right.capture_stamp_ns : msg.stamp_ns;
    const auto pose = session->add_frame(ls, find_corners(left, params.board), rs,
                                         find_corners(right, params.board));
    if (pose) {
      std::printf("pose %d taken: x %.2f y %.2f size %.2f skew %.2f, board disparity %.1f px\n",
                  pose->index, pose->view.x, pose->view.y, pose->view.size, pose->view.skew,
                  pose->disparity_px);
      if (!o.save_poses_dir.empty())
        if (auto st = save_pose_images(o.save_poses_dir, pose->index, left, right); !st)
          return fail(st.error(), 1);
    }
    if (pose || last_frame_ns - last_print_ns > 1'000'000'000) {
      print_progress(session->progress());
      last_print_ns = last_frame_ns;
    }
    if (session->enough_poses()) break;
  }
  if (!session) return fail("no stereo frame arrived: nothing written", 1);
  const auto verdict = session->finish();
  if (!verdict) return fail(verdict.error() + "; nothing written", 1);
  print_verdict(*verdict);
  if (!verdict->pass) {
    std::printf("nothing written\n");
    return 1;
  }
  return write_result(o, params, *verdict);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball calibrate live: stereo calibration of the running rig from stereo/frame. A "
      "pose is taken when the board has stood still in both eyes (free-running cameras), the "
      "console shows coverage of the view and depth and what to do next, and the calibration "
      "file is written only when the verdict (RMS, rectified row error, baseline, eye order) "
      "passes.",
      "stereoball-calibrate-live"};
  Options o;
  sb::node::add_common_flags(app, o.common, "", false);
  app.add_option("--board", o.board, "inner corners per row x per column")->capture_default_str();
  app.add_option("--square-mm", o.square_mm, "chessboard square side, mm (sets the unit of T)")
      ->check(CLI::Range(1.0, 1000.0))
      ->capture_default_str();
  app.add_option("--poses", o.poses, "poses to take before the verdict")
      ->check(CLI::Range(6, 200))
      ->capture_default_str();
  app.add_option("--still-s", o.still_s, "how long the board must stand still in both eyes, s")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  app.add_option("--max-motion-px", o.max_motion_px,
                 "largest corner motion that still counts as still, px")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  app.add_option("--max-rms-px", o.max_rms_px, "verdict: largest stereo RMS, px")
      ->check(CLI::Range(0.01, 10.0))
      ->capture_default_str();
  app.add_option("--max-row-error-px", o.max_row_error_px,
                 "verdict: largest mean rectified row error, px")
      ->check(CLI::Range(0.01, 10.0))
      ->capture_default_str();
  app.add_option("--baseline-m", o.baseline_m,
                 "the rig's measured baseline, m: the verdict fails beyond +-10 % (0 = unchecked)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  app.add_option("--timeout-s", o.timeout_s, "give up after this long, s")
      ->check(CLI::Range(1.0, 86400.0))
      ->capture_default_str();
  app.add_option("--stall-s", o.stall_s, "say so when no frame arrived for this long, s")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  app.add_option("-o,--output", o.output, "calibration file to write (.yaml)")->required();
  app.add_option("--save-poses", o.save_poses_dir,
                 "also save each pose's images here (for stereoball calibrate on files)");
  CLI11_PARSE(app, argc, argv);
  const auto board = stereoball::stereo::parse_board_size(o.board);
  if (!board)
    return fail("--board '" + o.board + "': expected COLSxROWS of inner corners, e.g. 9x6");
  live::LiveParams params;
  params.board.inner_corners = *board;
  params.board.square_m = o.square_mm * 1e-3;
  params.target_poses = o.poses;
  params.still.still_ns = static_cast<int64_t>(o.still_s * 1e9);
  params.still.max_motion_px = o.max_motion_px;
  params.max_rms_px = o.max_rms_px;
  params.max_row_error_px = o.max_row_error_px;
  if (o.baseline_m > 0) {
    params.min_baseline_m = o.baseline_m * 0.9;
    params.max_baseline_m = o.baseline_m * 1.1;
  }
  if (auto st = params.validate(); !st) return fail(st.error());
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  try {
    return run(o, params);
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
}
