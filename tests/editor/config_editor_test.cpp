// The configuration editor's server side: introspection, config <-> tree <-> YAML round trips
// that `plugslam validate` accepts, the CLI's messages on a bad edit, and saves confined to the
// editor's folder ('..', absolute paths and symlinks leading outside are refused).
#include "editor/config_editor.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "config_builder.h"
#include "plugin_manager.h"
#include "plugslam/errors.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace plugslam;
using namespace plugslam::runtime::editor;

namespace {

using plugslam::testing::TempDir;  // a fresh folder per test, removed after

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string program() { return plugslam::testing::buildDir() + "/bin/plugslam"; }
// The built-in default as a run hands it to the editor: the whole document, its base merged.
std::string defaultConfig() {
  return runtime::resolvedYaml(
      runtime::loadConfigFile(plugslam::testing::sourceDir() + "/configs/sim2d_double_laser.yaml"));
}

// The module at a path of slot keys and item indexes, e.g. {"pipeline", 0, "tracker", 0}.
json& moduleAt(json& tree, const std::vector<std::pair<std::string, size_t>>& path) {
  json* m = &tree;
  for (const auto& [key, index] : path) {
    json* next = nullptr;
    for (json& s : (*m)["slots"])
      if (s["key"] == key) next = &s["items"][index];
    if (!next) throw std::runtime_error("no slot " + key);
    m = next;
  }
  return *m;
}

class Editor : public ::testing::Test {
 protected:
  // The default config's plugins, loaded as a running host has them.
  void SetUp() override {
    for (const char* p : {"io", "laser2d", "odometry"}) plugins_.load(p);
  }
  plugslam::runtime::PluginManager plugins_;
  TempDir tmp;
};

TEST_F(Editor, SchemaListsEveryParameterWithItsIntrospection) {
  const json schema = schemaJson();
  const json* slice = nullptr;
  for (const json& t : schema["types"])
    if (t["name"] == "laser2d.PointToLineSlice") slice = &t;
  ASSERT_NE(slice, nullptr);
  EXPECT_EQ((*slice)["kind"], "AlignerSlice2D");
  const json* dist = nullptr;
  for (const json& p : (*slice)["params"])
    if (p["name"] == "max_distance") dist = &p;
  ASSERT_NE(dist, nullptr);
  EXPECT_EQ((*dist)["type"], "double");
  EXPECT_EQ((*dist)["unit"], "m");
  EXPECT_FALSE((*dist)["doc"].get<std::string>().empty());
  EXPECT_FALSE((*dist)["default"].get<std::string>().empty());
  // The root of a run config: its slots say which kinds go where.
  bool outputs = false;
  for (const json& s : schema["root"]["slots"])
    if (s["name"] == "outputs") outputs = s["list"].get<bool>() && s["kind"] == "Sink";
  EXPECT_TRUE(outputs);
}

TEST_F(Editor, TreeRoundTripsThroughYamlAndValidates) {
  const json tree = treeFromYaml(defaultConfig(), "default.yaml");
  json copy = tree;
  // Aligner slices of the tracker: two (front and rear lasers; the odometry is the motion
  // model's prediction), the first a point-to-line slice on "front".
  json& aligner = moduleAt(copy, {{"pipeline", 0}, {"tracker", 0}, {"aligner", 0}});
  json& slices = aligner["slots"][0]["items"];
  ASSERT_EQ(slices.size(), 2u);
  EXPECT_EQ(slices[0]["type"], "laser2d.PointToLineSlice");
  const std::string yaml = treeToYaml(tree);
  // Same tree again from the YAML it wrote: nothing lost, nothing added.
  EXPECT_EQ(treeFromYaml(yaml, "again.yaml"), tree);
  const Validation v = validateYaml(yaml, "edited.yaml", program());
  EXPECT_TRUE(v.ok) << ::testing::PrintToString(v.messages);
  ASSERT_FALSE(v.messages.empty());
  EXPECT_NE(v.messages.back().find("edited.yaml: OK"), std::string::npos) << v.messages.back();
}

TEST_F(Editor, EditsAreValidatedWithTheCliMessages) {
  json tree = treeFromYaml(defaultConfig(), "default.yaml");
  json& slice = moduleAt(tree, {{"pipeline", 0}, {"tracker", 0}, {"aligner", 0}, {"slices", 0}});
  // A value the parameter refuses (a string for a distance in metres).
  slice["params"].push_back({{"key", "max_distance"}, {"value", "far"}});
  Validation v = validateYaml(treeToYaml(tree), "edited.yaml", program());
  EXPECT_FALSE(v.ok);
  std::string all;
  for (const auto& m : v.messages) all += m + "\n";
  EXPECT_NE(all.find("edited.yaml"), std::string::npos) << all;
  EXPECT_NE(all.find("max_distance"), std::string::npos) << all;
  EXPECT_EQ(all.find("plugslam-editor-"), std::string::npos) << "temp path leaked: " << all;
  // Swapping the slice for another registered aligner slice, and removing the rear one.
  slice["params"] = json::array(
      {{{"key", "measurement"}, {"value", "front"}}, {{"key", "scene"}, {"value", "front"}}});
  slice["type"] = "laser2d.PointToPointSlice";
  json& slices = moduleAt(tree, {{"pipeline", 0}, {"tracker", 0}, {"aligner", 0}})["slots"][0];
  slices["items"].erase(1);
  const std::string yaml = treeToYaml(tree);
  v = validateYaml(yaml, "edited.yaml", program());
  EXPECT_TRUE(v.ok) << ::testing::PrintToString(v.messages) << yaml;
  EXPECT_NE(yaml.find("laser2d.PointToPointSlice"), std::string::npos);
  json again = treeFromYaml(yaml, "again.yaml");
  EXPECT_EQ(moduleAt(again, {{"pipeline", 0}, {"tracker", 0}, {"aligner", 0}})["slots"][0]["items"]
                .size(),
            1u)
      << yaml;
}

TEST_F(Editor, SavesStayInsideTheRoot) {
  const fs::path root = tmp.path() / "root";
  fs::create_directories(root / "sub");
  fs::create_directories(tmp.path() / "outside");
  fs::create_symlink(tmp.path() / "outside", root / "escape");
  fs::create_symlink(root / "sub", root / "inner");
  std::ofstream(tmp.path() / "outside" / "victim.yaml") << "keep: me\n";
  fs::create_symlink(tmp.path() / "outside" / "victim.yaml", root / "link.yaml");

  EXPECT_EQ(confinedPath(root, "a.yaml"), fs::canonical(root) / "a.yaml");
  EXPECT_EQ(confinedPath(root, "new/dir/b.yml"), fs::canonical(root) / "new/dir/b.yml");
  EXPECT_EQ(confinedPath(root, "inner/c.yaml"), fs::canonical(root) / "sub/c.yaml");
  for (const std::string& bad : std::vector<std::string>{
           "../x.yaml", "sub/../../x.yaml", "/tmp/x.yaml", (tmp.path() / "outside/y.yaml").string(),
           "escape/x.yaml", "link.yaml", "", "notes.txt", "sub/"}) {
    EXPECT_THROW(confinedPath(root, bad), InputError) << "'" << bad << "' accepted";
  }

  ConfigEditor editor(root, defaultConfig(), "default.yaml", program());
  const json tree = treeFromYaml(defaultConfig(), "default.yaml");
  const json saved = json::parse(
      editor.call("editor.save", json{{"path", "sub/mine.yaml"}, {"tree", tree}}.dump()));
  EXPECT_TRUE(saved["validation"]["ok"].get<bool>()) << saved.dump(2);
  EXPECT_EQ(slurp(root / "sub" / "mine.yaml"), saved["yaml"].get<std::string>());
  try {
    editor.call("editor.save", json{{"path", "escape/evil.yaml"}, {"tree", tree}}.dump());
    FAIL() << "a save through a symlink leading outside was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("outside"), std::string::npos) << e.what();
  }
  EXPECT_THROW(editor.call("editor.save", json{{"path", "link.yaml"}, {"yaml", "a: 1"}}.dump()),
               InputError);
  EXPECT_THROW(editor.call("editor.save", json{{"path", "../up.yaml"}, {"yaml", "a: 1"}}.dump()),
               InputError);
  EXPECT_FALSE(fs::exists(tmp.path() / "outside" / "evil.yaml"));
  EXPECT_FALSE(fs::exists(tmp.path() / "up.yaml"));
  EXPECT_EQ(slurp(tmp.path() / "outside" / "victim.yaml"), "keep: me\n");
}

// A config on a base is loaded as the document it runs: its base's path would mean nothing in
// the folder the editor validates in.
TEST_F(Editor, AConfigOnABaseLoadsAsTheWholeDocument) {
  tmp.write("base.yaml", defaultConfig());
  tmp.write("sub/variant.yaml", "base: ../base.yaml\nmax_frames: 7\n");
  ConfigEditor editor(tmp.path(), defaultConfig(), "default.yaml", program());
  const json loaded = json::parse(editor.call("editor.load", R"({"path": "sub/variant.yaml"})"));
  const std::string yaml = loaded["yaml"].get<std::string>();
  EXPECT_EQ(yaml.find("base:"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("max_frames: 7"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("rear_laser"), std::string::npos) << yaml;
  const json validated = json::parse(editor.call("editor.validate", json{{"yaml", yaml}}.dump()));
  EXPECT_TRUE(validated["validation"]["ok"].get<bool>()) << validated.dump(2);
}

TEST_F(Editor, MalformedRequestsAreRefusedWithAReason) {
  ConfigEditor editor(tmp.path(), defaultConfig(), "default.yaml", program());
  EXPECT_THROW(editor.call("editor.save", "{not json"), InputError);
  EXPECT_THROW(editor.call("editor.save", "{}"), InputError);
  EXPECT_THROW(editor.call("editor.save", R"({"path": "a.yaml", "tree": {"type": 3}})"),
               InputError);
  EXPECT_THROW(editor.call("editor.nothing", "{}"), InputError);
  const json cfg = json::parse(editor.call("editor.config", ""));
  EXPECT_EQ(cfg["name"], "default.yaml");
  EXPECT_EQ(cfg["root"], fs::canonical(tmp.path()).string());
  // Only plugslam validates: inside another program (this test) the editor refuses rather than
  // running that program as if it were plugslam.
  ConfigEditor bare(tmp.path(), defaultConfig(), "default.yaml");
  EXPECT_THROW(bare.call("editor.validate", R"({"yaml": "a: 1"})"), Error);
  EXPECT_TRUE(ConfigEditor::handles("editor.validate"));
  EXPECT_FALSE(ConfigEditor::handles("pause"));
}

}  // namespace
