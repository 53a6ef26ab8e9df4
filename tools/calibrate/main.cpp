// stereoball-calibrate: stereo calibration from chessboard pairs, written as
// one OpenCV FileStorage YAML that every StereoBall component reads.

#include "common/util/result.hpp"
#include "stereo/core/board_calibration.hpp"
#include "stereo/core/rectifier.hpp"
#include "stereo/core/still_board.hpp"
#include "stereo/io/calibration_file.hpp"

#include <glob.h>
#include <unistd.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include "common/util/cli11.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace {

using stereoball::stereo::BoardCalibrationParams;
using stereoball::stereo::BoardCalibrationResult;
using stereoball::stereo::PairCorners;
using PairList = std::vector<std::pair<std::string, std::string>>;

struct Options {
  std::string pairs_list;
  std::string left_glob;
  std::string right_glob;
  std::string board = "9x6";
  double square_mm = 25.0;
  int min_pairs = 6;
  double alpha = 0.0;
  double outlier_ratio = 3.0;
  double outlier_min_px = 0.3;
  int subpix_window_px = 11;
  std::string output;
  std::string save_rectified_dir;
  std::string sequence;
  double still_ms = 300.0;
  double still_px = 0.5;
};

int fail(const std::string& message) {
  std::cerr << "stereoball-calibrate: " << message << "\n";
  return 1;
}

std::vector<std::string> expand_glob(const std::string& pattern) {
  glob_t g{};
  std::vector<std::string> out;
  if (::glob(pattern.c_str(), 0, nullptr, &g) == 0) {
    for (std::size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  }
  ::globfree(&g);
  std::sort(out.begin(), out.end());
  return out;
}

stereoball::Result<PairList> collect_pairs(const Options& o) {
  if (!o.pairs_list.empty()) return stereoball::stereo::load_pair_list(o.pairs_list);
  const auto left = expand_glob(o.left_glob), right = expand_glob(o.right_glob);
  if (left.empty()) return stereoball::Error{"--left-glob '" + o.left_glob + "' matches no file"};
  if (right.empty())
    return stereoball::Error{"--right-glob '" + o.right_glob + "' matches no file"};
  if (left.size() != right.size()) {
    return stereoball::Error{"--left-glob matches " + std::to_string(left.size()) + " files but " +
                             "--right-glob matches " + std::to_string(right.size())};
  }
  PairList pairs;
  for (std::size_t i = 0; i < left.size(); ++i) pairs.emplace_back(left[i], right[i]);
  return pairs;
}

std::string base(const std::string& path) {
  return std::filesystem::path(path).filename();
}

// Detects the board in every pair; prints and skips the pairs where it is not usable.
std::vector<PairCorners> detect_all(const PairList& pairs, const BoardCalibrationParams& params,
                                    std::optional<cv::Size>& image_size) {
  std::vector<PairCorners> found;
  for (const auto& [lp, rp] : pairs) {
    const std::string label = base(lp) + " + " + base(rp);
    const cv::Mat l = cv::imread(lp, cv::IMREAD_GRAYSCALE);
    const cv::Mat r = cv::imread(rp, cv::IMREAD_GRAYSCALE);
    std::string why;
    if (l.empty() || r.empty()) {
      why = "cannot read " + (l.empty() ? lp : rp);
    } else if (l.size() != r.size() || (image_size && l.size() != *image_size)) {
      why = "image size differs from the first pair";
    }
    std::optional<std::vector<cv::Point2f>> cl, cr;
    if (why.empty() && !(cl = stereoball::stereo::find_board_corners(l, params))) {
      why = "board not found in left image";
    }
    if (why.empty() && !(cr = stereoball::stereo::find_board_corners(r, params))) {
      why = "board not found in right image";
    }
    if (!why.empty()) {
      std::cout << "  skip " << label << ": " << why << "\n";
      continue;
    }
    if (!image_size) image_size = l.size();
    PairCorners pc{label, *cl, *cr};
    if (stereoball::stereo::align_corner_order(pc.left_px, pc.right_px)) {
      std::cout << "  note " << label << ": right corners reordered to match left\n";
    }
    std::cout << "  ok   " << label << "\n";
    found.push_back(std::move(pc));
  }
  return found;
}

// One frame of a sequence: both eyes' files and capture stamps.
struct SequenceFrame {
  std::string left, right;
  int64_t left_ns = 0, right_ns = 0;
};

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out(1);
  for (char c : line) {
    if (c == ',') {
      out.emplace_back();
    } else if (c != '\r') {
      out.back() += c;
    }
  }
  return out;
}

bool parse_i64(const std::string& text, int64_t& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc{} && end == text.data() + text.size();
}

// frames.csv as stereoball-sim writes it: left,right,left_stamp_ns,right_stamp_ns[,...];
// files relative to the list's folder.
stereoball::Result<std::vector<SequenceFrame>> load_sequence(const std::string& path) {
  std::ifstream in(path);
  if (!in) return stereoball::Error{"--sequence " + path + ": cannot open"};
  std::string line;
  if (!std::getline(in, line) || line.rfind("left,right,left_stamp_ns,right_stamp_ns", 0) != 0) {
    return stereoball::Error{"--sequence " + path +
                             ": first line must be the header "
                             "'left,right,left_stamp_ns,right_stamp_ns'"};
  }
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::vector<SequenceFrame> frames;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty() || line == "\r") continue;
    const auto f = split_csv(line);
    SequenceFrame fr;
    if (f.size() < 4 || f[0].empty() || f[1].empty() || !parse_i64(f[2], fr.left_ns) ||
        !parse_i64(f[3], fr.right_ns)) {
      return stereoball::Error{"--sequence " + path + " line " + std::to_string(n) +
                               ": expected left file, right file, left and right capture stamps "
                               "(integer ns)"};
    }
    fr.left = (dir / f[0]).string();
    fr.right = (dir / f[1]).string();
    frames.push_back(std::move(fr));
  }
  if (frames.empty()) return stereoball::Error{"--sequence " + path + ": no frames"};
  return frames;
}

// Detects the board in every frame of a sequence and keeps one pair per pose in which the
// board stood still in both eyes (each eye on its own capture stamps).
stereoball::Result<std::vector<PairCorners>> detect_sequence(
    const std::vector<SequenceFrame>& frames, const BoardCalibrationParams& params,
    const stereoball::stereo::StillBoardParams& still, std::optional<cv::Size>& image_size,
    PairList& used) {
  stereoball::stereo::StillBoardSelector selector(still);
  std::vector<PairCorners> found;
  int both = 0;
  for (const SequenceFrame& f : frames) {
    std::vector<cv::Point2f> corners[2];
    const std::string* files[2] = {&f.left, &f.right};
    for (int e = 0; e < 2; ++e) {
      const cv::Mat img = cv::imread(*files[e], cv::IMREAD_GRAYSCALE);
      if (img.empty()) return stereoball::Error{"cannot read " + *files[e]};
      if (!image_size) image_size = img.size();
      if (img.size() != *image_size)
        return stereoball::Error{*files[e] + ": image size differs from the first frame"};
      corners[e] =
          stereoball::stereo::find_board_corners(img, params).value_or(std::vector<cv::Point2f>{});
    }
    both += !corners[0].empty() && !corners[1].empty() ? 1 : 0;
    // Feed the eyes in capture order: free-running eyes may be either way round.
    const bool left_first = f.left_ns <= f.right_ns;
    std::optional<stereoball::stereo::StillPose> pose;
    for (int k = 0; k < 2; ++k) {
      const bool left = (k == 0) == left_first;
      auto p = selector.add(left ? stereoball::stereo::Eye::kLeft : stereoball::stereo::Eye::kRight,
                            left ? f.left_ns : f.right_ns, corners[left ? 0 : 1]);
      if (p) pose = std::move(p);
    }
    if (!pose) continue;
    const std::string label = base(f.left) + " + " + base(f.right);
    PairCorners pc{label, pose->left_px, pose->right_px};
    stereoball::stereo::align_corner_order(pc.left_px, pc.right_px);
    std::printf("  take %s: board still in both eyes for %.0f ms (right eye %+.1f ms)\n",
                label.c_str(),
                (std::min(pose->left_stamp_ns, pose->right_stamp_ns) - pose->still_from_ns) * 1e-6,
                (f.right_ns - f.left_ns) * 1e-6);
    used.emplace_back(f.left, f.right);
    found.push_back(std::move(pc));
  }
  std::printf("%zu frames, board in both eyes in %d, %zu still poses taken\n", frames.size(), both,
              found.size());
  return found;
}

void print_report(const BoardCalibrationResult& r, double square_mm) {
  const auto& c = r.calibration;
  if (!r.dropped.empty()) {
    std::printf("dropped %zu inconsistent pair(s) (each against the calibration of the rest):\n",
                r.dropped.size());
    for (const auto& d : r.dropped)
      std::printf("  drop %s: %s\n", d.name.c_str(), d.reason.c_str());
    std::printf(
        "with every pair:            RMS %.4f px, rectified row error mean %.4f px, "
        "max %.4f px\n",
        r.all_pairs_rms_px, r.all_pairs_mean_row_error_px, r.all_pairs_max_row_error_px);
  } else {
    std::printf("dropped pairs:              none (every pair agrees with the rest)\n");
  }
  std::printf("pairs used:                 %zu\n", r.pair_names.size());
  std::printf("RMS reprojection error:     %.4f px (stereo), left %.4f px, right %.4f px\n",
              c.rms_px, r.left_rms_px, r.right_rms_px);
  std::printf(
      "rectified row error:        mean %.4f px, max %.4f px (|y_left - y_right| of "
      "matched corners of the pairs used)\n",
      r.mean_rectified_row_error_px, r.max_rectified_row_error_px);
  std::printf("rectified focal length:     %.2f px\n", stereoball::stereo::focal_px(c));
  std::printf("baseline:                   %.4f m (square size %.3g mm)\n",
              stereoball::stereo::baseline_m(c), square_mm);
  if (const auto problem = stereoball::stereo::single_camera_fit_problem(r))
    std::printf("note:                       %s\n", problem->c_str());
  std::printf("per-pair RMS error:\n");
  for (std::size_t i = 0; i < c.per_pair_rms_px.size(); ++i) {
    std::printf("  %-28s %.4f px\n", r.pair_names[i].c_str(), c.per_pair_rms_px[i]);
  }
}

// Side-by-side rectified pairs with horizontal guide lines, for a visual check.
stereoball::Status save_rectified(const std::string& dir, const PairList& pairs,
                                  const stereoball::stereo::StereoCalibration& calib) {
  auto rect = stereoball::stereo::Rectifier::create(calib);
  if (!rect) return stereoball::Error{rect.error()};
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return stereoball::Error{dir + ": cannot create (" + ec.message() + ")"};
  for (const auto& [lp, rp] : pairs) {
    cv::Mat l, r, both;
    if (!rect->rectify(cv::imread(lp), cv::imread(rp), l, r).ok()) continue;
    cv::hconcat(l, r, both);
    for (int y = 0; y < both.rows; y += 24) {
      cv::line(both, {0, y}, {both.cols - 1, y}, cv::Scalar(0, 255, 0), 1);
    }
    const std::string out =
        dir + "/rectified_" + std::filesystem::path(lp).stem().string() + ".png";
    if (!cv::imwrite(out, both)) return stereoball::Error{out + ": cannot write"};
  }
  return {};
}

int run(const Options& o) {
  const auto board = stereoball::stereo::parse_board_size(o.board);
  if (!board)
    return fail("--board '" + o.board + "': expected COLSxROWS of inner corners, e.g. 9x6");
  BoardCalibrationParams params;
  params.inner_corners = *board;
  params.square_m = o.square_mm * 1e-3;
  params.min_pairs = o.min_pairs;
  params.subpix_window_px = o.subpix_window_px;
  params.rectify.alpha = o.alpha;
  params.outlier_ratio = o.outlier_ratio;
  params.outlier_min_px = o.outlier_min_px;
  if (auto error = params.validate(); !error) return fail(error.error());
  std::optional<cv::Size> size;
  std::vector<PairCorners> corners;
  stereoball::Result<PairList> pairs = PairList{};
  if (!o.sequence.empty()) {
    stereoball::stereo::StillBoardParams still;
    still.still_ns = static_cast<int64_t>(o.still_ms * 1e6);
    still.max_motion_px = o.still_px;
    if (auto error = still.validate(); !error)
      return fail("--still-ms/--still-px: " + error.error());
    const auto frames = load_sequence(o.sequence);
    if (!frames) return fail(frames.error());
    std::cout << "detecting " << board->width << "x" << board->height << " board in "
              << frames->size() << " frames; a pose is taken when it stood still (< " << o.still_px
              << " px) in both eyes for " << o.still_ms << " ms\n";
    auto found = detect_sequence(*frames, params, still, size, *pairs);
    if (!found) return fail(found.error());
    corners = std::move(*found);
    if (static_cast<int>(corners.size()) < params.min_pairs) {
      return fail("the board stood still in both eyes for only " + std::to_string(corners.size()) +
                  " poses, need at least " + std::to_string(params.min_pairs) +
                  " (--min-pairs): hold it still longer than --still-ms at each pose");
    }
  } else {
    pairs = collect_pairs(o);
    if (!pairs) return fail(pairs.error());
    std::cout << "detecting " << board->width << "x" << board->height << " board in "
              << pairs->size() << " pairs\n";
    corners = detect_all(pairs.value(), params, size);
    if (static_cast<int>(corners.size()) < params.min_pairs) {
      return fail("board found in only " + std::to_string(corners.size()) + " of " +
                  std::to_string(pairs->size()) + " pairs, need at least " +
                  std::to_string(params.min_pairs) + " (--min-pairs)");
    }
  }
  const auto result = stereoball::stereo::calibrate_stereo(corners, *size, params);
  if (!result) return fail(result.error());
  print_report(result.value(), o.square_mm);
  if (auto swapped = stereoball::stereo::check_camera_order(result->calibration); !swapped) {
    return fail(swapped.error() + ": swap " +
                (!o.sequence.empty() ? std::string("the left and right columns of ") + o.sequence
                 : o.pairs_list.empty()
                     ? std::string("--left-glob and --right-glob")
                     : std::string("the left and right file of each pair in ") + o.pairs_list) +
                " (and the cameras' left/right devices if the images came from camera_server) and "
                "calibrate again; nothing written");
  }
  stereoball::stereo::CalibrationFileInfo info;
  info.mean_rectified_row_error_px = result->mean_rectified_row_error_px;
  info.square_size_m = params.square_m;
  info.board_inner_corners = *board;
  info.pair_names = result->pair_names;
  info.note = "written by stereoball-calibrate";
  if (auto error = stereoball::stereo::save_calibration(o.output, result->calibration, info);
      !error) {
    return fail(error.error());
  }
  std::cout << "wrote " << o.output << "\n";
  if (!o.save_rectified_dir.empty()) {
    if (auto error = save_rectified(o.save_rectified_dir, pairs.value(), result->calibration);
        !error) {
      return fail(error.error());
    }
    std::cout << "wrote rectified pairs to " << o.save_rectified_dir << "\n";
  }
  return 0;
}

}  // namespace

// `--live` hands the whole command line (less that flag) to stereoball-calibrate-live, which
// sits beside this program (build/bin or libexec/stereoball).
void exec_live_if_asked(int argc, char** argv) {
  std::vector<std::string> args;
  bool live = false;
  for (int i = 1; i < argc; ++i) {
    if (std::string_view(argv[i]) == "--live")
      live = true;
    else
      args.emplace_back(argv[i]);
  }
  if (!live) return;
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const auto program =
      (ec ? std::filesystem::path(argv[0]) : self).parent_path() / "stereoball-calibrate-live";
  std::vector<char*> live_argv{const_cast<char*>(program.c_str())};
  for (auto& a : args) live_argv.push_back(a.data());
  live_argv.push_back(nullptr);
  execv(program.c_str(), live_argv.data());
  std::fprintf(stderr, "stereoball-calibrate: --live: cannot start %s (%s)\n", program.c_str(),
               std::strerror(errno));
  std::exit(2);
}

int main(int argc, char** argv) {
  exec_live_if_asked(argc, argv);
  CLI::App app{
      "Stereo calibration from chessboard image pairs (sub-pixel corners, per-camera and joint "
      "stereo calibration, rectification). Writes one OpenCV FileStorage YAML with image size, "
      "K1 D1 K2 D2 R T R1 R2 P1 P2 Q, RMS and per-pair errors; prints the RMS, per-pair errors "
      "and the mean rectified row error of matched corners. Pairs without a visible board are "
      "listed and skipped.",
      "stereoball-calibrate"};
  Options o;
  auto* list = app.add_option("--pairs", o.pairs_list,
                              "image list in OpenCV stereo_calib.xml format (alternating left, "
                              "right; relative to the list's folder)")
                   ->check(CLI::ExistingFile);
  auto* lg = app.add_option("--left-glob", o.left_glob, "glob of left images (sorted by name)");
  auto* rg = app.add_option("--right-glob", o.right_glob, "glob of right images (sorted by name)");
  lg->needs(rg);
  rg->needs(lg);
  list->excludes(lg)->excludes(rg);
  auto* seq = app.add_option("--sequence", o.sequence,
                             "a recorded sequence: CSV 'left,right,left_stamp_ns,right_stamp_ns' "
                             "(as stereoball sim writes frames.csv for calibration scenes); takes "
                             "one pair per pose in which the board stood still in both eyes")
                  ->check(CLI::ExistingFile);
  seq->excludes(list)->excludes(lg)->excludes(rg);
  app.add_option("--still-ms", o.still_ms,
                 "with --sequence: how long the board must stand still in both eyes (each eye on "
                 "its own capture stamps)")
      ->capture_default_str();
  app.add_option("--still-px", o.still_px,
                 "with --sequence: the most a corner may move and still count as still, pixels")
      ->capture_default_str();
  app.add_option("--board", o.board, "inner corners per row x per column")->capture_default_str();
  app.add_option("--square-mm", o.square_mm, "chessboard square side in mm (sets the unit of T)")
      ->capture_default_str();
  app.add_option("--min-pairs", o.min_pairs, "fail if fewer pairs show the board")
      ->capture_default_str();
  app.add_option("--alpha", o.alpha,
                 "rectification zoom: 0 keeps only valid pixels, 1 keeps all source pixels")
      ->capture_default_str();
  app.add_option("--outlier-ratio", o.outlier_ratio,
                 "drop a pair whose stereo error against the calibration of the other pairs is "
                 "above this many times their median (and above --outlier-min-px): unsynchronised "
                 "cameras let the board move between the two shots; 0 keeps every pair")
      ->capture_default_str();
  app.add_option("--outlier-min-px", o.outlier_min_px,
                 "a pair is never dropped for an error below this, pixels")
      ->capture_default_str();
  app.add_option("--subpix-window", o.subpix_window_px, "cornerSubPix window size, pixels")
      ->capture_default_str();
  app.add_option("-o,--output", o.output, "calibration file to write (.yaml)")->required();
  app.add_option("--save-rectified", o.save_rectified_dir,
                 "also write side-by-side rectified pairs with row guide lines to this folder");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(e.what());
  }
  if (o.pairs_list.empty() && o.left_glob.empty() && o.sequence.empty()) {
    return fail("give the pairs with --pairs LIST, --left-glob G --right-glob G or --sequence CSV");
  }
  return run(o);
}
