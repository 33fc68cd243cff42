#include "shell/module_paths.h"

#include "config_builder.h"
#include "plugslam/errors.h"
#include "plugslam/registry.h"

namespace plugslam::runtime {

namespace {

std::string keysOf(const Configurable& c) {
  std::string out;
  for (auto* p : c.params()) out += (out.empty() ? "" : ", ") + p->name();
  for (auto* s : c.slots()) out += (out.empty() ? "" : ", ") + s->name();
  return out.empty() ? std::string("none") : out;
}

std::string join(const std::string& path, const std::string& part) {
  if (path.empty()) return part;
  return part[0] == '[' ? path + part : path + "." + part;
}

}  // namespace

PathTarget resolvePath(Configurable& root, const std::string& path) {
  const std::vector<std::string> parts = splitPath(path);
  PathTarget t;
  t.module = &root;
  std::string walked;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& p = parts[i];
    Configurable& cur = *t.module;
    const std::string where = walked.empty() ? std::string("the run") : "'" + walked + "'";
    if (p[0] == '[') throw InputError("'" + join(walked, p) + "': " + where + " is not a list");
    walked = join(walked, p);
    if (ParamBase* prm = cur.findParam(p)) {
      if (i + 1 != parts.size())
        throw InputError("'" + walked + "' is a parameter; it has no '" + parts[i + 1] + "'");
      t.param = prm;
      return t;
    }
    SlotBase* slot = cur.findSlot(p);
    if (!slot) {
      std::vector<std::string> keys;
      for (auto* prm : cur.params()) keys.push_back(prm->name());
      for (auto* s : cur.slots()) keys.push_back(s->name());
      std::string near = closestMatch(p, keys);
      throw InputError(
          "no parameter or module '" + p + "' in " + where +
          (near.empty() ? " (keys: " + keysOf(cur) + ")" : "; did you mean '" + near + "'?"));
    }
    auto items = slot->items();
    size_t index = 0;
    if (slot->isList()) {
      if (i + 1 == parts.size() || parts[i + 1][0] != '[')
        throw InputError("'" + walked + "' is a list of " + std::to_string(items.size()) +
                         " modules: add an index, e.g. " + walked + "[0]");
      ++i;
      index = std::stoul(parts[i].substr(1, parts[i].size() - 2));
      walked += parts[i];
      if (index >= items.size())
        throw InputError("'" + walked + "': the list has " + std::to_string(items.size()) +
                         " modules");
    } else if (items.empty()) {
      throw InputError("'" + walked + "' is empty (no " + slot->kind() + " configured)");
    }
    t.parent = &cur;
    t.slot = slot;
    t.index = index;
    t.module = items[index].get();
  }
  return t;
}

void walkModules(Configurable& root,
                 const std::function<void(Configurable&, const std::string&)>& visit) {
  std::function<void(Configurable&, const std::string&)> rec = [&](Configurable& c,
                                                                   const std::string& path) {
    for (auto* s : c.slots()) {
      auto items = s->items();
      for (size_t i = 0; i < items.size(); ++i) {
        std::string p = join(path, s->name());
        if (s->isList()) p += "[" + std::to_string(i) + "]";
        visit(*items[i], p);
        rec(*items[i], p);
      }
    }
  };
  rec(root, "");
}

Configurable& findModule(Configurable& root, const std::string& name) {
  Configurable* found = nullptr;
  walkModules(root, [&](Configurable& c, const std::string& path) {
    if (!found && (path == name || c.name() == name)) found = &c;
  });
  if (found) return *found;
  std::vector<std::string> names;
  walkModules(root, [&](Configurable&, const std::string& path) { names.push_back(path); });
  std::string near = closestMatch(name, names);
  throw InputError(
      "no module '" + name + "'" +
      (near.empty() ? std::string(" (see: list actions)") : "; did you mean '" + near + "'?"));
}

namespace {
// "MODULE.ACTION" -> the module and the action's name.
std::pair<Configurable*, std::string> splitAction(Configurable& root, const std::string& target) {
  const auto dot = target.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == target.size())
    throw InputError("expected MODULE.ACTION (e.g. pipeline.graph.optimize_now), got '" + target +
                     "'");
  return {&findModule(root, target.substr(0, dot)), target.substr(dot + 1)};
}
}  // namespace

void checkAction(Configurable& root, const std::string& target) {
  const auto [module, action] = splitAction(root, target);
  for (const Action& a : module->actions())
    if (a.name == action) return;
  module->invoke(action);  // not an action of the module: throws the error that lists them
}

std::string invokeAction(Configurable& root, const std::string& target,
                         const std::vector<std::string>& args) {
  const auto [module, action] = splitAction(root, target);
  return module->invoke(action, args);
}

}  // namespace plugslam::runtime
