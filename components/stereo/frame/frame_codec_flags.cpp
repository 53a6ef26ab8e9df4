#include "stereo/frame/frame_codec_flags.hpp"

#include "common/util/cli11.hpp"

namespace stereoball::stereo {

FrameCodecFlags::FrameCodecFlags(CLI::App& app) {
  app.add_option("--frame-encoding", encoding_,
                 "overrides frame_encoding of the config: raw (pixels), jpeg or png per eye")
      ->check(CLI::IsMember(frame_encoding_choices()));
  app.add_option("--jpeg-quality", quality_, "overrides jpeg_quality of the config (1-100)")
      ->check(CLI::Range(1, 100));
  app.add_option("--jpeg-chroma", chroma_,
                 "overrides jpeg_chroma of the config: 444 (full colour resolution), 422, 420")
      ->check(CLI::IsMember(jpeg_chroma_choices()));
}

void FrameCodecFlags::apply(FrameCodecParams& params) const {
  if (!encoding_.empty()) params.frame_encoding = encoding_;
  if (quality_ != 0) params.jpeg_quality = quality_;
  if (!chroma_.empty()) params.jpeg_chroma = chroma_;
}

}  // namespace stereoball::stereo
