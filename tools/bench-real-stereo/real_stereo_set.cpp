#include "real_stereo_set.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "ball_detector/pipeline/detector_params_file.hpp"
#include "common/params/params_file.hpp"
#include "common/params/yaml_load.hpp"

namespace stereoball::real_stereo {
namespace {

namespace fs = std::filesystem;

// Longest truth file read (a set of a few thousand pairs is a few hundred kB).
constexpr std::uintmax_t kMaxTruthBytes = 64u << 20;

Result<std::string> read_text(const std::string& path, std::uintmax_t max_bytes) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Error{path + ": no such file"};
  const auto size = fs::file_size(path, ec);
  if (ec) return Error{path + ": cannot read its size: " + ec.message()};
  if (size > max_bytes)
    return Error{path + ": " + std::to_string(size) + " bytes is larger than the " +
                 std::to_string(max_bytes) + " a truth file may have"};
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

Result<std::string> find_calibration(const std::string& dir) {
  const fs::path folder = fs::path(dir) / "calibration";
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    return Error{dir + ": no calibration/ folder (or give --calibration FILE)"};
  std::vector<std::string> yamls;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const auto ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".yaml" || ext == ".yml")) yamls.push_back(e.path());
  }
  if (yamls.size() != 1) {
    return Error{folder.string() + ": holds " + std::to_string(yamls.size()) +
                 " calibration files (*.yaml); exactly one expected (or give --calibration FILE)"};
  }
  return yamls.front();
}

// A node on one line (flow style), as the changed keys are listed.
std::string flow_text(const YAML::Node& node) {
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

// Merges over into base: mappings key by key, anything else replaced; every replaced value
// that differs from base's is added to changed as "dotted.key: value".
void merge(YAML::Node base, const YAML::Node& over, const std::string& prefix,
           std::vector<std::string>& changed) {
  for (const auto& kv : over) {
    const std::string key = kv.first.as<std::string>();
    const std::string path = prefix.empty() ? key : prefix + "." + key;
    if (kv.second.IsMap() && base[key] && base[key].IsMap()) {
      merge(base[key], kv.second, path, changed);
      continue;
    }
    const std::string value = flow_text(kv.second);
    if (!base[key] || flow_text(base[key]) != value) changed.push_back(path + ": " + value);
    base[key] = YAML::Clone(kv.second);
  }
}

std::string text_of(const YAML::Node& node) {
  YAML::Emitter out;
  out << node;
  return std::string(out.c_str()) + "\n";
}

}  // namespace

Result<std::vector<TruthRow>> load_truth(const std::string& path) {
  auto text = read_text(path, kMaxTruthBytes);
  if (!text) return Error{text.error()};
  return parse_truth(*text, path);
}

Result<RealStereoSet> open_set(const std::string& dir, const std::string& truth_path,
                               const std::string& calibration_path) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return Error{dir + ": no such folder (the real stereo set)"};
  for (const char* eye : {"left", "right"}) {
    if (!fs::is_directory(fs::path(dir) / eye, ec))
      return Error{dir + ": has no " + eye + "/ folder of images"};
  }
  RealStereoSet set;
  set.dir = dir;
  set.truth_path = truth_path.empty() ? dir + "/ball_truth.csv" : truth_path;
  if (calibration_path.empty()) {
    auto c = find_calibration(dir);
    if (!c) return Error{c.error()};
    set.calibration_path = *c;
  } else {
    if (!fs::is_regular_file(calibration_path, ec))
      return Error{calibration_path + ": no such calibration file"};
    set.calibration_path = calibration_path;
  }
  auto truth = load_truth(set.truth_path);
  if (!truth) return Error{truth.error()};
  set.truth = std::move(*truth);
  for (const auto& row : set.truth) {
    for (const auto& p : {set.left_path(row), set.right_path(row)}) {
      if (!fs::is_regular_file(p, ec))
        return Error{set.truth_path + ":" + std::to_string(row.line) + ": pair '" + row.pair +
                     "' names " + p + ", which does not exist"};
    }
  }
  const cv::Mat first = cv::imread(set.left_path(set.truth.front()), cv::IMREAD_UNCHANGED);
  if (first.empty()) return Error{set.left_path(set.truth.front()) + ": cannot read the image"};
  set.image_size = first.size();
  return set;
}

Result<cv::Size> parse_size(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || (in >> extra) || w < 16 || h < 16 ||
      w > 16384 || h > 16384) {
    return Error{"'" + text + "' is not a size WxH with sides in [16, 16384] (e.g. 2304x1296)"};
  }
  return cv::Size(w, h);
}

Result<DetectorConfig> compose_detector_config(const std::string& shipped_path,
                                               const DetectorOverrides& overrides) {
  auto base = params::load_yaml_file(shipped_path);
  if (!base) return Error{base.error()};
  DetectorConfig out;
  YAML::Node root = *base;
  if (!root.IsMap()) return Error{shipped_path + ": not a mapping of keys"};
  std::string name = shipped_path;
  if (!overrides.config_file.empty()) {
    auto over = params::load_yaml_file(overrides.config_file);
    if (!over) return Error{over.error()};
    if (!over->IsMap()) return Error{overrides.config_file + ": not a mapping of keys"};
    try {
      merge(root, *over, "", out.changed_keys);
    } catch (const YAML::Exception& e) {  // yaml-cpp reports a non-scalar key by throwing
      return Error{overrides.config_file + ": cannot merge: " + e.what()};
    }
    out.changes.push_back("keys of " + overrides.config_file);
    name = shipped_path + " + " + overrides.config_file;
  }
  if (overrides.ball_diameter_m) {
    root["ball"]["diameter_m"] = *overrides.ball_diameter_m;
    char value[32];
    std::snprintf(value, sizeof value, "%g", *overrides.ball_diameter_m);
    out.changes.push_back(std::string("ball.diameter_m: ") + value + " (--ball-diameter-m)");
  }
  if (overrides.no_floor_check) {
    root["floor"]["tolerance_m"] = 0.0;
    out.changes.push_back("floor.tolerance_m: 0 (--no-floor-check)");
  }
  if (overrides.image_limit) {
    root["image_limit"]["max_width_px"] = overrides.image_limit->width;
    root["image_limit"]["max_height_px"] = overrides.image_limit->height;
    out.changes.push_back("image_limit: " + std::to_string(overrides.image_limit->width) + "x" +
                          std::to_string(overrides.image_limit->height) + " (--image-limit)");
  }
  if (overrides.snapshot_skew_ns) {
    root["epipolar"]["skew_ns"] = *overrides.snapshot_skew_ns;
    out.changes.push_back("epipolar.skew_ns: " + std::to_string(*overrides.snapshot_skew_ns) +
                          " (--snapshot-skew-ms)");
  }
  out.yaml = text_of(root);
  auto file = params::ParamsFile::parse(out.yaml, "detector configuration (" + name + ")");
  if (!file) return Error{file.error()};
  auto p = ball_detector::read_detector_params(*file);
  if (!p) return Error{p.error()};
  out.params = *p;
  return out;
}

}  // namespace stereoball::real_stereo
