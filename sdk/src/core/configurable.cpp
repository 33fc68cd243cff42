#include "plugslam/configurable.h"

#include "plugslam/errors.h"
#include "plugslam/registry.h"

namespace plugslam {
inline namespace abi_v1 {

Configurable::~Configurable() = default;

ParamBase* Configurable::findParam(const std::string& name) const {
  for (auto* p : params_)
    if (p->name() == name) return p;
  return nullptr;
}

SlotBase* Configurable::findSlot(const std::string& name) const {
  for (auto* s : slots_)
    if (s->name() == name) return s;
  return nullptr;
}

void Configurable::addAction(std::string name, std::string doc,
                             std::function<std::string(const std::vector<std::string>&)> run) {
  actions_.push_back(Action{std::move(name), std::move(doc), std::move(run)});
}

std::string Configurable::invoke(const std::string& action, const std::vector<std::string>& args) {
  std::vector<std::string> names;
  for (auto& a : actions_) {
    if (a.name == action) return a.run(args);
    names.push_back(a.name);
  }
  std::string msg = "module '" + name_ + "' (" + type_name_ + ") has no action '" + action + "'";
  std::string near = closestMatch(action, names);
  if (!near.empty()) msg += "; did you mean '" + near + "'?";
  if (names.empty()) {
    msg += " (it has no actions)";
  } else {
    std::string list;
    for (auto& n : names) list += (list.empty() ? "" : ", ") + n;
    msg += " (actions: " + list + ")";
  }
  throw InputError(msg);
}

SlotBase::SlotBase(Configurable* owner, std::string name, std::string kind,
                   std::string default_type, std::string doc, bool is_list)
    : name_(std::move(name)),
      doc_(std::move(doc)),
      kind_(std::move(kind)),
      default_type_(std::move(default_type)),
      is_list_(is_list) {
  if (owner) owner->slots_.push_back(this);
}

SlotBase::~SlotBase() = default;

std::vector<std::string> SlotBase::defaultTypes() const {
  std::vector<std::string> out;
  size_t start = 0;
  while (start < default_type_.size()) {
    size_t end = default_type_.find(',', start);
    if (end == std::string::npos) end = default_type_.size();
    const size_t first = default_type_.find_first_not_of(' ', start);
    const size_t last = default_type_.find_last_not_of(' ', end - 1);
    if (first < end && last != std::string::npos && last >= first)
      out.push_back(default_type_.substr(first, last - first + 1));
    start = end + 1;
  }
  return out;
}

std::string SlotBase::joinTypes(const std::vector<std::string>& types) {
  std::string out;
  for (const auto& t : types) out += (out.empty() ? "" : ", ") + t;
  return out;
}

void SlotBase::wrongKind(const Configurable& item) const {
  throw ValueError("'" + name_ + "' expects a " + kind_ + ", but " + item.typeName() +
                   " is not one");
}

}  // namespace abi_v1
}  // namespace plugslam
