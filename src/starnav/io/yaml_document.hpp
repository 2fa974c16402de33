#pragma once
// The one way a YAML input (map_server metadata, elevation sidecars, sensor descriptions,
// scenarios and their --set values) is parsed: a syntax error is an Error naming the file and
// line, and a key given twice in any mapping is refused (yaml-cpp would keep the first silently).
//
// Before yaml-cpp builds its tree, one pass over the parser's events visits each node of the text
// once: it finds duplicate keys and counts the nodes the document holds once its aliases are
// expanded (an alias counts as every node of what it names). A document of more than
// kMaxYamlNodes such nodes is refused there, so that a few hundred bytes of nested aliases (a
// "billion laughs") cost milliseconds, and so does every reader that later walks the tree.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <string>
#include <string_view>

namespace starnav {

// The most bytes a YAML input may have (4 MiB: the largest scenario is under 10 KiB), checked
// from the file's size before it is read.
inline constexpr std::uint64_t kMaxYamlBytes = std::uint64_t{4} << 20;
// The most nodes (scalars, sequences, mappings) a YAML document may hold, aliases expanded.
inline constexpr std::uint64_t kMaxYamlNodes = 200000;

// Throws Error(source, line, key) for a syntax error, a duplicate key, more than kMaxYamlBytes or
// more than kMaxYamlNodes.
YAML::Node load_yaml_document(std::string_view text, const std::string& source);

// The text of a YAML file, refused from its size when it has more than kMaxYamlBytes.
std::string read_yaml_file(const std::string& path);

}  // namespace starnav
