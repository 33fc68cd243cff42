#pragma once
// Addressing a built module tree by pipeline path ("pipeline.tracker.aligner.slices[0].sigma"),
// as the YAML does; used by the shell's get/do/swap/list and by `plugslam run --do`.
#include <functional>
#include <string>
#include <vector>

#include "plugslam/configurable.h"

namespace plugslam::runtime {

/// What a path names: a module (and the slot holding it) or one parameter of a module.
struct PathTarget {
  Configurable* module = nullptr;  ///< the module named, or the owner of `param`
  ParamBase* param = nullptr;      ///< set when the path ends at a parameter
  SlotBase* slot = nullptr;        ///< the slot holding `module` (nullptr for the root)
  Configurable* parent = nullptr;  ///< the module owning `slot`
  size_t index = 0;                ///< position of `module` in a list slot
};

/// Resolves `path` from `root` (the run); throws InputError naming the first part that does not
/// exist and the keys that do.
PathTarget resolvePath(Configurable& root, const std::string& path);
/// Calls `visit(module, path)` for every module under `root` (not the root), depth first.
void walkModules(Configurable& root,
                 const std::function<void(Configurable& module, const std::string& path)>& visit);
/// The module whose pipeline path or instance name is `name`; throws InputError when none.
Configurable& findModule(Configurable& root, const std::string& name);
/// Checks that "MODULE.ACTION" names a module (by path or name) and one of its actions, without
/// running it; throws the InputError invokeAction would.
void checkAction(Configurable& root, const std::string& target);
/// Runs "MODULE.ACTION" with `args` (the module by path or name); returns the action's message.
std::string invokeAction(Configurable& root, const std::string& target,
                         const std::vector<std::string>& args);

}  // namespace plugslam::runtime
