#pragma once
// Configurable: the base of every module. It keeps the list of its parameters (Param<T>
// members), of the container entries it reads and writes (Input<T>, Output<T>), of its nested
// modules (Slot<I>, SlotList<I>) and of its runtime actions, so a whole pipeline is built, dumped,
// validated and driven from data alone.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plugslam/param.h"

namespace plugslam {
inline namespace abi_v1 {

class SlotBase;
class EntryBase;

/// A named operation a module exposes at runtime ("save_graph", "reset"); returns a message.
struct Action {
  std::string name;
  std::string doc;
  std::function<std::string(const std::vector<std::string>& args)> run;
};

/// Base of every configurable module.
class Configurable {
 public:
  /// Interface kind, overridden (shadowed) by each module interface; read by the registry.
  static constexpr const char* kKind = "Configurable";

  Configurable() = default;
  Configurable(const Configurable&) = delete;
  Configurable& operator=(const Configurable&) = delete;
  virtual ~Configurable();

  /// Validates cross-parameter invariants and prepares for use; called by the builder after
  /// every parameter and nested module is set. Throw ParamError to blame one parameter.
  virtual void configure() {}

  /// The parameters, in declaration order.
  const std::vector<ParamBase*>& params() const { return params_; }
  /// The nested module slots, in declaration order.
  const std::vector<SlotBase*>& slots() const { return slots_; }
  /// The container entries the module reads and writes, in declaration order (each also in
  /// params(), as the string parameter that names its property).
  const std::vector<EntryBase*>& entries() const { return entries_; }
  /// The runtime actions.
  const std::vector<Action>& actions() const { return actions_; }
  /// The parameter called `name`, or nullptr.
  ParamBase* findParam(const std::string& name) const;
  /// The slot called `name`, or nullptr.
  SlotBase* findSlot(const std::string& name) const;
  /// Runs an action by name; throws InputError listing the actions when unknown.
  std::string invoke(const std::string& action, const std::vector<std::string>& args = {});

  /// Registered type name ("laser2d.PointToLineSlice"); set by the registry on creation.
  const std::string& typeName() const { return type_name_; }
  /// Instance name: the YAML `name:` key, or derived from its place in the pipeline.
  const std::string& name() const { return name_; }
  /// Sets the instance name.
  void setName(std::string name) { name_ = std::move(name); }
  /// Sets the registered type name (the registry does this).
  void setTypeName(std::string type) { type_name_ = std::move(type); }

 protected:
  /// Exposes a runtime action.
  void addAction(std::string name, std::string doc,
                 std::function<std::string(const std::vector<std::string>&)> run);

 private:
  friend class ParamBase;
  friend class SlotBase;
  friend class EntryBase;
  std::vector<ParamBase*> params_;
  std::vector<SlotBase*> slots_;
  std::vector<EntryBase*> entries_;
  std::vector<Action> actions_;
  std::string type_name_;
  std::string name_;
};

/// Type-erased view of a nested module (or list of them) of some interface kind.
class SlotBase {
 public:
  SlotBase(const SlotBase&) = delete;
  SlotBase& operator=(const SlotBase&) = delete;
  virtual ~SlotBase();

  /// Key in YAML.
  const std::string& name() const { return name_; }
  /// One-line description.
  const std::string& doc() const { return doc_; }
  /// Interface kind the items must implement ("AlignerSlice").
  const std::string& kind() const { return kind_; }
  /// Type built when the YAML omits `type:` (or the key entirely); empty = no default. For a
  /// list: the types built when the YAML omits the key, comma-separated.
  const std::string& defaultType() const { return default_type_; }
  /// The default types one by one (one at most for a single slot).
  std::vector<std::string> defaultTypes() const;
  /// True for SlotList.
  bool isList() const { return is_list_; }

  /// Removes every item.
  virtual void clear() = 0;
  /// Appends (list) or sets (single) an item; throws ValueError if it has the wrong interface.
  virtual void assign(std::shared_ptr<Configurable> item) = 0;
  /// Replaces item `index`; throws ValueError if it has the wrong interface.
  virtual void replace(size_t index, std::shared_ptr<Configurable> item) = 0;
  /// The current items (0 or 1 for a single slot).
  virtual std::vector<std::shared_ptr<Configurable>> items() const = 0;

 protected:
  SlotBase(Configurable* owner, std::string name, std::string kind, std::string default_type,
           std::string doc, bool is_list);
  [[noreturn]] void wrongKind(const Configurable& item) const;
  /// "a, b, c": how a list's default types are kept in defaultType().
  static std::string joinTypes(const std::vector<std::string>& types);

 private:
  std::string name_, doc_, kind_, default_type_;
  bool is_list_;
};

/// One nested module implementing interface I (e.g. Slot<Splitter>).
template <class I>
class Slot final : public SlotBase {
 public:
  /// Declares the slot on `owner`; `default_type` is built when YAML names no type ("" = none).
  Slot(Configurable* owner, std::string name, std::string default_type, std::string doc)
      : SlotBase(owner, std::move(name), I::kKind, std::move(default_type), std::move(doc),
                 false) {}

  /// The module, or nullptr when empty.
  I* get() const { return item_.get(); }
  /// Shared ownership of the module.
  const std::shared_ptr<I>& shared() const { return item_; }
  I* operator->() const { return item_.get(); }
  I& operator*() const { return *item_; }
  explicit operator bool() const { return item_ != nullptr; }

  void clear() override { item_.reset(); }
  void assign(std::shared_ptr<Configurable> item) override {
    auto typed = std::dynamic_pointer_cast<I>(item);
    if (item && !typed) wrongKind(*item);
    item_ = std::move(typed);
  }
  void replace(size_t, std::shared_ptr<Configurable> item) override { assign(std::move(item)); }
  std::vector<std::shared_ptr<Configurable>> items() const override {
    if (!item_) return {};
    return {item_};
  }

 private:
  std::shared_ptr<I> item_;
};

/// An ordered list of nested modules implementing interface I (e.g. the aligner's slices).
template <class I>
class SlotList final : public SlotBase {
 public:
  /// Declares the list on `owner`.
  SlotList(Configurable* owner, std::string name, std::string doc)
      : SlotBase(owner, std::move(name), I::kKind, "", std::move(doc), true) {}
  /// Declares the list with the types built, in order, when the YAML omits the key.
  SlotList(Configurable* owner, std::string name, std::string doc,
           const std::vector<std::string>& default_types)
      : SlotBase(owner, std::move(name), I::kKind, joinTypes(default_types), std::move(doc),
                 true) {}

  size_t size() const { return items_.size(); }
  bool empty() const { return items_.empty(); }
  I& operator[](size_t i) const { return *items_[i]; }
  auto begin() const { return items_.begin(); }
  auto end() const { return items_.end(); }

  void clear() override { items_.clear(); }
  void assign(std::shared_ptr<Configurable> item) override {
    auto typed = std::dynamic_pointer_cast<I>(item);
    if (!typed) wrongKind(*item);
    items_.push_back(std::move(typed));
  }
  void replace(size_t index, std::shared_ptr<Configurable> item) override {
    auto typed = std::dynamic_pointer_cast<I>(item);
    if (!typed) wrongKind(*item);
    items_.at(index) = std::move(typed);
  }
  std::vector<std::shared_ptr<Configurable>> items() const override {
    return {items_.begin(), items_.end()};
  }

 private:
  std::vector<std::shared_ptr<I>> items_;
};

}  // namespace abi_v1
}  // namespace plugslam
