#pragma once
// The pipeline's parameters as a viewer client sees them: named by pipeline path, valued in JSON,
// set live between frames after the checks of `--set`. Shared by `run --serve` and
// `shell --serve`.
#include <functional>
#include <string>
#include <vector>

#include "plugslam/configurable.h"
#include "view/foxglove_protocol.h"

namespace plugslam::runtime {

/// The parameters of the tree under `root` by pipeline path ("pipeline.tracker.aligner.
/// slices[0].sigma"); only those in `names` when it is not empty (unknown names go to `errors`).
std::vector<foxglove::Parameter> listParameters(Configurable& root,
                                                const std::vector<std::string>& names,
                                                std::vector<std::string>& errors);
/// Why the parameter at `path` cannot change while a run is in progress, or "" when it can:
/// sources and outputs hold open files and threads, the graph back-end's loop search reads its
/// parameters on another thread, and module types are rebuilt, not set.
std::string liveRefusal(Configurable& root, const std::string& path);
/// Sets the parameter at `path` of the live tree to the YAML `value` and re-runs its module's
/// configure(), as the builder does; on failure restores the old value and throws.
void applyLive(Configurable& root, const std::string& path, const std::string& value);
/// The services every host offers (pause, resume, step, save_session, do) and one per module
/// action of the tree under `root` (may be null).
std::vector<foxglove::Service> standardServices(Configurable* root);

/// A service request's fields: "count" (step), "path" (save_session), "action" and "args" (do
/// and module actions). Throws InputError on a malformed request.
struct ServiceRequest {
  long long count = 1;
  std::string path;
  std::string action;
  std::vector<std::string> args;
};
/// Parses a JSON service request (an empty payload is an empty object).
ServiceRequest parseServiceRequest(const std::string& json);
/// Parses `json` into `request`; when it cannot, answers the call with `done(false, why)` and
/// returns false.
bool parseServiceRequest(const std::string& json, ServiceRequest& request,
                         const std::function<void(bool ok, std::string message)>& done);

}  // namespace plugslam::runtime
