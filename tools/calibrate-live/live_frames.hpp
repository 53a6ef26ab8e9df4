#pragma once
// A stereo/frame sample as the live calibration's input (terminal tool and calibration page).

#include "common/util/result.hpp"
#include "live_station.hpp"
#include "stereo/frame/frame_decoder.hpp"

namespace stereoball::calibrate_live {

/// The frame decoded at its own size with each eye's capture stamp (the frame's stamp when an
/// eye has none); the eyes may be views of msg's bytes or of decoder's buffers (valid until
/// the next call). Error: why the sample cannot be decoded.
Result<StationFrame> station_frame(const stereoball_msg_StereoFrame& msg,
                                   stereo::FrameDecoder& decoder);

}  // namespace stereoball::calibrate_live
