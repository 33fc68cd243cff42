#pragma once
// The Foxglove WebSocket protocol, v1 messages (foxglove/ws-protocol docs/spec.md; the same under
// the subprotocols foxglove.websocket.v1 and foxglove.sdk.v1): parsing what clients send, and
// building what the server sends. Pure functions, no I/O: the server and the fuzz target share
// them. Client input is untrusted: every malformed message is a ProtocolError saying why.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "plugslam/errors.h"
#include "view/view_hub.h"

namespace plugslam::runtime::foxglove {

/// The subprotocols served, in order of preference.
inline constexpr const char* kSubprotocols[] = {"foxglove.sdk.v1", "foxglove.websocket.v1"};

/// A client message the server cannot act on; what() is sent back in a status message.
class ProtocolError : public InputError {
 public:
  using InputError::InputError;
};

/// subscribe: (subscription id, channel id) pairs.
struct Subscribe {
  std::vector<std::pair<uint32_t, uint32_t>> subscriptions;
};
/// unsubscribe: subscription ids.
struct Unsubscribe {
  std::vector<uint32_t> ids;
};
/// getParameters (empty names: all).
struct GetParameters {
  std::vector<std::string> names;
  std::optional<std::string> id;
};
/// One parameter assignment; the value as YAML flow text (JSON is YAML), as `--set` takes it.
struct ParameterAssignment {
  std::string name;
  std::string value;
};
/// setParameters.
struct SetParameters {
  std::vector<ParameterAssignment> parameters;
  std::optional<std::string> id;
};
/// subscribeParameterUpdates / unsubscribeParameterUpdates (empty names: all).
struct ParameterUpdates {
  bool subscribe = true;
  std::vector<std::string> names;
};
/// A binary service call request.
struct ServiceCall {
  uint32_t service_id = 0;
  uint32_t call_id = 0;
  std::string encoding;
  std::string payload;
};
/// A well-formed message the server does not act on (clientInfo, connection graph, ...).
struct Ignored {
  std::string op;
};

/// Anything a client sends.
using ClientMessage = std::variant<Subscribe, Unsubscribe, GetParameters, SetParameters,
                                   ParameterUpdates, ServiceCall, Ignored>;

/// Parses a text frame (a JSON object with "op"); throws ProtocolError.
ClientMessage parseText(std::string_view text);
/// Parses a binary frame (opcode byte first); throws ProtocolError.
ClientMessage parseBinary(std::string_view bytes);

/// A parameter as the server reports it.
struct Parameter {
  std::string name;
  std::string value_json;  ///< the value as JSON text
  std::string type;        ///< "", "float64" or "float64_array" (the protocol's hints)
};
/// An advertised service.
struct Service {
  uint32_t id = 0;
  std::string name;            ///< "pause", "pipeline.graph.save_graph"
  std::string type;            ///< "plugslam.Pause", "plugslam.Action"
  std::string request_schema;  ///< JSON schema of the request
  std::string response_schema;
};

/// serverInfo.
std::string serverInfo(const std::string& name, const std::string& session_id);
/// status (level 0 info, 1 warning, 2 error).
std::string status(int level, const std::string& message, const std::string& id = "");
/// advertise.
std::string advertise(const std::vector<ViewChannel>& channels);
/// parameterValues.
std::string parameterValues(const std::vector<Parameter>& parameters,
                            const std::optional<std::string>& id);
/// advertiseServices.
std::string advertiseServices(const std::vector<Service>& services);
/// serviceCallFailure.
std::string serviceCallFailure(uint32_t service_id, uint32_t call_id, const std::string& message);
/// The binary Message Data header (opcode, subscription id, timestamp); the payload follows.
std::string messageDataHeader(uint32_t subscription, uint64_t log_time);
/// A service's JSON response: {"message": ...}.
std::string serviceResponse(const std::string& message);
/// A binary Service Call Response.
std::string serviceCallResponse(uint32_t service_id, uint32_t call_id, const std::string& encoding,
                                const std::string& payload);

}  // namespace plugslam::runtime::foxglove
