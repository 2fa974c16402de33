#include "starnav/io/yaml_document.hpp"

#include <set>
#include <vector>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

int line_of(const YAML::Node& node) { return node.Mark().is_null() ? 0 : node.Mark().line + 1; }

std::string joined(const std::string& prefix, const std::string& key) { return prefix.empty() ? key : prefix + "." + key; }

// Depth-first over every mapping and sequence; an explicit stack, since a hostile file can nest
// deeper than the call stack allows.
void refuse_duplicate_keys(const YAML::Node& root, const std::string& source) {
  std::vector<std::pair<YAML::Node, std::string>> pending{{root, ""}};
  while (!pending.empty()) {
    auto [node, prefix] = pending.back();
    pending.pop_back();
    if (node.IsMap()) {
      std::set<std::string> seen;
      for (auto it = node.begin(); it != node.end(); ++it) {
        const std::string key = it->first.IsScalar() ? it->first.Scalar() : std::string("?");
        if (it->first.IsScalar() && !seen.insert(key).second)
          throw Error("duplicate key", source, line_of(it->first), joined(prefix, key));
        pending.emplace_back(it->second, joined(prefix, key));
      }
    } else if (node.IsSequence()) {
      for (std::size_t i = 0; i < node.size(); ++i) pending.emplace_back(node[i], prefix + "[" + std::to_string(i) + "]");
    }
  }
}

}  // namespace

YAML::Node load_yaml_document(std::string_view text, const std::string& source) {
  YAML::Node doc;
  try {
    doc = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    throw Error("YAML syntax error: " + one_line(e.msg), source, e.mark.is_null() ? 0 : e.mark.line + 1);
  }
  refuse_duplicate_keys(doc, source);
  return doc;
}

}  // namespace starnav
