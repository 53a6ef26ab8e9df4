#pragma once
// The Foxglove message schemas the derived channels use, as OMG IDL (schema encoding
// "omgidl", message encoding "cdr"): field names, types and order follow Foxglove's published
// schemas (@foxglove/schemas 2.1.0, MIT), so Foxglove's Image and 3D panels draw them.

#include <string_view>

namespace stereoball::viewer::foxglove {

/// IDL text defining every Foxglove type below (module foxglove), one text for all channels.
std::string_view schema_idl();

inline constexpr std::string_view kCompressedImage = "foxglove::CompressedImage";
inline constexpr std::string_view kImageAnnotations = "foxglove::ImageAnnotations";
inline constexpr std::string_view kSceneUpdate = "foxglove::SceneUpdate";
inline constexpr std::string_view kFrameTransforms = "foxglove::FrameTransforms";

/// True for the schema names of derived channels (what `stereoball play` leaves out).
bool is_foxglove_schema(std::string_view schema_name);

}  // namespace stereoball::viewer::foxglove
