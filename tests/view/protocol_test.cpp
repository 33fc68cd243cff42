// The Foxglove WebSocket protocol layer: client messages parsed (and refused with a reason),
// server messages laid out as the spec says, --serve addresses, service requests.
#include <gtest/gtest.h>

#include "view/foxglove_protocol.h"
#include "view/foxglove_server.h"
#include "view/parameters.h"

namespace plugslam::runtime {
namespace {

namespace fg = foxglove;

TEST(FoxgloveProtocol, ParsesTheClientOps) {
  auto s = std::get<fg::Subscribe>(
      fg::parseText(R"({"op":"subscribe","subscriptions":[{"id":0,"channelId":3},{"id":7,"channelId":5}]})"));
  ASSERT_EQ(s.subscriptions.size(), 2u);
  EXPECT_EQ(s.subscriptions[1], std::make_pair(7u, 5u));
  auto u = std::get<fg::Unsubscribe>(fg::parseText(R"({"op":"unsubscribe","subscriptionIds":[4]})"));
  EXPECT_EQ(u.ids, std::vector<uint32_t>{4});
  auto g = std::get<fg::GetParameters>(fg::parseText(R"({"op":"getParameters","parameterNames":["a.b"],"id":"x"})"));
  EXPECT_EQ(g.names, std::vector<std::string>{"a.b"});
  EXPECT_EQ(g.id, std::optional<std::string>("x"));
  auto set = std::get<fg::SetParameters>(fg::parseText(
      R"({"op":"setParameters","parameters":[{"name":"a","value":0.5},{"name":"b","value":[1,2]},{"name":"c","value":"text"}]})"));
  ASSERT_EQ(set.parameters.size(), 3u);
  EXPECT_EQ(set.parameters[0].value, "0.5");
  EXPECT_EQ(set.parameters[1].value, "[1,2]");
  EXPECT_EQ(set.parameters[2].value, "\"text\"");  // YAML reads a JSON string as that string
  EXPECT_TRUE(std::holds_alternative<fg::Ignored>(fg::parseText(R"({"op":"clientInfo","name":"x"})")));
  auto p = std::get<fg::ParameterUpdates>(fg::parseText(R"({"op":"unsubscribeParameterUpdates"})"));
  EXPECT_FALSE(p.subscribe);
  EXPECT_TRUE(p.names.empty());

  std::string call("\x02\x05\x00\x00\x00\x09\x00\x00\x00\x04\x00\x00\x00json{}", 19);
  auto c = std::get<fg::ServiceCall>(fg::parseBinary(call));
  EXPECT_EQ(c.service_id, 5u);
  EXPECT_EQ(c.call_id, 9u);
  EXPECT_EQ(c.encoding, "json");
  EXPECT_EQ(c.payload, "{}");
}

TEST(FoxgloveProtocol, RefusesMalformedMessagesWithAReason) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "not valid JSON"},
      {"{", "not valid JSON"},
      {"\"op\"", "JSON object"},
      {"{}", "missing field 'op'"},
      {R"({"op":1})", "'op' must be a string"},
      {R"({"op":"nope"})", "unknown op 'nope'"},
      {R"({"op":"subscribe"})", "missing field 'subscriptions'"},
      {R"({"op":"subscribe","subscriptions":{}})", "must be an array"},
      {R"({"op":"subscribe","subscriptions":[1]})", "must be an object"},
      {R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]})", "out of range"},
      {R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":1}]})", "out of range"},
      {R"({"op":"subscribe","subscriptions":[{"id":1.5,"channelId":1}]})", "must be an integer"},
      {R"({"op":"setParameters","parameters":[{"name":"a"}]})", "cannot be unset"},
      {R"({"op":"setParameters","parameters":[{"name":"a","value":{"x":1}}]})", "object value"},
      {R"({"op":"setParameters","parameters":[{"name":"a","value":"QQ==","type":"byte_array"}]})", "byte_array"},
      {R"({"op":"getParameters","parameterNames":[1]})", "must hold strings"},
      {R"({"op":"getParameters","id":3})", "'id' must be a string"},
  };
  for (const auto& [text, why] : cases) {
    try {
      fg::parseText(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const fg::ProtocolError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << text << ": " << e.what();
    }
  }
  const std::string binary[] = {std::string(), std::string("\x01\x00\x00\x00\x00", 5),
                                std::string("\x02\x01", 2), std::string("\x07", 1),
                                std::string("\x02\x01\x00\x00\x00\x01\x00\x00\x00\xff\x00\x00\x00", 13)};
  for (const auto& b : binary) EXPECT_THROW(fg::parseBinary(b), fg::ProtocolError) << b.size();
}

TEST(FoxgloveProtocol, BinaryServerMessagesFollowTheSpec) {
  const std::string h = fg::messageDataHeader(0x01020304u, 0x0102030405060708ull);
  ASSERT_EQ(h.size(), 13u);
  EXPECT_EQ(h[0], '\x01');
  EXPECT_EQ(h.substr(1, 4), std::string("\x04\x03\x02\x01", 4));  // little-endian
  EXPECT_EQ(h.substr(5, 8), std::string("\x08\x07\x06\x05\x04\x03\x02\x01", 8));
  const std::string r = fg::serviceCallResponse(2, 3, "json", "{}");
  EXPECT_EQ(r, std::string("\x03\x02\x00\x00\x00\x03\x00\x00\x00\x04\x00\x00\x00json{}", 19));
  const std::string info = fg::serverInfo("plugslam", "42");
  EXPECT_NE(info.find("\"op\":\"serverInfo\""), std::string::npos);
  EXPECT_NE(info.find("\"parameters\""), std::string::npos);
  EXPECT_NE(info.find("\"services\""), std::string::npos);
  // Client text is echoed in replies: invalid UTF-8 must not make the reply throw.
  EXPECT_NO_THROW(fg::status(2, "bad \xff\xfe bytes"));
}

TEST(ServeAddress, ParsesTheForms) {
  ViewServerOptions o;
  parseServeAddress("", o);
  EXPECT_EQ(o.address, "127.0.0.1");
  EXPECT_EQ(o.port, 8765);
  parseServeAddress(":0", o);
  EXPECT_EQ(o.port, 0);
  parseServeAddress("0.0.0.0:9000", o);
  EXPECT_EQ(o.address, "0.0.0.0");
  EXPECT_EQ(o.port, 9000);
  parseServeAddress("[::1]:9001", o);
  EXPECT_EQ(o.address, "::1");
  parseServeAddress("9002", o);
  EXPECT_EQ(o.port, 9002);
  for (const char* bad : {"host:", "1.2.3.4:99999", "1.2.3.4:12ab"})
    EXPECT_THROW(parseServeAddress(bad, o), InputError) << bad;
}

TEST(ServiceRequests, ParseTheirFields) {
  auto r = parseServiceRequest(R"({"count":4,"path":"s","action":"a.b","args":["x","y"]})");
  EXPECT_EQ(r.count, 4);
  EXPECT_EQ(r.path, "s");
  EXPECT_EQ(r.action, "a.b");
  EXPECT_EQ(r.args, (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(parseServiceRequest("").count, 1);
  for (const char* bad : {"[]", "{", R"({"count":0})", R"({"count":"2"})", R"({"args":[1]})"})
    EXPECT_THROW(parseServiceRequest(bad), InputError) << bad;
}

}  // namespace
}  // namespace plugslam::runtime
