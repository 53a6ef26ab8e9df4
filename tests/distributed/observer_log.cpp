#include "observer_log.hpp"

#include <sstream>

namespace stereoball::distributed {

ObserverLog parse_observer_log(const std::string& text) {
  ObserverLog log;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.size() < 3 || line[1] != ' ') continue;
    std::istringstream in(line.substr(2));
    switch (line[0]) {
      case 'F': {
        FrameRx f{};
        if (in >> f.rx_ns >> f.stamp_ns >> f.seq >> f.bytes >> f.encoding) log.frames.push_back(f);
        break;
      }
      case 'G': {
        TruthRx g{};
        if (in >> g.rx_ns >> g.stamp_ns >> g.frame_seq >> g.robot_x_m >> g.robot_y_m >>
            g.robot_yaw_rad >> g.linear_mps >> g.angular_radps >> g.ball_x_m >> g.ball_y_m) {
          log.truths.push_back(g);
        }
        break;
      }
      case 'D': {
        DetectionRx d{};
        if (in >> d.rx_ns >> d.capture_ns >> d.publish_ns >> d.frame_seq >> d.status >>
            d.processing_ms) {
          log.detections.push_back(d);
        }
        break;
      }
      case 'T': {
        TrackRx t{};
        if (in >> t.rx_ns >> t.capture_ns >> t.publish_ns >> t.frame_seq >> t.state >>
            t.distance_m >> t.bearing_rad) {
          log.tracks.push_back(t);
        }
        break;
      }
      case 'C': {
        CommandRx c{};
        if (in >> c.rx_ns >> c.stamp_ns >> c.seq >> c.linear_mps >> c.angular_radps >>
            c.capture_ns) {
          log.commands.push_back(c);
        }
        break;
      }
      default:
        break;
    }
  }
  return log;
}

}  // namespace stereoball::distributed
