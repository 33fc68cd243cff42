#pragma once
// The one way plugslam reads YAML (configs, --set values, the editor's saves, sessions, text
// archives, map files). yaml-cpp builds an alias as a second reference to its anchor's node, so
// an alias inside its own anchor (`plugins: &p [io, *p]`) makes a cycle, and aliases of aliases
// make a tree far deeper or larger than its text: every walk that recurses over a node tree
// (variable expansion, the config builder, the emitter) would overflow the stack or never end.
// These functions check the text's parse events before yaml-cpp builds the tree.
#include <cstddef>
#include <iosfwd>
#include <string>

namespace YAML {
class Node;
}

namespace plugslam {
inline namespace abi_v1 {

/// The deepest nesting a document may have, aliases expanded (a scalar at the root is depth 1).
/// A config nests about 10 deep; yaml-cpp's own parser stops at 2000 without aliases.
constexpr int kMaxYamlDepth = 256;
/// The most nodes the aliases of one document may add (each alias adds its anchor's nodes).
constexpr std::size_t kMaxYamlAliasNodes = 1000000;

/// Parses the first document of `text` as YAML::Load does. An alias inside its own anchor,
/// nesting deeper than kMaxYamlDepth, or aliases adding more than kMaxYamlAliasNodes nodes throw
/// YAML::ParserException marked at the alias or collection that does it, as a syntax error is:
/// a caller reports both the same way (its file name, `e.mark.line + 1`, `e.msg`).
YAML::Node loadYaml(const std::string& text);
/// Reads the rest of `in` and parses it as loadYaml(text) does.
YAML::Node loadYaml(std::istream& in);
/// Reads the file at `path` as YAML::LoadFile does (YAML::BadFile when it cannot be opened),
/// with loadYaml's checks.
YAML::Node loadYamlFile(const std::string& path);

}  // namespace abi_v1
}  // namespace plugslam
