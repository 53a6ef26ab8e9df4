#pragma once
// The camera_server process: a source (two V4L2 cameras or image files) -> stereo/frame, and
// the calibration file -> stereo/calibration (transient-local), with health on the runner. A
// calibration file that changes while it runs (stereoball calibrate live writes it) is read
// again, checked as at start, and published; a bad one is reported and the old one kept.

#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "camera_server/core/camera_server_params.hpp"
#include "camera_server/core/eye_skew.hpp"
#include "camera_server/core/frame_builder.hpp"
#include "camera_server/core/frame_scaler.hpp"
#include "camera_server/io/file_source.hpp"
#include "camera_server/io/stereo_capture.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "stereo/core/eye_order.hpp"
#include "stereo/core/rectifier.hpp"
#include "stereo/frame/frame_compressor.hpp"
#include "stereo/frame/frame_transport.hpp"
#include "stereo/frame/preview_publisher.hpp"

namespace stereoball::camera_server {

/// Owns the source, the writers and the capture thread (V4L2) or playback timer (files).
class CameraServerNode {
 public:
  /// Opens the source and the calibration; the error is one line naming the problem
  /// (device missing/busy, unsupported format, calibration size != capture size, ...).
  /// devices makes the cameras (tests: scripted ones); empty = V4L2 devices.
  static Result<std::unique_ptr<CameraServerNode>> create(
      const CameraServerParams& params, node::Runner& runner,
      StereoCapture::DeviceFactory devices = {});
  ~CameraServerNode();
  CameraServerNode(const CameraServerNode&) = delete;
  CameraServerNode& operator=(const CameraServerNode&) = delete;

 private:
  CameraServerNode(const CameraServerParams& params, node::Runner& runner);
  Status open_source(StereoCapture::DeviceFactory devices);
  Status open_calibration(cv::Size capture_size);
  // The calibration file read and checked against the capture size, scaled to the published
  // size, with its rectifier.
  struct LoadedCalibration {
    stereo::StereoCalibration calibration;
    stereo::Rectifier rectifier;
  };
  Result<LoadedCalibration> load_calibration_file(cv::Size capture_size) const;
  void publish_calibration();
  void reload_calibration_if_changed();
  Status open_scaler(cv::Size capture_size);
  void check_transport(const std::string& raw_encoding);
  void report_oversize(uint64_t sample_bytes, const std::string& what);
  void check_sample(const stereo::FrameView& view);
  void start();
  void publish_file_pair(int64_t now_ns);
  void capture_loop();
  void publish(const stereo::FrameView& view);
  void offer_preview(const stereo::FrameView& view);
  void check_eye_order(const stereo::FrameView& view);
  void skip_eye_order(const std::string& why);
  const stereo::FrameView* scale(const stereo::FrameView& view, stereo::FrameView& storage);
  const stereo::FrameView* rectify(const stereo::FrameView& view, stereo::FrameView& storage);
  const stereo::FrameView* compress(const stereo::FrameView& view, stereo::FrameView& storage);
  void update_capture_health();
  void update_skew_health(int64_t now_ns);

  CameraServerParams params_;
  node::Runner& runner_;
  dds::DataWriter<stereoball_msg_StereoFrame> frame_writer_;
  dds::DataWriter<stereoball_msg_StereoCalibration> calibration_writer_;
  std::string source_name_;
  std::optional<FileSource> files_;
  std::unique_ptr<StereoCapture> capture_;
  FrameBuilder builder_;
  // calibration_, rectifier_ and eye_order_ change when the file is reloaded (runner thread)
  // while frames are published (capture thread): under calibration_mutex_.
  std::mutex calibration_mutex_;
  std::optional<stereo::StereoCalibration> calibration_;
  std::optional<stereo::Rectifier> rectifier_;  // of the published size (rectify, eye order)
  cv::Size capture_size_;                       // what the calibration must fit
  std::filesystem::file_time_type calibration_mtime_{};  // of the file last read or refused
  std::optional<FrameScaler> scaler_;                    // publish_width_px
  cv::Size publish_size_;                                // eyes as published (before compression)
  stereo::EyeOrderWatch eye_order_;                      // first frames: are the cameras swapped?
  cv::Mat eye_order_pixels_[2];    // yuyv/jpeg eyes of the checked frames, converted or decoded
  std::string eye_order_skipped_;  // why the last sampled frame could not be checked (once each)
  cv::Mat rectified_[2];
  std::optional<stereo::FrameCompressor> compressor_;  // frame_encoding jpeg/png
  // stereo/preview of raw frames, made only while a viewer reads it; created with the source
  // (it carries the source name).
  std::unique_ptr<stereo::PreviewPublisher> preview_;
  uint64_t file_seq_ = 0;
  bool files_done_ = false;
  uint64_t reported_drops_ = 0;
  stereo::TransportLimits transport_;
  bool oversize_reported_ = false;  // one warning per process
  uint64_t largest_sample_bytes_ = 0;
  EyeSkewStats skew_;           // V4L2: both capture stamps of every published pair
  int64_t skew_period_ns_ = 0;  // monotonic start of the skew statistic's period
  std::atomic<bool> stop_{false};
  std::thread capture_thread_;
};

}  // namespace stereoball::camera_server
