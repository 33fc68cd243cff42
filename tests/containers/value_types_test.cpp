#include "plugslam/value_types.h"

#include <gtest/gtest.h>

#include "plugslam/property_container.h"

namespace otherplugin {
struct Blob {
  std::vector<double> v;
};
void save(plugslam::OutArchive& ar, const Blob& b) { plugslam::save(ar, b.v); }
void load(plugslam::InArchive& ar, Blob& b) { plugslam::load(ar, b.v); }
struct Other {
  int x = 0;
};
void save(plugslam::OutArchive& ar, const Other& o) { ar.writeInt(o.x); }
void load(plugslam::InArchive& ar, Other& o) { o.x = static_cast<int>(ar.readInt()); }
}  // namespace otherplugin

namespace plugslam {
namespace {

TEST(ValueTypes, BuiltInsAreRegisteredUnderTheSdk) {
  const auto& vt = ValueTypes::instance();
  for (const char* tag : {"bool", "int32", "int64", "uint64", "double", "string", "vector<double>",
                          "points2d", "points3d", "vector2d", "vector3d", "matrix3d", "vectorxd",
                          "matrixxd", "isometry2d", "isometry3d", "container"}) {
    auto info = vt.findByTag(tag);
    ASSERT_TRUE(info.has_value()) << tag;
    EXPECT_EQ(info->owner, "sdk") << tag;
  }
  EXPECT_EQ(vt.tagOf(typeid(std::vector<Eigen::Vector2d>)), "points2d");
  EXPECT_EQ(vt.tagOf(typeid(PropertyContainer)), "container");
  EXPECT_EQ(vt.findByType(typeid(Eigen::Isometry3d))->tag, "isometry3d");
  EXPECT_EQ(typeName<std::vector<Eigen::Vector2d>>(), "std::vector<Eigen::Vector2d>");
  EXPECT_EQ(typeName<double>(), "double");
  auto p = vt.make("points3d", "cloud");
  EXPECT_EQ(p->name(), "cloud");
  EXPECT_EQ(p->type(), std::type_index(typeid(std::vector<Eigen::Vector3d>)));
  EXPECT_THROW(ValueTypes::instance().removeOwner("sdk"), InputError);
}

TEST(ValueTypes, PluginTypesAreAddedAndRemovedByOwner) {
  auto& vt = ValueTypes::instance();
  vt.add<otherplugin::Blob>("otherplugin.Blob", "otherplugin");
  vt.add<otherplugin::Other>("otherplugin.Other", "otherplugin");
  vt.add<otherplugin::Blob>("otherplugin.Blob", "otherplugin");  // identical: no-op
  EXPECT_EQ(vt.findByTag("otherplugin.Blob")->owner, "otherplugin");
  EXPECT_EQ(typeName<otherplugin::Other>(), "otherplugin.Other");

  EXPECT_THROW(vt.add<otherplugin::Other>("otherplugin.Blob", "otherplugin"), InputError);
  EXPECT_THROW(vt.add<otherplugin::Blob>("otherplugin.Blob", "thief"), InputError);
  EXPECT_THROW(vt.add<otherplugin::Blob>("otherplugin.Alias", "otherplugin"), InputError);
  EXPECT_THROW(vt.add<double>("double2", "otherplugin"), InputError);
  EXPECT_THROW(vt.add<otherplugin::Blob>("", "otherplugin"), InputError);
  EXPECT_THROW(vt.add<otherplugin::Blob>("has space", "otherplugin"), InputError);

  EXPECT_EQ(vt.removeOwner("otherplugin"), 2u);
  EXPECT_FALSE(vt.findByTag("otherplugin.Blob").has_value());
  EXPECT_EQ(vt.removeOwner("otherplugin"), 0u);
  try {
    vt.make("otherplugin.Blob", "b");
    FAIL();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'otherplugin.Blob'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("plugin 'otherplugin'"), std::string::npos) << msg;
  }
  // Reloading the plugin registers again.
  vt.add<otherplugin::Blob>("otherplugin.Blob", "otherplugin");
  EXPECT_TRUE(vt.findByTag("otherplugin.Blob").has_value());
  vt.removeOwner("otherplugin");
}

}  // namespace
}  // namespace plugslam
