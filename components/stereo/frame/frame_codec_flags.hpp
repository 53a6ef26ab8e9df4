#pragma once
// --frame-encoding / --jpeg-quality / --jpeg-chroma: the command-line overrides of a frame
// publisher's frame_encoding, jpeg_quality and jpeg_chroma (camera_server, simulator; used by
// the *-jpeg profiles).

#include <string>

#include "stereo/frame/frame_codec.hpp"

// Declared only: CLI/CLI.hpp costs seconds of compile time in every file that includes it; the
// files that add flags include it themselves.
namespace CLI {
class App;
}  // namespace CLI

namespace stereoball::stereo {

/// Registers the flags on an app and applies the ones given to the config's values.
class FrameCodecFlags {
 public:
  /// Adds --frame-encoding (raw|jpeg|png), --jpeg-quality (1-100) and --jpeg-chroma
  /// (444|422|420) to app.
  explicit FrameCodecFlags(CLI::App& app);
  /// Overrides the fields of params whose flag was given (after parsing).
  void apply(FrameCodecParams& params) const;

 private:
  std::string encoding_;
  int quality_ = 0;  // 0 = not given
  std::string chroma_;
};

}  // namespace stereoball::stereo
