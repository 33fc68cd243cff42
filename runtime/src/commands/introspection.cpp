#include "commands/introspection.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cctype>

#include <boost/filesystem.hpp>

#include "plugslam/entry.h"
#include "plugslam/errors.h"
#include "plugslam/registry.h"
#include "run_config.h"
#include "sweep/sweep_file.h"

namespace plugslam::runtime {

std::vector<std::string> loadAllPlugins(PluginManager& plugins) {
  std::vector<std::string> refusals;
  for (const auto& file : plugins.discover()) {
    try {
      plugins.load(file);
    } catch (const PluginError& e) {
      refusals.push_back(e.what());
    }
  }
  return refusals;
}

void loadPluginOf(PluginManager& plugins, const std::string& type) {
  auto dot = type.find('.');
  if (dot == std::string::npos || dot == 0) return;
  std::string plugin = type.substr(0, dot);
  if (plugin == "sdk" || plugins.isLoaded(plugin)) return;
  if (!plugins.resolve(plugin).empty()) plugins.load(plugin);
}

namespace {

// The entry whose property name `p` holds, or nullptr for a plain parameter.
const EntryBase* entryOf(const Configurable& obj, const ParamBase* p) {
  for (const EntryBase* e : obj.entries())
    if (&e->param() == p) return e;
  return nullptr;
}

// "reads the measurement entry of this name (laser2d.PointCloud2D)".
std::string entryText(const EntryBase& e) {
  return std::string(e.writes() ? "writes" : "reads") + " the " + containerName(e.container()) +
         " entry of this name (" + e.typeName() + ")";
}

std::string paramLine(const ParamBase& p, const EntryBase* entry) {
  std::string extra;
  if (p.range()) extra = fmt::format(", range [{:g}, {:g}]", p.range()->min, p.range()->max);
  if (!p.choices().empty()) {
    std::string c;
    for (auto& v : p.choices()) c += (c.empty() ? "" : "|") + v;
    extra += ", one of " + c;
  }
  return fmt::format("  {:<22} {:<14} default {}{}{}\n      {}\n{}", p.name(), p.typeName(),
                     p.defaultText(), p.unit().empty() ? "" : " [" + p.unit() + "]", extra, p.doc(),
                     entry ? "      " + entryText(*entry) + "\n" : "");
}

std::string md(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

}  // namespace

namespace {

// The parameters, nested modules and actions of a module, as `describe` prints them.
std::string describeBody(const Configurable& obj) {
  std::string out = "\nparameters:\n";
  if (obj.params().empty()) out += "  (none)\n";
  for (auto* p : obj.params()) out += paramLine(*p, entryOf(obj, p));
  if (!obj.slots().empty()) {
    out += "\nnested modules:\n";
    for (auto* s : obj.slots())
      out += fmt::format("  {:<22} {}{}{}\n      {}\n", s->name(),
                         s->isList() ? "list of " : "", s->kind(),
                         s->defaultType().empty() ? "" : ", default " + s->defaultType(), s->doc());
  }
  if (!obj.actions().empty()) {
    out += "\nactions:\n";
    for (auto& a : obj.actions()) out += fmt::format("  {:<22} {}\n", a.name, a.doc);
  }
  return out;
}

// The tables of a module in the markdown reference.
std::string referenceBody(const Configurable& obj) {
  std::string out;
  if (!obj.params().empty()) {
    out += "| key | type | default | unit | description |\n|---|---|---|---|---|\n";
    for (auto* p : obj.params()) {
      std::string doc = p->doc();
      if (!doc.empty() && doc.back() != '.') doc += ".";
      if (const EntryBase* e = entryOf(obj, p)) {
        std::string text = entryText(*e);
        text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
        doc += " " + text + ".";
      }
      if (p->range()) doc += fmt::format(" Range [{:g}, {:g}].", p->range()->min, p->range()->max);
      if (!p->choices().empty()) {
        std::string c;
        for (auto& v : p->choices()) c += (c.empty() ? "" : ", ") + v;
        doc += " One of: " + c + ".";
      }
      out += fmt::format("| `{}` | {} | `{}` | {} | {} |\n", p->name(), md(p->typeName()),
                         md(p->defaultText()), p->unit(), md(doc));
    }
    out += "\n";
  }
  if (!obj.slots().empty()) {
    out += "| nested module | kind | default | description |\n|---|---|---|---|\n";
    for (auto* s : obj.slots())
      out += fmt::format("| `{}` | {}{} | {} | {} |\n", s->name(), s->isList() ? "list of " : "",
                         s->kind(),
                         s->defaultType().empty() ? "—" : "`" + s->defaultType() + "`",
                         md(s->doc()));
    out += "\n";
  }
  if (!obj.actions().empty()) {
    out += "Actions: ";
    std::string a;
    for (auto& act : obj.actions())
      a += (a.empty() ? "" : ", ") + ("`" + act.name + "` (" + act.doc + ")");
    out += a + ".\n\n";
  }
  return out;
}

}  // namespace

std::string describeType(const std::string& type) {
  if (type == "sweep") return sweep::describeSweepFile();
  if (type == kTopLevelName) {
    RunConfig top;
    return fmt::format("{} (the top level of a config file)\n  {}\n  {}.\n", kTopLevelName,
                       kTopLevelDoc, kBaseKeyDoc) +
           describeBody(top);
  }
  auto& registry = Registry::instance();
  auto info = registry.find(type);
  if (!info) {
    std::string msg = "unknown type '" + type + "'";
    std::string near = registry.closest(type);
    if (!near.empty()) msg += "; did you mean '" + near + "'?";
    msg += " (`plugslam plugins` lists the types; `plugslam describe " + std::string(kTopLevelName) +
           "` the keys of a config file's top level, `plugslam describe sweep` those of a sweep file)";
    throw InputError(msg);
  }
  auto obj = registry.create(type);
  return fmt::format("{} ({}, plugin {})\n  {}\n", info->name, info->kind, info->plugin,
                     info->doc) +
         describeBody(*obj);
}

std::string configReferenceMarkdown(const std::vector<PluginInfo>& plugins) {
  auto& registry = Registry::instance();
  std::string out =
      "# Configuration reference\n\n"
      "Generated by `plugslam reference` from the type registry; do not edit by hand.\n"
      "Every type is written `<plugin>.<Type>` in YAML; each parameter below is a key of its map.\n\n";
  std::vector<std::string> names{"sdk"};
  for (auto& p : plugins) names.push_back(p.name);
  std::sort(names.begin() + 1, names.end());
  {
    RunConfig top;
    out += fmt::format("## The top level of a config file\n\n{} (`plugslam describe {}`)\n\n{}.\n\n",
                       kTopLevelDoc, kTopLevelName, kBaseKeyDoc);
    out += referenceBody(top);
  }
  for (const auto& plugin : names) {
    auto types = registry.typesOf(plugin);
    if (types.empty()) continue;
    std::sort(types.begin(), types.end(),
              [](const TypeInfo& a, const TypeInfo& b) { return a.name < b.name; });
    out += "## Plugin `" + plugin + "`\n\n";
    for (const auto& t : types) {
      auto obj = registry.create(t.name);
      out += fmt::format("### `{}` ({})\n\n{}\n\n", t.name, t.kind, t.doc);
      out += referenceBody(*obj);
    }
  }
  return out;
}

}  // namespace plugslam::runtime
