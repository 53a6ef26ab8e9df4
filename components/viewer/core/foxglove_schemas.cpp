#include "viewer/core/foxglove_schemas.hpp"

namespace stereoball::viewer::foxglove {

std::string_view schema_idl() {
  // Types in dependency order: a type is defined before the first struct that uses it.
  static constexpr std::string_view kIdl = R"(module foxglove {
  struct Time { uint32 sec; uint32 nsec; };
  struct Duration { int32 sec; uint32 nsec; };
  struct Color { double r; double g; double b; double a; };
  struct Point2 { double x; double y; };
  struct Point3 { double x; double y; double z; };
  struct Vector3 { double x; double y; double z; };
  struct Quaternion { double x; double y; double z; double w; };
  struct Pose { Vector3 position; Quaternion orientation; };
  struct KeyValuePair { string key; string value; };
  struct CompressedImage { Time timestamp; string frame_id; sequence<uint8> data; string format; };
  struct CircleAnnotation {
    Time timestamp; Point2 position; double diameter; double thickness;
    Color fill_color; Color outline_color; sequence<KeyValuePair> metadata;
  };
  enum PointsAnnotationType { UNKNOWN, POINTS, LINE_LOOP, LINE_STRIP, LINE_LIST };
  struct PointsAnnotation {
    Time timestamp; PointsAnnotationType type; sequence<Point2> points; Color outline_color;
    sequence<Color> outline_colors; Color fill_color; double thickness;
    sequence<KeyValuePair> metadata;
  };
  struct TextAnnotation {
    Time timestamp; Point2 position; string text; double font_size;
    Color text_color; Color background_color; sequence<KeyValuePair> metadata;
  };
  struct ImageAnnotations {
    Time timestamp; sequence<CircleAnnotation> circles; sequence<PointsAnnotation> points;
    sequence<TextAnnotation> texts; sequence<KeyValuePair> metadata;
  };
  struct ArrowPrimitive {
    Pose pose; double shaft_length; double shaft_diameter; double head_length;
    double head_diameter; Color color;
  };
  struct CubePrimitive { Pose pose; Vector3 size; Color color; };
  struct SpherePrimitive { Pose pose; Vector3 size; Color color; };
  struct CylinderPrimitive {
    Pose pose; Vector3 size; double bottom_scale; double top_scale; Color color;
  };
  enum LineType { LINE_STRIP, LINE_LOOP, LINE_LIST };
  struct LinePrimitive {
    LineType type; Pose pose; double thickness; boolean scale_invariant;
    sequence<Point3> points; Color color; sequence<Color> colors; sequence<uint32> indices;
  };
  struct TriangleListPrimitive {
    Pose pose; sequence<Point3> points; Color color; sequence<Color> colors;
    sequence<uint32> indices;
  };
  struct TextPrimitive {
    Pose pose; boolean billboard; double font_size; boolean scale_invariant; Color color;
    string text;
  };
  struct ModelPrimitive {
    Pose pose; Vector3 scale; Color color; boolean override_color; string url;
    string media_type; sequence<uint8> data;
  };
  struct SceneEntity {
    Time timestamp; string frame_id; string id; Duration lifetime; boolean frame_locked;
    sequence<KeyValuePair> metadata; sequence<ArrowPrimitive> arrows;
    sequence<CubePrimitive> cubes; sequence<SpherePrimitive> spheres;
    sequence<CylinderPrimitive> cylinders; sequence<LinePrimitive> lines;
    sequence<TriangleListPrimitive> triangles; sequence<TextPrimitive> texts;
    sequence<ModelPrimitive> models;
  };
  enum SceneEntityDeletionType { MATCHING_ID, ALL };
  struct SceneEntityDeletion { Time timestamp; SceneEntityDeletionType type; string id; };
  struct SceneUpdate { sequence<SceneEntityDeletion> deletions; sequence<SceneEntity> entities; };
  struct FrameTransform {
    Time timestamp; string parent_frame_id; string child_frame_id; Vector3 translation;
    Quaternion rotation;
  };
  struct FrameTransforms { sequence<FrameTransform> transforms; };
};
)";
  return kIdl;
}

bool is_foxglove_schema(std::string_view schema_name) {
  return schema_name.starts_with("foxglove::") || schema_name.starts_with("foxglove.");
}

}  // namespace stereoball::viewer::foxglove
