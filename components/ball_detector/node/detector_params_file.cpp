#include "ball_detector/node/detector_params_file.hpp"

#include <cmath>

namespace stereoball::ball_detector {
namespace {

void read_k_values(params::ParamsFile& file, std::vector<int>& out) {
  std::vector<double> ks;
  file.read("p2p.k_values", ks);
  out.clear();
  for (double k : ks) {
    if (k != std::floor(k) || k < 1 || k > 31) {
      file.fail(file.name() + ": key 'p2p.k_values': entries must be whole numbers in [1, 31]");
      return;
    }
    out.push_back(static_cast<int>(k));
  }
}

// Only the detector settings a deployment tunes; the rest keep the core's defaults.
void read_p2p(params::ParamsFile& file, PixelToPixelParams& p) {
  read_k_values(file, p.k_values);
  file.read("p2p.min_radius_px", p.min_radius_px, 0.0, 4000.0);
  file.read("p2p.max_radius_px", p.max_radius_px, 1.0, 4000.0);
  file.read("p2p.min_separation_px", p.min_separation_px, 0.0, 4000.0);
  file.read("p2p.min_score", p.min_score, 0.0, 1.0);
  file.read("p2p.max_peaks_examined", p.max_peaks_examined, 1, 1000);
  file.read("p2p.edge_min_threshold", p.edge.min_high_threshold, 1.0, 1000.0);
  file.read("p2p.min_inside_fraction", p.refine_params.min_inside_fraction, 0.0, 1.0);
}

}  // namespace

Result<BallDetectorParams> read_detector_params(params::ParamsFile& file) {
  BallDetectorParams p;
  file.read("ball.diameter_m", p.ball_diameter_m, 0.001, 5.0);
  file.read("epipolar.tolerance_px", p.epipolar_tolerance_px, 0.0, 100.0);
  file.read("size.max_relative_error", p.size_max_relative_error, 0.001, 10.0);
  file.read("max_candidates_per_eye", p.max_candidates_per_eye, 1, 50);
  file.read("right_eye_partner_boxes", p.right_eye_partner_boxes);
  file.read("predicted_partner.enabled", p.predicted_partner);
  file.read("predicted_partner.min_inside_fraction", p.predicted_partner_min_inside_fraction, 0.0,
            1.0);
  file.read("track_prior.gate_m", p.track_prior_gate_m, 0.0, 10.0);
  file.read("track_prior.window", p.prior_window);
  file.read("track_prior.max_age_ns", p.track_prior_max_age_ns, std::int64_t{0},
            std::int64_t{10'000'000'000});
  file.read("track_prior.min_inside_fraction", p.prior_min_inside_fraction, 0.0, 1.0);
  std::string input = to_string(p.input);
  file.read_choice("input", input, {"grey", "saturation", "value", "red", "green", "blue"});
  if (auto parsed = parse_detector_input(input)) p.input = *parsed;
  read_p2p(file, p.p2p);
  file.read("p2p.perspective_outline", p.perspective_outline);
  file.read("floor.camera_height_m", p.floor_camera_height_m, 0.0, 10.0);
  file.read("floor.camera_pitch_rad", p.floor_camera_pitch_rad, -1.57, 1.57);
  file.read("floor.tolerance_m", p.floor_tolerance_m, 0.0, 10.0);
  file.read("appearance.enabled", p.appearance.enabled);
  file.read("appearance.min_similarity", p.appearance.min_similarity, 0.0, 1.0);
  file.read("appearance.learn_rate", p.appearance.learn_rate, 0.001, 1.0);
  file.read("appearance.frames_to_learn", p.appearance.frames_to_learn, 1, 1000);
  file.read("appearance.forget_after_ns", p.appearance.forget_after_ns, std::int64_t{0},
            std::int64_t{3'600'000'000'000});
  if (auto e = p.validate()) file.fail(file.name() + ": " + *e);
  if (auto e = file.finish()) return Error{*e};
  return p;
}

Result<BallDetectorParams> load_detector_params(const std::string& path) {
  auto file = params::ParamsFile::load(path);
  if (!file) return Error{file.error()};
  return read_detector_params(*file);
}

}  // namespace stereoball::ball_detector
