// `flipper serve` and `flipper dds`: their options, shared by flipper and flipper-frontends so both
// parse, help and fail alike; run_serve / run_dds_node differ (frontends.hpp).
#include "commands.hpp"
#include "common.hpp"

namespace flipper::cli {

// flipper serve [--config F] [--set k=v]: serve.host:serve.port until SIGINT/SIGTERM.
void add_serve_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "serve", "Serve the web page and the session protocol over HTTP (serve.host:serve.port)");
  static CommonOptions opts;
  add_common_options(*cmd, opts);
  on_run(*cmd, [] { return run_serve(opts); });
}

// flipper dds [--config F] [--set k=v]: answers rt/flipper/request on rt/flipper/answer, with the
// config's other DDS services (plans, lexicon replication), until SIGINT/SIGTERM.
void add_dds_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "dds", "Serve session-protocol requests over Cyclone DDS (rt/flipper/request -> answer)");
  static CommonOptions opts;
  add_common_options(*cmd, opts);
  on_run(*cmd, [] { return run_dds_node(opts); });
}

// flipper accounts add|passwd|list|remove|invite|revoke [NAME] [--config F] [--set k=v]: the
// accounts of `flipper serve` (docs/accounts.md). Passwords are read from standard input.
void add_accounts_command(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("accounts", "Manage the accounts of flipper serve (serve.accounts)");
  cmd->require_subcommand(1);
  static CommonOptions opts;
  static AccountsArgs args;
  const auto action = [&](const char* name, const char* help, bool takes_name) {
    auto* sub = cmd->add_subcommand(name, help);
    add_common_options(*sub, opts);
    if (takes_name) sub->add_option("name", args.name, "The account's name")->required();
    on_run(*sub, [name] {
      args.action = name;
      return run_accounts(opts, args);
    });
    return sub;
  };
  action("add", "Add an account (password from standard input; empty: codes only)", true)
      ->add_option("--role", args.role, "user, participant or admin")
      ->check(CLI::IsMember({"user", "participant", "admin"}));
  action("passwd", "Set an account's password (from standard input)", true);
  action("list", "List the accounts", false)->add_flag("--json", args.json, "JSON Lines");
  action("remove", "Remove an account (its rules keep its name, which stays taken)", true);
  auto* invite = action("invite", "Print a one-time login code (and link) for NAME", true);
  invite->add_option("--days", args.days, "Days the code is valid")->check(CLI::Range(1, 365));
  invite->add_option("--url", args.url, "The server's address, to print a link");
  invite->add_option("--role", args.role, "Role of the account when it is new")
      ->check(CLI::IsMember({"user", "participant", "admin"}));
  action("revoke", "End every login of NAME (the browser must log in again)", true);
}

}  // namespace flipper::cli
