// loadYaml: the documents yaml-cpp would build into a cycle, or into a tree too deep or too large
// to walk, are refused at the line of the alias or collection that does it; others load as
// YAML::Load loads them.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <sstream>
#include <string>

#include "plugslam/archive.h"
#include "plugslam/errors.h"
#include "plugslam/property_container.h"
#include "plugslam/yaml_load.h"

namespace plugslam {
namespace {

// The refusal's line (1-based) and message; fails the test when the text loads.
std::pair<int, std::string> refusal(const std::string& text) {
  try {
    loadYaml(text);
  } catch (const YAML::ParserException& e) {
    return {e.mark.line + 1, e.msg};
  }
  ADD_FAILURE() << "loaded: " << text;
  return {0, ""};
}

std::string nested(int depth, const std::string& inner) {
  return std::string(depth, '[') + inner + std::string(depth, ']');
}

TEST(LoadYaml, AnAliasInsideItsOwnAnchorIsACycleAtItsLine) {
  auto [line, message] = refusal("plugins: &p [io, *p]");  // the 21 bytes the fuzzer found
  EXPECT_EQ(line, 1);
  EXPECT_EQ(message, "alias *p is inside its own anchor &p (line 1): a cycle, the value would never end");
  std::tie(line, message) = refusal("a: 1\nb: &outer\n  c: [1, {d: *outer}]\n");
  EXPECT_EQ(line, 3);
  EXPECT_NE(message.find("alias *outer is inside its own anchor &outer (line 2)"),
            std::string::npos);
  // As a key too.
  std::tie(line, message) = refusal("&k {x: 1, *k : 2}");
  EXPECT_EQ(line, 1);
}

TEST(LoadYaml, AliasesOfClosedAnchorsLoadAsYamlCppLoadsThem) {
  const std::string text = "a: &a {x: 1, y: [2, 3]}\nb: [*a, *a]\nc: &s text\nd: *s\n";
  const YAML::Node n = loadYaml(text);
  EXPECT_EQ(YAML::Dump(n), YAML::Dump(YAML::Load(text)));
  EXPECT_EQ(n["b"][1]["y"][1].as<int>(), 3);
  EXPECT_EQ(n["d"].as<std::string>(), "text");
  EXPECT_TRUE(loadYaml("").IsNull());
  EXPECT_EQ(loadYaml("first: 1\n---\nsecond: 2\n")["first"].as<int>(), 1);
}

TEST(LoadYaml, NestingIsBounded) {
  // The root sequence is depth 1 and the scalar inside the innermost one depth + 1.
  EXPECT_NO_THROW(loadYaml(nested(kMaxYamlDepth - 1, "x")));
  auto [line, message] = refusal("a: 1\nb: " + nested(kMaxYamlDepth, "x"));
  EXPECT_EQ(line, 2);
  EXPECT_EQ(message, "nested deeper than 256 levels");
  // Through aliases: each line nests 100 deep, the third alias goes past the bound.
  std::string text = "a: &a " + nested(100, "x") + "\n";
  text += "b: &b " + nested(100, "*a") + "\n";
  EXPECT_NO_THROW(loadYaml(text));
  text += "c: " + nested(100, "*b") + "\n";
  std::tie(line, message) = refusal(text);
  EXPECT_EQ(line, 3);
  EXPECT_EQ(message, "alias *b nests the document deeper than 256 levels");
}

TEST(LoadYaml, AliasExpansionIsBounded) {
  // Nine levels of ten aliases each would be 10^9 nodes: refused at once, not walked.
  std::string text = "a: &a [x, x, x, x, x, x, x, x, x, x]\n";
  for (char c = 'b'; c <= 'i'; ++c) {
    const std::string alias = std::string("*") + char(c - 1);
    text += std::string(1, c) + ": &" + c + " [" + alias;
    for (int i = 1; i < 10; ++i) text += ", " + alias;
    text += "]\n";
  }
  auto [line, message] = refusal(text);
  EXPECT_EQ(line, 6);  // f: 10^5 nodes per alias, the sum passes 10^6 in its line
  EXPECT_EQ(message, "aliases expand the document by more than 1000000 nodes (alias *e)");
}

TEST(LoadYaml, FilesAndStreamsAreCheckedToo) {
  EXPECT_THROW(loadYamlFile("/nonexistent/plugslam/file.yaml"), YAML::BadFile);
  std::istringstream in("plugins: &p [io, *p]");
  EXPECT_THROW(loadYaml(in), YAML::ParserException);
}

TEST(LoadYaml, ATextArchiveWithACycleIsAParseError) {
  std::istringstream in("plugslam_archive: 1\ndata: &d {x: *d}\n");
  try {
    auto ar = makeInArchive(in, ArchiveFormat::kText, "cycle.yaml");
    PropertyContainer c;
    load(*ar, c);
    FAIL() << "loaded";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "cycle.yaml");
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(e.message().find("alias *d is inside its own anchor &d"), std::string::npos);
  }
}

}  // namespace
}  // namespace plugslam
