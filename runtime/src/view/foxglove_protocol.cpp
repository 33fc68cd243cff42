#include "view/foxglove_protocol.h"

#include <cstring>
#include <nlohmann/json.hpp>

namespace plugslam::runtime::foxglove {

using nlohmann::json;

namespace {

// A client may not ask for more than this in one message: far beyond what any viewer sends,
// small enough that a hostile list costs nothing.
constexpr size_t kMaxListItems = 100000;

const json& member(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end()) throw ProtocolError(std::string("missing field '") + key + "'");
  return *it;
}

uint32_t u32(const json& j, const char* what) {
  if (!j.is_number_integer() && !j.is_number_unsigned())
    throw ProtocolError(std::string("'") + what + "' must be an integer, got " + j.type_name());
  if (j.is_number_unsigned()) {
    const auto v = j.get<uint64_t>();
    if (v > 0xFFFFFFFFull) throw ProtocolError(std::string("'") + what + "' is out of range");
    return static_cast<uint32_t>(v);
  }
  const auto v = j.get<int64_t>();
  if (v < 0 || v > 0xFFFFFFFFll) throw ProtocolError(std::string("'") + what + "' is out of range");
  return static_cast<uint32_t>(v);
}

const json& list(const json& j, const char* key) {
  const json& a = member(j, key);
  if (!a.is_array()) throw ProtocolError(std::string("'") + key + "' must be an array");
  if (a.size() > kMaxListItems) throw ProtocolError(std::string("'") + key + "' is too long");
  return a;
}

std::vector<std::string> names(const json& j, const char* key) {
  std::vector<std::string> out;
  if (!j.contains(key)) return out;  // absent = all, as an empty list
  for (const auto& n : list(j, key)) {
    if (!n.is_string()) throw ProtocolError(std::string("'") + key + "' must hold strings");
    out.push_back(n.get<std::string>());
  }
  return out;
}

std::optional<std::string> requestId(const json& j) {
  auto it = j.find("id");
  if (it == j.end() || it->is_null()) return std::nullopt;
  if (!it->is_string()) throw ProtocolError("'id' must be a string");
  return it->get<std::string>();
}

uint32_t readU32(std::string_view b, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(static_cast<uint8_t>(b[at + i])) << (8 * i);
  return v;
}

void putU32(std::string& o, uint32_t v) {
  for (int i = 0; i < 4; ++i) o.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void putU64(std::string& o, uint64_t v) {
  for (int i = 0; i < 8; ++i) o.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

}  // namespace

ClientMessage parseText(std::string_view text) {
  json j = json::parse(text.begin(), text.end(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw ProtocolError("not valid JSON");
  if (!j.is_object()) throw ProtocolError("a text message must be a JSON object");
  const json& op_field = member(j, "op");
  if (!op_field.is_string()) throw ProtocolError("'op' must be a string");
  const std::string op = op_field.get<std::string>();
  try {
    if (op == "subscribe") {
      Subscribe s;
      for (const auto& item : list(j, "subscriptions")) {
        if (!item.is_object()) throw ProtocolError("each subscription must be an object");
        s.subscriptions.emplace_back(u32(member(item, "id"), "id"),
                                     u32(member(item, "channelId"), "channelId"));
      }
      return s;
    }
    if (op == "unsubscribe") {
      Unsubscribe u;
      for (const auto& id : list(j, "subscriptionIds")) u.ids.push_back(u32(id, "subscriptionIds"));
      return u;
    }
    if (op == "getParameters") return GetParameters{names(j, "parameterNames"), requestId(j)};
    if (op == "setParameters") {
      SetParameters s;
      s.id = requestId(j);
      for (const auto& p : list(j, "parameters")) {
        if (!p.is_object()) throw ProtocolError("each parameter must be an object");
        const json& name = member(p, "name");
        if (!name.is_string()) throw ProtocolError("a parameter's 'name' must be a string");
        auto value = p.find("value");
        if (value == p.end() || value->is_null())
          throw ProtocolError("parameter '" + name.get<std::string>() +
                              "' has no value (parameters cannot be unset)");
        if (auto type = p.find("type"); type != p.end() && *type == "byte_array")
          throw ProtocolError("parameter '" + name.get<std::string>() +
                              "': byte_array values are not supported");
        if (value->is_object())
          throw ProtocolError("parameter '" + name.get<std::string>() +
                              "': an object value is not a parameter");
        // JSON is YAML's flow syntax: the value goes to the --set parser as it came.
        s.parameters.push_back(ParameterAssignment{name.get<std::string>(), value->dump()});
      }
      return s;
    }
    if (op == "subscribeParameterUpdates") return ParameterUpdates{true, names(j, "parameterNames")};
    if (op == "unsubscribeParameterUpdates")
      return ParameterUpdates{false, names(j, "parameterNames")};
    // Known ops of capabilities we do not offer, and the foxglove.sdk.v1 greeting: acknowledged
    // by ignoring them, as the spec lets a server do.
    for (const char* known : {"clientInfo", "advertise", "unadvertise", "subscribeConnectionGraph",
                              "unsubscribeConnectionGraph", "fetchAsset"})
      if (op == known) return Ignored{op};
  } catch (const json::exception& e) {
    throw ProtocolError(std::string("malformed '") + op + "': " + e.what());
  }
  throw ProtocolError("unknown op '" + op.substr(0, 64) + "'");
}

ClientMessage parseBinary(std::string_view b) {
  if (b.empty()) throw ProtocolError("empty binary message");
  const auto opcode = static_cast<uint8_t>(b[0]);
  if (opcode == 0x02) {
    if (b.size() < 13) throw ProtocolError("service call request too short");
    ServiceCall c;
    c.service_id = readU32(b, 1);
    c.call_id = readU32(b, 5);
    const uint32_t n = readU32(b, 9);
    if (n > b.size() - 13) throw ProtocolError("service call request: encoding length too large");
    c.encoding.assign(b.substr(13, n));
    c.payload.assign(b.substr(13 + n));
    return c;
  }
  if (opcode == 0x01) throw ProtocolError("client publishing is not supported");
  throw ProtocolError("unknown binary opcode " + std::to_string(opcode));
}

std::string serverInfo(const std::string& name, const std::string& session_id) {
  return json{{"op", "serverInfo"},
              {"name", name},
              {"capabilities", {"parameters", "parametersSubscribe", "services"}},
              {"supportedEncodings", {"json"}},
              {"metadata", json::object()},
              {"sessionId", session_id}}
      .dump();
}

std::string status(int level, const std::string& message, const std::string& id) {
  json j{{"op", "status"}, {"level", level}, {"message", message}};
  if (!id.empty()) j["id"] = id;
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string advertise(const std::vector<ViewChannel>& channels) {
  json list = json::array();
  for (const auto& c : channels)
    list.push_back(json{{"id", c.id},
                        {"topic", c.topic},
                        {"encoding", "json"},
                        {"schemaName", c.schema_name},
                        {"schema", c.schema},
                        {"schemaEncoding", "jsonschema"}});
  return json{{"op", "advertise"}, {"channels", std::move(list)}}.dump();
}

std::string parameterValues(const std::vector<Parameter>& parameters,
                            const std::optional<std::string>& id) {
  json list = json::array();
  for (const auto& p : parameters) {
    json item{{"name", p.name}, {"value", json::parse(p.value_json, nullptr, false)}};
    if (item["value"].is_discarded()) item["value"] = p.value_json;
    if (!p.type.empty()) item["type"] = p.type;
    list.push_back(std::move(item));
  }
  json j{{"op", "parameterValues"}, {"parameters", std::move(list)}};
  if (id) j["id"] = *id;
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string advertiseServices(const std::vector<Service>& services) {
  json list = json::array();
  for (const auto& s : services)
    list.push_back(json{{"id", s.id},
                        {"name", s.name},
                        {"type", s.type},
                        {"requestSchema", s.request_schema},
                        {"responseSchema", s.response_schema}});
  return json{{"op", "advertiseServices"}, {"services", std::move(list)}}.dump();
}

std::string serviceCallFailure(uint32_t service_id, uint32_t call_id, const std::string& message) {
  return json{{"op", "serviceCallFailure"},
              {"serviceId", service_id},
              {"callId", call_id},
              {"message", message}}
      .dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string serviceResponse(const std::string& message) {
  return json{{"message", message}}.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string messageDataHeader(uint32_t subscription, uint64_t log_time) {
  std::string o;
  o.push_back('\x01');
  putU32(o, subscription);
  putU64(o, log_time);
  return o;
}

std::string serviceCallResponse(uint32_t service_id, uint32_t call_id, const std::string& encoding,
                                const std::string& payload) {
  std::string o;
  o.push_back('\x03');
  putU32(o, service_id);
  putU32(o, call_id);
  putU32(o, static_cast<uint32_t>(encoding.size()));
  o += encoding;
  o += payload;
  return o;
}

}  // namespace plugslam::runtime::foxglove
