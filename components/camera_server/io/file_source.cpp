#include "camera_server/io/file_source.hpp"

#include <glob.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace stereoball::camera_server {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> glob_files(const std::string& pattern) {
  std::vector<std::string> out;
  glob_t g{};
  if (::glob(pattern.c_str(), 0, nullptr, &g) == 0) {
    for (size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  }
  ::globfree(&g);
  std::sort(out.begin(), out.end());
  return out;
}

Result<std::vector<std::pair<std::string, std::string>>> pairs_from_globs(
    const FileSourceParams& p) {
  const auto left = glob_files(p.left_glob);
  const auto right = glob_files(p.right_glob);
  if (left.empty()) return fail("left_glob \"" + p.left_glob + "\" matched no files");
  if (right.empty()) return fail("right_glob \"" + p.right_glob + "\" matched no files");
  if (left.size() != right.size()) {
    return fail("left_glob matched " + std::to_string(left.size()) + " files but right_glob " +
                std::to_string(right.size()) + "; they must pair one to one");
  }
  std::vector<std::pair<std::string, std::string>> out;
  for (size_t i = 0; i < left.size(); ++i) out.emplace_back(left[i], right[i]);
  return out;
}

Result<std::vector<std::pair<std::string, std::string>>> pairs_from_dir(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return fail("pairs_dir \"" + dir + "\" is not a folder");
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const size_t at = name.rfind("left");
    if (!entry.is_regular_file() || at == std::string::npos) continue;
    std::string partner = name;
    partner.replace(at, 4, "right");
    const fs::path right = entry.path().parent_path() / partner;
    if (!fs::is_regular_file(right, ec)) {
      return fail("pairs_dir: " + entry.path().string() + " has no partner " + right.string());
    }
    out.emplace_back(entry.path().string(), right.string());
  }
  if (out.empty()) return fail("pairs_dir \"" + dir + "\" holds no left*/right* image pairs");
  std::sort(out.begin(), out.end());
  return out;
}

int imread_flags(const std::string& encoding) {
  if (encoding == "bgr8") return cv::IMREAD_COLOR;
  if (encoding == "mono8") return cv::IMREAD_GRAYSCALE;
  return cv::IMREAD_UNCHANGED;
}

Result<cv::Mat> load(const std::string& path, const std::string& encoding) {
  cv::Mat m = cv::imread(path, imread_flags(encoding));
  if (m.empty()) return fail(path + ": cannot read or decode the image");
  if (m.depth() != CV_8U) return fail(path + ": only 8-bit images are supported");
  // as_read keeps grey or colour; an alpha channel carries nothing for the detector.
  if (m.channels() == 4) cv::cvtColor(m, m, cv::COLOR_BGRA2BGR);
  if (m.channels() != 1 && m.channels() != 3) {
    return fail(path + ": unsupported channel count " + std::to_string(m.channels()));
  }
  if (!m.isContinuous()) m = m.clone();
  return m;
}

std::string size_text(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows);
}

}  // namespace

Result<FileSource> FileSource::open(const FileSourceParams& params) {
  if (params.encoding != "as_read" && params.encoding != "bgr8" && params.encoding != "mono8") {
    return fail("file encoding must be as_read, bgr8 or mono8, got \"" + params.encoding + "\"");
  }
  auto names =
      params.pairs_dir.empty() ? pairs_from_globs(params) : pairs_from_dir(params.pairs_dir);
  if (!names) return Error{names.error()};
  FileSource src;
  src.description_ = params.pairs_dir.empty()
                         ? "files:" + params.left_glob + "+" + params.right_glob
                         : "files:" + params.pairs_dir;
  for (const auto& [lp, rp] : *names) {
    auto l = load(lp, params.encoding);
    if (!l) return Error{l.error()};
    auto r = load(rp, params.encoding);
    if (!r) return Error{r.error()};
    if (l->size() != r->size() || l->type() != r->type()) {
      return fail(lp + " is " + size_text(*l) + " with " + std::to_string(l->channels()) +
                  " channel(s) but " + rp + " is " + size_text(*r) + " with " +
                  std::to_string(r->channels()));
    }
    if (!src.pairs_.empty() && (l->size() != src.pairs_.front().left.size() ||
                                l->type() != src.pairs_.front().left.type())) {
      return fail(lp + " (" + size_text(*l) + ", " + std::to_string(l->channels()) +
                  " channel(s)) differs from " + src.pairs_.front().left_path + " (" +
                  size_text(src.pairs_.front().left) +
                  "); all pairs must share size and encoding (file_encoding bgr8 or mono8 "
                  "unifies colour and grey)");
    }
    src.pairs_.push_back(FilePair{lp, rp, std::move(*l), std::move(*r)});
  }
  src.encoding_ = src.pairs_.front().left.channels() == 1 ? "mono8" : "bgr8";
  return src;
}

}  // namespace stereoball::camera_server
