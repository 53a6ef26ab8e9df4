#pragma once
// The derived Foxglove messages (CDR, schemas in foxglove_schemas.hpp) built from what the
// viewer knows: images per eye, the detection drawn on each eye, the 3D scene (robot, ball
// estimate and its spread, register, predictions, search direction, ground truth) and the
// frame transforms between world, robot and camera. Stamps in ns since the epoch.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "viewer/core/foxglove_schemas.hpp"
#include "viewer/core/scene.hpp"
#include "viewer/core/view_model.hpp"

namespace stereoball::viewer::foxglove {

enum class Eye { kLeft, kRight };

/// Frame ids used in the 3D scene: world (simulator) -> robot (x forward, y left, z up) ->
/// camera (left rectified optical frame: x right, y down, z forward).
inline constexpr std::string_view kWorldFrame = "world";
inline constexpr std::string_view kRobotFrame = "robot";
inline constexpr std::string_view kCameraFrame = "camera";

/// foxglove.CompressedImage of one eye (format "jpeg").
std::vector<uint8_t> compressed_image(int64_t stamp_ns, Eye eye, std::span<const uint8_t> jpeg);

/// foxglove.ImageAnnotations for one eye: the circle, its centre, the epipolar row across the
/// image (width_px wide, as shown) and a text with the score or the rejection reason. scale is
/// shown pixels per detection pixel (below 1 when the eye is shown scaled down).
std::vector<uint8_t> image_annotations(const Detection& d, Eye eye, uint32_t width_px,
                                       double scale = 1.0);

/// foxglove.SceneUpdate replacing every entity with the scene's current state.
std::vector<uint8_t> scene_update(const Scene& scene, int64_t stamp_ns);

/// foxglove.FrameTransforms: world -> robot (from ground truth when there is one, else
/// identity) and robot -> camera.
std::vector<uint8_t> frame_transforms(const Scene& scene, int64_t stamp_ns);

/// The latest state, track, command and detection as one flat JSON object for plotting.
std::string plot_json(const Scene& scene);
/// JSON schema of plot_json (schema encoding "jsonschema").
std::string_view plot_json_schema();

/// Frame id of an eye's images ("camera" for the left eye, "camera_right" for the right).
std::string_view eye_frame(Eye eye);

}  // namespace stereoball::viewer::foxglove

namespace stereoball::viewer::foxglove {

/// A derived channel: topic name and Foxglove schema (all CDR + omgidl).
struct DerivedTopic {
  std::string_view topic;
  std::string_view schema_name;
};
/// Every derived channel, in a fixed order (the index is used by DerivedChannel below).
inline constexpr DerivedTopic kDerivedTopics[] = {{"view/left/image", kCompressedImage},
                                                  {"view/right/image", kCompressedImage},
                                                  {"view/left/annotations", kImageAnnotations},
                                                  {"view/right/annotations", kImageAnnotations},
                                                  {"view/scene", kSceneUpdate},
                                                  {"view/transforms", kFrameTransforms}};
enum class DerivedChannel : size_t {
  kLeftImage,
  kRightImage,
  kLeftAnnotations,
  kRightAnnotations,
  kScene,
  kTransforms
};

}  // namespace stereoball::viewer::foxglove
