#include "flipper/wiring/yaml_file.hpp"

#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/config/regular_file.hpp"
#include "flipper/toolkit/config/yaml_bounds.hpp"

namespace flipper::wiring {

YAML::Node load_bounded_yaml_file(const std::string& path, const std::string& what) {
  const std::string failed = "cannot read " + what + " '" + path + "': ";
  try {
    const std::string text = toolkit::config::read_regular_file(
        path, toolkit::config::yaml_bounds::kMaxConfigBytes, what, sdk::codes::kBadConfig);
    YAML::Node root = YAML::Load(text);
    // Before anything walks the tree: an alias bomb loads at once and expands when walked.
    toolkit::config::yaml_bounds::check_expanded_size(root, what + " '" + path + "'");
    return root;
  } catch (const YAML::Exception& e) {
    throw sdk::Error(sdk::codes::kBadConfig, failed + e.what());
  } catch (const sdk::Error& e) {  // its message names the file already
    throw sdk::Error(sdk::codes::kBadConfig, e.what());
  }
}

}  // namespace flipper::wiring
