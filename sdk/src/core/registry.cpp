#include "plugslam/registry.h"

#include <algorithm>

#include "builtin_types.h"
#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t sub = prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_d = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    size_t d = editDistance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

Registry& Registry::instance() {
  // Built-ins are registered on first use, not by static initializers (see STYLE.md).
  static Registry* registry = [] {
    auto* r = new Registry();
    Registrar registrar(*r, "sdk", nullptr);
    registerBuiltinTypes(registrar);
    return r;
  }();
  return *registry;
}

void Registry::add(TypeInfo info) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& t : types_)
    if (t.name == info.name)
      throw InputError("type '" + info.name + "' is registered twice (by plugin '" + t.plugin +
                       "' and by plugin '" + info.plugin + "')");
  types_.push_back(std::move(info));
}

std::optional<TypeInfo> Registry::find(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& t : types_)
    if (t.name == name) return t;
  return std::nullopt;
}

std::shared_ptr<Configurable> Registry::create(const std::string& name) const {
  TypeInfo info;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& t : types_)
      if (t.name == name) info = t;
  }
  if (!info.factory) {
    std::string msg = "unknown type '" + name + "'";
    std::string near = closest(name);
    if (!near.empty()) msg += "; did you mean '" + near + "'?";
    throw InputError(msg);
  }
  std::shared_ptr<void> lib = info.library.lock();
  Configurable* raw = info.factory();
  // The deleter holds the library: the plugin's code (destructor, vtable) stays mapped until
  // the last object it made is gone, so a plugin can be unloaded while objects still live.
  std::shared_ptr<Configurable> obj(raw, [lib](Configurable* p) { delete p; });
  obj->setTypeName(info.name);
  return obj;
}

std::vector<TypeInfo> Registry::types(const std::string& kind) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<TypeInfo> out;
  for (const auto& t : types_)
    if (kind.empty() || t.kind == kind) out.push_back(t);
  std::sort(out.begin(), out.end(),
            [](const TypeInfo& a, const TypeInfo& b) { return a.name < b.name; });
  return out;
}

std::vector<TypeInfo> Registry::typesOf(const std::string& plugin) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<TypeInfo> out;
  for (const auto& t : types_)
    if (t.plugin == plugin) out.push_back(t);
  return out;
}

void Registry::removePlugin(const std::string& plugin) {
  std::lock_guard<std::mutex> lock(mutex_);
  types_.erase(std::remove_if(types_.begin(), types_.end(),
                              [&](const TypeInfo& t) { return t.plugin == plugin; }),
               types_.end());
}

std::string Registry::closest(const std::string& name, const std::string& kind) const {
  std::vector<std::string> names;
  for (const auto& t : types(kind)) names.push_back(t.name);
  return closestMatch(name, names);
}

Registrar::Registrar(Registry& registry, std::string plugin, std::shared_ptr<void> library)
    : registry_(registry), plugin_(std::move(plugin)), library_(std::move(library)) {}

void Registrar::addFactory(const std::string& type, const char* kind, const std::string& doc,
                           std::function<Configurable*()> factory) {
  if (type.empty() || type.find('.') != std::string::npos)
    throw InputError("plugin '" + plugin_ + "' registers an invalid type name '" + type +
                     "' (expected a plain name like 'PointToLineSlice')");
  std::string full = plugin_ + "." + type;
  registry_.add(TypeInfo{full, plugin_, kind, doc, std::move(factory), library_});
  added_.push_back(full);
}

}  // namespace abi_v1
}  // namespace plugslam
