#include "entry_check.h"

#include <map>
#include <set>
#include <string>
#include <typeindex>
#include <vector>

#include "plugslam/entry.h"
#include "plugslam/preprocessor.h"
#include "plugslam/property.h"
#include "plugslam/registry.h"
#include "plugslam/source.h"

namespace plugslam::runtime {

namespace {

// One declared entry of one module of the run, with its pipeline path.
struct Use {
  const Configurable* module;
  const EntryBase* entry;
  std::string module_path;  // "pipeline.tracker.aligner.slices[0]"
  std::string kind;         // the interface the module fills ("AlignerSlice2D")
  bool backend;             // under a loop detector or validator: its "measurement" is a scene
};

// Back-end modules align local maps with each other: what a slice there calls its measurement
// is the query map's scene.
bool isBackendKind(const std::string& kind) {
  return kind == "LoopDetector" || kind == "LoopValidator";
}

bool isAlignerSliceKind(const std::string& kind) {
  return kind == "AlignerSlice2D" || kind == "AlignerSlice3D";
}

bool isTrackerSliceKind(const std::string& kind) {
  return kind == "TrackerSlice2D" || kind == "TrackerSlice3D";
}

// Every slot in the module tree under `module`.
void collectSlots(const Configurable& module, std::vector<const SlotBase*>& out) {
  for (const SlotBase* slot : module.slots()) {
    out.push_back(slot);
    for (const auto& item : slot->items())
      if (item) collectSlots(*item, out);
  }
}

std::vector<const SlotBase*> allSlots(const Configurable& root) {
  std::vector<const SlotBase*> out;
  collectSlots(root, out);
  return out;
}

void collect(const Configurable& module, const std::string& path, const std::string& kind,
             bool backend, std::vector<Use>& uses) {
  for (const EntryBase* e : module.entries()) uses.push_back({&module, e, path, kind, backend});
  for (const SlotBase* slot : module.slots()) {
    const bool inner = backend || isBackendKind(slot->kind());
    const auto items = slot->items();
    for (size_t i = 0; i < items.size(); ++i) {
      std::string p = path.empty() ? slot->name() : path + "." + slot->name();
      if (slot->isList()) p += "[" + std::to_string(i) + "]";
      collect(*items[i], p, slot->kind(), inner, uses);
    }
  }
}

// The deepest YAML node along `path` (the key itself when the config sets it, else the module).
YAML::Node nodeAt(const YAML::Node& root, const std::string& path) {
  YAML::Node cur;
  cur.reset(root);
  for (const std::string& part : splitPath(path)) {
    if (!cur.IsDefined() || cur.IsScalar() || cur.IsNull()) break;
    const YAML::Node& c = cur;
    YAML::Node next;
    if (part[0] == '[') {
      const size_t index = std::stoul(part.substr(1, part.size() - 2));
      if (!c.IsSequence() || index >= c.size()) break;
      next.reset(c[index]);
    } else {
      if (!c.IsMap() || !c[part]) break;
      next.reset(c[part]);
    }
    cur.reset(next);
  }
  return cur;
}

// Who writes one name of a container.
struct Writer {
  std::type_index type;
  std::string path;         // the writing module's pipeline path
  std::string module_type;  // its registered type
};

// Who writes each name of one container.
struct Writers {
  std::map<std::string, Writer> by_name;
  std::string list() const {
    std::string out;
    for (const auto& [name, w] : by_name) out += (out.empty() ? "" : ", ") + name;
    return out.empty() ? "none" : out;
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& [name, w] : by_name) out.push_back(name);
    return out;
  }
};

}  // namespace

void checkEntries(const RunConfig& run, const ConfigDocument& doc, ConfigBuilder& builder) {
  std::vector<Use> uses;
  collect(run, "", RunConfig::kKind, false, uses);
  Writers raw, measurement, scene;
  const std::string source_type = run.source ? run.source->typeName() : std::string("source");
  if (run.source)
    for (const ProvidedEntry& p : run.source->provides())
      raw.by_name.emplace(p.name, Writer{p.type, "source", source_type});
  for (const Use& u : uses) {
    if (!u.entry->writes() || u.entry->container() == Container::raw) continue;
    Writers& w = u.entry->container() == Container::measurement ? measurement : scene;
    // The first writer stands for the rest.
    w.by_name.emplace(u.entry->name(), Writer{u.entry->type(), u.module_path, u.module->typeName()});
  }
  const bool source_declares = !raw.by_name.empty();
  // A preprocessor (tracker slice) that declares no output may write any measurement (scene)
  // entry, for example one written against the old interface with plain string parameters:
  // that container is then not checked rather than wrongly reported.
  bool measurement_known = true, scene_known = true;
  for (const SlotBase* slot : allSlots(run)) {
    const bool preprocessor = slot->kind() == std::string(PreProcessor::kKind);
    const bool tracker_slice = isTrackerSliceKind(slot->kind());
    if (!preprocessor && !tracker_slice) continue;
    for (const auto& item : slot->items()) {
      if (!item) continue;
      bool writes = false;
      for (const EntryBase* e : item->entries()) writes = writes || e->writes();
      if (writes) continue;
      (preprocessor ? measurement_known : scene_known) = false;
    }
  }

  for (const Use& u : uses) {
    const EntryBase& e = *u.entry;
    const std::string path = u.module_path + "." + e.key();
    auto report = [&](const std::string& message) {
      builder.report(nodeAt(doc.root, path), path, message);
    };
    if (e.writes()) {
      if (isAlignerSliceKind(u.kind))
        report(u.module->typeName() + " is an aligner slice, which only reads; it declares " +
               e.describe());
      continue;
    }
    // Which container feeds this read, and who writes it.
    const Writers* writers = &scene;
    std::string message;
    if (e.container() == Container::raw) {
      if (!source_declares) continue;  // a source that declares nothing is not checked
      writers = &raw;
      message = "the source (" + source_type + ") provides no raw entry '" + e.name() + "'";
    } else if (e.container() == Container::measurement && !u.backend) {
      if (!measurement_known) continue;
      writers = &measurement;
      message = "no preprocessor writes measurement entry '" + e.name() + "'";
    } else {
      if (!scene_known) continue;
      message = "no tracker slice writes scene entry '" + e.name() + "'";
      if (e.container() == Container::measurement)
        message += " (in the back-end a slice's measurement is a local map's scene)";
    }
    const auto found = writers->by_name.find(e.name());
    if (found == writers->by_name.end()) {
      message += " (" + e.typeName() + ")";
      const std::string near = closestMatch(e.name(), writers->names());
      if (!near.empty()) message += "; did you mean '" + near + "'?";
      message += std::string(writers == &raw           ? "; it provides: "
                             : writers == &measurement ? "; the preprocessors write: "
                                                       : "; the tracker slices write: ") +
                 writers->list();
      report(message);
      continue;
    }
    const Writer& w = found->second;
    if (w.type != e.type())
      report("reads '" + e.name() + "' as " + e.typeName() + ", but " + w.path + " (" +
             w.module_type + ") writes it as " + typeDisplayName(w.type));
  }
}

}  // namespace plugslam::runtime
