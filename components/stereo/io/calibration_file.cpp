#include "stereo/io/calibration_file.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>

namespace stereoball::stereo {
namespace {

using CalibResult = Result<StereoCalibration>;

std::string shape_text(const cv::Mat& m) {
  return std::to_string(m.rows) + "x" + std::to_string(m.cols);
}

// An opencv-matrix node's header checked before OpenCV reads it: OpenCV allocates rows x cols
// as the header says (a garbled "rows" became 2^31 rows, 48 GB, found by fuzzing), so both must
// be small integers matching the data list.
Status check_matrix_header(const cv::FileNode& node, const char* name) {
  constexpr int kMaxSide = 16;  // the largest calibration matrix is 4x4, distortion 1x14
  if (!node.isMap()) return Error{std::string(name) + ": not a matrix"};
  const cv::FileNode rows = node["rows"], cols = node["cols"], data = node["data"];
  if (!rows.isInt() || !cols.isInt() || !data.isSeq()) {
    return Error{std::string(name) + ": not a matrix (needs integer rows, cols and a data list)"};
  }
  const int r = static_cast<int>(rows), c = static_cast<int>(cols);
  if (r < 1 || c < 1 || r > kMaxSide || c > kMaxSide) {
    return Error{std::string(name) + ": " + std::to_string(r) + "x" + std::to_string(c) +
                 " is not a calibration matrix size (1-" + std::to_string(kMaxSide) + " per side)"};
  }
  if (data.size() != static_cast<std::size_t>(r) * static_cast<std::size_t>(c)) {
    return Error{std::string(name) + ": data has " + std::to_string(data.size()) + " values for " +
                 std::to_string(r) + "x" + std::to_string(c)};
  }
  return {};
}

// Reads the matrix node `name` into m (any shape); error names the field.
Status read_matrix_node(const cv::FileStorage& fs, const char* name, cv::Mat& m) {
  const cv::FileNode node = fs[name];
  if (node.empty() || node.isNone()) return Error{std::string(name) + ": missing"};
  if (auto e = check_matrix_header(node, name); !e) return e;
  try {
    node >> m;
  } catch (const std::exception&) {  // cv::Exception or what OpenCV lets through
    return Error{std::string(name) + ": not a matrix"};
  }
  return {};
}

// Reads a matrix node of exactly rows x cols into out; error names the field.
template <int M, int N>
Status read_matx(const cv::FileStorage& fs, const char* name, cv::Matx<double, M, N>& out) {
  cv::Mat m;
  if (auto e = read_matrix_node(fs, name, m); !e) return e;
  if (m.empty()) return Error{std::string(name) + ": not a matrix"};
  if (m.total() != static_cast<std::size_t>(M * N) || m.channels() != 1 ||
      (m.rows != M && !(N == 1 && m.cols == M && m.rows == 1))) {
    return Error{std::string(name) + ": expected " + std::to_string(M) + "x" + std::to_string(N) +
                 ", got " + shape_text(m)};
  }
  m.convertTo(m, CV_64F);
  out = cv::Matx<double, M, N>(reinterpret_cast<const double*>(m.reshape(1, 1).data));
  return {};
}

Status read_distortion(const cv::FileStorage& fs, const char* name, std::vector<double>& out) {
  cv::Mat m;
  if (auto e = read_matrix_node(fs, name, m); !e) return e;
  if (m.channels() != 1 || (m.rows != 1 && m.cols != 1) || !is_valid_distortion_size(m.total())) {
    return Error{std::string(name) + ": expected 1xN with N in {4, 5, 8, 12, 14}, got " +
                 shape_text(m)};
  }
  m.convertTo(m, CV_64F);
  m = m.reshape(1, 1).clone();
  out.assign(m.begin<double>(), m.end<double>());
  return {};
}

Status read_size(const cv::FileStorage& fs, cv::Size& out) {
  const cv::FileNode w = fs["image_width"], h = fs["image_height"];
  if (w.empty() || w.isNone()) return Error{"image_width: missing"};
  if (h.empty() || h.isNone()) return Error{"image_height: missing"};
  if (!w.isInt()) return Error{"image_width: not an integer"};
  if (!h.isInt()) return Error{"image_height: not an integer"};
  out = cv::Size(static_cast<int>(w), static_cast<int>(h));
  return {};
}

Status read_all(const cv::FileStorage& fs, StereoCalibration& c) {
  if (auto e = read_size(fs, c.image_size); !e) return e;
  if (auto e = read_matx(fs, "K1", c.k1); !e) return e;
  if (auto e = read_distortion(fs, "D1", c.d1); !e) return e;
  if (auto e = read_matx(fs, "K2", c.k2); !e) return e;
  if (auto e = read_distortion(fs, "D2", c.d2); !e) return e;
  if (auto e = read_matx(fs, "R", c.r); !e) return e;
  if (auto e = read_matx(fs, "T", c.t); !e) return e;
  if (auto e = read_matx(fs, "R1", c.r1); !e) return e;
  if (auto e = read_matx(fs, "R2", c.r2); !e) return e;
  if (auto e = read_matx(fs, "P1", c.p1); !e) return e;
  if (auto e = read_matx(fs, "P2", c.p2); !e) return e;
  if (auto e = read_matx(fs, "Q", c.q); !e) return e;
  // Quality figures are optional: a hand-made or simulated calibration has none.
  const cv::FileNode rms = fs["rms_px"];
  if (!rms.empty() && !rms.isNone()) {
    if (!rms.isReal() && !rms.isInt()) return Error{"rms_px: not a number"};
    c.rms_px = static_cast<double>(rms);
  }
  const cv::FileNode per_pair = fs["per_pair_rms_px"];
  if (!per_pair.empty() && !per_pair.isNone()) {
    if (!per_pair.isSeq()) return Error{"per_pair_rms_px: not a sequence"};
    for (const auto& v : per_pair) c.per_pair_rms_px.push_back(static_cast<double>(v));
  }
  return validate_calibration(c);
}

CalibResult parse_storage(cv::FileStorage& fs, const std::string& origin) {
  StereoCalibration c;
  try {
    if (auto e = read_all(fs, c); !e) return Error{origin + ": " + e.error()};
  } catch (const cv::Exception& ex) {
    return Error{origin + ": malformed calibration (" + ex.err + ")"};
  } catch (const std::exception& ex) {
    return Error{origin + ": malformed calibration (" + ex.what() + ")"};
  }
  return c;
}

// No distortion is written as five zeros so every file has the same shape.
cv::Mat distortion_row(const std::vector<double>& d) {
  if (d.empty()) return cv::Mat::zeros(1, 5, CV_64F);
  return cv::Mat(d, true).reshape(1, 1);
}

void write_all(cv::FileStorage& fs, const StereoCalibration& c, const CalibrationFileInfo& info) {
  fs << "image_width" << c.image_size.width << "image_height" << c.image_size.height;
  fs << "K1" << cv::Mat(c.k1) << "D1" << distortion_row(c.d1);
  fs << "K2" << cv::Mat(c.k2) << "D2" << distortion_row(c.d2);
  fs << "R" << cv::Mat(c.r) << "T" << cv::Mat(c.t);
  fs << "R1" << cv::Mat(c.r1) << "R2" << cv::Mat(c.r2);
  fs << "P1" << cv::Mat(c.p1) << "P2" << cv::Mat(c.p2) << "Q" << cv::Mat(c.q);
  fs << "rms_px" << c.rms_px;
  fs << "per_pair_rms_px"
     << "[";
  for (double e : c.per_pair_rms_px) fs << e;
  fs << "]";
  if (info.mean_rectified_row_error_px >= 0) {
    fs << "mean_rectified_row_error_px" << info.mean_rectified_row_error_px;
  }
  if (info.square_size_m > 0) fs << "square_size_m" << info.square_size_m;
  if (!info.board_inner_corners.empty()) {
    fs << "board_inner_corners"
       << "[" << info.board_inner_corners.width << info.board_inner_corners.height << "]";
  }
  if (!info.pair_names.empty()) {
    fs << "pairs"
       << "[";
    for (const auto& n : info.pair_names) fs << n;
    fs << "]";
  }
  if (!info.note.empty()) fs << "note" << info.note;
}

// What OpenCV's FileStorage must not see. Its YAML reader (4.6) loops forever on text after
// the document marker on the same line followed by a malformed value ("---a: t\nb: -\nc",
// found by fuzzing); OpenCV writes "---" on a line of its own. A calibration is a few KiB.
Status check_before_opencv(const std::string& text) {
  constexpr std::size_t kMaxBytes = std::size_t{1} << 20;
  if (text.size() > kMaxBytes) return Error{"larger than 1 MiB (these files are a few KiB)"};
  std::size_t line = 1;
  for (std::size_t at = 0; at < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view l(text.data() + at, end - at);
    if (l.substr(0, 3) == "---" && l.find_first_not_of(" \t\r", 3) != std::string_view::npos) {
      return Error{"line " + std::to_string(line) + ": text after the document marker '---'"};
    }
    at = end + 1;
  }
  return {};
}

// Reads a file that OpenCV will parse, bounded and checked first (see check_before_opencv);
// what names the kind of file in errors.
Result<std::string> read_small_file(const std::string& path, const char* what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{path + ": no such " + what};
  const auto size = std::filesystem::file_size(path, ec);
  if (ec || size > (std::uintmax_t{1} << 20)) {
    return Error{path + ": cannot be read, or larger than 1 MiB (a " + what + " is a few KiB)"};
  }
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in && !in.eof()) return Error{path + ": cannot be read"};
  if (auto e = check_before_opencv(text); !e) return Error{path + ": " + e.error()};
  return text;
}

// Parses calibration text (YAML, XML or JSON, as OpenCV writes them); origin names it in errors.
CalibResult parse_text(const std::string& text, const std::string& origin) {
  if (auto e = check_before_opencv(text); !e) return Error{origin + ": " + e.error()};
  cv::FileStorage fs;
  try {
    if (!fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY)) {
      return Error{origin + ": cannot be parsed as OpenCV FileStorage (YAML/XML/JSON)"};
    }
  } catch (const cv::Exception& ex) {
    return Error{origin + ": not a valid calibration (" + ex.err + ")"};
  } catch (const std::exception& ex) {  // OpenCV's parser also lets std::length_error out
    return Error{origin + ": not a valid calibration (" + ex.what() + ")"};
  }
  return parse_storage(fs, origin);
}

}  // namespace

CalibResult load_calibration(const std::string& path) {
  auto text = read_small_file(path, "calibration file");
  if (!text.ok()) return Error{text.error()};
  return parse_text(text.value(), path);
}

CalibResult parse_calibration(const std::string& text) {
  return parse_text(text, "calibration text");
}

std::string calibration_to_yaml(const StereoCalibration& calib, const CalibrationFileInfo& info) {
  cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  write_all(fs, calib, info);
  return fs.releaseAndGetString();
}

Status save_calibration(const std::string& path, const StereoCalibration& calib,
                        const CalibrationFileInfo& info) {
  if (auto e = validate_calibration(calib); !e)
    return Error{"refusing to write invalid calibration: " + e.error()};
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE);
    if (!fs.isOpened()) return Error{path + ": cannot open for writing"};
    write_all(fs, calib, info);
    fs.release();
  } catch (const cv::Exception& ex) {
    return Error{path + ": write failed (" + ex.err + ")"};
  }
  return {};
}

Result<std::vector<std::pair<std::string, std::string>>> load_pair_list(const std::string& path) {
  auto text = read_small_file(path, "pair list");
  if (!text.ok()) return Error{text.error()};
  std::vector<std::string> names;
  try {
    cv::FileStorage fs(text.value(), cv::FileStorage::READ | cv::FileStorage::MEMORY);
    if (!fs.isOpened()) return Error{path + ": cannot be read as OpenCV FileStorage"};
    const cv::FileNode list = fs.getFirstTopLevelNode();
    if (!list.isSeq()) return Error{path + ": first entry is not a list of image names"};
    for (const auto& n : list) {
      if (!n.isString()) return Error{path + ": list entry is not a string"};
      names.push_back(static_cast<std::string>(n));
    }
  } catch (const cv::Exception& ex) {
    return Error{path + ": malformed pair list (" + ex.err + ")"};
  } catch (const std::exception& ex) {
    return Error{path + ": malformed pair list (" + ex.what() + ")"};
  }
  if (names.empty()) return Error{path + ": image list is empty"};
  if (names.size() % 2 != 0) {
    return Error{path + ": odd number of images (" + std::to_string(names.size()) +
                 "), expected alternating left, right"};
  }
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::vector<std::pair<std::string, std::string>> pairs;
  for (std::size_t i = 0; i < names.size(); i += 2) {
    auto resolve = [&](const std::string& n) {
      const std::filesystem::path p(n);
      return (p.is_absolute() ? p : dir / p).string();
    };
    pairs.emplace_back(resolve(names[i]), resolve(names[i + 1]));
  }
  return pairs;
}

}  // namespace stereoball::stereo
