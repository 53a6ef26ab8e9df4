#include "view_server.hpp"

#include <chrono>
#include <cstring>
#include <map>

#include "common/node/node_runner.hpp"
#include "page_asset.hpp"
#include "viewer/core/foxglove_protocol.hpp"
#include "viewer/core/foxglove_schemas.hpp"
#include "viewer/core/pair_message.hpp"
#include "ws_transport.hpp"

namespace stereoball::view {
namespace {

namespace fg = viewer::foxglove;

constexpr size_t kMaxIncomingBytes = 64 * 1024;  // clients send small JSON only
constexpr uint32_t kPlotChannelId = 100;

// Foxglove channel id of a derived channel (1-based, in kDerivedTopics order).
uint32_t channel_id(fg::DerivedChannel c) {
  return static_cast<uint32_t>(c) + 1;
}

std::vector<fg::Channel> advertised_channels() {
  std::vector<fg::Channel> out;
  for (size_t i = 0; i < std::size(fg::kDerivedTopics); ++i) {
    const auto& t = fg::kDerivedTopics[i];
    out.push_back({static_cast<uint32_t>(i + 1), std::string(t.topic), "cdr",
                   std::string(t.schema_name), std::string(fg::schema_idl()), "omgidl"});
  }
  out.push_back({kPlotChannelId, "view/plot", "json", "stereoball.view.Plot",
                 std::string(fg::plot_json_schema()), "jsonschema"});
  return out;
}

// The page's binary image message (viewer/core/pair_message.hpp).
std::string pair_message(const viewer::PairJpeg& pair) {
  viewer::PairHeader h;
  h.frame_seq = pair.frame_seq;
  h.capture_ms = pair.capture_stamp_ns / 1e6;
  h.source_width_px = pair.left.source_width_px;
  h.source_height_px = pair.left.source_height_px;
  h.received_ms = pair.taken_stamp_ns / 1e6;
  h.encoded_ms = pair.encoded_stamp_ns / 1e6;
  return viewer::pair_message(h, pair.left.bytes, pair.right.bytes);
}

}  // namespace

struct ViewServer::Impl {
  enum class Kind { kBrowser, kFoxglove };
  struct Client {
    Kind kind;
    viewer::ClientFlow flow;
    fg::Subscriptions subscriptions;
    bool cut = false;  // being dropped: send nothing more
  };

  ServerParams params;
  std::function<std::string(int64_t)> scene_json;
  std::function<std::string()> plot_json;
  CalibrationHooks calibration;
  ViewServer* owner = nullptr;
  std::unique_ptr<WsTransport> transport;
  std::map<uint64_t, Client> clients;  // touched on the transport thread only
  std::vector<fg::Channel> channels = advertised_channels();
  std::vector<uint32_t> channel_ids;
  std::string session_id = std::to_string(node::now_ns());
  std::atomic<int> pairs_pending{0};
  std::atomic<uint64_t> pairs_from_preview{0};
  std::atomic<uint64_t> connections{0}, disconnected_slow{0}, pairs_encoded{0}, images_sent{0},
      images_dropped{0}, bad_client_messages{0}, browsers{0}, foxglove_clients{0};

  bool wants_images(const Client& c) const {
    return c.kind == Kind::kBrowser ||
           c.subscriptions.subscription_for(channel_id(fg::DerivedChannel::kLeftImage)) ||
           c.subscriptions.subscription_for(channel_id(fg::DerivedChannel::kRightImage));
  }

  void update_counts() {
    uint64_t b = 0, f = 0;
    bool wanted = false;
    for (const auto& [id, c] : clients) {
      (c.kind == Kind::kBrowser ? b : f)++;
      wanted |= wants_images(c);
    }
    browsers = b;
    foxglove_clients = f;
    owner->images_wanted_.store(wanted);
    update_ready();
  }

  // Whether some client would take an image now; wakes the frame pump when one would.
  void update_ready() {
    bool ready = false;
    for (const auto& [id, c] : clients)
      ready |= !c.cut && wants_images(c) && c.flow.ready_for_image(transport->queued_bytes(id));
    {
      std::lock_guard lock(owner->ready_mutex_);
      if (owner->ready_for_image_ == ready) return;
      owner->ready_for_image_ = ready;
    }
    if (ready) owner->ready_changed_.notify_all();
  }

  void cut_off(uint64_t id, Client& c) {
    if (c.cut) return;
    c.cut = true;
    ++disconnected_slow;
    transport->terminate(id);
  }

  // Sends unless the client is too far behind (then it is cut off and false returned).
  bool send(uint64_t id, Client& c, const void* data, size_t size, bool binary) {
    if (c.cut) return false;
    if (c.flow.offer_message(transport->queued_bytes(id), node::monotonic_ns()) ==
        viewer::Decision::kDisconnect) {
      cut_off(id, c);
      return false;
    }
    return transport->send(id, data, size, binary);
  }
  bool send_text(uint64_t id, Client& c, const std::string& text) {
    return send(id, c, text.data(), text.size(), false);
  }

  void status(uint64_t id, Client& c, fg::StatusLevel level, const std::string& text) {
    send_text(id, c, fg::status_json(level, text));
  }

  void on_open(uint64_t id, const std::string& subprotocol) {
    const bool foxglove = subprotocol == fg::kSubprotocol;
    auto [it, added] =
        clients.emplace(id, Client{foxglove ? Kind::kFoxglove : Kind::kBrowser,
                                   viewer::ClientFlow(params.flow, /*acks=*/!foxglove),
                                   {}});
    ++connections;
    if (foxglove) {
      send_text(id, it->second, fg::server_info_json("stereoball view", session_id));
      send_text(id, it->second, fg::advertise_json(channels));
    }
    update_counts();
  }

  void on_close(uint64_t id) {
    clients.erase(id);
    update_counts();
  }

  void on_foxglove_text(uint64_t id, Client& c, const std::string& text) {
    const auto message = fg::parse_client_message(text);
    std::vector<std::string> problems;
    if (const auto* s = std::get_if<fg::Subscribe>(&message)) {
      problems = c.subscriptions.subscribe(*s, channel_ids);
    } else if (const auto* u = std::get_if<fg::Unsubscribe>(&message)) {
      problems = c.subscriptions.unsubscribe(*u);
    } else if (const auto* n = std::get_if<fg::Unsupported>(&message)) {
      problems.push_back("operation '" + n->op + "' is not supported by this server");
    } else {
      ++bad_client_messages;
      status(id, c, fg::StatusLevel::kError, std::get<fg::Malformed>(message).problem);
    }
    for (const auto& p : problems) status(id, c, fg::StatusLevel::kWarning, p);
    update_counts();
  }

  void on_message(uint64_t id, bool text, const std::string& payload) {
    auto it = clients.find(id);
    if (it == clients.end()) return;
    Client& c = it->second;
    if (c.kind == Kind::kBrowser) {
      if (text && payload == "ack") {
        c.flow.on_ack();
        update_ready();
      } else if (text && payload == "scene-ack") {
        c.flow.on_scene_ack();
      } else if (text && calibration.on_action &&
                 (payload == "calibrate:finish" || payload == "calibrate:write")) {
        calibration.on_action(payload.substr(10));
      } else {
        ++bad_client_messages;  // the page sends nothing else: count it, act on nothing
      }
    } else if (!text) {
      ++bad_client_messages;
      status(id, c, fg::StatusLevel::kError,
             "binary client messages are not supported (no clientPublish capability)");
    } else {
      on_foxglove_text(id, c, payload);
    }
  }

  HttpReply on_http(const std::string& resource) {
    if (resource == "/" || resource.starts_with("/?") || resource == "/index.html")
      return {200, "text/html; charset=utf-8", std::string(page_html())};
    if (resource == "/stats") return {200, "application/json", stats_json()};
    if (resource == "/common.css")
      return {200, "text/css; charset=utf-8", std::string(common_css())};
    if (resource == "/calibrate" || resource.starts_with("/calibrate?")) {
      if (!calibration.state_json)
        return {404, "text/plain",
                "no calibration here: start it with stereoball calibrate live (or stereoball "
                "view --calibrate)\n"};
      return {200, "text/html; charset=utf-8", std::string(calibrate_page_html())};
    }
    if (resource == "/calibrate/state" && calibration.state_json)
      return {200, "application/json", calibration.state_json()};
    return {404, "text/plain", "not found\n"};
  }

  std::string stats_json() const {
    char buf[400];
    std::snprintf(
        buf, sizeof buf,
        "{\"browsers\":%llu,\"foxglove_clients\":%llu,\"connections\":%llu,"
        "\"disconnected_slow\":%llu,\"pairs_encoded\":%llu,\"images_sent\":%llu,"
        "\"images_dropped\":%llu,\"bad_client_messages\":%llu,\"pairs_from_preview\":%llu}\n",
        (unsigned long long)browsers.load(), (unsigned long long)foxglove_clients.load(),
        (unsigned long long)connections.load(), (unsigned long long)disconnected_slow.load(),
        (unsigned long long)pairs_encoded.load(), (unsigned long long)images_sent.load(),
        (unsigned long long)images_dropped.load(), (unsigned long long)bad_client_messages.load(),
        (unsigned long long)pairs_from_preview.load());
    return buf;
  }

  // Both eyes as Foxglove Message Data frames for one subscriber (built once per pair).
  struct FoxgloveImages {
    std::vector<uint8_t> left, right;
  };

  void deliver_pair(const viewer::PairJpeg& pair) {
    std::string browser_message;
    std::optional<FoxgloveImages> cdr;
    const int64_t now = node::monotonic_ns();
    for (auto& [id, c] : clients) {
      if (c.cut || !wants_images(c)) continue;
      switch (c.flow.offer_image(transport->queued_bytes(id), now)) {
        case viewer::Decision::kDisconnect:
          cut_off(id, c);
          continue;
        case viewer::Decision::kDrop:
          ++images_dropped;
          continue;
        case viewer::Decision::kSend:
          break;
      }
      ++images_sent;
      if (c.kind == Kind::kBrowser) {
        if (browser_message.empty()) browser_message = pair_message(pair);
        transport->send(id, browser_message.data(), browser_message.size(), true);
        continue;
      }
      if (!cdr) {
        cdr = FoxgloveImages{
            fg::compressed_image(pair.capture_stamp_ns, fg::Eye::kLeft, pair.left.bytes),
            fg::compressed_image(pair.capture_stamp_ns, fg::Eye::kRight, pair.right.bytes)};
      }
      const auto stamp = static_cast<uint64_t>(pair.capture_stamp_ns);
      if (auto s = c.subscriptions.subscription_for(channel_id(fg::DerivedChannel::kLeftImage))) {
        const auto frame = fg::message_data(*s, stamp, cdr->left);
        transport->send(id, frame.data(), frame.size(), true);
      }
      if (auto s = c.subscriptions.subscription_for(channel_id(fg::DerivedChannel::kRightImage))) {
        const auto frame = fg::message_data(*s, stamp, cdr->right);
        transport->send(id, frame.data(), frame.size(), true);
      }
    }
    update_ready();
  }

  void deliver_derived(const std::vector<viewer::DerivedMessage>& messages) {
    for (auto& [id, c] : clients) {
      if (c.kind != Kind::kFoxglove) continue;
      for (const auto& m : messages) {
        const auto sub = c.subscriptions.subscription_for(channel_id(m.channel));
        if (!sub) continue;
        const auto frame = fg::message_data(*sub, static_cast<uint64_t>(m.stamp_ns), m.cdr);
        if (!send(id, c, frame.data(), frame.size(), true)) break;
      }
    }
  }

  void push_scene() {
    update_ready();  // a Foxglove client's backlog drains without telling anyone
    const int64_t now = node::now_ns();
    std::string scene, plot;
    for (auto& [id, c] : clients) {
      if (c.kind == Kind::kBrowser) {
        if (c.cut) continue;
        const auto d = c.flow.offer_scene(transport->queued_bytes(id), node::monotonic_ns());
        if (d == viewer::Decision::kDisconnect) cut_off(id, c);
        if (d != viewer::Decision::kSend) continue;
        if (scene.empty()) scene = scene_json(now);
        transport->send(id, scene.data(), scene.size(), false);
      } else if (const auto sub = c.subscriptions.subscription_for(kPlotChannelId)) {
        if (plot.empty()) plot = plot_json();
        const auto frame =
            fg::message_data(*sub, static_cast<uint64_t>(now),
                             std::span(reinterpret_cast<const uint8_t*>(plot.data()), plot.size()));
        send(id, c, frame.data(), frame.size(), true);
      }
    }
  }
};

ViewServer::ViewServer(const ServerParams& params, std::function<std::string(int64_t)> scene_json,
                       std::function<std::string()> plot_json)
    : impl_(std::make_unique<Impl>()) {
  impl_->params = params;
  impl_->scene_json = std::move(scene_json);
  impl_->plot_json = std::move(plot_json);
  impl_->owner = this;
  for (const auto& c : impl_->channels) impl_->channel_ids.push_back(c.id);
  Impl* impl = impl_.get();
  WsTransport::Handlers handlers{
      [impl](uint64_t id, const std::string& p) { impl->on_open(id, p); },
      [impl](uint64_t id) { impl->on_close(id); },
      [impl](uint64_t id, bool text, const std::string& m) { impl->on_message(id, text, m); },
      [impl](const std::string& resource) { return impl->on_http(resource); }};
  impl_->transport = std::make_unique<WsTransport>(
      std::move(handlers), std::vector<std::string>{std::string(fg::kSubprotocol)},
      kMaxIncomingBytes);
}

void ViewServer::set_calibration(CalibrationHooks hooks) {
  impl_->calibration = std::move(hooks);
}

ViewServer::~ViewServer() {
  stop();
}

Result<std::string> ViewServer::start() {
  if (auto st = impl_->params.flow.validate(); !st) return Error{st.error()};
  if (!(impl_->params.scene_rate_hz > 0 && impl_->params.scene_rate_hz <= 120))
    return Error{"scene_rate_hz must be in (0, 120]"};
  uint16_t port = 0;
  const auto err = impl_->transport->start(impl_->params.bind_address, impl_->params.port, port);
  if (!err.empty()) return Error{err};
  Impl* impl = impl_.get();
  impl_->transport->every(static_cast<int64_t>(1e9 / impl_->params.scene_rate_hz),
                          [impl] { impl->push_scene(); });
  return "http://" + impl_->params.bind_address + ":" + std::to_string(port) + "/";
}

void ViewServer::stop() {
  impl_->transport->stop();
}

bool ViewServer::wait_until_ready_for_image(int64_t timeout_ns) {
  std::unique_lock lock(ready_mutex_);
  return ready_changed_.wait_for(lock, std::chrono::nanoseconds(timeout_ns),
                                 [this] { return ready_for_image_; });
}

void ViewServer::publish_pair(std::shared_ptr<const viewer::PairJpeg> pair) {
  Impl* impl = impl_.get();
  ++(pair->from_preview ? impl->pairs_from_preview : impl->pairs_encoded);
  // At most two pairs wait for the server thread; beyond that a pair is not queued at all
  // (a newer one follows), so a busy server never piles up images.
  if (impl->pairs_pending.fetch_add(1) >= 2) {
    --impl->pairs_pending;
    ++impl->images_dropped;
    return;
  }
  impl->transport->post([impl, pair] {
    --impl->pairs_pending;
    impl->deliver_pair(*pair);
  });
}

void ViewServer::publish_derived(std::vector<viewer::DerivedMessage> messages) {
  if (messages.empty()) return;
  Impl* impl = impl_.get();
  impl->transport->post([impl, m = std::move(messages)] { impl->deliver_derived(m); });
}

ServerStats ViewServer::stats() const {
  return {impl_->browsers,          impl_->foxglove_clients,    impl_->connections,
          impl_->disconnected_slow, impl_->pairs_encoded,       impl_->images_sent,
          impl_->images_dropped,    impl_->bad_client_messages, impl_->pairs_from_preview};
}

}  // namespace stereoball::view
