// stereoball view [--domain N] [--port P] [--bind ADDR]
// An ordinary DDS subscriber that shows what the robot sees: a web page (served by this
// process, nothing from the internet) with both eyes, the detections drawn on them, the
// track state and register, a top view, commands and e-stop over time and every node's
// health; and, on the same port, the Foxglove WebSocket protocol (foxglove.websocket.v1).
// With --calibrate (what `stereoball calibrate live` starts) it also serves the calibration
// page at /calibrate (calibration_pump.hpp).

#include "common/util/cli11.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "calibration_pump.hpp"
#include "common/dds/reader.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "frame_pump.hpp"
#include "live_flags.hpp"
#include "stereoball/topics.hpp"
#include "view_server.hpp"
#include "viewer/bridge/derived_channels.hpp"

namespace sb = stereoball;

namespace {

struct Options {
  sb::view::ServerParams server;
  sb::viewer::DeriverParams derive;
  double image_rate_hz = 30;
  bool no_preview = false;
  bool calibrate = false;
  sb::calibrate_live::LiveFlags live;
  bool open_browser = false;
};

extern "C" char** environ;

// Opens url in the desktop's browser (xdg-open), without waiting for it; false when there is
// none.
bool open_in_browser(const std::string& url) {
  const char* opener = "/usr/bin/xdg-open";
  if (!std::filesystem::exists(opener)) return false;
  pid_t pid = 0;
  char* argv[] = {const_cast<char*>(opener), const_cast<char*>(url.c_str()), nullptr};
  if (posix_spawn(&pid, opener, nullptr, nullptr, argv, environ) != 0) return false;
  std::thread([pid] { waitpid(pid, nullptr, 0); }).detach();
  return true;
}

// Every non-image input: converted under one lock, derived messages handed to the server.
template <typename T, typename F>
void subscribe(sb::node::Runner& runner, std::vector<std::shared_ptr<void>>& keep,
               const sb::topics::Topic<T>& topic, F on_sample) {
  auto reader = std::make_shared<sb::dds::DataReader<T>>(runner.participant(), topic);
  keep.push_back(reader);
  runner.on_data(reader->handle(), [reader, on_sample, &runner, name = topic.spec.name] {
    for (auto& s : reader->take(64)) {
      runner.health().count(std::string(name).c_str());
      on_sample(*s);
    }
  });
}

}  // namespace

int main(int argc, char** argv) {
  sb::node::block_termination_signals();
  CLI::App app{
      "stereoball view: a live viewer in the browser (both eyes with detections, track state, "
      "top view, commands, node health) and a Foxglove WebSocket server (connect Foxglove to "
      "ws://ADDR:PORT), on one port. Only subscribes: nothing on the robot waits for it."};
  Options o;
  sb::node::CommonOptions common;
  app.add_option("-p,--port", o.server.port, "TCP port (0 = any free port)")->capture_default_str();
  app.add_option("-b,--bind", o.server.bind_address,
                 "address to listen on (0.0.0.0 = every interface, for other machines)")
      ->capture_default_str();
  app.add_option("--image-hz", o.image_rate_hz, "images per second sent at most")
      ->check(CLI::Range(1.0, 120.0))
      ->capture_default_str();
  app.add_option("--jpeg-quality", o.derive.encoder.jpeg_quality, "JPEG quality 1..100")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--max-width", o.derive.encoder.max_width_px,
                 "scale wider images down to this width (0 = never)")
      ->capture_default_str();
  app.add_option("--max-input-width", o.derive.encoder.max_input_width_px,
                 "refuse eyes wider than this (raw size, JPEG/PNG header: checked before decoding)")
      ->capture_default_str();
  app.add_option("--max-input-height", o.derive.encoder.max_input_height_px,
                 "refuse eyes taller than this (as --max-input-width)")
      ->capture_default_str();
  app.add_flag("--no-preview", o.no_preview,
               "always show stereo/frame, even when its publisher offers stereo/preview (JPEG "
               "eyes made on the robot while a viewer reads them)");
  double stall_s = 5;
  app.add_option("--client-stall-s", stall_s,
                 "cut off a client whose backlog stays over the image drop limit this long")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  app.add_flag("--calibrate", o.calibrate,
               "also serve the calibration page at /calibrate (stereoball calibrate live): "
               "takes the flags below and -o FILE")
      ->group("Calibration");
  sb::calibrate_live::add_live_flags(app, o.live);
  app.add_flag("--open", o.open_browser, "open the page in the desktop's browser (xdg-open)");
  sb::node::add_common_flags(app, common, "", false);
  CLI11_PARSE(app, argc, argv);
  std::optional<sb::calibrate_live::StationParams> calibration;
  if (o.calibrate) {
    auto params = sb::calibrate_live::station_params(o.live);
    if (!params) {
      std::fprintf(stderr, "stereoball view: %s\n", params.error().c_str());
      return 2;
    }
    calibration = *params;
  }
  o.server.flow.stall_timeout_ns = static_cast<int64_t>(stall_s * 1e9);
  if (auto st = o.derive.validate(); !st) {
    std::fprintf(stderr, "stereoball view: %s\n", st.error().c_str());
    return 2;
  }
  try {
    sb::node::Runner runner("viewer", common);
    std::mutex mutex;
    sb::viewer::Deriver deriver(o.derive);
    sb::view::ViewServer server(
        o.server,
        [&](int64_t now_ns) {
          std::lock_guard lock(mutex);
          return deriver.scene().to_json(now_ns).dump();
        },
        [&] {
          std::lock_guard lock(mutex);
          return sb::viewer::foxglove::plot_json(deriver.scene());
        });
    std::unique_ptr<sb::view::CalibrationPump> calibration_pump;
    if (calibration) {
      calibration_pump = std::make_unique<sb::view::CalibrationPump>(
          runner.participant(), *calibration, o.live.output,
          static_cast<int64_t>(o.live.timeout_s * 1e9));
      auto* pump = calibration_pump.get();
      server.set_calibration({[pump] { return pump->state_json(); },
                              [pump](const std::string& action) {
                                if (action == "finish") pump->request_finish();
                                if (action == "write") pump->request_write();
                              }});
    }
    auto url = server.start();
    if (!url) {
      std::fprintf(stderr, "stereoball view: %s\n", url.error().c_str());
      return 1;
    }
    std::string ws = *url;
    ws.replace(0, 4, "ws");
    std::printf("viewer: %s (Foxglove: %s, domain %d%s%s)\n", url->c_str(), ws.c_str(),
                common.domain_id, common.partition.empty() ? "" : ", partition ",
                common.partition.c_str());
    if (calibration_pump) {
      std::printf("calibration page: %scalibrate (board %s, writes %s once the verdict passes)\n",
                  url->c_str(), o.live.board.c_str(), o.live.output.c_str());
      if (o.open_browser && !open_in_browser(*url + "calibrate"))
        std::printf("no xdg-open here: open the address above in a browser\n");
      calibration_pump->start();
    } else if (o.open_browser && !open_in_browser(*url)) {
      std::printf("no xdg-open here: open the address above in a browser\n");
    }
    std::fflush(stdout);

    std::vector<std::shared_ptr<void>> readers;
    const auto now = [] { return sb::node::monotonic_ns(); };
    auto forward = [&](auto make) {
      std::vector<sb::viewer::DerivedMessage> out;
      {
        std::lock_guard lock(mutex);
        out = make();
      }
      server.publish_derived(std::move(out));
    };
    subscribe(runner, readers, sb::topics::kBallDetection,
              [&](const auto& m) { forward([&] { return deriver.on_detection(m); }); });
    subscribe(runner, readers, sb::topics::kBallTrack,
              [&](const auto& m) { forward([&] { return deriver.on_track(m, now()); }); });
    subscribe(runner, readers, sb::topics::kGroundTruth,
              [&](const auto& m) { forward([&] { return deriver.on_truth(m, now()); }); });
    subscribe(runner, readers, sb::topics::kVelocityCommand, [&](const auto& m) {
      std::lock_guard lock(mutex);
      deriver.on_command(m);
    });
    subscribe(runner, readers, sb::topics::kEmergencyStop, [&](const auto& m) {
      std::lock_guard lock(mutex);
      deriver.on_estop(m);
    });
    subscribe(runner, readers, sb::topics::kComponentStatus, [&](const auto& m) {
      std::lock_guard lock(mutex);
      deriver.on_health(m);
    });

    sb::view::FramePump pump(runner.participant(), o.derive.encoder, o.image_rate_hz, !o.no_preview,
                             server);
    pump.start();
    runner.every(1'000'000'000, [&](int64_t) {
      const auto s = server.stats();
      runner.health().set_state(true, std::to_string(s.browsers) + " browser(s), " +
                                          std::to_string(s.foxglove_clients) +
                                          " Foxglove client(s)");
    });
    const int rc = runner.run();
    pump.stop();
    if (calibration_pump) calibration_pump->stop();
    server.stop();
    return rc;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stereoball view: %s\n", e.what());
    return 1;
  }
}
