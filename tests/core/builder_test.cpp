// The YAML builder's contract: every error names file:line:column, the pipeline path and what
// was expected; near misses get a "did you mean".
#include <gtest/gtest.h>

#include "config_builder.h"
#include "plugslam/errors.h"
#include "plugslam/registry.h"
#include "temp_dir.h"

using namespace plugslam;
using namespace plugslam::runtime;

namespace {

class Knob : public Configurable {
 public:
  static constexpr const char* kKind = "Knob";
  Param<double> max_distance{this, "max_distance", 0.5, "m", "max association distance",
                             Range{0.0, 10.0}};
  Param<std::string> measurement{this, "measurement", "front", "", "measurement entry"};
};
class Dial : public Knob {};
class Lever : public Knob {
 public:
  void configure() override {
    if (measurement() == "forbidden") throw ParamError("measurement", "may not be 'forbidden'");
  }
};
class Other : public Configurable {
 public:
  static constexpr const char* kKind = "Other";
};
class Aligner : public Configurable {
 public:
  static constexpr const char* kKind = "Aligner";
  Param<int> iterations{this, "iterations", 10, "", "iterations", Range{1, 100}};
  SlotList<Knob> slices{this, "slices", "one per cue"};
};
class Root : public Configurable {
 public:
  Slot<Aligner> aligner{this, "aligner", "btest.Aligner", "the aligner"};
  Slot<Knob> extra{this, "extra", "", "optional knob"};
  Param<std::vector<std::string>> plugins{this, "plugins", {}, "", "plugins"};
};

void ensureRegistered() {
  static bool done = [] {
    Registrar r(Registry::instance(), "btest", nullptr);
    r.add<Dial>("Dial", "a dial");
    r.add<Lever>("Lever", "a lever");
    r.add<Aligner>("Aligner", "an aligner");
    r.add<Other>("Other", "not a knob");
    return true;
  }();
  (void)done;
}

std::string buildError(const std::string& yaml, const std::vector<std::string>& sets = {}) {
  ensureRegistered();
  auto doc = loadConfigText(yaml, "cfg.yaml");
  for (auto& s : sets) applyOverride(doc, s);
  PluginManager plugins;
  ConfigBuilder builder(doc, plugins);
  Root root;
  try {
    builder.configureRoot(root);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

void expectContains(const std::string& s, const std::string& part) {
  EXPECT_NE(s.find(part), std::string::npos) << "'" << part << "' not in: " << s;
}

const char* kGood = R"(aligner:
  iterations: 5
  slices:
    - {type: btest.Dial, measurement: front, max_distance: 0.3}
    - {type: btest.Lever, measurement: rear, max_distance: 0.7}
)";

}  // namespace

TEST(Builder, BuildsNestedModulesAndDefaults) {
  ensureRegistered();
  auto doc = loadConfigText(kGood, "cfg.yaml");
  PluginManager plugins;
  ConfigBuilder builder(doc, plugins);
  Root root;
  builder.configureRoot(root);
  ASSERT_TRUE(root.aligner);
  EXPECT_EQ(root.aligner->typeName(), "btest.Aligner");  // default type, no `type:` given
  EXPECT_EQ(root.aligner->iterations(), 5);
  ASSERT_EQ(root.aligner->slices.size(), 2u);
  EXPECT_DOUBLE_EQ(root.aligner->slices[1].max_distance(), 0.7);
  EXPECT_EQ(root.aligner->slices[1].name(), "aligner.slices[1]");
  EXPECT_FALSE(root.extra);
  auto dumped = dumpConfig(*root.aligner);
  EXPECT_EQ(dumped["slices"][0]["type"].as<std::string>(), "btest.Dial");
}

TEST(Builder, UnknownKeyIsLocatedAndSuggested) {
  std::string e = buildError("aligner:\n  slices:\n    - {type: btest.Dial, max_distnce: 0.3}\n");
  expectContains(e, "cfg.yaml:3:26: aligner.slices[0].max_distnce: unknown key 'max_distnce'");
  expectContains(e, "did you mean 'max_distance'?");
}

TEST(Builder, WrongTypeIsLocated) {
  std::string e = buildError(std::string(kGood) + "extra: {type: btest.Dial, max_distance: far}\n");
  expectContains(e, "cfg.yaml:6:41: extra.max_distance: expected a number, got 'far'");
}

TEST(Builder, OutOfRangeIsLocated) {
  std::string e = buildError("aligner:\n  slices:\n    - type: btest.Dial\n      max_distance: 12\n");
  expectContains(e, "cfg.yaml:4:21: aligner.slices[0].max_distance: value 12 is out of range [0, 10]");
}

TEST(Builder, UnknownTypeSuggests) {
  std::string e = buildError("aligner:\n  slices:\n    - {type: btest.Dail}\n");
  expectContains(e, "cfg.yaml:3:14: aligner.slices[0].type: unknown type 'btest.Dail'");
  expectContains(e, "did you mean 'btest.Dial'?");
}

TEST(Builder, MissingPluginIsNamed) {
  std::string e = buildError("extra: nosuchplugin.Thing\n");
  expectContains(e, "cfg.yaml:1:8: extra: type 'nosuchplugin.Thing' needs plugin 'nosuchplugin'");
  expectContains(e, "not found");
}

TEST(Builder, DuplicateKeyAndDuplicateNameAreErrors) {
  std::string e = buildError("aligner:\n  iterations: 3\n  iterations: 4\n");
  expectContains(e, "cfg.yaml:3:3: aligner.iterations: duplicate key 'iterations' (first given at line 2)");
  e = buildError(
      "aligner:\n  slices:\n    - {type: btest.Dial, name: front}\n    - {type: btest.Dial, name: front}\n");
  expectContains(e, "cfg.yaml:4:32: aligner.slices[1].name: duplicate module name 'front' (first used at cfg.yaml:3:32)");
}

TEST(Builder, WrongKindIsExplained) {
  std::string e = buildError("extra: btest.Other\n");
  expectContains(e, "'btest.Other' is an Other, but 'extra' expects a Knob");
}

TEST(Builder, ModuleValidationPointsAtTheParameter) {
  std::string e = buildError("extra:\n  type: btest.Lever\n  measurement: forbidden\n");
  expectContains(e, "cfg.yaml:3:16: extra.measurement: may not be 'forbidden'");
}

TEST(Builder, YamlSyntaxErrorIsLocated) {
  std::string e;
  try {
    loadConfigText("aligner:\n  slices: [a, b\n", "cfg.yaml");
  } catch (const ConfigError& err) {
    e = err.what();
  }
  expectContains(e, "cfg.yaml:");
  expectContains(e, "invalid YAML");
}

TEST(Builder, AnAliasCycleIsLocatedInTheFileAndInTheSet) {
  std::string e;
  try {
    loadConfigText("aligner:\n  slices: &s [a, *s]\n", "cfg.yaml");
  } catch (const ConfigError& err) {
    e = err.what();
  }
  expectContains(e, "cfg.yaml:2:");
  expectContains(e, "invalid YAML: alias *s is inside its own anchor &s");
  e.clear();
  try {
    auto doc = loadConfigText(kGood, "cfg.yaml");
    applyOverride(doc, "aligner.slices=&s [a, *s]");
  } catch (const ConfigError& err) {
    e = err.what();
  }
  expectContains(e, "--set aligner.slices=&s [a, *s]: aligner.slices: invalid YAML value: alias *s");
}

TEST(Builder, SetOverridesAndIsCheckedLikeYaml) {
  EXPECT_EQ(buildError(kGood, {"aligner.slices[1].max_distance=0.9"}), "");
  std::string e = buildError(kGood, {"aligner.slices[1].max_distance=99"});
  expectContains(e, "--set aligner.slices[1].max_distance=99: aligner.slices[1].max_distance: value 99 is out of range");
  e = buildError(kGood, {"aligner.iteratons=3"});
  expectContains(e, "did you mean 'iterations'?");
  EXPECT_THROW(buildError(kGood, {"aligner.slices[7].max_distance=1"}), ConfigError);
  EXPECT_THROW(buildError(kGood, {"no_equals_sign"}), InputError);
  EXPECT_THROW(buildError(kGood, {"a..b=1"}), InputError);
}

TEST(Builder, SplitPath) {
  EXPECT_EQ(splitPath("pipeline.aligner.slices[1].max_distance"),
            (std::vector<std::string>{"pipeline", "aligner", "slices", "[1]", "max_distance"}));
  EXPECT_THROW(splitPath("a[x]"), InputError);
  EXPECT_THROW(splitPath("a[1"), InputError);
}

// Item 17.31: one pass reports every error of a file, each located, in file order; the module
// whose key failed does not run its own checks on half-read values.
TEST(Builder, ReportsEveryErrorOfTheFile) {
  ensureRegistered();
  const char* yaml = R"(aligner:
  iteratons: 5
  slices:
    - {type: btest.Dial, max_distnce: 0.3}
    - {type: btest.Dail}
    - {type: btest.Lever, measurement: forbidden}
    - {type: btest.Dial, max_distance: 12}
extra: {type: btest.Dial, max_distance: far}
)";
  auto doc = loadConfigText(yaml, "cfg.yaml");
  PluginManager plugins;
  ConfigBuilder builder(doc, plugins);
  Root root;
  try {
    builder.configureRoot(root);
    FAIL() << "a broken config was accepted";
  } catch (const ConfigErrorList& e) {
    const auto& errors = e.errors();
    ASSERT_EQ(errors.size(), 6u) << e.what();
    EXPECT_EQ(std::string(errors[0].what()),
              "cfg.yaml:2:3: aligner.iteratons: unknown key 'iteratons' for btest.Aligner; did you mean "
              "'iterations'?");
    expectContains(errors[1].what(), "cfg.yaml:4:26: aligner.slices[0].max_distnce: unknown key");
    expectContains(errors[2].what(), "cfg.yaml:5:14: aligner.slices[1].type: unknown type 'btest.Dail'");
    expectContains(errors[3].what(), "cfg.yaml:6:40: aligner.slices[2].measurement: may not be 'forbidden'");
    expectContains(errors[4].what(), "cfg.yaml:7:40: aligner.slices[3].max_distance: value 12 is out of range");
    expectContains(errors[5].what(), "cfg.yaml:8:41: extra.max_distance: expected a number, got 'far'");
    // The first error's fields, so code that reads one ConfigError still sees a real one.
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.path(), "aligner.iteratons");
    expectContains(e.what(), "6 errors in cfg.yaml");
  }
}

TEST(Builder, ABadKeySkipsTheModulesOwnChecks) {
  // Lever's configure() would also complain about 'forbidden'; the typo is the one error.
  std::string e = buildError("extra:\n  type: btest.Lever\n  measurement: forbidden\n  max_distnce: 1\n");
  expectContains(e, "extra.max_distnce: unknown key");
  EXPECT_EQ(e.find("may not be 'forbidden'"), std::string::npos) << e;
}

TEST(Builder, OneErrorPerPluginThatDoesNotLoad) {
  std::string e = buildError("aligner:\n  slices: [nosuchplugin.A, nosuchplugin.B]\n");
  expectContains(e, "cfg.yaml:2:12: aligner.slices[0]: type 'nosuchplugin.A' needs plugin 'nosuchplugin'");
  expectContains(e, "cfg.yaml:2:28: aligner.slices[1]: type 'nosuchplugin.B' needs plugin "
                    "'nosuchplugin', which did not load (see the error at cfg.yaml:2:12)");
}

// ---- configs on a base (`base: FILE`) ----------------------------------------------------------

namespace {

// The errors of building `doc` (empty when it builds), one per line.
std::string buildErrors(const ConfigDocument& doc, Root& root) {
  ensureRegistered();
  PluginManager plugins;
  ConfigBuilder builder(doc, plugins);
  try {
    builder.configureRoot(root);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string loadError(const std::string& file) {
  try {
    loadConfigFile(file);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ConfigBase, ChangesTheBaseByKeyAndByListEntry) {
  const plugslam::testing::TempDir dir;
  dir.write("base.yaml", std::string(kGood) + "extra: {type: btest.Dial, measurement: x}\n");
  const std::string top = dir.write("sub/top.yaml",
                                    "base: ../base.yaml\n"
                                    "aligner:\n"
                                    "  iterations: 7\n"
                                    "  slices[1].max_distance: 0.9\n"
                                    "  slices[2]: {type: btest.Dial, measurement: third}\n");
  const ConfigDocument doc = loadConfigFile(top);
  Root root;
  ASSERT_EQ(buildErrors(doc, root), "");
  EXPECT_EQ(root.aligner->iterations(), 7);
  ASSERT_EQ(root.aligner->slices.size(), 3u);
  EXPECT_DOUBLE_EQ(root.aligner->slices[0].max_distance(), 0.3);  // the base's
  EXPECT_DOUBLE_EQ(root.aligner->slices[1].max_distance(), 0.9);
  EXPECT_EQ(root.aligner->slices[1].measurement(), "rear");       // kept: merged by key
  EXPECT_EQ(root.aligner->slices[1].typeName(), "btest.Lever");
  EXPECT_EQ(root.aligner->slices[2].measurement(), "third");      // [length] appends
  EXPECT_EQ(root.extra->measurement(), "x");
  // The document a run uses: the base's keys in their order, this file's written in.
  EXPECT_EQ(resolvedYaml(doc),
            "aligner:\n"
            "  iterations: 7\n"
            "  slices:\n"
            "    - {type: btest.Dial, measurement: front, max_distance: 0.3}\n"
            "    - {type: btest.Lever, measurement: rear, max_distance: 0.9}\n"
            "    - {type: btest.Dial, measurement: third}\n"
            "extra: {type: btest.Dial, measurement: x}\n");
}

TEST(ConfigBase, AModuleWithItsTypeAndAListReplaceTheBases) {
  const plugslam::testing::TempDir dir;
  dir.write("base.yaml", std::string(kGood) + "extra: {type: btest.Dial, measurement: x}\n");
  const std::string top = dir.write(
      "top.yaml", "base: base.yaml\nextra: {type: btest.Dial}\naligner.slices: [btest.Dial]\n");
  Root root;
  ASSERT_EQ(buildErrors(loadConfigFile(top), root), "");
  EXPECT_EQ(root.extra->measurement(), "front");  // the default, not the base's x
  ASSERT_EQ(root.aligner->slices.size(), 1u);
  EXPECT_DOUBLE_EQ(root.aligner->slices[0].max_distance(), 0.5);
  EXPECT_EQ(root.aligner->iterations(), 5);  // the rest of the aligner is the base's
}

TEST(ConfigBase, ErrorsNameTheFileLineAndKeyThatWroteTheValue) {
  const plugslam::testing::TempDir dir;
  // base.yaml line 4: a bad value the top file leaves alone.
  dir.write("base.yaml",
            "aligner:\n  slices:\n    - {type: btest.Dial, max_distance: 0.3}\n"
            "    - {type: btest.Lever, max_distance: 42}\n");
  const std::string top = dir.write("top.yaml",
                                    "# a variant\n"
                                    "base: base.yaml\n"
                                    "aligner.slices[0].max_distance: 77\n"
                                    "aligner.slices[1]:\n"
                                    "  measurment: rear\n");
  Root root;
  const std::string e = buildErrors(loadConfigFile(top), root);
  expectContains(e, dir.file("top.yaml") + ":3:33: aligner.slices[0].max_distance: value 77 is out of range");
  expectContains(e, dir.file("base.yaml") + ":4:41: aligner.slices[1].max_distance: value 42 is out of range");
  expectContains(e, dir.file("top.yaml") + ":5:15: aligner.slices[1].measurment: unknown key 'measurment'");
  // A --set still wins over both files.
  ConfigDocument doc = loadConfigFile(top);
  applyOverride(doc, "aligner.slices[0].max_distance=88");
  Root again;
  expectContains(buildErrors(doc, again),
                 "--set aligner.slices[0].max_distance=88: aligner.slices[0].max_distance: value 88");
}

TEST(ConfigBase, ChainsListsAndBadBases) {
  const plugslam::testing::TempDir dir;
  dir.write("a.yaml", "aligner: {iterations: 2}\n");
  dir.write("b.yaml", "base: a.yaml\nextra: {type: btest.Dial, measurement: b}\n");
  dir.write("c.yaml", "extra.measurement: c\naligner.iterations: 3\n");
  const std::string top = dir.write("top.yaml", "base: [b.yaml, c.yaml]\naligner.iterations: 4\n");
  ConfigDocument doc = loadConfigFile(top);
  Root root;
  ASSERT_EQ(buildErrors(doc, root), "");
  EXPECT_EQ(root.aligner->iterations(), 4);
  EXPECT_EQ(root.extra->measurement(), "c");
  EXPECT_EQ(sourceOf(doc, "aligner.iterations"), top);
  EXPECT_EQ(sourceOf(doc, "extra.measurement"), dir.file("c.yaml"));
  EXPECT_EQ(sourceOf(doc, "extra.type"), dir.file("b.yaml"));
  EXPECT_EQ(sourceOf(doc, "aligner"), dir.file("a.yaml"));

  dir.write("loop1.yaml", "base: loop2.yaml\n");
  dir.write("loop2.yaml", "aligner: {}\nbase: loop1.yaml\n");
  expectContains(loadError(dir.file("loop1.yaml")),
                 dir.file("loop2.yaml") + ":2:7: base: a cycle of bases: " + dir.file("loop1.yaml") +
                     " -> " + dir.file("loop2.yaml") + " -> " + dir.file("loop1.yaml"));
  dir.write("missing.yaml", "extra: {}\nbase: nowhere.yaml\n");
  expectContains(loadError(dir.file("missing.yaml")),
                 dir.file("missing.yaml") + ":2:7: base: the base config '" +
                     dir.file("nowhere.yaml") + "' is not a readable file");
  dir.write("past.yaml", "base: a.yaml\naligner.slices[3]: btest.Dial\n");
  expectContains(loadError(dir.file("past.yaml")),
                 "past.yaml:2:1: aligner.slices[3]: no such list element (the list has 0 entries");
  dir.write("none.yaml", "base: []\n");
  expectContains(loadError(dir.file("none.yaml")), "none.yaml:1:7: base: an empty list");
  dir.write("twice.yaml", "base: a.yaml\nextra: {}\nextra: {}\n");
  expectContains(loadError(dir.file("twice.yaml")), "twice.yaml:3:1: extra: duplicate key 'extra'");
  EXPECT_THROW(applyOverride(doc, "base=a.yaml"), ConfigError);
}

TEST(ConfigBase, SetAppendsAtTheListsLength) {
  auto doc = loadConfigText(kGood, "cfg.yaml");
  applyOverride(doc, "aligner.slices[2]={type: btest.Dial, measurement: x}");
  Root root;
  ASSERT_EQ(buildErrors(doc, root), "");
  ASSERT_EQ(root.aligner->slices.size(), 3u);
  EXPECT_EQ(root.aligner->slices[2].measurement(), "x");
  EXPECT_THROW(applyOverride(doc, "aligner.slices[4]={type: btest.Dial}"), ConfigError);
}
