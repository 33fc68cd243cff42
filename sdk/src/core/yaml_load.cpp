#include "plugslam/yaml_load.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

namespace {

// Follows the parse events of one document and measures the tree yaml-cpp would build from them,
// aliases expanded, without building it: a cyclic or exponential document costs no more than its
// text. yaml-cpp numbers anchors 1, 2, ... in the order they are defined (0: none), and
// an alias names the anchor defined last under its name, which may be one still open.
class AliasCheck final : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnAnchor(const YAML::Mark&, const std::string& name) override { pending_name_ = name; }

  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { leaf(mark, anchor); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                const std::string&) override {
    leaf(mark, anchor);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    open(mark, anchor);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    open(mark, anchor);
  }
  void OnMapEnd() override { close(); }

  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    if (anchor >= anchors_.size()) return;  // yaml-cpp refuses an unknown anchor itself
    const Anchor& a = anchors_[anchor];
    if (!a.closed)
      throw YAML::ParserException(
          mark, "alias *" + a.name + " is inside its own anchor &" + a.name + " (line " +
                    std::to_string(a.mark.line + 1) + "): a cycle, the value would never end");
    if (depth() + a.height > kMaxYamlDepth)
      throw YAML::ParserException(mark, "alias *" + a.name + " nests the document deeper than " +
                                            std::to_string(kMaxYamlDepth) + " levels");
    alias_nodes_ += a.size;
    if (alias_nodes_ > kMaxYamlAliasNodes)
      throw YAML::ParserException(mark, "aliases expand the document by more than " +
                                            std::to_string(kMaxYamlAliasNodes) +
                                            " nodes (alias *" + a.name + ")");
    child(a.height, a.size);
  }

 private:
  struct Open {
    YAML::anchor_t anchor;
    int height = 0;        // of the highest child so far
    std::size_t size = 1;  // nodes, itself included
  };
  struct Anchor {
    std::string name;
    YAML::Mark mark;
    bool closed = false;
    int height = 0;
    std::size_t size = 0;
  };

  int depth() const { return static_cast<int>(open_.size()); }

  void define(const YAML::Mark& mark, YAML::anchor_t anchor) {
    if (anchor == YAML::NullAnchor) return;
    if (anchors_.size() <= anchor) anchors_.resize(anchor + 1);
    anchors_[anchor] = Anchor{pending_name_, mark};
    pending_name_.clear();
  }
  void finish(YAML::anchor_t anchor, int height, std::size_t size) {
    if (anchor != YAML::NullAnchor) {
      anchors_[anchor].closed = true;
      anchors_[anchor].height = height;
      anchors_[anchor].size = size;
    }
    child(height, size);
  }
  void child(int height, std::size_t size) {
    if (open_.empty()) return;
    open_.back().height = std::max(open_.back().height, height);
    open_.back().size += size;
  }
  void checkDepth(const YAML::Mark& mark) const {
    if (depth() + 1 > kMaxYamlDepth)
      throw YAML::ParserException(
          mark, "nested deeper than " + std::to_string(kMaxYamlDepth) + " levels");
  }

  void leaf(const YAML::Mark& mark, YAML::anchor_t anchor) {
    checkDepth(mark);
    define(mark, anchor);
    finish(anchor, 1, 1);
  }
  void open(const YAML::Mark& mark, YAML::anchor_t anchor) {
    checkDepth(mark);
    define(mark, anchor);
    open_.push_back(Open{anchor});
  }
  void close() {
    const Open o = open_.back();
    open_.pop_back();
    finish(o.anchor, o.height + 1, o.size);
  }

  std::vector<Open> open_;
  std::vector<Anchor> anchors_;  // by anchor number
  std::string pending_name_;
  std::size_t alias_nodes_ = 0;
};

}  // namespace

YAML::Node loadYaml(const std::string& text) {
  {
    std::istringstream in(text);
    YAML::Parser parser(in);
    AliasCheck check;
    parser.HandleNextDocument(check);  // the first document, the one YAML::Load returns
  }
  return YAML::Load(text);
}

YAML::Node loadYaml(std::istream& in) {
  std::ostringstream text;
  text << in.rdbuf();
  return loadYaml(text.str());
}

YAML::Node loadYamlFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw YAML::BadFile(path);
  return loadYaml(in);
}

}  // namespace abi_v1
}  // namespace plugslam
