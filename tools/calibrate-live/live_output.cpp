#include "live_output.hpp"

#include <filesystem>
#include <system_error>

#include "stereo/io/calibration_file.hpp"

namespace stereoball::calibrate_live {

Status write_live_calibration(const std::string& path, const LiveParams& params,
                              const Verdict& verdict, const std::string& note) {
  if (!verdict.pass) return Error{path + ": not written, the verdict failed"};
  if (path.empty()) return Error{"no output file given (-o FILE)"};
  stereo::CalibrationFileInfo info;
  info.mean_rectified_row_error_px = verdict.result.mean_rectified_row_error_px;
  info.square_size_m = params.board.square_m;
  info.board_inner_corners = params.board.inner_corners;
  info.pair_names = verdict.result.pair_names;
  info.note = note;
  // Written beside, then renamed: a reader watching path (camera_server) never sees half a
  // file. The temporary keeps the extension, which picks the format.
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path partial = target.parent_path() / ("." + target.stem().string() + ".writing" +
                                                   target.extension().string());
  if (auto st = stereo::save_calibration(partial.string(), verdict.result.calibration, info); !st)
    return st;
  std::error_code ec;
  fs::rename(partial, target, ec);
  if (ec) {
    fs::remove(partial, ec);
    return Error{path + ": cannot write (" + ec.message() + ")"};
  }
  return {};
}

}  // namespace stereoball::calibrate_live
