#include "view/parameters.h"

#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include "editor/config_editor.h"
#include "plugslam/errors.h"
#include "plugslam/yaml_load.h"
#include "shell/module_paths.h"

namespace plugslam::runtime {

using nlohmann::json;

namespace {

json scalarJson(const YAML::Node& n, const std::string& type) {
  if (type.find("bool") != std::string::npos) return n.as<bool>();
  if (type.find("int") != std::string::npos) return n.as<long long>();
  if (type.find("double") != std::string::npos) return n.as<double>();
  return n.as<std::string>();
}

json valueJson(const ParamBase& p) {
  const YAML::Node n = p.toYaml();
  const std::string type = p.typeName();
  try {
    if (n.IsSequence()) {
      json a = json::array();
      for (const auto& item : n) a.push_back(scalarJson(item, type));
      return a;
    }
    if (n.IsNull()) return nullptr;
    return scalarJson(n, type);
  } catch (const YAML::Exception&) {
    return p.valueText();
  }
}

void addParams(Configurable& module, const std::string& path, std::vector<foxglove::Parameter>& out) {
  for (ParamBase* p : module.params()) {
    const std::string name = path.empty() ? p->name() : path + "." + p->name();
    const std::string type = p->typeName();
    std::string hint;
    if (type == "double") hint = "float64";
    if (type == "list<double>") hint = "float64_array";
    out.push_back(foxglove::Parameter{name, valueJson(*p).dump(-1, ' ', false,
                                                               json::error_handler_t::replace),
                                      hint});
  }
}

}  // namespace

std::vector<foxglove::Parameter> listParameters(Configurable& root,
                                                const std::vector<std::string>& names,
                                                std::vector<std::string>& errors) {
  std::vector<foxglove::Parameter> all;
  addParams(root, "", all);
  walkModules(root, [&](Configurable& m, const std::string& path) { addParams(m, path, all); });
  if (names.empty()) return all;
  std::vector<foxglove::Parameter> out;
  for (const auto& n : names) {
    bool found = false;
    for (const auto& p : all)
      if (p.name == n) {
        out.push_back(p);
        found = true;
      }
    if (!found) {
      try {
        resolvePath(root, n);  // its message names what exists there
        errors.push_back("'" + n + "' is a module, not a parameter");
      } catch (const std::exception& e) {
        errors.push_back(e.what());
      }
    }
  }
  return out;
}

std::string liveRefusal(Configurable& root, const std::string& path) {
  PathTarget t = resolvePath(root, path);
  if (!t.param) return "'" + path + "' is a module: its type changes between runs (shell: swap)";
  auto starts = [&](const std::string& prefix) {
    return path.compare(0, prefix.size(), prefix) == 0 &&
           (path.size() == prefix.size() || path[prefix.size()] == '.' || path[prefix.size()] == '[');
  };
  if (path == "plugins") return "plugins are loaded when the run is built";
  if (starts("source")) return "the source's parameters are read when it opens its data";
  if (starts("outputs")) return "outputs are set up when the run starts";
  if (starts("pipeline.graph"))
    return "the graph back-end's loop search reads its parameters on another thread";
  return "";
}

void applyLive(Configurable& root, const std::string& path, const std::string& value) {
  PathTarget t = resolvePath(root, path);
  if (!t.param) throw InputError("'" + path + "' is not a parameter");
  const YAML::Node old = YAML::Clone(t.param->toYaml());
  const bool was_set = t.param->isSet();
  try {
    t.param->fromYaml(loadYaml(value));
    t.module->configure();
  } catch (...) {
    if (was_set) t.param->fromYaml(old);
    else t.param->reset();
    try {
      t.module->configure();
    } catch (...) {
      // It held before with the old value.
    }
    throw;
  }
}

std::vector<foxglove::Service> standardServices(Configurable* root) {
  const std::string empty = R"({"type":"object","properties":{}})";
  const std::string reply =
      R"({"type":"object","properties":{"message":{"type":"string"}},"required":["message"]})";
  std::vector<foxglove::Service> s = {
      {0, "pause", "plugslam.Pause", empty, reply},
      {0, "resume", "plugslam.Resume", empty, reply},
      {0, "step", "plugslam.Step",
       R"({"type":"object","properties":{"count":{"type":"integer","minimum":1}}})", reply},
      {0, "save_session", "plugslam.SaveSession",
       R"J({"type":"object","properties":{"path":{"type":"string","description":"folder under the output folder (default: session)"}}})J",
       reply},
      {0, "do", "plugslam.Action",
       R"({"type":"object","properties":{"action":{"type":"string","description":"MODULE.ACTION"},"args":{"type":"array","items":{"type":"string"}}},"required":["action"]})",
       reply}};
  // The page's configuration editor (runtime/src/editor): JSON in, JSON out.
  for (const std::string& name : editor::ConfigEditor::serviceNames())
    s.push_back(foxglove::Service{0, name, "plugslam.Editor", R"({"type":"object"})",
                                  R"({"type":"object"})"});
  if (!root) return s;
  const std::string args =
      R"({"type":"object","properties":{"args":{"type":"array","items":{"type":"string"}}}})";
  walkModules(*root, [&](Configurable& m, const std::string& path) {
    for (const auto& a : m.actions())
      s.push_back(foxglove::Service{0, path + "." + a.name, "plugslam.Action", args, reply});
  });
  return s;
}

ServiceRequest parseServiceRequest(const std::string& text) {
  ServiceRequest r;
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) return r;
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw InputError("the request must be a JSON object");
  if (auto it = j.find("count"); it != j.end()) {
    if (!it->is_number_integer() || it->get<long long>() < 1)
      throw InputError("'count' must be an integer >= 1");
    r.count = it->get<long long>();
  }
  if (auto it = j.find("path"); it != j.end()) {
    if (!it->is_string()) throw InputError("'path' must be a string");
    r.path = it->get<std::string>();
  }
  if (auto it = j.find("action"); it != j.end()) {
    if (!it->is_string()) throw InputError("'action' must be a string");
    r.action = it->get<std::string>();
  }
  if (auto it = j.find("args"); it != j.end()) {
    if (!it->is_array()) throw InputError("'args' must be an array of strings");
    for (const auto& a : *it) {
      if (!a.is_string()) throw InputError("'args' must be an array of strings");
      r.args.push_back(a.get<std::string>());
    }
  }
  return r;
}

bool parseServiceRequest(const std::string& json, ServiceRequest& request,
                         const std::function<void(bool ok, std::string message)>& done) {
  try {
    request = parseServiceRequest(json);
    return true;
  } catch (const std::exception& e) {
    done(false, e.what());
    return false;
  }
}

}  // namespace plugslam::runtime
