#include "plugslam/entry.h"

#include "core/enum_names.h"
#include "plugslam/configurable.h"
#include "plugslam/errors.h"
#include "plugslam/property.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
constexpr EnumName<Container> kContainerNames[] = {
    {Container::raw, "raw"}, {Container::measurement, "measurement"}, {Container::scene, "scene"}};
}  // namespace

const char* containerName(Container container) { return enumName(kContainerNames, container, "?"); }

EntryBase::EntryBase(Configurable* owner, Container container, bool writes, std::type_index type,
                     std::string key, std::string default_name, std::string doc)
    : param_(owner, std::move(key), std::move(default_name), "", std::move(doc)),
      container_(container),
      writes_(writes),
      type_(type) {
  if (owner) owner->entries_.push_back(this);
}

EntryBase::~EntryBase() = default;

std::string EntryBase::typeName() const { return typeDisplayName(type_); }

std::string EntryBase::describe() const {
  return std::string(writes_ ? "writes " : "reads ") + containerName(container_) + " entry '" +
         name() + "' (" + typeName() + ")";
}

const PropertyContainer& EntryBase::in(const Frame& frame) const {
  switch (container_) {
    case Container::raw:
      return frame.raw;
    case Container::measurement:
      return frame.measurement;
    case Container::scene:
      break;
  }
  throw InputError("'" + key() + "' names a scene entry, which is not part of a frame");
}

PropertyContainer& EntryBase::in(Frame& frame) const {
  return const_cast<PropertyContainer&>(in(static_cast<const Frame&>(frame)));
}

void EntryBase::throwReadOnly() const {
  throw InputError("'" + key() + "' " + describe() + ", but was given a read-only container");
}

}  // namespace abi_v1
}  // namespace plugslam
