#pragma once
// The Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1), server side, without
// sockets: the JSON the server sends, parsing of what clients send, each client's
// subscriptions, and the binary Message Data frame (opcode 1).

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace stereoball::viewer::foxglove {

inline constexpr std::string_view kSubprotocol = "foxglove.websocket.v1";
inline constexpr uint8_t kOpMessageData = 0x01;

/// A channel the server advertises.
struct Channel {
  uint32_t id = 0;
  std::string topic;
  std::string encoding;         ///< "cdr" or "json"
  std::string schema_name;      ///< e.g. "foxglove::CompressedImage"
  std::string schema;           ///< IDL text (omgidl) or JSON schema (jsonschema)
  std::string schema_encoding;  ///< "omgidl" or "jsonschema"
};

enum class StatusLevel { kInfo = 0, kWarning = 1, kError = 2 };

std::string server_info_json(std::string_view name, std::string_view session_id);
std::string advertise_json(std::span<const Channel> channels);
std::string status_json(StatusLevel level, std::string_view message);

/// A client's subscribe request: (subscription id, channel id) pairs.
struct Subscribe {
  std::vector<std::pair<uint32_t, uint32_t>> subscriptions;
};
/// A client's unsubscribe request.
struct Unsubscribe {
  std::vector<uint32_t> subscription_ids;
};
/// An operation this server does not offer (e.g. clientPublish), named for the status reply.
struct Unsupported {
  std::string op;
};
/// A text message that is not valid protocol JSON; the text says what is wrong.
struct Malformed {
  std::string problem;
};
using ClientMessage = std::variant<Subscribe, Unsubscribe, Unsupported, Malformed>;

/// Parses one text message from a client (never throws).
ClientMessage parse_client_message(std::string_view text);

/// One client's subscriptions. Requests that break the protocol's rules are refused with a
/// message for a status reply; the rest of the request still applies.
class Subscriptions {
 public:
  /// Applies a subscribe; returns one problem per refused pair (unknown channel, id in use).
  std::vector<std::string> subscribe(const Subscribe& request,
                                     const std::vector<uint32_t>& known_channels);
  /// Applies an unsubscribe; returns one problem per unknown subscription id.
  std::vector<std::string> unsubscribe(const Unsubscribe& request);
  /// Subscription id of this client on channel_id, if subscribed.
  std::optional<uint32_t> subscription_for(uint32_t channel_id) const;
  size_t size() const { return by_subscription_.size(); }

 private:
  std::map<uint32_t, uint32_t> by_subscription_;  // subscription id -> channel id
};

/// Binary Message Data: opcode 1, uint32 subscription id, uint64 receive time (ns), payload
/// (little-endian).
std::vector<uint8_t> message_data(uint32_t subscription_id, uint64_t receive_time_ns,
                                  std::span<const uint8_t> payload);

}  // namespace stereoball::viewer::foxglove
