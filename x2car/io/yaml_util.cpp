#include "x2car/io/yaml_util.hpp"

#include "x2car/core/error.hpp"

namespace x2car::io {

std::size_t yaml_line(const YAML::Mark& mark) {
  return mark.line < 0 ? 0 : static_cast<std::size_t>(mark.line) + 1;
}

std::size_t yaml_line(const YAML::Node& node) { return yaml_line(node.Mark()); }

YAML::Node load_yaml(std::string_view text, const std::string& source) {
  try {
    return YAML::Load(std::string(text));
  } catch (const YAML::Exception& error) {
    throw InputError(source, yaml_line(error.mark), {}, "invalid YAML: " + error.msg);
  }
}

YAML::Node load_yaml_mapping(std::string_view text, const std::string& source) {
  YAML::Node root = load_yaml(text, source);
  if (!root.IsMap()) throw InputError(source, "expected a YAML mapping at the top level");
  return root;
}

}  // namespace x2car::io
