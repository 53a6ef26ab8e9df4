#include "viewer/core/foxglove_protocol.hpp"

#include <algorithm>
#include <cstring>

#include <nlohmann/json.hpp>

namespace stereoball::viewer::foxglove {
namespace {

using nlohmann::json;

// A protocol id: a non-negative integer that fits uint32.
std::optional<uint32_t> id_field(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key)) return std::nullopt;
  const json& v = object.at(key);
  if (!v.is_number_integer()) return std::nullopt;
  const auto n = v.get<int64_t>();
  if (n < 0 || n > UINT32_MAX) return std::nullopt;
  return static_cast<uint32_t>(n);
}

ClientMessage parse_subscribe(const json& j) {
  if (!j.contains("subscriptions") || !j["subscriptions"].is_array())
    return Malformed{"subscribe without a 'subscriptions' array"};
  Subscribe s;
  for (const auto& item : j["subscriptions"]) {
    const auto id = id_field(item, "id");
    const auto channel = id_field(item, "channelId");
    if (!id || !channel)
      return Malformed{"subscribe: each subscription needs integer 'id' and 'channelId'"};
    s.subscriptions.emplace_back(*id, *channel);
  }
  return s;
}

ClientMessage parse_unsubscribe(const json& j) {
  if (!j.contains("subscriptionIds") || !j["subscriptionIds"].is_array())
    return Malformed{"unsubscribe without a 'subscriptionIds' array"};
  Unsubscribe u;
  for (const auto& item : j["subscriptionIds"]) {
    if (!item.is_number_integer() || item.get<int64_t>() < 0 || item.get<int64_t>() > UINT32_MAX)
      return Malformed{"unsubscribe: subscription ids must be non-negative integers"};
    u.subscription_ids.push_back(item.get<uint32_t>());
  }
  return u;
}

}  // namespace

std::string server_info_json(std::string_view name, std::string_view session_id) {
  return json{{"op", "serverInfo"},
              {"name", name},
              {"capabilities", json::array()},
              {"sessionId", session_id}}
      .dump();
}

std::string advertise_json(std::span<const Channel> channels) {
  json list = json::array();
  for (const auto& c : channels) {
    list.push_back({{"id", c.id},
                    {"topic", c.topic},
                    {"encoding", c.encoding},
                    {"schemaName", c.schema_name},
                    {"schema", c.schema},
                    {"schemaEncoding", c.schema_encoding}});
  }
  return json{{"op", "advertise"}, {"channels", list}}.dump();
}

std::string status_json(StatusLevel level, std::string_view message) {
  return json{{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}}.dump();
}

ClientMessage parse_client_message(std::string_view text) {
  const json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return Malformed{"not valid JSON"};
  if (!j.is_object() || !j.contains("op") || !j["op"].is_string())
    return Malformed{"a JSON object with a string 'op' is required"};
  const auto op = j["op"].get<std::string>();
  if (op == "subscribe") return parse_subscribe(j);
  if (op == "unsubscribe") return parse_unsubscribe(j);
  return Unsupported{op};
}

std::vector<std::string> Subscriptions::subscribe(const Subscribe& request,
                                                  const std::vector<uint32_t>& known_channels) {
  std::vector<std::string> problems;
  for (const auto& [id, channel] : request.subscriptions) {
    if (std::find(known_channels.begin(), known_channels.end(), channel) == known_channels.end()) {
      problems.push_back("subscription " + std::to_string(id) + ": unknown channel " +
                         std::to_string(channel));
    } else if (by_subscription_.count(id)) {
      problems.push_back("subscription id " + std::to_string(id) + " is already in use");
    } else if (subscription_for(channel)) {
      problems.push_back("channel " + std::to_string(channel) + " is already subscribed");
    } else {
      by_subscription_[id] = channel;
    }
  }
  return problems;
}

std::vector<std::string> Subscriptions::unsubscribe(const Unsubscribe& request) {
  std::vector<std::string> problems;
  for (uint32_t id : request.subscription_ids) {
    if (by_subscription_.erase(id) == 0)
      problems.push_back("unknown subscription id " + std::to_string(id));
  }
  return problems;
}

std::optional<uint32_t> Subscriptions::subscription_for(uint32_t channel_id) const {
  for (const auto& [id, channel] : by_subscription_)
    if (channel == channel_id) return id;
  return std::nullopt;
}

std::vector<uint8_t> message_data(uint32_t subscription_id, uint64_t receive_time_ns,
                                  std::span<const uint8_t> payload) {
  std::vector<uint8_t> out(1 + 4 + 8 + payload.size());
  out[0] = kOpMessageData;
  // The protocol is little-endian, like every host this runs on (x86-64, arm64).
  std::memcpy(out.data() + 1, &subscription_id, 4);
  std::memcpy(out.data() + 5, &receive_time_ns, 8);
  if (!payload.empty()) std::memcpy(out.data() + 13, payload.data(), payload.size());
  return out;
}

}  // namespace stereoball::viewer::foxglove
