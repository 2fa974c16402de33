#include "starnav/io/yaml_document.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include <set>
#include <sstream>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/core/input_file.hpp"

namespace starnav {

namespace {

int line_of(const YAML::Mark& mark) { return mark.is_null() ? 0 : mark.line + 1; }

// One pass over the parser's events: each node of the text is visited once, whatever aliases
// point at it. Refuses a key given twice in a mapping, an alias inside the node it names (yaml-cpp
// would build a cycle that no reader could walk to its end), and a document of more than
// kMaxYamlNodes nodes once its aliases are expanded.
class DocumentScan final : public YAML::EventHandler {
 public:
  explicit DocumentScan(const std::string& source) : source_(source) {}

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { leaf(mark, anchor, nullptr); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, const std::string& value) override {
    leaf(mark, anchor, &value);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    if (anchor >= anchor_nodes_.size() || anchor_nodes_[anchor] == 0)
      throw Error("an alias inside the node its anchor names (a cycle)", source_, line_of(mark), path());
    arrive(mark, nullptr);
    add(mark, anchor_nodes_[anchor]);
    depart();
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    open(mark, anchor, false);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    open(mark, anchor, true);
  }
  void OnMapEnd() override { close(); }

 private:
  struct Frame {
    bool map = false;
    YAML::anchor_t anchor = YAML::NullAnchor;
    YAML::Mark mark;
    std::uint64_t nodes = 1;  // of this node's subtree, aliases expanded
    bool at_key = true;       // a mapping: the next node is a key
    std::string key;          // a mapping: the key of the value being read
    std::size_t index = 0;    // a sequence: the position of the element being read
    std::set<std::string> keys;
  };

  // Where the node being read sits: "navigation.goals[1]".
  std::string path() const {
    // Appended piece by piece (concatenation chains trip GCC 12's -Wrestrict).
    std::string p;
    for (const Frame& f : frames_) {
      if (f.map && !f.at_key) {
        if (!p.empty()) p += '.';
        p += printable(f.key, 60);
      } else if (!f.map) {
        p += '[';
        p += std::to_string(f.index);
        p += ']';
      }
    }
    return p;
  }

  // A node begins inside the innermost frame: a mapping's key is checked against its others.
  void arrive(const YAML::Mark& mark, const std::string* scalar) {
    if (frames_.empty() || !frames_.back().map || !frames_.back().at_key) return;
    Frame& f = frames_.back();
    f.key = scalar ? *scalar : std::string("?");
    if (scalar && !f.keys.insert(*scalar).second) {
      const std::string at = path();
      throw Error("duplicate key", source_, line_of(mark), (at.empty() ? "" : at + ".") + printable(*scalar, 60));
    }
  }
  // A node ended: the frame moves on to its next key, value or element.
  void depart() {
    if (frames_.empty()) return;
    Frame& f = frames_.back();
    if (f.map) f.at_key = !f.at_key;
    else ++f.index;
  }
  void add(const YAML::Mark& mark, std::uint64_t nodes) {
    total_ += nodes;
    if (!frames_.empty()) frames_.back().nodes += nodes;
    if (total_ > kMaxYamlNodes)
      throw Error("holds more than " + std::to_string(kMaxYamlNodes) + " YAML nodes once its aliases are expanded", source_,
                  line_of(mark));
  }
  void remember(YAML::anchor_t anchor, std::uint64_t nodes) {
    if (anchor == YAML::NullAnchor) return;
    if (anchor >= anchor_nodes_.size()) anchor_nodes_.resize(anchor + 1, 0);
    anchor_nodes_[anchor] = nodes;
  }
  void leaf(const YAML::Mark& mark, YAML::anchor_t anchor, const std::string* scalar) {
    arrive(mark, scalar);
    add(mark, 1);
    remember(anchor, 1);
    depart();
  }
  void open(const YAML::Mark& mark, YAML::anchor_t anchor, bool map) {
    arrive(mark, nullptr);
    total_ += 1;
    Frame f;
    f.map = map;
    f.anchor = anchor;
    f.mark = mark;
    frames_.push_back(std::move(f));
  }
  void close() {
    const Frame f = std::move(frames_.back());
    frames_.pop_back();
    remember(f.anchor, f.nodes);
    if (!frames_.empty()) frames_.back().nodes += f.nodes;
    depart();
  }

  const std::string& source_;
  std::vector<Frame> frames_;
  std::vector<std::uint64_t> anchor_nodes_;  // by anchor id (yaml-cpp numbers each definition anew); 0 until its node ends
  std::uint64_t total_ = 0;
};

[[noreturn]] void throw_syntax_error(const YAML::Exception& e, const std::string& source) {
  throw Error("YAML syntax error: " + one_line(e.msg), source, e.mark.is_null() ? 0 : e.mark.line + 1);
}

}  // namespace

YAML::Node load_yaml_document(std::string_view text, const std::string& source) {
  if (text.size() > kMaxYamlBytes)
    throw Error("is " + std::to_string(text.size()) + " bytes, more than the " + std::to_string(kMaxYamlBytes) +
                    " a YAML document may have",
                source);
  const std::string copy(text);
  try {
    std::istringstream in(copy);
    YAML::Parser parser(in);
    DocumentScan scan(source);
    parser.HandleNextDocument(scan);
  } catch (const YAML::Exception& e) {
    throw_syntax_error(e, source);
  }
  try {
    return YAML::Load(copy);
  } catch (const YAML::Exception& e) {
    throw_syntax_error(e, source);
  }
}

std::string read_yaml_file(const std::string& path) { return read_input_file(path, kMaxYamlBytes); }

}  // namespace starnav
