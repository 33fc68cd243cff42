// plugslam plugins | describe TYPE | config TYPE | config --resolved FILE | reference
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <iostream>
#include <map>

#include "cli.h"
#include "commands/commands.h"
#include "commands/introspection.h"
#include "config_builder.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/registry.h"

namespace plugslam::runtime {

void addPluginsCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand("plugins", "List the plugins found on the search path and their types");
  cmd->callback([&exit_code] {
    PluginManager plugins;
    auto refusals = loadAllPlugins(plugins);
    std::cout << "search path:\n";
    for (auto& d : plugins.searchPath()) std::cout << "  " << d << "\n";
    auto print_types = [](const std::string& plugin) {
      for (const auto& t : Registry::instance().typesOf(plugin))
        std::cout << fmt::format("    {:<34} {:<14} {}\n", t.name, t.kind, t.doc);
    };
    std::cout << "\nsdk (built in)\n";
    print_types("sdk");
    for (const auto& p : plugins.loaded()) {
      std::cout << fmt::format("\n{} {} ({})\n  {}\n", p.name, p.version, p.path, p.description);
      print_types(p.name);
    }
    for (const auto& r : refusals) std::cout << "\nrefused: " << r << "\n";
    exit_code = kOk;
  });
}

void addDescribeCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand("describe", "Show a type's parameters (type, default, unit, doc)");
  static std::string type;
  cmd->add_option("TYPE", type,
                  std::string("type name, e.g. sdk.Pipeline; `") + kTopLevelName +
                      "`: the top-level keys of a config file; `sweep`: the keys of a sweep file")
      ->required();
  cmd->callback([&exit_code] {
    PluginManager plugins;
    loadPluginOf(plugins, type);
    std::cout << describeType(type);
    exit_code = kOk;
  });
}

void addConfigCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand(
      "config", "A type's default YAML, or --resolved FILE: the document a run uses");
  static std::string type, resolved;
  static std::vector<std::string> sets;
  static bool defaults = false;
  // The default mode; the flag stays accepted so older scripts and docs keep working.
  cmd->add_flag("--defaults", defaults, "the type's defaults (what it prints for a TYPE anyway)");
  cmd->add_option("TYPE", type, "type name, e.g. sdk.Pipeline");
  cmd->add_option("--resolved", resolved,
                  "a config file: print the whole document a run of it uses, its bases merged "
                  "(what a session saves)");
  cmd->add_option("--set", sets, "with --resolved: override a parameter: PATH=VALUE (repeatable)");
  cmd->callback([&exit_code] {
    if (resolved.empty() == type.empty())
      throw InputError("config: give either a TYPE (its defaults) or --resolved FILE (the "
                       "document a run of FILE uses)");
    if (!resolved.empty()) {
      ConfigDocument doc = loadConfigFile(resolved);
      for (const auto& s : sets) applyOverride(doc, s);
      std::cout << resolvedYaml(doc);
      exit_code = kOk;
      return;
    }
    if (!sets.empty()) throw InputError("config: --set goes with --resolved FILE");
    PluginManager plugins;
    loadPluginOf(plugins, type);
    auto& registry = Registry::instance();
    if (!registry.find(type)) describeType(type);  // throws the "unknown type" error
    auto obj = registry.create(type);
    // Default nested modules are part of the defaults a user would edit.
    for (auto* s : obj->slots())
      if (!s->isList() && !s->defaultType().empty()) {
        loadPluginOf(plugins, s->defaultType());
        s->assign(registry.create(s->defaultType()));
      }
    YAML::Emitter out;
    out << dumpConfig(*obj);
    std::cout << out.c_str() << "\n";
    exit_code = kOk;
  });
}

void addReferenceCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand(
      "reference", "Write the configuration reference (markdown) of every type found");
  static std::string out_file;
  cmd->add_option("-o,--output", out_file, "file to write (default: standard output)");
  cmd->callback([&exit_code] {
    PluginManager plugins;
    auto refusals = loadAllPlugins(plugins);
    for (auto& r : refusals) std::cerr << "refused: " << r << "\n";
    std::string md = configReferenceMarkdown(plugins.loaded());
    if (out_file.empty())
      std::cout << md;
    else
      writeFileAtomically(out_file, md);
    exit_code = kOk;
  });
}

}  // namespace plugslam::runtime
