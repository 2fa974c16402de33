#pragma once
// The one way a YAML input (map_server metadata, elevation sidecars, sensor descriptions) is
// parsed: a syntax error is an Error naming the file and line, and a key given twice in any
// mapping is refused (yaml-cpp would keep the first silently; the scenario reader refuses too).
#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>

namespace starnav {

// Throws Error(source, line, key) for a syntax error or a duplicate key.
YAML::Node load_yaml_document(std::string_view text, const std::string& source);

}  // namespace starnav
