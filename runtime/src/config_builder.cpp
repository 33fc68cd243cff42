#include "config_builder.h"

#include <boost/filesystem.hpp>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "build_paths.h"
#include "plugslam/errors.h"
#include "plugslam/yaml_load.h"

namespace plugslam::runtime {

namespace {

std::string kindList(const Registry& registry, const std::string& kind) {
  std::string out;
  for (const auto& t : registry.types(kind)) out += (out.empty() ? "" : ", ") + t.name;
  return out.empty() ? std::string("none is registered") : out;
}

std::string keyList(const Configurable& obj) {
  std::vector<std::string> keys{"type", "name"};
  for (auto* p : obj.params()) keys.push_back(p->name());
  for (auto* s : obj.slots()) keys.push_back(s->name());
  std::string out;
  for (auto& k : keys) out += (out.empty() ? "" : ", ") + k;
  return out;
}

std::string join(const std::string& path, const std::string& key) {
  if (path.empty()) return key;
  if (!key.empty() && key[0] == '[') return path + key;
  return path + "." + key;
}

}  // namespace

std::vector<std::string> splitPath(const std::string& path) {
  std::vector<std::string> parts;
  std::string cur;
  auto bad = [&](const std::string& why) {
    throw InputError("malformed parameter path '" + path + "': " + why);
  };
  for (size_t i = 0; i < path.size(); ++i) {
    char c = path[i];
    if (c == '.') {
      if (cur.empty() && (parts.empty() || parts.back()[0] != '[')) bad("empty component");
      if (!cur.empty()) parts.push_back(cur);
      cur.clear();
    } else if (c == '[') {
      if (!cur.empty()) parts.push_back(cur);
      cur.clear();
      size_t close = path.find(']', i);
      if (close == std::string::npos) bad("missing ']'");
      std::string idx = path.substr(i + 1, close - i - 1);
      if (idx.empty() || idx.find_first_not_of("0123456789") != std::string::npos)
        bad("index '" + idx + "' is not a non-negative integer");
      parts.push_back("[" + idx + "]");
      i = close;
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) parts.push_back(cur);
  if (parts.empty()) bad("it is empty");
  return parts;
}

std::string dataFolder() {
  const char* env = std::getenv("PLUGSLAM_DATA");
  if (env && *env) return env;
  return (boost::filesystem::path(build_paths::sourceDir()) / ".." / "shared" / "data")
      .lexically_normal()
      .string();
}

void expandVariables(YAML::Node node, const std::string& file) {
  if (node.IsMap()) {
    for (auto it = node.begin(); it != node.end(); ++it) expandVariables(it->second, file);
    return;
  }
  if (node.IsSequence()) {
    for (auto it = node.begin(); it != node.end(); ++it) expandVariables(*it, file);
    return;
  }
  if (!node.IsScalar() || node.Scalar().find("${") == std::string::npos) return;
  const std::string& text = node.Scalar();
  const auto error = [&](const std::string& message) {
    throw ConfigError(file, node.Mark().line + 1, node.Mark().column + 1, "", message);
  };
  std::string out;
  for (size_t at = 0;;) {
    const size_t open = text.find("${", at);
    if (open == std::string::npos) {
      out += text.substr(at);
      break;
    }
    const size_t close = text.find('}', open);
    if (close == std::string::npos) error("unterminated '${' in '" + text + "'");
    const std::string name = text.substr(open + 2, close - open - 2);
    if (name != "PLUGSLAM_DATA")
      error("unknown variable '${" + name + "}': a config knows ${PLUGSLAM_DATA}, the data folder");
    out += text.substr(at, open - at) + dataFolder();
    at = close + 1;
  }
  node = out;  // the node keeps its mark: later errors still point at this line
}

ConfigDocument loadConfigText(const std::string& text, const std::string& name) {
  ConfigDocument doc;
  doc.file = name;
  try {
    doc.root = loadYaml(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(name, e.mark.line + 1, e.mark.column + 1, "", "invalid YAML: " + e.msg);
  }
  if (doc.root.IsNull()) doc.root = YAML::Node(YAML::NodeType::Map);
  if (!doc.root.IsMap())
    throw ConfigError(name, doc.root.Mark().line + 1, doc.root.Mark().column + 1, "",
                      "expected a map of top-level keys (plugins, source, pipeline, outputs)");
  expandVariables(doc.root, name);
  return doc;
}

ConfigDocument loadConfigFile(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("cannot open config file '" + file + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return loadConfigText(ss.str(), file);
}

void applyOverride(ConfigDocument& doc, const std::string& assignment,
                   const std::string& origin_text) {
  const std::string origin = origin_text.empty() ? "--set " + assignment : origin_text;
  auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set expects PATH=VALUE (for example source.path=log.gz), got '" +
                     assignment + "'");
  std::string path = assignment.substr(0, eq);
  std::string text = assignment.substr(eq + 1);
  YAML::Node value;
  try {
    value = loadYaml(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(origin, 0, 0, path, "invalid YAML value: " + e.msg);
  }
  try {
    expandVariables(value, origin);
  } catch (const ConfigError& e) {
    throw ConfigError(origin, 0, 0, path, e.message());
  }
  auto parts = splitPath(path);
  YAML::Node cur = doc.root;
  std::string walked;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string& p = parts[i];
    walked = join(walked, p);
    if (p[0] == '[') {
      size_t idx = std::stoul(p.substr(1, p.size() - 2));
      if (!cur.IsSequence() || idx >= cur.size())
        throw ConfigError(origin, 0, 0, walked,
                          "no such list element (the list has " +
                              std::to_string(cur.IsSequence() ? cur.size() : 0) + " entries)");
      cur.reset(cur[idx]);
    } else {
      if (cur.IsScalar()) {
        // A slot given as a bare type name ("splitter: sdk.DistanceSplitter") becomes a map.
        YAML::Node m(YAML::NodeType::Map);
        m["type"] = cur.Scalar();
        cur = m;
      }
      if (!cur.IsMap() && !cur.IsNull())
        throw ConfigError(origin, 0, 0, walked, "is not a map");
      if (!cur[p]) cur[p] = YAML::Node(YAML::NodeType::Map);
      cur.reset(cur[p]);
    }
  }
  const std::string& last = parts.back();
  if (last[0] == '[') {
    size_t idx = std::stoul(last.substr(1, last.size() - 2));
    if (!cur.IsSequence() || idx >= cur.size())
      throw ConfigError(origin, 0, 0, path, "no such list element");
    cur[idx] = value;
  } else {
    if (cur.IsScalar()) {
      YAML::Node m(YAML::NodeType::Map);
      m["type"] = cur.Scalar();
      cur = m;
    }
    cur[last] = value;
  }
  doc.overrides[path] = origin;
}

ConfigBuilder::ConfigBuilder(const ConfigDocument& doc, PluginManager& plugins, Registry& registry)
    : doc_(doc), plugins_(plugins), registry_(registry) {
  if (!doc_.file.empty() && doc_.file[0] != '<') {
    // Plugins may sit next to the config that names them.
    boost::filesystem::path dir = boost::filesystem::path(doc_.file).parent_path();
    if (!dir.empty()) plugins_.addSearchDir(dir.string());
  }
}

ConfigErrorList::ConfigErrorList(std::vector<ConfigError> errors)
    : ConfigError(errors.at(0).file(), errors[0].line(), errors[0].column(), errors[0].path(),
                  errors[0].message()),
      errors_(std::move(errors)) {
  for (const auto& e : errors_) text_ += std::string(e.what()) + "\n";
  text_ += std::to_string(errors_.size()) + " errors";
  if (!errors_[0].file().empty() && errors_[0].line() > 0) text_ += " in " + errors_[0].file();
}

ConfigError ConfigBuilder::locate(const YAML::Node& node, const std::string& path,
                                  const std::string& message) const {
  // Errors on values that came from --set point at the command line, not the file.
  for (const auto& [p, origin] : doc_.overrides) {
    if (path == p || path.rfind(p + ".", 0) == 0 || path.rfind(p + "[", 0) == 0)
      return ConfigError(origin, 0, 0, path, message);
  }
  int line = 0, col = 0;
  if (node.IsDefined()) {
    auto m = node.Mark();
    if (m.line >= 0) {
      line = m.line + 1;
      col = m.column + 1;
    }
  }
  return ConfigError(doc_.file, line, col, path, message);
}

std::string ConfigBuilder::where(const YAML::Node& node, const std::string& path) const {
  const ConfigError e = locate(node, path, "");
  std::string s = e.file();
  if (e.line() > 0) s += ":" + std::to_string(e.line()) + ":" + std::to_string(e.column());
  return s;
}

void ConfigBuilder::fail(const YAML::Node& node, const std::string& path,
                         const std::string& message) const {
  throw locate(node, path, message);
}

void ConfigBuilder::report(const YAML::Node& node, const std::string& path,
                           const std::string& message) {
  errors_.push_back(locate(node, path, message));
}

void ConfigBuilder::check() const {
  if (errors_.empty()) return;
  if (errors_.size() == 1) throw errors_.front();
  throw ConfigErrorList(errors_);
}

void ConfigBuilder::loadPlugins(const std::string& key) {
  YAML::Node list = doc_.root[key];
  if (!list) return;
  if (!list.IsSequence()) return report(list, key, "expected a list of plugin names or paths");
  for (size_t i = 0; i < list.size(); ++i) {
    std::string path = key + "[" + std::to_string(i) + "]";
    if (!list[i].IsScalar()) {
      report(list[i], path, "expected a plugin name or path");
      continue;
    }
    try {
      plugins_.load(list[i].Scalar());
    } catch (const PluginError& e) {
      report(list[i], path, e.what());
      failed_plugins_[list[i].Scalar()] = where(list[i], path);
    }
  }
}

std::string ConfigBuilder::resolveType(const SlotBase& slot, const std::string& type,
                                       const YAML::Node& at, const std::string& path) {
  auto dot = type.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == type.size())
    fail(at, path,
         "type '" + type + "' must be written <plugin>.<Type> (e.g. sdk.Pipeline); " +
             slot.kind() + " types: " + kindList(registry_, slot.kind()));
  if (!registry_.find(type)) {
    std::string plugin = type.substr(0, dot);
    if (!plugins_.isLoaded(plugin) && registry_.typesOf(plugin).empty()) {
      // One error per plugin that does not load, not one per type of it.
      if (auto failed = failed_plugins_.find(plugin); failed != failed_plugins_.end())
        fail(at, path, "type '" + type + "' needs plugin '" + plugin +
                           "', which did not load (see the error at " + failed->second + ")");
      // A type names its plugin, so the plugin is loaded on first use.
      try {
        plugins_.load(plugin);
      } catch (const PluginError& e) {
        failed_plugins_[plugin] = where(at, path);
        fail(at, path, "type '" + type + "' needs plugin '" + plugin + "': " + e.what());
      }
    }
  }
  auto info = registry_.find(type);
  if (!info) {
    std::string msg = "unknown type '" + type + "'";
    std::string near = registry_.closest(type, slot.kind());
    if (near.empty()) near = registry_.closest(type);
    if (!near.empty())
      msg += "; did you mean '" + near + "'?";
    else
      msg += "; " + slot.kind() + " types: " + kindList(registry_, slot.kind());
    fail(at, path, msg);
  }
  if (info->kind != slot.kind())
    fail(at, path,
         "'" + type + "' is " + withArticle(info->kind) + ", but '" + slot.name() + "' expects " +
             withArticle(slot.kind()) + " (" + kindList(registry_, slot.kind()) + ")");
  return type;
}

std::shared_ptr<Configurable> ConfigBuilder::create(const SlotBase& slot, const YAML::Node& node,
                                                    const std::string& path) {
  std::string type;
  YAML::Node params;
  bool has_params = false;
  YAML::Node type_node = node;
  // A list's items name their type; its defaults are whole items (fillSlot).
  const std::string default_type = slot.isList() ? std::string() : slot.defaultType();
  if (!node || node.IsNull()) {
    type = default_type;
  } else if (node.IsScalar()) {
    type = node.Scalar();
  } else if (node.IsMap()) {
    // reset(), not operator=: assigning a yaml-cpp node overwrites the node it refers to.
    params.reset(node);
    has_params = true;
    if (node["type"]) {
      type_node.reset(node["type"]);
      if (!type_node.IsScalar()) fail(type_node, join(path, "type"), "expected a type name");
      type = type_node.Scalar();
    } else {
      type = default_type;
    }
  } else {
    fail(node, path,
         "expected a type name or a map with 'type:' and parameters for a " + slot.kind());
  }
  if (type.empty())
    fail(node, path,
         "missing 'type:'; '" + slot.name() + "' takes " + withArticle(slot.kind()) + ": " +
             kindList(registry_, slot.kind()));
  resolveType(slot, type, type_node, has_params && node["type"] ? join(path, "type") : path);
  auto obj = registry_.create(type);
  configureObject(*obj, params, path);
  return obj;
}

void ConfigBuilder::fillSlot(SlotBase& slot, const YAML::Node& node, const std::string& path) {
  slot.clear();
  if (slot.isList()) {
    if (!node || node.IsNull()) {
      // The key omitted: the list's default items, if it has some.
      const std::vector<std::string> types = slot.defaultTypes();
      for (size_t i = 0; i < types.size(); ++i)
        slot.assign(create(slot, YAML::Node(types[i]), path + "[" + std::to_string(i) + "]"));
      return;
    }
    if (!node.IsSequence()) fail(node, path, "expected a list of " + slot.kind() + " modules");
    for (size_t i = 0; i < node.size(); ++i) {
      std::string p = path + "[" + std::to_string(i) + "]";
      try {
        auto obj = create(slot, node[i], p);
        try {
          slot.assign(obj);
        } catch (const ValueError& e) {
          fail(node[i], p, e.what());
        }
      } catch (const ConfigError& e) {
        errors_.push_back(e);  // the next item is checked too
      }
    }
    return;
  }
  if ((!node || node.IsNull()) && slot.defaultType().empty()) return;
  auto obj = create(slot, node, path);
  try {
    slot.assign(obj);
  } catch (const ValueError& e) {
    fail(node, path, e.what());
  }
}

void ConfigBuilder::configure(Configurable& obj, const YAML::Node& node, const std::string& path) {
  configureObject(obj, node, path);
  check();
}

void ConfigBuilder::configureObject(Configurable& obj, const YAML::Node& node,
                                    const std::string& path) {
  if (obj.name().empty()) obj.setName(path);
  const size_t errors_before = errors_.size();
  std::set<SlotBase*> filled;
  if (node && !node.IsNull()) {
    if (!node.IsMap()) return report(node, path, "expected a map of parameters");
    std::map<std::string, int> seen;
    for (auto it = node.begin(); it != node.end(); ++it) try {
      // Copies: yaml-cpp's iterator proxy dies at the end of the statement.
      const YAML::Node key = it->first;
      const YAML::Node value = it->second;
      if (!key.IsScalar()) fail(key, path, "expected a parameter name as key");
      const std::string& k = key.Scalar();
      std::string p = join(path, k);
      if (auto prev = seen.find(k); prev != seen.end())
        fail(key, p, "duplicate key '" + k + "' (first given at line " +
                         std::to_string(prev->second) + ")");
      seen[k] = key.Mark().line + 1;
      if (k == "type") continue;
      if (k == "name") {
        if (!value.IsScalar() || value.Scalar().empty())
          fail(value, p, "expected a non-empty module name");
        const std::string& n = value.Scalar();
        auto where = std::to_string(value.Mark().line + 1) + ":" +
                     std::to_string(value.Mark().column + 1);
        if (auto dup = names_.find(n); dup != names_.end())
          fail(value, p, "duplicate module name '" + n + "' (first used at " + dup->second + ")");
        names_[n] = doc_.file + ":" + where;
        obj.setName(n);
        continue;
      }
      if (ParamBase* param = obj.findParam(k)) {
        try {
          param->fromYaml(value);
        } catch (const ValueError& e) {
          fail(value, p, std::string(e.what()) + " (" + param->name() + ": " + param->typeName() +
                             (param->unit().empty() ? "" : " [" + param->unit() + "]") + ", " +
                             param->doc() + ")");
        }
        continue;
      }
      if (SlotBase* slot = obj.findSlot(k)) {
        filled.insert(slot);  // a slot that fails stays empty rather than taking its default
        fillSlot(*slot, value, p);
        continue;
      }
      std::vector<std::string> keys;
      for (auto* prm : obj.params()) keys.push_back(prm->name());
      for (auto* s : obj.slots()) keys.push_back(s->name());
      std::string near = closestMatch(k, keys);
      std::string msg = "unknown key '" + k + "' for " +
                        (obj.typeName().empty() ? std::string("this section") : obj.typeName());
      if (!near.empty())
        msg += "; did you mean '" + near + "'?";
      else
        msg += " (valid keys: " + keyList(obj) + ")";
      fail(key, p, msg);
    } catch (const ConfigError& e) {
      errors_.push_back(e);  // the next key is checked too
    }
  }
  for (SlotBase* slot : obj.slots()) {
    if (filled.count(slot)) continue;
    try {
      fillSlot(*slot, YAML::Node(), join(path, slot->name()));
    } catch (const ConfigError& e) {
      errors_.push_back(e);
    }
  }
  // A module with a bad key (or a bad nested module) is not asked to check itself: its
  // cross-parameter checks would run on values the user did not write.
  if (errors_.size() > errors_before) return;
  try {
    obj.configure();
  } catch (const ParamError& e) {
    // Point at the offending parameter when the YAML has it, else at the module.
    YAML::Node at = node;
    try {
      for (const auto& part : splitPath(e.path())) {
        if (!at || !(at.IsMap() || at.IsSequence())) break;
        YAML::Node next = part[0] == '[' ? at[std::stoul(part.substr(1, part.size() - 2))]
                                         : at[part];
        if (!next) break;
        at.reset(next);
      }
    } catch (const std::exception&) {
    }
    report(at, join(path, e.path()), e.message());
  } catch (const ConfigError& e) {
    errors_.push_back(e);
  } catch (const InputError& e) {
    report(node, path, e.what());
  }
}

void ConfigBuilder::configureRoot(Configurable& root, const std::vector<std::string>& skip_keys) {
  YAML::Node filtered(YAML::NodeType::Map);
  // The root map minus skipped keys; the entries are the original nodes, so marks survive.
  for (auto it = doc_.root.begin(); it != doc_.root.end(); ++it) {
    bool skip = false;
    for (auto& k : skip_keys) skip = skip || (it->first.IsScalar() && it->first.Scalar() == k);
    if (!skip) filtered.force_insert(it->first, it->second);
  }
  configureObject(root, filtered, "");
  check();
}

std::string withArticle(const std::string& noun) {
  const bool vowel = !noun.empty() && std::string("AEIOUaeiou").find(noun[0]) != std::string::npos;
  return (vowel ? "an " : "a ") + noun;
}

YAML::Node dumpConfig(const Configurable& obj, bool with_type) {
  YAML::Node out(YAML::NodeType::Map);
  if (with_type && !obj.typeName().empty()) out["type"] = obj.typeName();
  for (auto* p : obj.params()) out[p->name()] = p->toYaml();
  for (auto* s : obj.slots()) {
    auto items = s->items();
    if (s->isList()) {
      YAML::Node seq(YAML::NodeType::Sequence);
      for (auto& i : items) seq.push_back(dumpConfig(*i));
      out[s->name()] = seq;
    } else if (!items.empty()) {
      out[s->name()] = dumpConfig(*items[0]);
    }
  }
  return out;
}

}  // namespace plugslam::runtime
