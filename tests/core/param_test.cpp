#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "plugslam/configurable.h"
#include "plugslam/errors.h"
#include "plugslam/registry.h"

using namespace plugslam;

namespace {

class Widget : public Configurable {
 public:
  Param<double> max_distance{this, "max_distance", 0.5, "m", "max association distance",
                             Range{0.0, 10.0}};
  Param<int> iterations{this, "iterations", 10, "", "outer iterations", Range{1, 100}};
  Param<bool> enabled{this, "enabled", true, "", "on/off"};
  Param<std::string> solver{this, "solver", "gn", "", "solver", Choices{{"gn", "lm"}}};
  Param<std::vector<double>> offset{this, "offset", {0, 0, 0}, "m, m, rad", "mount pose"};
  Widget() {
    addAction("ping", "answers pong", [](const std::vector<std::string>& a) {
      return "pong" + std::to_string(a.size());
    });
  }
};

}  // namespace

TEST(Param, DeclaresItselfOnItsOwnerInOrder) {
  Widget w;
  ASSERT_EQ(w.params().size(), 5u);
  EXPECT_EQ(w.params()[0]->name(), "max_distance");
  EXPECT_EQ(w.params()[0]->unit(), "m");
  EXPECT_EQ(w.params()[0]->doc(), "max association distance");
  EXPECT_EQ(w.params()[0]->typeName(), "double");
  EXPECT_EQ(w.params()[4]->typeName(), "list<double>");
  EXPECT_EQ(w.findParam("iterations"), &w.iterations);
  EXPECT_EQ(w.findParam("nope"), nullptr);
}

TEST(Param, ReadsLikeItsValue) {
  Widget w;
  double d = w.max_distance;
  EXPECT_DOUBLE_EQ(d, 0.5);
  EXPECT_EQ(w.iterations(), 10);
  w.max_distance = 2.0;
  EXPECT_DOUBLE_EQ(w.max_distance.value(), 2.0);
  EXPECT_TRUE(w.max_distance.isSet());
  w.max_distance.reset();
  EXPECT_DOUBLE_EQ(w.max_distance(), 0.5);
  EXPECT_FALSE(w.max_distance.isSet());
}

TEST(Param, FromYamlChecksTypeRangeAndChoices) {
  Widget w;
  w.max_distance.fromYaml(YAML::Load("3"));
  EXPECT_DOUBLE_EQ(w.max_distance(), 3.0);
  EXPECT_THROW(w.max_distance.fromYaml(YAML::Load("abc")), ValueError);
  EXPECT_THROW(w.max_distance.fromYaml(YAML::Load("[1, 2]")), ValueError);
  try {
    w.max_distance.fromYaml(YAML::Load("11"));
    FAIL() << "out of range accepted";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("out of range [0, 10]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(w.iterations.fromYaml(YAML::Load("1.5")), ValueError);
  EXPECT_THROW(w.iterations.fromYaml(YAML::Load("99999999999")), ValueError);
  EXPECT_THROW(w.enabled.fromYaml(YAML::Load("yes please")), ValueError);
  w.enabled.fromYaml(YAML::Load("false"));
  EXPECT_FALSE(w.enabled());
  EXPECT_THROW(w.solver.fromYaml(YAML::Load("dogleg")), ValueError);
  w.solver.fromYaml(YAML::Load("lm"));
  EXPECT_EQ(w.solver(), "lm");
  w.offset.fromYaml(YAML::Load("[1, 2.5, -3]"));
  EXPECT_EQ(w.offset(), (std::vector<double>{1, 2.5, -3}));
  EXPECT_THROW(w.offset.fromYaml(YAML::Load("[1, x]")), ValueError);
  EXPECT_THROW(w.offset.fromYaml(YAML::Load("1")), ValueError);
}

TEST(Param, RendersDefaultsAsYamlText) {
  Widget w;
  EXPECT_EQ(w.max_distance.defaultText(), "0.5");
  EXPECT_EQ(w.enabled.defaultText(), "true");
  EXPECT_EQ(w.offset.defaultText(), "[0, 0, 0]");
  EXPECT_EQ(w.solver.choices().size(), 2u);
}

TEST(Configurable, ActionsRunByNameAndUnknownOnesSuggest) {
  Widget w;
  w.setName("widget");
  EXPECT_EQ(w.invoke("ping", {"a", "b"}), "pong2");
  try {
    w.invoke("pong");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'ping'"), std::string::npos) << e.what();
  }
}

TEST(Registry, CreatesByNameWithKindAndSuggestsNearMisses) {
  auto& registry = Registry::instance();
  Registrar r(registry, "paramtest", nullptr);
  r.add<Widget>("Widget", "a test widget");
  auto info = registry.find("paramtest.Widget");
  ASSERT_TRUE(info);
  EXPECT_EQ(info->kind, "Configurable");
  auto obj = registry.create("paramtest.Widget");
  EXPECT_EQ(obj->typeName(), "paramtest.Widget");
  EXPECT_NE(dynamic_cast<Widget*>(obj.get()), nullptr);
  try {
    registry.create("paramtest.Widgte");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'paramtest.Widget'"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(r.add<Widget>("Widget", "again"), InputError);
  EXPECT_THROW(r.add<Widget>("bad.name", "dots are for plugins"), InputError);
  registry.removePlugin("paramtest");
  EXPECT_FALSE(registry.find("paramtest.Widget"));
}

TEST(Registry, BuiltinsAreRegistered) {
  EXPECT_TRUE(Registry::instance().find("sdk.Pipeline"));
}

TEST(EditDistance, Basics) {
  EXPECT_EQ(editDistance("kitten", "sitting"), 3u);
  EXPECT_EQ(closestMatch("max_distnce", {"max_distance", "min_distance", "iterations"}),
            "max_distance");
  EXPECT_EQ(closestMatch("zzzzzz", {"max_distance"}), "");
}
