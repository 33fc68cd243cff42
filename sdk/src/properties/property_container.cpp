#include "plugslam/property_container.h"

#include "plugslam/value_types.h"

namespace plugslam {
inline namespace abi_v1 {

PropertyContainer::PropertyContainer() = default;

PropertyContainer::PropertyContainer(const PropertyContainer& other) {
  properties_.reserve(other.properties_.size());
  for (const auto& p : other.properties_) properties_.push_back(p->clone());
  reindex();
}

PropertyContainer::PropertyContainer(PropertyContainer&& other) noexcept = default;

PropertyContainer& PropertyContainer::operator=(const PropertyContainer& other) {
  if (this != &other) {
    PropertyContainer copy(other);  // clone first: a failing clone leaves *this untouched
    *this = std::move(copy);
  }
  return *this;
}

PropertyContainer& PropertyContainer::operator=(PropertyContainer&& other) noexcept = default;

PropertyContainer::~PropertyContainer() = default;

std::unique_ptr<PropertyContainer> PropertyContainer::clone() const {
  return std::make_unique<PropertyContainer>(*this);
}

PropertyBase& PropertyContainer::add(std::unique_ptr<PropertyBase> property) {
  if (!property) throw InputError("PropertyContainer::add: null property");
  PropertyBase& ref = *property;
  if (has(property->name())) {
    replace(std::move(property));
  } else {
    append(std::move(property));
  }
  return ref;
}

PropertyBase& PropertyContainer::at(const std::string& name) {
  if (PropertyBase* p = property(name)) return *p;
  std::string available;
  for (const auto& p : properties_) available += (available.empty() ? "" : ", ") + p->name();
  throw PropertyNotFound(name, available);
}

const PropertyBase& PropertyContainer::at(const std::string& name) const {
  return const_cast<PropertyContainer*>(this)->at(name);
}

PropertyBase* PropertyContainer::property(const std::string& name) {
  auto it = index_.find(name);
  return it == index_.end() ? nullptr : properties_[it->second].get();
}

const PropertyBase* PropertyContainer::property(const std::string& name) const {
  auto it = index_.find(name);
  return it == index_.end() ? nullptr : properties_[it->second].get();
}

bool PropertyContainer::has(const std::string& name) const { return index_.count(name) > 0; }

bool PropertyContainer::erase(const std::string& name) {
  auto it = index_.find(name);
  if (it == index_.end()) return false;
  properties_.erase(properties_.begin() + static_cast<std::ptrdiff_t>(it->second));
  reindex();
  return true;
}

void PropertyContainer::clear() {
  properties_.clear();
  index_.clear();
}

std::vector<std::string> PropertyContainer::names() const {
  std::vector<std::string> out;
  out.reserve(properties_.size());
  for (const auto& p : properties_) out.push_back(p->name());
  return out;
}

void PropertyContainer::throwMismatch(const PropertyBase& p,
                                      const std::type_index& requested) const {
  throw PropertyTypeMismatch(p.name(), typeDisplayName(requested), p.typeName());
}

void PropertyContainer::append(std::unique_ptr<PropertyBase> p) {
  index_.emplace(p->name(), properties_.size());
  properties_.push_back(std::move(p));
}

void PropertyContainer::replace(std::unique_ptr<PropertyBase> p) {
  properties_[index_.at(p->name())] = std::move(p);
}

void PropertyContainer::reindex() {
  index_.clear();
  for (std::size_t i = 0; i < properties_.size(); ++i) index_.emplace(properties_[i]->name(), i);
}

void save(OutArchive& ar, const PropertyContainer& container) {
  const ValueTypes& types = ValueTypes::instance();
  ar.beginObject();
  for (const PropertyBase& p : container) {
    const std::string tag = types.tagOf(p.type());
    if (tag.empty()) {
      throw Error("cannot save property '" + p.name() + "': its type " + p.typeName() +
                  " has no value-type tag (register it with ValueTypes::add<T>(tag, owner))");
    }
    ar.key(p.name());
    ar.beginObject();
    ar.key("type");
    ar.writeString(tag);
    ar.key("value");
    p.saveValue(ar);
    ar.endObject();
  }
  ar.endObject();
}

void load(InArchive& ar, PropertyContainer& container) {
  const ValueTypes& types = ValueTypes::instance();
  PropertyContainer result;  // filled aside so a failed load leaves `container` as it was
  ar.beginObject();
  for (const auto& name : ar.keys()) {
    ar.key(name);
    ar.beginObject();
    ar.key("type");
    const std::string tag = ar.readString();
    auto info = types.findByTag(tag);
    if (!info) ar.fail(ValueTypes::unknownTagMessage(tag));
    std::unique_ptr<PropertyBase> p = info->make(name);
    ar.key("value");
    p->loadValue(ar);
    ar.endObject();
    result.add(std::move(p));
  }
  ar.endObject();
  container = std::move(result);
}

}  // namespace abi_v1
}  // namespace plugslam
