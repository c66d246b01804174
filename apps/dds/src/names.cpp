#include "flipper/dds/names.hpp"

#include <cctype>

#include "flipper/sdk/errors.hpp"

namespace flipper::dds {

std::string node_topic(const std::string& ns, const std::string& leaf) {
  return ns.empty() ? "rt/flipper/" + leaf : "rt/" + ns + "/flipper/" + leaf;
}

std::string action_prefix(const std::string& ns, const std::string& action) {
  return (ns.empty() ? "" : ns + "/") + action + "/_action/";
}

void check_namespace(const std::string& ns, const std::string& key) {
  constexpr std::size_t kMax = 64;
  bool ok = ns.size() <= kMax;
  for (std::size_t i = 0; ok && i < ns.size(); ++i) {
    const auto c = static_cast<unsigned char>(ns[i]);
    ok = std::isalpha(c) || c == '_' || (i > 0 && std::isdigit(c));
  }
  if (!ok)
    throw sdk::Error(sdk::codes::kBadConfig,
                     key + " '" + ns.substr(0, kMax) +
                         "' is not a ROS 2 name token (a letter or '_', then letters, digits or "
                         "'_', at most 64 characters)");
}

}  // namespace flipper::dds
