#include "plugslam/property.h"

#include "plugslam/property_container.h"
#include "plugslam/value_types.h"

namespace plugslam {
inline namespace abi_v1 {

PropertyBase::~PropertyBase() = default;

std::string PropertyBase::typeName() const { return typeDisplayName(type()); }

std::string PropertyBase::tag() const { return ValueTypes::instance().tagOf(type()); }

namespace detail {

void throwNotSerializable(const std::string& property, const std::type_index& type) {
  throw Error("property '" + property + "' holds " + typeDisplayName(type) +
              ", which has no save(OutArchive&, const T&) / load(InArchive&, T&) overloads");
}

void throwNotCopyable(const std::string& property, const std::type_index& type) {
  throw Error("property '" + property + "' holds " + typeDisplayName(type) +
              ", which cannot be copied");
}

}  // namespace detail

template class Property<bool>;
template class Property<std::int32_t>;
template class Property<std::int64_t>;
template class Property<std::uint64_t>;
template class Property<double>;
template class Property<std::string>;
template class Property<std::vector<double>>;
template class Property<std::vector<std::int64_t>>;
template class Property<std::vector<std::string>>;
template class Property<std::map<std::string, double>>;
template class Property<std::map<std::string, std::string>>;
template class Property<Eigen::Vector2d>;
template class Property<Eigen::Vector3d>;
template class Property<Eigen::Vector4d>;
template class Property<Eigen::Matrix2d>;
template class Property<Eigen::Matrix3d>;
template class Property<Eigen::Matrix4d>;
template class Property<Eigen::Matrix<double, 6, 6>>;
template class Property<Eigen::VectorXd>;
template class Property<Eigen::MatrixXd>;
template class Property<Eigen::Isometry2d>;
template class Property<Eigen::Isometry3d>;
template class Property<std::vector<Eigen::Vector2d>>;
template class Property<std::vector<Eigen::Vector3d>>;
template class Property<PropertyContainer>;

}  // namespace abi_v1
}  // namespace plugslam
