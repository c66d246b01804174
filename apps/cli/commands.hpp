#pragma once
// Subcommands of build/bin/flipper. Each lives in its own file and registers itself on the app;
// main.cpp only wires them. Every subcommand takes --config FILE and repeated --set key=value
// (see common.hpp). Exit status: 0 ok, 1 the work failed, 2 misuse or bad config.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace flipper::cli {
void add_plugins_command(CLI::App& app);   // plugins.cpp
void add_plugin_command(CLI::App& app);    // plugin_new.cpp (plugin new: scaffold a plugin)
void add_config_command(CLI::App& app);    // config.cpp   (config check)
void add_run_command(CLI::App& app);       // run.cpp
void add_session_command(CLI::App& app);   // session.cpp
void add_repl_command(CLI::App& app);      // repl.cpp
void add_replay_command(CLI::App& app);    // replay.cpp
void add_bench_command(CLI::App& app);     // bench.cpp    (bench planners)
void add_runs_command(CLI::App& app);      // runs.cpp     (runs list, runs show)
void add_lexicon_command(CLI::App& app);   // lexicon.cpp  (lexicon list|export|import)
void add_serve_command(CLI::App& app);     // frontend_commands.cpp (apps/studio: HTTP, web page)
void add_dds_command(CLI::App& app);       // frontend_commands.cpp (DDS node, dds security)
void add_accounts_command(CLI::App& app);  // frontend_commands.cpp (the studio's accounts)
void add_frontend_command(CLI::App& app);  // frontend_host.cpp (any front-end module)

struct CommonOptions;
/// `serve`, `dds`, `dds security` and `accounts` load their front-end module and run there
/// (frontend_host.cpp, frontend_module.hpp).
int run_serve(const CommonOptions& opts);
int run_dds_node(const CommonOptions& opts);

/// `flipper dds security init DIR` / `add DIR NAME [--namespace NS]...` (dds module,
/// dds_security.cpp).
struct DdsSecurityArgs {
  std::string dir;
  std::string name;
  std::vector<std::string> namespaces;
  std::string file;           ///< sign: the lab's CSR; install: the CA's outbox folder
  long days = 365;            ///< add, sign, renew: lifetime of the certificate and permissions
  std::string role = "site";  ///< add, sign: site, robot or operator (its permissions)
  std::string enclave;        ///< export: the SROS2 enclave name
};
int run_dds_security(const std::string& action, const DdsSecurityArgs& args);
/// `flipper accounts ACTION NAME`: the studio's accounts (docs/accounts.md); runs in the serve
/// module (accounts_run.cpp) beside the server that reads them.
struct AccountsArgs {
  std::string action;  ///< add, passwd, list, remove, invite, revoke
  std::string name;
  std::string role;   ///< "" : add makes a user, invite a participant
  int days = 7;       ///< invite: how long the code lasts
  std::string url;    ///< invite: the server's address, for the printed link
  bool json = false;  ///< list
};
int run_accounts(const CommonOptions& opts, const AccountsArgs& args);
}  // namespace flipper::cli
