#include "tracking_run.hpp"

#include <algorithm>
#include <cmath>

#include "ball_detector/core/circle_fit.hpp"
#include "stereo/core/sphere_outline.hpp"

namespace stereoball::bench_tracking {
namespace {

namespace bd = ball_detector;

FrameRecord judge(const simulator::GroundTruth& g, const bd::StereoDetection& d,
                  const tracker::Track& track) {
  FrameRecord r;
  r.ball_present = g.ball_present;
  r.ball_visible = g.ball_present && g.ball_visible_left && g.ball_visible_right;
  r.ball_fully_visible = g.ball_present && g.ball_fully_visible_left && g.ball_fully_visible_right;
  r.raw_found = d.status == bd::DetectionStatus::kFound;
  r.accepted = tracker::is_accepted(track.verdict);
  r.stamp_ns = static_cast<std::int64_t>(std::llround(g.sim_time_s * 1e9));
  r.detection_status = bd::to_string(d.status);
  r.search = bd::to_string(d.search);
  r.detection_reason = d.reason;
  r.verdict = std::string(tracker::to_string(track.verdict));
  r.verdict_reason = track.reason;
  r.track_state = std::string(tracker::to_string(track.state));
  r.found_left_x_px = d.left.x_px, r.found_left_y_px = d.left.y_px;
  r.found_radius_px = d.left.radius_px;
  r.no_ball_in_view = !r.ball_present;
  if (!r.ball_present) return r;
  r.true_left_x_px = g.ball_left_px.x, r.true_left_y_px = g.ball_left_px.y;
  const auto& c = g.ball_camera_m;
  r.true_distance_m = std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
  if (r.raw_found) {
    // In 3D: a close ball's outline centre lies pixels away from where its centre projects
    // (10 px at 0.45 m), yet the detection is of the ball. Judged also when its centre is out
    // of one image (the ball entering or leaving the view): a detection of it is not off-ball.
    const double ex = d.position_m[0] - c.x, ey = d.position_m[1] - c.y, ez = d.position_m[2] - c.z;
    const double error_m = std::sqrt(ex * ex + ey * ey + ez * ez);
    r.raw_on_ball = error_m <= g.ball_radius_m;
    if (r.raw_on_ball && r.ball_visible) {  // the error table keeps to the visible ball
      r.error_m = error_m;
      r.error_xyz_m[0] = ex, r.error_xyz_m[1] = ey, r.error_xyz_m[2] = ez;
    }
  }
  r.accepted_on_ball = r.accepted && r.raw_on_ball;
  r.no_ball_in_view = !g.ball_visible_left && !g.ball_visible_right && !r.raw_on_ball;
  return r;
}

// A candidate that is the ball's outline: centre and radius close to the true ones.
bool on_outline(const bd::Circle& c, double x_px, double y_px, double r_px) {
  return std::hypot(c.x_px - x_px, c.y_px - y_px) <= std::max(3.0, 0.2 * r_px) &&
         std::abs(c.radius_px - r_px) <= 0.25 * r_px;
}

bool any_on_outline(const std::vector<bd::Circle>& cs, double x_px, double y_px, double r_px) {
  return std::any_of(cs.begin(), cs.end(),
                     [&](const bd::Circle& c) { return on_outline(c, x_px, y_px, r_px); });
}

// Whether refinement seeded with the true circle itself stays on the outline and scores
// min_score: if so, a miss comes from the peaks (none on the ball, or one merged into a
// neighbour); if not, the refinement is pulled off even from a perfect seed.
bool refines_onto_outline(const bd::EdgeMap& edges, const bd::Circle& truth,
                          const bd::RefineParams& scoring, double min_score) {
  const auto refined = bd::refine_circle(edges, truth, scoring);
  return refined && refined->score >= min_score &&
         on_outline(*refined, truth.x_px, truth.y_px, truth.radius_px);
}

// Where the chain lost a fully visible ball (FrameRecord::miss_cause).
void diagnose_miss(const bd::StereoPipeline& pipeline, const bd::BallDetectorParams& params,
                   const simulator::GroundTruth& g, const bd::StereoDetection& d, FrameRecord& r) {
  if (!r.ball_fully_visible || r.accepted_on_ball) return;
  if (r.raw_on_ball) {
    r.miss_cause = "tracker";
    return;
  }
  const auto camera = pipeline.left_camera();
  if (!camera) return;
  const auto& c = g.ball_camera_m;
  const auto outline = stereo::sphere_outline(*camera, cv::Vec3d(c.x, c.y, c.z), g.ball_radius_m);
  if (!outline) return;
  const double r_px = outline->mean_radius_px();
  r.true_radius_px = r_px;
  const cv::Point2d centre = outline->centre_px;
  // The true outline against the edges the left detector saw last (whole eye or a crop).
  const bd::EdgeMap& edges = pipeline.left_edges();
  bd::RefineParams scoring = params.detector_params().refine_params;
  if (params.perspective_outline) scoring.camera = camera;
  const bd::Circle truth{centre.x + edges.frame_px.x, centre.y + edges.frame_px.y, r_px, 0.0};
  r.truth_coverage = edges.edges.empty() ? -1.0 : bd::score_circle(edges, truth, scoring);
  const bool left_ok = any_on_outline(pipeline.left_candidates(), centre.x, centre.y, r_px);
  const double right_x = centre.x + (g.ball_right_px.x - g.ball_left_px.x);
  const bool right_ok = any_on_outline(pipeline.right_candidates(), right_x, centre.y, r_px);
  if (!left_ok) {
    r.miss_cause = r.truth_coverage < params.p2p.min_score ? "left_edges"
                   : refines_onto_outline(edges, truth, scoring, params.p2p.min_score)
                       ? "left_peaks"
                       : "left_refine";
  } else if (!right_ok) {
    r.miss_cause = "right_search";
  } else if (d.status != bd::DetectionStatus::kFound) {
    r.miss_cause = std::string("pair_") + bd::to_string(d.status);
  } else {
    r.miss_cause = "pair_other";
  }
}

// For a detection with the ball in view, on it or not: how far each eye's circle lies from the
// true outline there (off the ball, this tells which eye's circle took the pair off it).
void measure_outline_errors(const bd::StereoPipeline& pipeline, const simulator::GroundTruth& g,
                            const bd::StereoDetection& d, FrameRecord& r) {
  if (!r.raw_found || !r.ball_visible) return;
  const auto& c = g.ball_camera_m;
  const cv::Vec3d centre_left(c.x, c.y, c.z);
  const auto left_camera = pipeline.left_camera();
  const auto right_camera = pipeline.right_camera();
  if (!left_camera || !right_camera || c.z <= 0) return;
  // The right rectified camera sits one baseline to the right; the truth's projected right
  // centre gives that baseline without reaching into the pipeline.
  const double baseline_m =
      c.x - (g.ball_right_px.x - right_camera->principal_px.x) * c.z / right_camera->focal_px;
  const cv::Vec3d centre_right(c.x - baseline_m, c.y, c.z);
  const auto write = [&](const std::optional<stereo::SphereOutline>& o, const bd::Circle& found,
                         double* out) {
    if (!o) return;
    out[0] = found.x_px - o->centre_px.x;
    out[1] = found.y_px - o->centre_px.y;
    out[2] = found.radius_px - o->mean_radius_px();
  };
  write(stereo::sphere_outline(*left_camera, centre_left, g.ball_radius_m), d.left,
        r.outline_error_left_px);
  write(stereo::sphere_outline(*right_camera, centre_right, g.ball_radius_m), d.right,
        r.outline_error_right_px);
}

}  // namespace

RunOutcome run_scenario(const RunConfig& config, const FrameSink& on_frame) {
  RunOutcome out;
  out.result.scenario = config.scenario.name;
  auto loop = sim_loop::SimLoop::create(config);
  if (!loop) {
    out.error = loop.error();
    return out;
  }
  while ((*loop)->frames_done() < (*loop)->frame_count()) {
    const std::int64_t index = (*loop)->frames_done();
    const sim_loop::LoopFrame f = (*loop)->step();
    if (on_frame) on_frame(index, f);
    FrameRecord r = judge(f.truth, f.detection, f.track);
    diagnose_miss((*loop)->pipeline(), config.detector, f.truth, f.detection, r);
    measure_outline_errors((*loop)->pipeline(), f.truth, f.detection, r);
    r.cpu_ms = f.detector_cpu_ms;
    r.wall_ms = f.detector_wall_ms;
    out.result.frames.push_back(r);
  }
  return out;
}

}  // namespace stereoball::bench_tracking
