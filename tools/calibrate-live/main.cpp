// stereoball calibrate live (also `stereoball calibrate --live`): calibrates the running rig
// from stereo/frame. By default it starts `stereoball view --calibrate` with the same flags: the
// calibration page in the browser (both eyes with the board corners drawn, coverage, poses,
// verdict, a button that writes the file). With --terminal it runs on the console instead: a
// pose is taken only when the board has stood still in both eyes, the console shows coverage
// and what to do next, and the file is written only when the verdict passes. Both use one
// implementation (live_station.hpp).

#include <unistd.h>
#include <opencv2/imgcodecs.hpp>
#include "common/util/cli11.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "common/dds/reader.hpp"
#include "common/dds/waitset.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "live_flags.hpp"
#include "live_frames.hpp"
#include "live_output.hpp"

namespace {

namespace sb = stereoball;
namespace live = stereoball::calibrate_live;

struct Options {
  sb::node::CommonOptions common;
  live::LiveFlags flags;
  std::string save_poses_dir;
  bool terminal = false;
};

volatile std::sig_atomic_t g_stop = 0;

void request_stop(int) {
  g_stop = 1;
}

int fail(const std::string& message, int code = 2) {
  std::fprintf(stderr, "stereoball calibrate live: %s\n", message.c_str());
  return code;
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

int run(const Options& o, const live::StationParams& params) {
  sb::dds::DomainParticipant participant(
      {o.common.domain_id, o.common.partition, o.common.key_file});
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(participant, sb::topics::kStereoFrame);
  sb::dds::ReadCondition readable(frames.handle());
  sb::dds::WaitSet waitset(participant);
  waitset.attach(readable.handle(), 0);
  sb::stereo::FrameDecoder decoder;
  live::LiveStation station(params);
  const int64_t start_ns = sb::node::monotonic_ns();
  int64_t last_print_ns = 0;
  std::printf(
      "waiting for stereo/frame on domain %d%s; show the %s board to both cameras and "
      "hold it still at each place\n",
      o.common.domain_id,
      o.common.partition.empty() ? "" : (" partition " + o.common.partition).c_str(),
      o.flags.board.c_str());
  while (!g_stop && !station.verdict() && station.fatal().empty()) {
    const int64_t now = sb::node::monotonic_ns();
    if (now - start_ns > static_cast<int64_t>(o.flags.timeout_s * 1e9)) {
      std::printf("time is up (--timeout-s %.0f)\n", o.flags.timeout_s);
      break;
    }
    if (const auto stall = station.check_stall(now); !stall.empty())
      std::printf("%s\n", stall.c_str());
    waitset.wait(100'000'000);
    auto sample = frames.take_latest();
    if (!sample) continue;
    auto frame = live::station_frame(**sample, decoder);
    if (!frame) {
      std::printf("%s\n", frame.error().c_str());
      continue;
    }
    if (!station.session() && !frame->rectified)
      std::printf("frames of %dx%d from %s\n", frame->left.cols, frame->left.rows,
                  frame->source.c_str());
    const auto step = station.add_frame(*frame, sb::node::monotonic_ns());
    if (!station.fatal().empty()) break;
    if (step.pose) {
      std::printf("pose %d taken: x %.2f y %.2f size %.2f skew %.2f, board disparity %.1f px\n",
                  step.pose->index, step.pose->view.x, step.pose->view.y, step.pose->view.size,
                  step.pose->view.skew, step.pose->disparity_px);
      if (!o.save_poses_dir.empty())
        if (auto st =
                save_pose_images(o.save_poses_dir, step.pose->index, frame->left, frame->right);
            !st)
          return fail(st.error(), 1);
    }
    const int64_t shown = sb::node::monotonic_ns();
    if (station.session() && (step.pose || shown - last_print_ns > 1'000'000'000)) {
      print_progress(station.session()->progress());
      last_print_ns = shown;
    }
  }
  station.finish_now();
  if (!station.fatal().empty()) return fail(station.fatal(), 1);
  const auto& verdict = *station.verdict();
  std::printf("\nper-pose stereo RMS:\n");
  for (const auto& line : live::verdict_lines(verdict)) std::printf("%s\n", line.c_str());
  if (!verdict.pass) {
    std::printf("nothing written\n");
    return 1;
  }
  if (auto st = live::write_live_calibration(o.flags.output, params.live, verdict,
                                             "written by stereoball calibrate live");
      !st)
    return fail(st.error(), 1);
  std::printf(
      "wrote %s; camera_server publishes it within a second when its calibration_file names "
      "this file (it reloads a changed file)\n",
      o.flags.output.c_str());
  return 0;
}

// Without --terminal: the calibration page, `stereoball view --calibrate` with the same
// arguments (the view parses and checks them).
int exec_page(int argc, char** argv) {
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::string program =
      ((ec ? std::filesystem::path(argv[0]) : self).parent_path() / "stereoball-view").string();
  std::vector<std::string> args{program, "--calibrate"};
  for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
  std::vector<char*> view_argv;
  for (auto& a : args) view_argv.push_back(a.data());
  view_argv.push_back(nullptr);
  execv(program.c_str(), view_argv.data());
  return fail(program + ": cannot start the calibration page (" + std::strerror(errno) +
                  "); use --terminal for the console",
              1);
}

}  // namespace

int main(int argc, char** argv) {
  bool terminal = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    terminal |= a == "--terminal";
    if (a == "-h" || a == "--help" || a == "--help-all") terminal = true;
  }
  if (!terminal) return exec_page(argc, argv);
  CLI::App app{
      "stereoball calibrate live: stereo calibration of the running rig from stereo/frame. "
      "Without --terminal it opens the calibration page (stereoball view --calibrate, same "
      "flags plus --port, --bind, --open). A pose is taken when the board has stood still in "
      "both eyes (free-running cameras), coverage of the view and depth is shown with what to "
      "do next, and the calibration file is written only when the verdict (RMS, rectified row "
      "error, baseline, eye order) passes.",
      "stereoball-calibrate-live"};
  Options o;
  sb::node::add_common_flags(app, o.common, "", false);
  live::add_live_flags(app, o.flags);
  app.add_flag("--terminal", o.terminal, "calibrate on the console instead of the page");
  app.add_option("--save-poses", o.save_poses_dir,
                 "also save each pose's images here (for stereoball calibrate on files)");
  CLI11_PARSE(app, argc, argv);
  const auto params = live::station_params(o.flags);
  if (!params) return fail(params.error());
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  try {
    return run(o, *params);
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
}
