// Writer throughput on 640x480 BGR stereo frames (both eyes in one message, like stereo/frame)
// versus a raw sequential write of the same bytes to the same disk, in the same run. Each
// measurement ends with fdatasync (bytes on the device) and the two alternate over several
// rounds so page-cache writeback of one does not bill the other. Prints MB/s, CPU ms per MB,
// and the ratio.
//   recorder_bench [--frames N] [--rounds R] [--dir DIR] [--level L] [--chunk-mb M] [--none]

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "recorder/core/writer.hpp"
#include "recorder/io/file_io.hpp"

using namespace stereoball::recorder;
using stereoball::Status;

namespace {

constexpr int kWidth = 640, kHeight = 480;
constexpr size_t kEyeBytes = size_t{kWidth} * kHeight * 3;

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// A synthetic camera-like image: smooth gradient, a ball, and sensor noise (so zstd has work).
void render(std::vector<uint8_t>& img, int frame, std::mt19937& rng) {
  const int cx = 100 + (frame * 7) % 440, cy = 240, r = 40;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      uint8_t* p = &img[(size_t(y) * kWidth + x) * 3];
      const bool ball = (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r;
      const uint8_t noise = static_cast<uint8_t>(rng() & 7);
      p[0] = static_cast<uint8_t>(ball ? 30 : (x / 3) + noise);
      p[1] = static_cast<uint8_t>(ball ? 140 : (y / 2) + noise);
      p[2] = static_cast<uint8_t>(ball ? 250 : 90 + noise);
    }
  }
}

struct Figures {
  double wall_s = 1e30, cpu_s = 1e30;  // best over rounds
  void keep_best(double w, double c) {
    wall_s = std::min(wall_s, w);
    cpu_s = std::min(cpu_s, c);
  }
};

int die(const std::string& what) {
  std::fprintf(stderr, "recorder_bench: %s\n", what.c_str());
  return 1;
}

// Runs body(sink) on a fresh file, syncs, returns {wall, cpu} seconds or an error.
Status timed(const std::string& path, Figures& f, const std::function<Status(FileSink&)>& body) {
  auto sink = FileSink::create(path);
  if (!sink) return stereoball::Error{sink.error()};
  const double w0 = wall_seconds(), c0 = cpu_seconds();
  if (auto e = body(**sink); !e) return e;
  if (auto e = (*sink)->sync(); !e) return e;
  f.keep_best(wall_seconds() - w0, cpu_seconds() - c0);
  std::filesystem::remove(path);
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 300, rounds = 3;
  std::string dir = std::filesystem::temp_directory_path().string();
  WriterParams params;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--frames" && has_value)
      frames = std::stoi(argv[++i]);
    else if (a == "--rounds" && has_value)
      rounds = std::stoi(argv[++i]);
    else if (a == "--dir" && has_value)
      dir = argv[++i];
    else if (a == "--level" && has_value)
      params.zstd_level = std::stoi(argv[++i]);
    else if (a == "--chunk-mb" && has_value)
      params.chunk_size_bytes = std::stoull(argv[++i]) << 20;
    else if (a == "--none")
      params.compression = Compression::kNone;
    else {
      return die(
          "usage: recorder_bench [--frames N] [--rounds R] [--dir DIR] [--level L] "
          "[--chunk-mb M] [--none]");
    }
  }
  if (auto bad = params.validate(); !bad) return die(bad.error());
  if (frames < 1 || rounds < 1) return die("--frames and --rounds must be >= 1");

  // Pre-render a loop of distinct frames so rendering is not measured.
  constexpr int kDistinct = 16;
  std::mt19937 rng(1);
  std::vector<std::vector<uint8_t>> payloads(kDistinct, std::vector<uint8_t>(2 * kEyeBytes + 64));
  std::vector<uint8_t> eye(kEyeBytes);
  for (int f = 0; f < kDistinct; ++f) {
    render(eye, f, rng);
    std::copy(eye.begin(), eye.end(), payloads[f].begin() + 32);
    render(eye, f + 1, rng);
    std::copy(eye.begin(), eye.end(), payloads[f].begin() + 32 + kEyeBytes);
  }
  const double total_mb = double(frames) * payloads[0].size() / 1e6;
  Figures raw, mcap;
  uint64_t file_bytes = 0;
  for (int round = 0; round < rounds; ++round) {
    auto raw_err = timed(dir + "/recorder_bench.raw", raw, [&](FileSink& sink) -> Status {
      for (int i = 0; i < frames; ++i) {
        if (auto e = sink.write(payloads[i % kDistinct]); !e) return e;
      }
      return {};
    });
    if (!raw_err.ok()) return die(raw_err.error());
    auto mcap_err = timed(dir + "/recorder_bench.mcap", mcap, [&](FileSink& sink) -> Status {
      McapWriter writer(params);
      if (auto e = writer.open(sink); !e) return e;
      const auto schema = writer.add_schema("stereoball::msg::StereoFrame", "omgidl",
                                            std::string_view("module stereoball {};"));
      const auto channel = writer.add_channel(schema.value(), "stereo/frame", "cdr");
      uint64_t t = 1'700'000'000'000'000'000ull;
      for (int i = 0; i < frames; ++i) {
        t += 16'666'667;
        if (auto e = writer.write({channel.value(), uint32_t(i), t, t, payloads[i % kDistinct]});
            !e) {
          return e;
        }
      }
      if (auto e = writer.close(); !e) return e;
      file_bytes = writer.stats().file_bytes;
      return {};
    });
    if (!mcap_err.ok()) return die(mcap_err.error());
  }

  const double raw_mbps = total_mb / raw.wall_s, mcap_mbps = total_mb / mcap.wall_s;
  std::printf(
      "input: %d frames x %zu bytes (640x480 bgr8 stereo) = %.1f MB per round, %d rounds, "
      "best round, incl. fdatasync, dir %s\n",
      frames, payloads[0].size(), total_mb, rounds, dir.c_str());
  std::printf("compression: %s level %d, chunk %.1f MiB\n",
              params.compression == Compression::kZstd ? "zstd" : "none", params.zstd_level,
              params.chunk_size_bytes / 1048576.0);
  std::printf("raw write:    %8.1f MB/s  cpu %.2f ms/MB\n", raw_mbps, 1e3 * raw.cpu_s / total_mb);
  std::printf("mcap writer:  %8.1f MB/s  cpu %.2f ms/MB  file %.1f MB (%.0f%% of input)\n",
              mcap_mbps, 1e3 * mcap.cpu_s / total_mb, file_bytes / 1e6,
              100.0 * file_bytes / (total_mb * 1e6));
  std::printf("ratio mcap/raw: %.2f   sustained stereo frames/s: %.0f (60 Hz needs 60)\n",
              mcap_mbps / raw_mbps, frames / mcap.wall_s);
  return 0;
}
