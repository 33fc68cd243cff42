#include "plugslam/property_container.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace plugslam {
namespace {

TEST(PropertyContainer, TypedAccessByName) {
  PropertyContainer c;
  c.set<double>("range", 2.5);
  c.set<std::string>("frame", "laser");
  c.emplace<std::vector<Eigen::Vector2d>>("points", 3, Eigen::Vector2d(1.0, 2.0));

  EXPECT_EQ(c.size(), 3u);
  EXPECT_DOUBLE_EQ(c.get<double>("range"), 2.5);
  EXPECT_EQ(c.get<std::string>("frame"), "laser");
  ASSERT_EQ(c.get<std::vector<Eigen::Vector2d>>("points").size(), 3u);
  EXPECT_EQ(c.get<std::vector<Eigen::Vector2d>>("points")[2], Eigen::Vector2d(1.0, 2.0));

  c.get<double>("range") = 4.0;  // get returns a reference into the container
  EXPECT_DOUBLE_EQ(c.get<double>("range"), 4.0);
  const PropertyContainer& cc = c;
  EXPECT_DOUBLE_EQ(cc.get<double>("range"), 4.0);

  EXPECT_TRUE(c.has("frame"));
  EXPECT_FALSE(c.has("nope"));
  EXPECT_TRUE(c.holds<std::string>("frame"));
  EXPECT_FALSE(c.holds<double>("frame"));
  EXPECT_EQ(c.names(), (std::vector<std::string>{"range", "frame", "points"}));

  c.set("literal", "abc");  // a string literal is stored as std::string, not const char*
  EXPECT_TRUE(c.holds<std::string>("literal"));
  c.set("pose", Eigen::Isometry2d::Identity() * Eigen::Translation2d(1.0, 2.0));  // T deduced
  EXPECT_TRUE(c.holds<Eigen::Isometry2d>("pose"));
}

TEST(PropertyContainer, FindReturnsNullWhenAbsent) {
  PropertyContainer c;
  c.set<int>("n", 7);
  ASSERT_NE(c.find<int>("n"), nullptr);
  EXPECT_EQ(*c.find<int>("n"), 7);
  EXPECT_EQ(c.find<int>("m"), nullptr);
  const PropertyContainer& cc = c;
  EXPECT_EQ(cc.find<int>("m"), nullptr);
  EXPECT_THROW(c.find<double>("n"), PropertyTypeMismatch);
}

TEST(PropertyContainer, MissingNameNamesTheNameAndTheAvailableOnes) {
  PropertyContainer c;
  c.set<double>("alpha", 1.0);
  c.set<double>("beta", 2.0);
  try {
    c.get<double>("gamma");
    FAIL() << "expected PropertyNotFound";
  } catch (const PropertyNotFound& e) {
    const std::string msg = e.what();
    EXPECT_EQ(e.name(), "gamma");
    EXPECT_NE(msg.find("'gamma'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("alpha, beta"), std::string::npos) << msg;
  }
  PropertyContainer empty;
  try {
    empty.at("x");
    FAIL() << "expected PropertyNotFound";
  } catch (const PropertyNotFound& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
}

TEST(PropertyContainer, WrongTypeNamesBothTypesReadably) {
  PropertyContainer c;
  c.set<std::vector<Eigen::Vector2d>>("points", {});
  c.set<std::string>("frame", "x");
  try {
    c.get<double>("points");
    FAIL() << "expected PropertyTypeMismatch";
  } catch (const PropertyTypeMismatch& e) {
    const std::string msg = e.what();
    EXPECT_EQ(e.name(), "points");
    EXPECT_NE(msg.find("'points'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("std::vector<Eigen::Vector2d>"), std::string::npos) << msg;
    EXPECT_NE(msg.find("double"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("Matrix<"), std::string::npos) << "mangled/expanded name in: " << msg;
  }
  try {
    c.get<Eigen::Isometry2d>("frame");
    FAIL() << "expected PropertyTypeMismatch";
  } catch (const PropertyTypeMismatch& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("std::string"), std::string::npos) << msg;
    EXPECT_NE(msg.find("Eigen::Isometry2d"), std::string::npos) << msg;
  }
  // Assigning another type to an existing name is refused, not silently retyped.
  EXPECT_THROW(c.set<double>("frame", 1.0), PropertyTypeMismatch);
  EXPECT_EQ(c.get<std::string>("frame"), "x");
}

struct Unregistered {
  int a = 0;
};

TEST(PropertyContainer, UnregisteredTypesGetADemangledName) {
  PropertyContainer c;
  c.set<Unregistered>("u", Unregistered{3});
  EXPECT_EQ(c.get<Unregistered>("u").a, 3);
  try {
    c.get<int>("u");
    FAIL();
  } catch (const PropertyTypeMismatch& e) {
    EXPECT_NE(std::string(e.what()).find("plugslam::(anonymous namespace)::Unregistered"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(c.at("u").serializable());
}

TEST(PropertyContainer, SetAssignsInPlaceAndEmplaceReplacesInPlace) {
  PropertyContainer c;
  c.set<int>("a", 1);
  c.set<int>("b", 2);
  c.set<int>("a", 10);
  EXPECT_EQ(c.names(), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(c.get<int>("a"), 10);
  c.emplace<std::string>("s", 3, 'x');
  EXPECT_EQ(c.get<std::string>("s"), "xxx");
  c.emplace<std::string>("s", 2, 'y');
  EXPECT_EQ(c.get<std::string>("s"), "yy");
  EXPECT_EQ(c.names(), (std::vector<std::string>{"a", "b", "s"}));
  EXPECT_THROW(c.emplace<double>("s", 1.0), PropertyTypeMismatch);
}

TEST(PropertyContainer, EraseKeepsOrderAndIndex) {
  PropertyContainer c;
  for (int i = 0; i < 5; ++i) c.set<int>("p" + std::to_string(i), i);
  EXPECT_TRUE(c.erase("p1"));
  EXPECT_FALSE(c.erase("p1"));
  EXPECT_EQ(c.names(), (std::vector<std::string>{"p0", "p2", "p3", "p4"}));
  EXPECT_EQ(c.get<int>("p3"), 3);
  EXPECT_EQ(c.get<int>("p4"), 4);
  c.clear();
  EXPECT_TRUE(c.empty());
}

TEST(PropertyContainer, IterationInInsertionOrder) {
  PropertyContainer c;
  c.set<double>("z", 1.0);
  c.set<int>("a", 2);
  c.set<std::string>("m", "3");
  std::vector<std::string> seen;
  for (const PropertyBase& p : c) seen.push_back(p.name() + ":" + p.typeName());
  EXPECT_EQ(seen, (std::vector<std::string>{"z:double", "a:std::int32_t", "m:std::string"}));
  for (PropertyBase& p : c) {
    if (p.type() == typeid(double)) static_cast<Property<double>&>(p).value() = 9.0;
  }
  EXPECT_DOUBLE_EQ(c.get<double>("z"), 9.0);
}

TEST(PropertyContainer, CopyIsDeepAndMoveTransfers) {
  PropertyContainer inner;
  inner.set<std::vector<double>>("v", {1.0, 2.0});
  PropertyContainer c;
  c.set<double>("x", 1.0);
  c.set<PropertyContainer>("inner", inner);

  PropertyContainer copy = c;
  copy.get<double>("x") = 2.0;
  copy.get<PropertyContainer>("inner").get<std::vector<double>>("v").push_back(3.0);
  EXPECT_DOUBLE_EQ(c.get<double>("x"), 1.0);
  EXPECT_EQ(c.get<PropertyContainer>("inner").get<std::vector<double>>("v").size(), 2u);
  EXPECT_EQ(copy.get<PropertyContainer>("inner").get<std::vector<double>>("v").size(), 3u);

  std::unique_ptr<PropertyContainer> cl = c.clone();
  EXPECT_EQ(cl->names(), c.names());
  EXPECT_NE(&cl->get<double>("x"), &c.get<double>("x"));

  const double* addr = &c.get<double>("x");
  PropertyContainer moved = std::move(c);
  EXPECT_EQ(&moved.get<double>("x"), addr);  // moving keeps the properties themselves

  PropertyContainer assigned;
  assigned.set<int>("old", 1);
  assigned = moved;
  EXPECT_FALSE(assigned.has("old"));
  EXPECT_EQ(assigned.names(), moved.names());
}

TEST(PropertyContainer, NestedContainers) {
  PropertyContainer root;
  auto& a = root.emplace<PropertyContainer>("a");
  auto& b = a.emplace<PropertyContainer>("b");
  b.set<Eigen::Vector3d>("p", Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(root.get<PropertyContainer>("a").get<PropertyContainer>("b").get<Eigen::Vector3d>("p"),
            Eigen::Vector3d(1, 2, 3));
  try {
    root.get<PropertyContainer>("a").get<double>("b");
    FAIL();
  } catch (const PropertyTypeMismatch& e) {
    EXPECT_NE(std::string(e.what()).find("plugslam::PropertyContainer"), std::string::npos)
        << e.what();
  }
}

TEST(PropertyContainer, AddReplacesWhateverTheType) {
  PropertyContainer c;
  c.set<int>("a", 1);
  c.set<int>("b", 2);
  c.add(std::make_unique<Property<std::string>>("a", "now a string"));
  EXPECT_EQ(c.names(), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(c.get<std::string>("a"), "now a string");
  EXPECT_THROW(c.add(nullptr), InputError);
}

struct MoveOnly {
  MoveOnly() = default;
  MoveOnly(MoveOnly&&) = default;
  MoveOnly& operator=(MoveOnly&&) = default;
  std::unique_ptr<int> p;
};

TEST(PropertyContainer, CopyingANonCopyableValueThrowsClearly) {
  PropertyContainer c;
  c.emplace<MoveOnly>("m");
  try {
    PropertyContainer copy = c;
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be copied"), std::string::npos) << e.what();
  }
  PropertyContainer moved = std::move(c);  // moving is always fine
  EXPECT_TRUE(moved.has("m"));
}

}  // namespace
}  // namespace plugslam
