#pragma once
// Deterministic synthetic scenes with ground-truth circles, for tests and the bench.
// Same seed and size -> bit-identical image on every platform (own RNG arithmetic).

#include "ball_detector/core/circle.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace stereoball::ball_detector {

/// Small deterministic generator (mt19937 raw output; own uniform and normal transforms).
class SceneRng {
 public:
  explicit SceneRng(std::uint32_t seed);
  double uniform(double lo, double hi);  ///< uniform in [lo, hi)
  double normal(double sigma);           ///< zero-mean Gaussian
  int integer(int lo, int hi);           ///< uniform in [lo, hi]

 private:
  std::uint32_t next();
  std::uint64_t state_;
};

/// What a ball looks like.
struct BallSpec {
  Circle circle;                  ///< position and radius, pixels (score unused)
  cv::Scalar colour{0, 0, 200};   ///< main colour, BGR
  cv::Scalar colour2{0, 0, 200};  ///< second colour (two-colour textures), BGR
  bool two_colour = false;        ///< curved seam splits the ball into two colours
  double seam_angle_rad = 0.0;    ///< orientation of the seam
  double shading = 0.25;          ///< darkening toward the rim (3D look), [0, 1)
};

/// Draws an anti-aliased (4x4 supersampled) ball onto a CV_8UC3 image.
void render_ball(cv::Mat& bgr, const BallSpec& ball);

/// Kinds of scene in the suite.
enum class SceneKind {
  kPlain,
  kTwoColour,
  kLighting,
  kNoise,
  kBlur,
  kOcclusion,
  kClutter,
  kMultiple,
  kNoBall,
  kLinesOnly
};

/// Display name of a scene kind.
std::string scene_kind_name(SceneKind kind);

/// An orange disc on grey with three white spots of spot_radius_px centred spot_offset_px from
/// its centre, exact to 1/16 px (anti-aliased): with spot_offset + spot_radius a pixel or two
/// short of radius, colour edges see each spot's boundary beside the rim, as on a panelled
/// ball near its outline.
cv::Mat spotted_disc_image(cv::Size size, cv::Point centre_px, int radius_px, int spot_offset_px,
                           int spot_radius_px);

/// One synthetic image and its ground truth (full visible-or-occluded ball discs).
struct SyntheticScene {
  cv::Mat image;              ///< CV_8UC3
  std::vector<Circle> truth;  ///< ground-truth circles (score 1)
  SceneKind kind = SceneKind::kPlain;
};

/// One scene of the given kind; deterministic in (kind, size, seed).
SyntheticScene make_scene(SceneKind kind, cv::Size size, std::uint32_t seed);

/// A 3-channel 8-bit img with Gaussian noise of sigma grey levels per channel, as a camera adds
/// (seeded: the same seed gives the same noise).
cv::Mat with_sensor_noise(const cv::Mat& img, int seed, double sigma = 2.0);

/// The bench suite: per_kind scenes of every kind at the given size.
std::vector<SyntheticScene> make_suite(cv::Size size, int per_kind, std::uint32_t seed);

}  // namespace stereoball::ball_detector
