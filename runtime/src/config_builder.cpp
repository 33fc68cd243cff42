#include "config_builder.h"

#include <boost/filesystem.hpp>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
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

namespace {

using Fail = std::function<void(const std::string& path, const std::string& message)>;

// The index of a path part "[i]" (splitPath checked its digits).
size_t indexOf(const std::string& part) {
  try {
    return std::stoul(part.substr(1, part.size() - 2));
  } catch (const std::out_of_range&) {
    return std::numeric_limits<size_t>::max();  // past the end of any list
  }
}

// A slot given as a bare type name ("splitter: sdk.DistanceSplitter") becomes the map
// {type: name}, so that a parameter can be set in it.
void typeNameToMap(YAML::Node& node) {
  if (!node.IsScalar()) return;
  YAML::Node m(YAML::NodeType::Map);
  m["type"] = node.Scalar();
  node = m;
}

// The node `parts` (but the last) lead to from `cur`, as --set and a base's overrides address
// it: "[i]" enters a list's entry i, a name a map's key (made when missing). `walked` is `path`
// and the parts followed, for errors.
YAML::Node descend(YAML::Node cur, const std::vector<std::string>& parts, std::string& walked,
                   const Fail& fail) {
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string& p = parts[i];
    walked = join(walked, p);
    if (p[0] == '[') {
      const size_t idx = indexOf(p);
      if (!cur.IsSequence() || idx >= cur.size())
        fail(walked, "no such list element (the list has " +
                         std::to_string(cur.IsSequence() ? cur.size() : 0) + " entries)");
      cur.reset(cur[idx]);
    } else {
      typeNameToMap(cur);
      if (!cur.IsMap() && !cur.IsNull()) fail(walked, "is not a map");
      if (!cur[p]) cur[p] = YAML::Node(YAML::NodeType::Map);
      cur.reset(cur[p]);
    }
  }
  return cur;
}

// The entry `last` (a key, or "[i]": i = the list's length appends) of `parent`; `fail`s when
// the list has no such entry.
YAML::Node entry(YAML::Node parent, const std::string& last, const std::string& path,
                 const Fail& fail) {
  if (last[0] != '[') {
    typeNameToMap(parent);
    if (!parent.IsMap() && !parent.IsNull()) fail(path, "is not a map");
    return parent[last];
  }
  const size_t idx = indexOf(last);
  if (!parent.IsSequence() || idx > parent.size())
    fail(path, "no such list element (the list has " +
                   std::to_string(parent.IsSequence() ? parent.size() : 0) +
                   " entries; [" + std::to_string(parent.IsSequence() ? parent.size() : 0) +
                   "] appends one)");
  if (idx == parent.size()) parent.push_back(YAML::Node());
  return parent[idx];
}

// True when the pipeline path `p` lies inside `path` (not `path` itself).
bool isUnder(const std::string& p, const std::string& path) {
  return p.size() > path.size() && p.compare(0, path.size(), path) == 0 &&
         (path.empty() || p[path.size()] == '.' || p[path.size()] == '[');
}

// Forgets which file wrote what at and under `path`.
void forgetSources(ConfigDocument& doc, const std::string& path) {
  for (auto it = doc.sources.begin(); it != doc.sources.end();)
    it = it->first == path || isUnder(it->first, path) ? doc.sources.erase(it) : std::next(it);
}

void mergeMap(ConfigDocument& doc, YAML::Node into, const YAML::Node& over,
              const std::string& path, const ConfigDocument& from);

// Writes `value`, `from`'s node at `path`, over `target`, `doc`'s node there: a map without
// `type:` changes doc's map (or module) key by key; anything else, a module named by its
// `type:` included, replaces what doc had there.
void mergeValue(ConfigDocument& doc, YAML::Node target, const YAML::Node& value,
                const std::string& path, const ConfigDocument& from) {
  if (value.IsMap() && !value["type"] && (target.IsMap() || target.IsScalar())) {
    typeNameToMap(target);
    return mergeMap(doc, target, value, path, from);
  }
  target = value;
  forgetSources(doc, path);
  doc.sources[path] = sourceOf(from, path);
  for (const auto& [p, file] : from.sources)
    if (isUnder(p, path)) doc.sources[p] = file;
}

void mergeMap(ConfigDocument& doc, YAML::Node into, const YAML::Node& over,
              const std::string& path, const ConfigDocument& from) {
  std::map<std::string, int> seen;
  for (auto it = over.begin(); it != over.end(); ++it) {
    // Copies: yaml-cpp's iterator proxy dies at the end of the statement.
    const YAML::Node key = it->first;
    const YAML::Node value = it->second;
    const Fail fail = [&](const std::string& at, const std::string& message) {
      throw ConfigError(sourceOf(from, at), key.Mark().line + 1, key.Mark().column + 1, at,
                        message);
    };
    if (!key.IsScalar()) fail(path, "expected a key or a --set style path as key");
    const std::string& k = key.Scalar();
    if (auto prev = seen.find(k); prev != seen.end())
      fail(join(path, k), "duplicate key '" + k + "' (first given at line " +
                              std::to_string(prev->second) + ")");
    seen[k] = key.Mark().line + 1;
    std::vector<std::string> parts;
    try {
      parts = splitPath(k);
    } catch (const InputError& e) {
      fail(join(path, k), e.what());
    }
    std::string walked = path;
    YAML::Node parent = descend(into, parts, walked, fail);
    const std::string at = join(walked, parts.back());
    mergeValue(doc, entry(parent, parts.back(), at, fail), value, at, from);
  }
}

// Loads a config file; `chain` holds the files that start from it, to refuse a cycle of bases.
ConfigDocument loadDocument(const std::string& text, const std::string& name,
                            std::vector<std::string>& chain);

// Writes `from`'s document over `doc`'s, each value keeping the file that wrote it.
void mergeDocument(ConfigDocument& doc, const ConfigDocument& from) {
  if (!doc.sources.count("")) doc.sources[""] = doc.file;
  mergeMap(doc, doc.root, from.root, "", from);
}

// A config with `base: FILE` (or a list of files): the first file's document (its own base
// resolved first), each next one written over it, then this one's keys.
ConfigDocument composeOnBase(ConfigDocument doc, std::vector<std::string>& chain) {
  const YAML::Node ref = doc.root["base"];
  namespace fs = boost::filesystem;
  std::vector<YAML::Node> names;
  if (ref.IsSequence())
    for (const YAML::Node& n : ref) names.push_back(n);
  else
    names.push_back(ref);
  if (names.empty())
    throw ConfigError(doc.file, ref.Mark().line + 1, ref.Mark().column + 1, "base",
                      "an empty list: name the configs this one starts from, or drop 'base:'");
  std::optional<ConfigDocument> out;
  for (const YAML::Node& name : names) {
    const auto fail = [&](const std::string& message) {
      throw ConfigError(doc.file, name.Mark().line + 1, name.Mark().column + 1, "base", message);
    };
    if (!name.IsScalar() || name.Scalar().empty())
      fail("expected the path of a config this one starts from (relative to this file), or a "
           "list of them");
    fs::path base_path(name.Scalar());
    // A name like "<editor>" is no file: its base is relative to the current folder.
    if (base_path.is_relative() && doc.file.rfind('<', 0) != 0)
      base_path = fs::path(doc.file).parent_path() / base_path;
    const std::string base_file = base_path.lexically_normal().string();
    boost::system::error_code ec;
    for (const std::string& f : chain)
      if (fs::equivalent(f, base_file, ec)) {
        std::string cycle;
        for (const std::string& c : chain) cycle += c + " -> ";
        fail("a cycle of bases: " + cycle + base_file);
      }
    // A regular file only: a device or a pipe could be endless.
    std::ifstream in;
    if (fs::is_regular_file(base_file, ec)) in.open(base_file, std::ios::binary);
    if (!in.is_open() || !in) fail("the base config '" + base_file + "' is not a readable file");
    std::stringstream text;
    text << in.rdbuf();
    ConfigDocument base = loadDocument(text.str(), base_file, chain);
    if (out)
      mergeDocument(*out, base);
    else
      out = std::move(base);
  }
  doc.root.remove("base");
  mergeDocument(*out, doc);
  out->file = doc.file;
  return std::move(*out);
}

ConfigDocument loadDocument(const std::string& text, const std::string& name,
                            std::vector<std::string>& chain) {
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
  if (!doc.root["base"]) return doc;
  chain.push_back(name);
  doc = composeOnBase(std::move(doc), chain);
  chain.pop_back();
  return doc;
}

}  // namespace

ConfigDocument loadConfigText(const std::string& text, const std::string& name) {
  std::vector<std::string> chain;
  return loadDocument(text, name, chain);
}

ConfigDocument loadConfigFile(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("cannot open config file '" + file + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return loadConfigText(ss.str(), file);
}

std::string sourceOf(const ConfigDocument& doc, const std::string& path) {
  // The longest listed path that is `path` or holds it.
  for (std::string p = path;;) {
    if (auto it = doc.sources.find(p); it != doc.sources.end()) return it->second;
    if (p.empty()) return doc.file;
    const size_t cut = p.find_last_of(".[");
    p = cut == std::string::npos ? std::string() : p.substr(0, cut);
  }
}

std::string resolvedYaml(const ConfigDocument& doc) { return YAML::Dump(doc.root) + "\n"; }

void applyOverride(ConfigDocument& doc, const std::string& assignment,
                   const std::string& origin_text) {
  const std::string origin = origin_text.empty() ? "--set " + assignment : origin_text;
  auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set expects PATH=VALUE (for example source.path=log.gz), got '" +
                     assignment + "'");
  std::string path = assignment.substr(0, eq);
  std::string text = assignment.substr(eq + 1);
  const Fail fail = [&](const std::string& at, const std::string& message) {
    throw ConfigError(origin, 0, 0, at, message);
  };
  YAML::Node value;
  try {
    value = loadYaml(text);
  } catch (const YAML::Exception& e) {
    fail(path, "invalid YAML value: " + e.msg);
  }
  try {
    expandVariables(value, origin);
  } catch (const ConfigError& e) {
    fail(path, e.message());
  }
  auto parts = splitPath(path);
  if (parts[0] == "base")
    fail(path, "a config's base is read when its file is loaded: write 'base:' in the file");
  std::string walked;
  YAML::Node parent = descend(doc.root, parts, walked, fail);
  YAML::Node target = entry(parent, parts.back(), path, fail);
  target = value;
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
  return ConfigError(sourceOf(doc_, path), line, col, path, message);
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
        if (auto dup = names_.find(n); dup != names_.end())
          fail(value, p, "duplicate module name '" + n + "' (first used at " + dup->second + ")");
        names_[n] = where(value, p);
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
      // A key a base's override wrote as a path ("splitter.angel: 1") is no node of the file:
      // its value is.
      fail(key.Mark().line >= 0 ? key : value, p, msg);
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
