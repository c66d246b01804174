// The dds front-end module (frontend_module.hpp): `flipper dds` (dds_run.cpp), `flipper dds
// security` (dds_security.cpp) and the DDS services of a `session` or `repl` whose config asks for
// them (dds_services.cpp).
#include "commands.hpp"
#include "common.hpp"
#include "dds_node_services.hpp"
#include "flipper/sdk/frontend.hpp"
#include "flipper/wiring/config_schema.hpp"
#include "frontend_module.hpp"

namespace flipper::cli {

int dds_node_main(const CommonOptions& opts);
int dds_security_main(const std::string& action, const DdsSecurityArgs& args);

namespace {

class DdsModule final : public sdk::Frontend {
 public:
  explicit DdsModule(const sdk::Params& /*params*/) {}
  /// Its settings are the config's dds.* keys (docs/config.md), not module parameters.
  static sdk::ParamSchema schema() { return {}; }

  int run(sdk::FrontendHost& host) override {
    // A module holds its own copy of the kernel's config code, so it installs the composed
    // schema too (docs/config.md "Who declares a key").
    wiring::install_config_schema();
    auto* call = static_cast<InTreeCall*>(host.internals(kInTreeTag));
    if (call == nullptr) refuse_foreign_host("dds");
    if (call->command == "dds security") return dds_security_main(call->action, *call->security);
    if (call->command == "dds services") {
      auto running = std::make_shared<NodeServices>(NodeServices::start(*call->host));
      const NodeServices* services = running.get();
      call->services->opener = [services](const wiring::SessionHost& h) {
        return services->open(h);
      };
      call->services->running = std::move(running);
      return kExitOk;
    }
    return dds_node_main(*call->opts);
  }
};

}  // namespace
}  // namespace flipper::cli

FLIPPER_FRONTEND(flipper::cli::DdsModule, "dds", FLIPPER_PLUGIN_VERSION,
                 "The session protocol over Cyclone DDS, DDS Security keystores, DDS services")
