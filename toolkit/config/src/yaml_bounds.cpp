#include "flipper/toolkit/config/yaml_bounds.hpp"

#include <vector>

#include "flipper/sdk/errors.hpp"

namespace flipper::toolkit::config::yaml_bounds {

void check_expanded_size(const YAML::Node& root, const std::string& source) {
  std::size_t nodes = 1;
  std::vector<YAML::Node> todo{root};
  auto add = [&](const YAML::Node& n) {
    if (++nodes > kMaxConfigNodes)
      throw sdk::Error(sdk::codes::kBadConfig,
                       "config " + source + ": the document has more than " +
                           std::to_string(kMaxConfigNodes) +
                           " YAML nodes once its aliases are expanded (an alias counts as the "
                           "nodes it repeats); the limit for a config is " +
                           std::to_string(kMaxConfigNodes) + " nodes");
    todo.push_back(n);
  };
  while (!todo.empty()) {
    const YAML::Node n = todo.back();
    todo.pop_back();
    if (n.IsMap()) {
      for (const auto& kv : n) {
        add(kv.first);
        add(kv.second);
      }
    } else if (n.IsSequence()) {
      for (const auto& e : n) add(e);
    }
  }
}

namespace {
bool holds_null(const YAML::Node& n) {
  if (!n.IsMap()) return false;
  for (const auto& kv : n)
    if (kv.second.IsNull() || holds_null(kv.second)) return true;
  return false;
}
}  // namespace

YAML::Node without_nulls(const YAML::Node& n) {
  // A map without null values below it is returned as it is: copying it would re-register each
  // of its nodes with yaml-cpp's memory once per level of nesting.
  if (!holds_null(n)) return n;
  YAML::Node out(YAML::NodeType::Map);
  for (const auto& kv : n)
    if (!kv.second.IsNull()) out.force_insert(kv.first.Scalar(), without_nulls(kv.second));
  return out;
}

}  // namespace flipper::toolkit::config::yaml_bounds
