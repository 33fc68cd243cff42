#pragma once
// What a viewer client may ask of the host it watches: the pipeline's parameters (by pipeline
// path, set with the checks of `--set`) and its actions as services (pause, resume, step, save
// the session, every module action). `plugslam run` and `plugslam shell` each implement it. Every
// call is asynchronous: the host runs it at a safe moment (between frames) and calls `done`, on
// any thread; the server never waits for it.
#include <functional>
#include <string>
#include <vector>

#include "view/foxglove_protocol.h"

namespace plugslam::runtime {

/// The host behind a viewer server.
class ViewControl {
 public:
  /// A parameter read or set: the values now, and one message per refused assignment.
  using ParametersDone =
      std::function<void(std::vector<foxglove::Parameter> values, std::vector<std::string> errors)>;
  /// A service's outcome: ok and its message (the response), or the reason it failed.
  using CallDone = std::function<void(bool ok, std::string message)>;

  virtual ~ViewControl();
  /// The services offered (ids are given by the server). Stable for the host's life.
  virtual std::vector<foxglove::Service> services() = 0;
  /// Reads parameters by path (empty: all).
  virtual void getParameters(std::vector<std::string> names, ParametersDone done) = 0;
  /// Sets parameters, each validated like `--set PATH=VALUE`; reports the values after.
  virtual void setParameters(std::vector<foxglove::ParameterAssignment> assignments,
                             ParametersDone done) = 0;
  /// Calls a service by name with its JSON request.
  virtual void call(const std::string& service, const std::string& request, CallDone done) = 0;
};

}  // namespace plugslam::runtime
