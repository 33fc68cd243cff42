#include "editor/config_editor.h"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <boost/dll/runtime_symbol_info.hpp>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "config_builder.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/registry.h"
#include "plugslam/yaml_load.h"
#include "run_config.h"

namespace plugslam::runtime::editor {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string yamlText(const YAML::Node& n) {
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << n;
  return out.c_str();
}

json describe(const Configurable& obj) {
  json params = json::array(), slots = json::array();
  for (const ParamBase* p : obj.params()) {
    json j{{"name", p->name()}, {"type", p->typeName()}, {"default", p->defaultText()},
           {"unit", p->unit()}, {"doc", p->doc()},       {"choices", p->choices()}};
    if (p->range()) {
      j["min"] = p->range()->min;
      j["max"] = p->range()->max;
    }
    params.push_back(std::move(j));
  }
  for (const SlotBase* s : obj.slots())
    slots.push_back({{"name", s->name()},
                     {"kind", s->kind()},
                     {"list", s->isList()},
                     {"default", s->defaultType()},
                     {"doc", s->doc()}});
  return {{"params", std::move(params)}, {"slots", std::move(slots)}};
}

// The slots of a type, by key: which keys of a module's YAML are nested modules.
std::vector<const SlotBase*> slotsOf(const std::string& type,
                                     std::vector<std::shared_ptr<Configurable>>& keep) {
  if (type.empty()) return {};
  try {
    keep.push_back(Registry::instance().create(type));
  } catch (const Error&) {
    return {};  // unknown type: every key is kept as a value; validation names the type
  }
  std::vector<const SlotBase*> out;
  for (const SlotBase* s : keep.back()->slots()) out.push_back(s);
  return out;
}

json moduleFromYaml(const YAML::Node& node, const std::string& default_type,
                    const std::vector<const SlotBase*>* root_slots,
                    std::vector<std::shared_ptr<Configurable>>& keep) {
  json m{{"type", default_type}, {"name", ""}, {"params", json::array()}, {"slots", json::array()}};
  if (node.IsScalar()) {
    m["type"] = node.Scalar();
    return m;
  }
  if (node.IsMap() && node["type"] && node["type"].IsScalar()) m["type"] = node["type"].Scalar();
  if (node.IsMap() && node["name"] && node["name"].IsScalar()) m["name"] = node["name"].Scalar();
  const std::vector<const SlotBase*> slots =
      root_slots ? *root_slots : slotsOf(m["type"].get<std::string>(), keep);
  if (!node.IsMap()) return m;
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>("");
    if (key == "type" || key == "name") continue;
    const SlotBase* slot = nullptr;
    for (const SlotBase* s : slots)
      if (s->name() == key) slot = s;
    if (!slot) {
      m["params"].push_back({{"key", key}, {"value", yamlText(kv.second)}});
      continue;
    }
    json items = json::array();
    if (slot->isList() && kv.second.IsSequence()) {
      for (const auto& item : kv.second)
        items.push_back(moduleFromYaml(item, slot->defaultType(), nullptr, keep));
    } else if (!kv.second.IsNull()) {
      items.push_back(moduleFromYaml(kv.second, slot->defaultType(), nullptr, keep));
    }
    m["slots"].push_back({{"key", key},
                          {"kind", slot->kind()},
                          {"list", slot->isList()},
                          {"items", std::move(items)}});
  }
  return m;
}

const json& member(const json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key))
    throw InputError("editor tree: " + where + " has no '" + key + "'");
  return j.at(key);
}

YAML::Node moduleToYaml(const json& m, const std::string& where, bool root) {
  YAML::Node n(YAML::NodeType::Map);
  const std::string type = m.value("type", "");
  const std::string name = m.value("name", "");
  if (!root && !type.empty()) n["type"] = type;
  if (!name.empty()) n["name"] = name;
  for (const json& p : member(m, "params", where)) {
    const std::string key = member(p, "key", where + ".params").get<std::string>();
    const std::string value = member(p, "value", where + "." + key).get<std::string>();
    if (key.empty() || key == "type" || key == "name")
      throw InputError("editor tree: " + where + " has a parameter named '" + key + "'");
    try {
      n[key] = loadYaml(value);
    } catch (const YAML::Exception& e) {
      throw InputError(
          fmt::format("{}.{}: '{}' is not a YAML value: {}", where, key, value, e.msg));
    }
  }
  for (const json& s : member(m, "slots", where)) {
    const std::string key = member(s, "key", where + ".slots").get<std::string>();
    const json& items = member(s, "items", where + "." + key);
    if (s.value("list", false)) {
      YAML::Node list(YAML::NodeType::Sequence);
      for (size_t i = 0; i < items.size(); ++i)
        list.push_back(moduleToYaml(items[i], fmt::format("{}.{}[{}]", where, key, i), false));
      n[key] = list;
    } else if (!items.empty()) {
      n[key] = moduleToYaml(items[0], where + "." + key, false);
    }
  }
  return n;
}

std::string readAll(FILE* f) {
  std::string out;
  char buf[4096];
  size_t k;
  while ((k = fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, k);
  return out;
}

std::string replaceAll(std::string s, const std::string& from, const std::string& to) {
  if (from.empty()) return s;
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

// Drops the logger's "[12:00:00.000] [error] " prefix: the page shows the message itself.
std::string stripLogPrefix(const std::string& line) {
  const size_t level = line.find("] [");
  if (line.rfind('[', 0) != 0 || level == std::string::npos) return line;
  const size_t end = line.find("] ", level + 3);
  return end == std::string::npos ? line : line.substr(end + 2);
}

}  // namespace

json schemaJson() {
  json types = json::array();
  for (const TypeInfo& t : Registry::instance().types()) {
    json j{{"name", t.name}, {"kind", t.kind}, {"plugin", t.plugin}, {"doc", t.doc}};
    try {
      const auto obj = Registry::instance().create(t.name);
      j.update(describe(*obj));
    } catch (const Error& e) {
      j["error"] = e.what();
    }
    types.push_back(std::move(j));
  }
  RunConfig root;
  return {{"types", std::move(types)}, {"root", describe(root)}};
}

json treeFromYaml(const std::string& text, const std::string& name) {
  const ConfigDocument doc = loadConfigText(text, name);
  RunConfig root;
  std::vector<const SlotBase*> slots;
  for (const SlotBase* s : root.slots()) slots.push_back(s);
  std::vector<std::shared_ptr<Configurable>> keep;
  return moduleFromYaml(doc.root, "", &slots, keep);
}

std::string treeToYaml(const json& tree) {
  YAML::Emitter out;
  out << moduleToYaml(tree, "config", true);
  if (!out.good()) throw InputError(std::string("editor tree: ") + out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

Validation validateYaml(const std::string& text, const std::string& shown_name,
                        const std::string& program) {
  std::string tmpl = (fs::temp_directory_path() / "plugslam-editor-XXXXXX").string();
  if (!mkdtemp(tmpl.data())) throw Error("cannot create a temporary folder to validate in");
  const fs::path dir(tmpl), file = dir / "config.yaml";
  Validation v;
  try {
    { std::ofstream(file) << text; }
    std::string exe = program;
    if (exe.empty()) {
      // Only the plugslam executable validates: any other host (a test) must say which one.
      const boost::filesystem::path self = boost::dll::program_location();
      if (self.filename() != "plugslam")
        throw Error("cannot validate: '" + self.string() + "' is not plugslam");
      exe = self.string();
    }
    // Quoted for the shell: both paths are ours (a temp folder, the executable).
    const std::string cmd = fmt::format("'{}' validate '{}' 2>&1", exe, file.string());
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) throw Error("cannot run plugslam validate");
    const std::string out = readAll(p);
    const int status = pclose(p);
    v.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    std::istringstream lines(replaceAll(out, file.string(), shown_name));
    for (std::string line; std::getline(lines, line);)
      if (!line.empty()) v.messages.push_back(stripLogPrefix(line));
  } catch (...) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    throw;
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
  return v;
}

fs::path confinedPath(const fs::path& root, const std::string& relative) {
  std::error_code ec;
  const fs::path base = fs::canonical(root, ec);
  if (ec) throw InputError("the editor's folder '" + root.string() + "' does not exist");
  const fs::path rel(relative);
  if (relative.empty()) throw InputError("no file name given");
  if (relative.find('\0') != std::string::npos) throw InputError("refused: a NUL in the path");
  if (rel.is_absolute() || rel.has_root_name() || rel.has_root_directory())
    throw InputError("refused: '" + relative + "' is absolute; give a path inside " +
                     base.string());
  for (const fs::path& part : rel)
    if (part == "..")
      throw InputError("refused: '" + relative + "' climbs out with '..'; give a path inside " +
                       base.string());
  const std::string ext = rel.extension().string();
  if (ext != ".yaml" && ext != ".yml")
    throw InputError("refused: '" + relative + "' is not a .yaml or .yml file");
  // Symlinks anywhere on the way (the file itself included) are followed: where it really lands
  // must still be inside the root.
  const fs::path real = fs::weakly_canonical(base / rel, ec);
  if (ec) throw InputError("refused: cannot resolve '" + relative + "': " + ec.message());
  const auto mismatch = std::mismatch(base.begin(), base.end(), real.begin(), real.end());
  if (mismatch.first != base.end())
    throw InputError("refused: '" + relative + "' leads outside " + base.string() +
                     " (through a symlink)");
  return real;
}

namespace {
std::mutex root_mutex;
fs::path root_path;
}  // namespace

void setEditorRoot(const fs::path& root) {
  std::lock_guard<std::mutex> lock(root_mutex);
  root_path = root;
}

fs::path editorRoot() {
  std::lock_guard<std::mutex> lock(root_mutex);
  if (root_path.empty()) root_path = fs::current_path();
  return root_path;
}

ConfigEditor::ConfigEditor(fs::path root, std::string config_yaml, std::string config_name,
                           std::string program)
    : config_yaml_(std::move(config_yaml)),
      config_name_(std::move(config_name)),
      program_(std::move(program)) {
  std::error_code ec;
  root_ = fs::canonical(root, ec);
  if (ec) throw InputError("the editor's folder '" + root.string() + "' does not exist");
}

std::vector<std::string> ConfigEditor::serviceNames() {
  return {"editor.schema", "editor.config", "editor.load", "editor.validate", "editor.save"};
}

bool ConfigEditor::handles(const std::string& service) {
  for (const auto& s : serviceNames())
    if (s == service) return true;
  return false;
}

std::string ConfigEditor::call(const std::string& service, const std::string& request) const {
  try {
    return answer(service, request);
  } catch (const json::exception& e) {
    // A field of the wrong JSON type somewhere in the request.
    throw InputError(service + ": malformed request: " + e.what());
  }
}

std::string ConfigEditor::answer(const std::string& service, const std::string& request) const {
  json req = json::object();
  if (!request.empty()) {
    req = json::parse(request, nullptr, false);
    if (req.is_discarded() || !req.is_object())
      throw InputError(service + ": the request is not a JSON object");
  }
  auto str = [&](const char* key) {
    if (!req.contains(key) || !req[key].is_string())
      throw InputError(service + ": the request needs \"" + key + "\" (a string)");
    return req[key].get<std::string>();
  };
  // The YAML of a request: its "tree", else its "yaml" text.
  auto yamlOf = [&]() {
    if (req.contains("tree")) return treeToYaml(req["tree"]);
    return str("yaml");
  };
  auto validation = [](const Validation& v) {
    return json{{"ok", v.ok}, {"messages", v.messages}};
  };
  if (service == "editor.schema") return schemaJson().dump();
  if (service == "editor.config")
    return json{{"name", config_name_},
                {"root", root_.string()},
                {"yaml", config_yaml_},
                {"tree", treeFromYaml(config_yaml_, config_name_)}}
        .dump();
  if (service == "editor.load") {
    const std::string rel = str("path");
    const fs::path file = confinedPath(root_, rel);
    std::ifstream in(file);
    if (!in) throw InputError("cannot read '" + rel + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    std::string yaml = ss.str();
    // A config on a base is edited, validated and saved as the whole document it runs: its
    // base's path means nothing in the folder a validation runs in.
    const ConfigDocument doc = loadConfigText(yaml, file.string());
    if (!doc.sources.empty()) yaml = resolvedYaml(doc);
    return json{{"name", rel}, {"yaml", yaml}, {"tree", treeFromYaml(yaml, rel)}}.dump();
  }
  if (service == "editor.validate") {
    const std::string yaml = yamlOf();
    return json{{"yaml", yaml},
                {"validation", validation(validateYaml(yaml, "(edited config)", program_))}}
        .dump();
  }
  if (service == "editor.save") {
    const std::string rel = str("path");
    const fs::path file = confinedPath(root_, rel);
    const std::string yaml = yamlOf();
    std::error_code ec;
    fs::create_directories(file.parent_path(), ec);
    if (ec) throw InputError("cannot create the folder of '" + rel + "': " + ec.message());
    writeFileAtomically(file.string(), [&](std::ostream& out) { out << yaml; });
    return json{{"path", file.string()},
                {"yaml", yaml},
                {"validation", validation(validateYaml(yaml, rel, program_))}}
        .dump();
  }
  throw InputError("unknown editor service '" + service + "'");
}

}  // namespace plugslam::runtime::editor
