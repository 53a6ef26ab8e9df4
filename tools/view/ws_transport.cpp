// Compiled as C++17 (see ws_transport.hpp).
#include "ws_transport.hpp"

#include <pthread.h>

#define ASIO_STANDALONE
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include <chrono>
#include <map>
#include <thread>

namespace stereoball::view {

using WsServer = websocketpp::server<websocketpp::config::asio>;
using Hdl = websocketpp::connection_hdl;

struct WsTransport::Impl {
  Handlers handlers;
  std::vector<std::string> subprotocols;
  WsServer server;
  std::map<uint64_t, WsServer::connection_ptr> connections;
  std::map<Hdl, uint64_t, std::owner_less<Hdl>> ids;
  uint64_t next_id = 1;
  std::vector<std::unique_ptr<asio::steady_timer>> timers;
  std::thread thread;

  WsServer::connection_ptr find(uint64_t id) const {
    auto it = connections.find(id);
    return it == connections.end() ? nullptr : it->second;
  }

  void arm(asio::steady_timer* timer, int64_t period_ns, std::function<void()> fn) {
    timer->expires_after(std::chrono::nanoseconds(period_ns));
    timer->async_wait([this, timer, period_ns, fn](const std::error_code& ec) {
      if (ec) return;
      fn();
      arm(timer, period_ns, fn);
    });
  }
};

WsTransport::WsTransport(Handlers handlers, std::vector<std::string> subprotocols,
                         size_t max_incoming_bytes)
    : impl_(std::make_unique<Impl>()) {
  impl_->handlers = std::move(handlers);
  impl_->subprotocols = std::move(subprotocols);
  auto& s = impl_->server;
  s.clear_access_channels(websocketpp::log::alevel::all);
  s.clear_error_channels(websocketpp::log::elevel::all);
  s.set_max_message_size(max_incoming_bytes);
  s.set_max_http_body_size(max_incoming_bytes);
  s.set_open_handshake_timeout(5000);
  s.set_close_handshake_timeout(1000);
  Impl* impl = impl_.get();
  // No Nagle delay: an image message's last partial segment would otherwise wait for the
  // client's (delayed, up to 40 ms) acknowledgement of the previous one.
  s.set_socket_init_handler([](Hdl, asio::ip::tcp::socket& socket) {
    std::error_code ec;
    socket.set_option(asio::ip::tcp::no_delay(true), ec);
  });
  s.set_validate_handler([impl](Hdl h) {
    auto con = impl->server.get_con_from_hdl(h);
    for (const auto& offered : con->get_requested_subprotocols()) {
      for (const auto& ours : impl->subprotocols) {
        if (offered == ours) {
          websocketpp::lib::error_code ec;
          con->select_subprotocol(offered, ec);
          return true;
        }
      }
    }
    return true;
  });
  s.set_open_handler([impl](Hdl h) {
    auto con = impl->server.get_con_from_hdl(h);
    const uint64_t id = impl->next_id++;
    impl->connections[id] = con;
    impl->ids[h] = id;
    impl->handlers.on_open(id, con->get_subprotocol());
  });
  auto closed = [impl](Hdl h) {
    auto it = impl->ids.find(h);
    if (it == impl->ids.end()) return;
    const uint64_t id = it->second;
    impl->ids.erase(it);
    impl->connections.erase(id);
    impl->handlers.on_close(id);
  };
  s.set_close_handler(closed);
  s.set_fail_handler(closed);
  s.set_message_handler([impl](Hdl h, WsServer::message_ptr m) {
    auto it = impl->ids.find(h);
    if (it == impl->ids.end()) return;
    impl->handlers.on_message(it->second, m->get_opcode() == websocketpp::frame::opcode::text,
                              m->get_payload());
  });
  s.set_http_handler([impl](Hdl h) {
    auto con = impl->server.get_con_from_hdl(h);
    const HttpReply reply = impl->handlers.on_http(con->get_resource());
    con->set_status(static_cast<websocketpp::http::status_code::value>(reply.status));
    if (!reply.content_type.empty()) con->append_header("Content-Type", reply.content_type);
    con->append_header("Cache-Control", "no-store");
    con->set_body(reply.body);
  });
}

WsTransport::~WsTransport() {
  stop();
}

std::string WsTransport::start(const std::string& bind_address, uint16_t port,
                               uint16_t& bound_port) {
  auto& s = impl_->server;
  websocketpp::lib::error_code ec;
  s.init_asio(ec);
  if (ec) return "cannot start the web server: " + ec.message();
  s.set_reuse_addr(true);
  std::error_code aec;
  const auto address = asio::ip::make_address(bind_address, aec);
  if (aec) return "'" + bind_address + "' is not an IP address";
  const asio::ip::tcp::endpoint endpoint(address, port);
  const std::string where = bind_address + ":" + std::to_string(port);
  // Bind a probe first: websocketpp reports any failure as "Underlying Transport Error",
  // while the socket's own error says what is wrong ("Address already in use").
  {
    asio::ip::tcp::acceptor probe(s.get_io_service());
    probe.open(endpoint.protocol(), aec);
    // As the server itself does: a port left in TIME_WAIT by a restarted viewer is free.
    if (!aec) probe.set_option(asio::socket_base::reuse_address(true), aec);
    if (!aec) probe.bind(endpoint, aec);
    if (aec) return "cannot listen on " + where + ": " + aec.message();
  }
  s.listen(endpoint, ec);
  if (ec) return "cannot listen on " + where + ": " + ec.message();
  s.start_accept(ec);
  if (ec) return "cannot accept on " + where + ": " + ec.message();
  const auto local = s.get_local_endpoint(aec);
  bound_port = aec ? port : local.port();
  Impl* impl = impl_.get();
  impl_->thread = std::thread([impl] {
    pthread_setname_np(pthread_self(), "view-web");  // per-thread CPU in the benchmark
    impl->server.run();
  });
  return "";
}

void WsTransport::stop() {
  if (!impl_->thread.joinable()) return;
  Impl* impl = impl_.get();
  post([impl] {
    websocketpp::lib::error_code ec;
    impl->server.stop_listening(ec);
    for (auto& t : impl->timers) t->cancel();
    std::vector<WsServer::connection_ptr> open;
    for (auto& [id, con] : impl->connections) open.push_back(con);
    for (auto& con : open)
      con->terminate(websocketpp::error::make_error_code(websocketpp::error::general));
    impl->server.stop();
  });
  impl_->thread.join();
}

void WsTransport::post(std::function<void()> fn) {
  asio::post(impl_->server.get_io_service(), std::move(fn));
}

void WsTransport::every(int64_t period_ns, std::function<void()> fn) {
  Impl* impl = impl_.get();
  post([impl, period_ns, fn] {
    impl->timers.push_back(std::make_unique<asio::steady_timer>(impl->server.get_io_service()));
    impl->arm(impl->timers.back().get(), period_ns, fn);
  });
}

bool WsTransport::send(uint64_t id, const void* data, size_t size, bool binary) {
  auto con = impl_->find(id);
  if (!con) return false;
  const auto ec = con->send(
      data, size, binary ? websocketpp::frame::opcode::binary : websocketpp::frame::opcode::text);
  return !ec;
}

size_t WsTransport::queued_bytes(uint64_t id) const {
  auto con = impl_->find(id);
  return con ? con->get_buffered_amount() : 0;
}

void WsTransport::terminate(uint64_t id) {
  auto con = impl_->find(id);
  if (!con) return;
  // Later, not inside the caller's loop: terminating runs the close handler at once.
  post([con] { con->terminate(websocketpp::error::make_error_code(websocketpp::error::general)); });
}

}  // namespace stereoball::view
