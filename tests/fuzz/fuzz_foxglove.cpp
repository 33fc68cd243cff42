// The viewer server's parser of client messages (Foxglove WebSocket protocol): a text frame or a
// binary frame (the first input byte picks: even = text, odd = binary), then what the server does
// with the parsed fields that come from the client: a service request's JSON and a parameter's
// value as YAML (the --set parser).
#include <yaml-cpp/yaml.h>

#include "fuzz_common.h"
#include "plugslam/errors.h"
#include "plugslam/yaml_load.h"
#include "view/foxglove_protocol.h"
#include "view/parameters.h"

namespace fg = plugslam::runtime::foxglove;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string body = plugslam::fuzz::text(data + 1, size - 1);
  try {
    const fg::ClientMessage m = (data[0] & 1) ? fg::parseBinary(body) : fg::parseText(body);
    if (const auto* call = std::get_if<fg::ServiceCall>(&m))
      plugslam::runtime::parseServiceRequest(call->payload);
    if (const auto* set = std::get_if<fg::SetParameters>(&m))
      for (const auto& p : set->parameters) {
        try {
          plugslam::loadYaml(p.value);
        } catch (const YAML::Exception&) {
          // The --set path reports these as a ConfigError; what matters here is no crash.
        }
      }
  } catch (const plugslam::Error&) {
  }
  return 0;
}
