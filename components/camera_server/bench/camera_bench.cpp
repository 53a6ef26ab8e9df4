// stereoball-bench-camera: conversion and file-source timing of the camera server.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <numeric>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>
#include <vector>
#include "common/util/cli11.hpp"

#include "camera_server/core/format_negotiation.hpp"
#include "camera_server/core/frame_builder.hpp"
#include "camera_server/core/frame_scaler.hpp"
#include "camera_server/core/pixel_convert.hpp"
#include "camera_server/io/file_source.hpp"
#include "stereo/image/yuyv_convert.hpp"

namespace sc = stereoball::camera_server;

namespace {

int64_t clock_ns(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

struct Stats {
  double median_us = 0, p99_us = 0, max_us = 0, mean_us = 0;
};

Stats stats_of(std::vector<double> us) {
  Stats s;
  if (us.empty()) return s;
  std::sort(us.begin(), us.end());
  s.median_us = us[us.size() / 2];
  s.p99_us = us[std::min(us.size() - 1, us.size() * 99 / 100)];
  s.max_us = us.back();
  s.mean_us = std::accumulate(us.begin(), us.end(), 0.0) / us.size();
  return s;
}

// Wall and CPU microseconds per call of f over n calls.
template <typename F>
std::pair<Stats, double> time_calls(int n, F&& f) {
  std::vector<double> wall;
  const int64_t cpu0 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
  for (int i = 0; i < n; ++i) {
    const int64_t t0 = clock_ns(CLOCK_MONOTONIC);
    f();
    wall.push_back((clock_ns(CLOCK_MONOTONIC) - t0) * 1e-3);
  }
  const double cpu_us = (clock_ns(CLOCK_PROCESS_CPUTIME_ID) - cpu0) * 1e-3 / n;
  return {stats_of(wall), cpu_us};
}

void print(const char* what, const std::pair<Stats, double>& r) {
  std::printf("  %-44s median %8.1f us  p99 %8.1f us  mean %8.1f us  cpu %8.1f us/call\n", what,
              r.first.median_us, r.first.p99_us, r.first.mean_us, r.second);
}

// A real colour image at 640x480, packed as YUYV (BT.601 limited range, chroma averaged).
std::vector<uint8_t> yuyv_from(const cv::Mat& bgr) {
  cv::Mat yuv;
  cv::cvtColor(bgr, yuv, cv::COLOR_BGR2YCrCb);
  std::vector<uint8_t> out(static_cast<size_t>(bgr.cols) * bgr.rows * 2);
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; x += 2) {
      const cv::Vec3b a = yuv.at<cv::Vec3b>(y, x), b = yuv.at<cv::Vec3b>(y, x + 1);
      uint8_t* q = &out[(static_cast<size_t>(y) * bgr.cols + x) * 2];
      q[0] = static_cast<uint8_t>(16 + a[0] * 219 / 255);
      q[1] = static_cast<uint8_t>(16 + ((a[2] + b[2]) / 2) * 224 / 255);
      q[2] = static_cast<uint8_t>(16 + b[0] * 219 / 255);
      q[3] = static_cast<uint8_t>(16 + ((a[1] + b[1]) / 2) * 224 / 255);
    }
  }
  return out;
}

void bench_conversion(int iterations) {
  cv::Mat colour =
      cv::imread(SB_SHARED_DATA_DIR "/opencv-samples/basketball1.png", cv::IMREAD_COLOR);
  if (colour.empty()) colour = cv::Mat(480, 640, CV_8UC3, cv::Scalar(40, 120, 200));
  cv::resize(colour, colour, cv::Size(640, 480));
  const std::vector<uint8_t> yuyv = yuyv_from(colour);
  const cv::Mat yuyv_mat(480, 640, CV_8UC2, const_cast<uint8_t*>(yuyv.data()));
  cv::Mat out(480, 640, CV_8UC3);
  std::printf("YUYV -> BGR, 640x480, %d iterations (output buffer reused):\n", iterations);
  print("camera_server yuyv_to_bgr (1 thread)", time_calls(iterations, [&] {
          (void)stereoball::stereo::yuyv_to_bgr(yuyv, 640, 480, 1280, out);
        }));
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  print("cv::cvtColor COLOR_YUV2BGR_YUYV (1 thread)",
        time_calls(iterations, [&] { cv::cvtColor(yuyv_mat, out, cv::COLOR_YUV2BGR_YUYV); }));
  cv::setNumThreads(threads);
  char label[64];
  std::snprintf(label, sizeof label, "cv::cvtColor COLOR_YUV2BGR_YUYV (%d threads)", threads);
  print(label,
        time_calls(iterations, [&] { cv::cvtColor(yuyv_mat, out, cv::COLOR_YUV2BGR_YUYV); }));

  std::vector<uint8_t> jpeg;
  cv::imencode(".jpg", colour, jpeg, {cv::IMWRITE_JPEG_QUALITY, 80});
  std::printf("MJPEG -> BGR, 640x480, %zu-byte frame (quality 80):\n", jpeg.size());
  print("camera_server mjpeg_to_bgr (cv::imdecode)",
        time_calls(iterations / 4 + 1, [&] { (void)sc::mjpeg_to_bgr(jpeg, 640, 480, out); }));
}

// The file source as the node runs it: tick at rate_hz, build the frame view, copy both eyes
// into one message-sized buffer (stand-in for the DDS serialization that comes later).
void bench_file_source(const std::string& encoding, double rate_hz, double seconds) {
  auto src = sc::FileSource::open({SB_SHARED_DATA_DIR "/opencv-samples/left*.jpg",
                                   SB_SHARED_DATA_DIR "/opencv-samples/right*.jpg", "", encoding});
  if (!src) {
    std::fprintf(stderr, "file source: %s\n", src.error().c_str());
    return;
  }
  const int64_t period = static_cast<int64_t>(1e9 / rate_hz);
  const int frames = static_cast<int>(seconds * rate_hz);
  std::vector<uint8_t> message;
  std::vector<double> build_us, lateness_us;
  const int64_t cpu0 = clock_ns(CLOCK_PROCESS_CPUTIME_ID);
  const int64_t start = clock_ns(CLOCK_MONOTONIC) + period;
  for (int i = 0; i < frames; ++i) {
    const int64_t due = start + i * period;
    std::this_thread::sleep_for(std::chrono::nanoseconds(due - clock_ns(CLOCK_MONOTONIC)));
    const int64_t t0 = clock_ns(CLOCK_MONOTONIC);
    const sc::FilePair& p = src->pair(static_cast<size_t>(i) % src->size());
    auto view = stereoball::stereo::view_of_images(p.left, p.right, i, clock_ns(CLOCK_REALTIME));
    message.resize(view->left.bytes + view->right.bytes);
    std::copy_n(view->left.data, view->left.bytes, message.data());
    std::copy_n(view->right.data, view->right.bytes, message.data() + view->left.bytes);
    const int64_t t1 = clock_ns(CLOCK_MONOTONIC);
    build_us.push_back((t1 - t0) * 1e-3);
    lateness_us.push_back((t0 - due) * 1e-3);
  }
  const double cpu_s = (clock_ns(CLOCK_PROCESS_CPUTIME_ID) - cpu0) * 1e-9;
  const double wall_s = frames / rate_hz;
  const Stats b = stats_of(build_us);
  const Stats l = stats_of(lateness_us);
  std::printf("File source %s %dx%d at %.0f Hz, %d frames (%zu real pairs, looping):\n",
              src->encoding().c_str(), src->image_size().width, src->image_size().height, rate_hz,
              frames, src->size());
  std::printf("  tick -> message ready  median %6.1f us  p99 %6.1f us  max %6.1f us\n", b.median_us,
              b.p99_us, b.max_us);
  std::printf("  timer wake-up lateness median %6.1f us  p99 %6.1f us (scheduler, not the path)\n",
              l.median_us, l.p99_us);
  std::printf("  CPU %.1f us per frame = %.2f %% of one core\n", cpu_s * 1e6 / frames,
              100.0 * cpu_s / wall_s);
}

void bench_v4l2_core_path(int iterations) {
  sc::RawStereoPair pair;
  cv::Mat colour(480, 640, CV_8UC3);
  cv::randu(colour, 0, 255);
  pair.left.bytes = yuyv_from(colour);
  pair.left.fourcc = sc::kFourccYuyv;
  pair.left.width_px = 640;
  pair.left.height_px = 480;
  pair.left.step_bytes = 1280;
  pair.right = pair.left;
  sc::FrameBuilder builder(sc::FrameBuilderParams{"bgr8"});
  std::printf("V4L2 core path per stereo pair (YUYV 640x480 x2 -> bgr8 view):\n");
  print("FrameBuilder::step", time_calls(iterations, [&] { (void)builder.step(pair); }));
}

// publish_width_px: both eyes of a real 2304x1296 rig pair scaled to 1152x648 (FrameScaler).
void bench_publish_width(int iterations) {
  const std::string dir = std::string(SB_SHARED_DATA_DIR) + "/real-stereo-basketball/";
  const cv::Mat l = cv::imread(dir + "left/left_01.jpg", cv::IMREAD_COLOR);
  const cv::Mat r = cv::imread(dir + "right/right_01.jpg", cv::IMREAD_COLOR);
  if (l.empty() || r.empty()) {
    std::printf("publish_width_px: %s not found, skipped\n", dir.c_str());
    return;
  }
  const auto view = stereoball::stereo::view_of_images(l, r, 0, 0);
  sc::FrameScaler scaler(1152);
  std::printf("publish_width_px 1152 on a real %dx%d bgr8 pair (INTER_AREA, both eyes):\n", l.cols,
              l.rows);
  print("FrameScaler::step", time_calls(iterations, [&] { (void)scaler.step(*view); }));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Camera server timing: YUYV/MJPEG conversion vs OpenCV, and the file-source "
      "capture-to-publish core path (640x480). Prints figures; asserts nothing."};
  int iterations = 300;
  double seconds = 5.0;
  double rate_hz = 30.0;
  app.add_option("--iterations", iterations, "conversion calls per figure")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--seconds", seconds, "file-source run length, s")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  app.add_option("--rate", rate_hz, "file-source rate, Hz")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  bench_conversion(iterations);
  bench_v4l2_core_path(iterations);
  bench_publish_width(std::max(1, iterations / 10));
  bench_file_source("as_read", rate_hz, seconds);
  bench_file_source("bgr8", rate_hz, seconds);
  return 0;
}
