// The host's composition of the config schema (docs/config.md "Who declares a key").
#include "flipper/wiring/config_schema.hpp"

#include <mutex>

#include "flipper/dds/config_keys.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/config_handles.hpp"
#include "flipper/studio/config_keys.hpp"

namespace flipper::wiring {

sdk::ParamSchema config_schema() {
  const sdk::ParamSchema naturalization = naturalization::keys::config_schema();
  const sdk::ParamSchema studio = studio::keys::config_schema();
  const sdk::ParamSchema dds = dds::keys::config_schema();
  return sdk::param::compose({&kernel::Config::kernel_schema(), &naturalization, &studio, &dds});
}

void install_config_schema() {
  static std::once_flag once;
  std::call_once(once, [] { kernel::Config::install_schema(config_schema()); });
}

kernel::Config load_config(const std::optional<std::string>& file,
                           const std::vector<std::string>& overrides) {
  install_config_schema();
  kernel::Config config = kernel::Config::load(file, overrides);
  naturalization::apply_weights_switch(config);  // lexicon.weights: the scorer's per_user
  return config;
}

}  // namespace flipper::wiring
