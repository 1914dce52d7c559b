// Shared helpers for the YAML files x2car reads (camera intrinsics, ground truth, Autoware
// extrinsics, simulate --config), so that every one reports a parse error and a node's line the
// same way: as an InputError naming the file and the 1-based line.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <string>
#include <string_view>

namespace x2car::io {

// The 1-based line of a mark (a parse error's) or of a node; 0 when yaml-cpp does not know it
// (a node made in memory, or an undefined one).
std::size_t yaml_line(const YAML::Mark& mark);
std::size_t yaml_line(const YAML::Node& node);

// Parses `text`; a YAML::Exception becomes InputError(source, its line, "invalid YAML: <why>"), and
// a key given twice in any mapping InputError(source, its second line, the key, "key given twice").
// An empty text gives a null node.
YAML::Node load_yaml(std::string_view text, const std::string& source);

// load_yaml, and the top level must be a mapping: InputError(source, "expected a YAML mapping at
// the top level") otherwise (an empty text included).
YAML::Node load_yaml_mapping(std::string_view text, const std::string& source);

}  // namespace x2car::io
