#include "x2car/io/yaml_util.hpp"

#include <fmt/format.h>

#include <map>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

// yaml-cpp keeps a key given twice and answers lookups with the first: a file whose second value
// is silently ignored. Every mapping, at any depth, must name each key once.
// `path`: the node's own field ("camera_matrix", "sensors[2]"; empty at the top).
void reject_repeated_keys(const YAML::Node& node, const std::string& source,
                          const std::string& path) {
  if (node.IsMap()) {
    std::map<std::string, std::size_t> lines;  // key -> its first line
    for (const auto& entry : node) {
      const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : std::string("?");
      const std::string field = path.empty() ? key : path + "." + key;
      if (entry.first.IsScalar()) {
        const auto [first, inserted] = lines.emplace(key, yaml_line(entry.first));
        if (!inserted) {
          throw InputError(source, yaml_line(entry.first), field,
                           fmt::format("key given twice (first on line {})", first->second));
        }
      }
      reject_repeated_keys(entry.second, source, field);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      reject_repeated_keys(node[i], source, fmt::format("{}[{}]", path, i));
    }
  }
}

}  // namespace

std::size_t yaml_line(const YAML::Mark& mark) {
  return mark.line < 0 ? 0 : static_cast<std::size_t>(mark.line) + 1;
}

std::size_t yaml_line(const YAML::Node& node) { return yaml_line(node.Mark()); }

YAML::Node load_yaml(std::string_view text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& error) {
    throw InputError(source, yaml_line(error.mark), {}, "invalid YAML: " + error.msg);
  }
  reject_repeated_keys(root, source, {});
  return root;
}

YAML::Node load_yaml_mapping(std::string_view text, const std::string& source) {
  YAML::Node root = load_yaml(text, source);
  if (!root.IsMap()) throw InputError(source, "expected a YAML mapping at the top level");
  return root;
}

}  // namespace x2car::io
