#include "plugslam/value_types.h"

#include "plugslam/sensor_data.h"
#include "plugslam/landmarks/feature_set.h"
#include "plugslam/landmarks/landmark_map.h"

#include <cxxabi.h>

#include <algorithm>
#include <cstdlib>

#include "plugslam/errors.h"
#include "plugslam/property_container.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {

void replaceAll(std::string& s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) {
    s.replace(p, from.size(), to);
  }
}

std::string demangle(const char* mangled) {
  int status = 0;
  char* d = abi::__cxa_demangle(mangled, nullptr, nullptr, &status);
  std::string s = (status == 0 && d) ? d : mangled;
  std::free(d);
  replaceAll(s, "std::__cxx11::basic_string<char, std::char_traits<char>, std::allocator<char> >",
             "std::string");
  replaceAll(s, "std::__cxx11::", "std::");
  replaceAll(s, "plugslam::abi_v1::", "plugslam::");
  return s;
}

}  // namespace

std::string typeDisplayName(const std::type_index& type) {
  if (auto info = ValueTypes::instance().findByType(type)) return info->display_name;
  return demangle(type.name());
}

ValueTypes& ValueTypes::instance() {
  static ValueTypes registry;
  return registry;
}

ValueTypes::ValueTypes() {
  const std::string sdk = "sdk";
  add<bool>("bool", sdk);
  add<std::int32_t>("int32", sdk, "std::int32_t");
  add<std::int64_t>("int64", sdk, "std::int64_t");
  add<std::uint64_t>("uint64", sdk, "std::uint64_t");
  add<double>("double", sdk);
  add<std::string>("string", sdk, "std::string");
  add<std::vector<double>>("vector<double>", sdk, "std::vector<double>");
  add<std::vector<std::int64_t>>("vector<int64>", sdk, "std::vector<std::int64_t>");
  add<std::vector<std::string>>("vector<string>", sdk, "std::vector<std::string>");
  add<std::map<std::string, double>>("map<string,double>", sdk, "std::map<std::string, double>");
  add<std::map<std::string, std::string>>("map<string,string>", sdk,
                                          "std::map<std::string, std::string>");
  add<Eigen::Vector2d>("vector2d", sdk, "Eigen::Vector2d");
  add<Eigen::Vector3d>("vector3d", sdk, "Eigen::Vector3d");
  add<Eigen::Vector4d>("vector4d", sdk, "Eigen::Vector4d");
  add<Eigen::Matrix2d>("matrix2d", sdk, "Eigen::Matrix2d");
  add<Eigen::Matrix3d>("matrix3d", sdk, "Eigen::Matrix3d");
  add<Eigen::Matrix4d>("matrix4d", sdk, "Eigen::Matrix4d");
  add<Eigen::Matrix<double, 6, 6>>("matrix6d", sdk, "Eigen::Matrix<double, 6, 6>");
  add<Eigen::VectorXd>("vectorxd", sdk, "Eigen::VectorXd");
  add<Eigen::MatrixXd>("matrixxd", sdk, "Eigen::MatrixXd");
  add<Eigen::Isometry2d>("isometry2d", sdk, "Eigen::Isometry2d");
  add<Eigen::Isometry3d>("isometry3d", sdk, "Eigen::Isometry3d");
  add<std::vector<Eigen::Vector2d>>("points2d", sdk, "std::vector<Eigen::Vector2d>");
  add<std::vector<Eigen::Vector3d>>("points3d", sdk, "std::vector<Eigen::Vector3d>");
  add<PropertyContainer>("container", sdk, "plugslam::PropertyContainer");
  add<LaserScan>("LaserScan", sdk, "plugslam::LaserScan");
  add<Odometry2D>("Odometry2D", sdk, "plugslam::Odometry2D");
  add<Image>("Image", sdk, "plugslam::Image");
  add<DepthImage>("DepthImage", sdk, "plugslam::DepthImage");
  add<CameraInfo>("CameraInfo", sdk, "plugslam::CameraInfo");
  add<FeatureSet>("FeatureSet", sdk, "plugslam::FeatureSet");
  add<LandmarkMap>("LandmarkMap", sdk, "plugslam::LandmarkMap");
}

void ValueTypes::addEntry(ValueTypeInfo info) {
  if (info.tag.empty() || info.tag.find_first_of(" \t\r\n") != std::string::npos) {
    throw InputError("invalid value-type tag '" + info.tag +
                     "': expected a non-empty name "
                     "without spaces, like 'laser2d.Scan'");
  }
  if (info.owner.empty()) throw InputError("value type '" + info.tag + "' needs an owner");
  if (!info.make) throw InputError("value type '" + info.tag + "' has no factory");
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& e : entries_) {
    const bool same_tag = e.tag == info.tag;
    const bool same_type = e.type == info.type;
    if (same_tag && same_type && e.owner == info.owner) return;  // idempotent re-registration
    if (same_tag) {
      throw InputError("value-type tag '" + info.tag + "' is already registered by '" + e.owner +
                       "'" + (same_type ? "" : " for another type"));
    }
    if (same_type) {
      throw InputError("cannot register '" + info.tag + "' for '" + info.owner +
                       "': that C++ type is already registered as '" + e.tag + "' by '" + e.owner +
                       "'");
    }
  }
  entries_.push_back(std::move(info));
}

std::optional<ValueTypeInfo> ValueTypes::findByTag(const std::string& tag) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& e : entries_) {
    if (e.tag == tag) return e;
  }
  return std::nullopt;
}

std::optional<ValueTypeInfo> ValueTypes::findByType(const std::type_index& type) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& e : entries_) {
    if (e.type == type) return e;
  }
  return std::nullopt;
}

std::string ValueTypes::tagOf(const std::type_index& type) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& e : entries_) {
    if (e.type == type) return e.tag;
  }
  return "";
}

std::string ValueTypes::unknownTagMessage(const std::string& tag) {
  const auto dot = tag.find('.');
  std::string msg = "unknown value type '" + tag + "'";
  if (dot != std::string::npos && dot > 0) {
    msg += ": no loaded plugin registers it (is the plugin '" + tag.substr(0, dot) + "' loaded?)";
  } else {
    msg += ": not a built-in type and no loaded plugin registers it";
  }
  return msg;
}

std::unique_ptr<PropertyBase> ValueTypes::make(const std::string& tag,
                                               const std::string& name) const {
  std::function<std::unique_ptr<PropertyBase>(const std::string&)> factory;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& e : entries_) {
      if (e.tag == tag) factory = e.make;
    }
  }
  if (!factory) throw InputError(unknownTagMessage(tag));
  return factory(name);
}

std::size_t ValueTypes::removeOwner(const std::string& owner) {
  if (owner == "sdk") throw InputError("the SDK's built-in value types cannot be removed");
  std::lock_guard<std::mutex> lock(mutex_);
  const auto before = entries_.size();
  entries_.erase(std::remove_if(entries_.begin(), entries_.end(),
                                [&](const ValueTypeInfo& e) { return e.owner == owner; }),
                 entries_.end());
  return before - entries_.size();
}

std::vector<std::string> ValueTypes::tags() const {
  std::vector<std::string> out;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& e : entries_) out.push_back(e.tag);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace abi_v1
}  // namespace plugslam
