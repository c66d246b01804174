// The serve front-end module (frontend_module.hpp): `flipper serve` (serve_run.cpp) and
// `flipper accounts` (accounts_run.cpp), which manages the accounts the server reads.
#include "commands.hpp"
#include "common.hpp"
#include "flipper/sdk/frontend.hpp"
#include "flipper/wiring/config_schema.hpp"
#include "frontend_module.hpp"

namespace flipper::cli {

int serve_main(const CommonOptions& opts);
int accounts_main(const CommonOptions& opts, const AccountsArgs& args);

namespace {

class ServeModule final : public sdk::Frontend {
 public:
  explicit ServeModule(const sdk::Params& /*params*/) {}
  /// Its settings are the config's serve.* keys (docs/config.md), not module parameters.
  static sdk::ParamSchema schema() { return {}; }

  int run(sdk::FrontendHost& host) override {
    // A module holds its own copy of the kernel's config code, so it installs the composed
    // schema too (docs/config.md "Who declares a key").
    wiring::install_config_schema();
    auto* call = static_cast<InTreeCall*>(host.internals(kInTreeTag));
    if (call == nullptr) refuse_foreign_host("serve");
    if (call->command == "accounts") return accounts_main(*call->opts, *call->accounts);
    return serve_main(*call->opts);
  }
};

}  // namespace
}  // namespace flipper::cli

FLIPPER_FRONTEND(flipper::cli::ServeModule, "serve", FLIPPER_PLUGIN_VERSION,
                 "Flipper Studio: the web page and the session protocol over HTTP")
