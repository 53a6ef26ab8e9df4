#include "viewer/core/foxglove_protocol.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <nlohmann/json.hpp>

namespace stereoball::viewer::foxglove {
namespace {

TEST(FoxgloveProtocol, AdvertiseListsEveryChannelWithItsSchema) {
  const std::vector<Channel> channels = {{3, "a", "cdr", "foxglove::X", "idl", "omgidl"},
                                         {7, "b", "json", "Plot", "{}", "jsonschema"}};
  const auto j = nlohmann::json::parse(advertise_json(channels));
  EXPECT_EQ(j["op"], "advertise");
  ASSERT_EQ(j["channels"].size(), 2u);
  EXPECT_EQ(j["channels"][1]["id"], 7);
  EXPECT_EQ(j["channels"][1]["schemaEncoding"], "jsonschema");
  EXPECT_EQ(j["channels"][0]["schemaName"], "foxglove::X");
  EXPECT_EQ(nlohmann::json::parse(server_info_json("s", "1"))["op"], "serverInfo");
}

TEST(FoxgloveProtocol, ParsesSubscribeAndUnsubscribe) {
  const auto s = parse_client_message(
      R"({"op":"subscribe","subscriptions":[{"id":0,"channelId":3},{"id":9,"channelId":7}]})");
  ASSERT_TRUE(std::holds_alternative<Subscribe>(s));
  const auto& pairs = std::get<Subscribe>(s).subscriptions;
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[1], std::make_pair(9u, 7u));
  const auto u = parse_client_message(R"({"op":"unsubscribe","subscriptionIds":[9]})");
  ASSERT_TRUE(std::holds_alternative<Unsubscribe>(u));
  EXPECT_EQ(std::get<Unsubscribe>(u).subscription_ids, std::vector<uint32_t>{9});
}

TEST(FoxgloveProtocol, MalformedMessagesAreNamedNotThrown) {
  for (const char* bad :
       {"", "{", "[1,2]", R"({"op":5})", R"({"op":"subscribe"})",
        R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":3}]})",
        R"({"op":"subscribe","subscriptions":[{"id":1.5,"channelId":3}]})",
        R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":99999999999}]})",
        R"({"op":"unsubscribe","subscriptionIds":["x"]})", "\xff\xfe"}) {
    const auto m = parse_client_message(bad);
    ASSERT_TRUE(std::holds_alternative<Malformed>(m)) << bad;
    EXPECT_FALSE(std::get<Malformed>(m).problem.empty());
  }
  const auto other = parse_client_message(R"({"op":"advertise","channels":[]})");
  ASSERT_TRUE(std::holds_alternative<Unsupported>(other));
  EXPECT_EQ(std::get<Unsupported>(other).op, "advertise");
}

TEST(Subscriptions, RefusesUnknownChannelsReusedIdsAndUnknownUnsubscribes) {
  Subscriptions subs;
  const std::vector<uint32_t> known = {1, 2};
  auto problems = subs.subscribe({{{0, 1}, {1, 5}, {0, 2}}}, known);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_NE(problems[0].find("unknown channel 5"), std::string::npos);
  EXPECT_NE(problems[1].find("already in use"), std::string::npos);
  EXPECT_EQ(subs.subscription_for(1), 0u);
  EXPECT_FALSE(subs.subscription_for(2));
  problems = subs.unsubscribe({{0, 42}});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("42"), std::string::npos);
  EXPECT_EQ(subs.size(), 0u);
}

TEST(FoxgloveProtocol, MessageDataIsOpcodeOneThenIdTimeAndPayloadLittleEndian) {
  const std::vector<uint8_t> payload = {7, 8, 9};
  const auto frame = message_data(0x01020304, 0x1122334455667788ull, payload);
  ASSERT_EQ(frame.size(), 16u);
  EXPECT_EQ(frame[0], 1);
  EXPECT_EQ(frame[1], 0x04);
  EXPECT_EQ(frame[4], 0x01);
  EXPECT_EQ(frame[5], 0x88);
  EXPECT_EQ(frame[12], 0x11);
  EXPECT_EQ(frame[13], 7);
  EXPECT_EQ(frame[15], 9);
}

}  // namespace
}  // namespace stereoball::viewer::foxglove
