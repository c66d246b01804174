// `flipper serve`, `flipper dds` and `flipper accounts`: their options, parsed by flipper before
// their front-end module is loaded (frontend_host.cpp), so misuse never loads it.
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

// flipper dds [--config F] [--set k=v]: answers rt/<ns>/flipper/request on .../answer, with the
// config's other DDS services (plans, lexicon replication), until SIGINT/SIGTERM.
// flipper dds security init DIR | add DIR NAME [--namespace NS]... [--days N] | request DIR NAME
// | sign DIR CSR [--namespace NS]... [--days N] | renew DIR NAME [--days N] | revoke DIR NAME |
// install DIR NAME FROM | export DIR NAME KEYSTORE --enclave E: the DDS Security keystore
// (apps/dds/keystore.hpp, lab_keys.hpp).
void add_dds_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "dds",
      "Serve session-protocol requests over Cyclone DDS (rt/<ns>/flipper/request -> answer)");
  static CommonOptions opts;
  add_common_options(*cmd, opts);
  auto* security = cmd->add_subcommand(
      "security", "Make the DDS Security keystore: a project CA, identities, permissions");
  security->require_subcommand(1);
  static CommonOptions init_opts, add_opts, request_opts, sign_opts, renew_opts, install_opts,
      revoke_opts, export_opts;
  static DdsSecurityArgs init_args, add_args, request_args, sign_args, renew_args, install_args,
      revoke_args, export_args;
  const auto role = [](CLI::App& sub, DdsSecurityArgs& args) {
    sub.add_option("--role", args.role,
                   "site (lexicon, its namespaces), robot (its namespaces) or operator (requests "
                   "to the namespaces; default every robot)")
        ->check(CLI::IsMember({"site", "robot", "operator"}));
  };
  const auto days = [](CLI::App& sub, DdsSecurityArgs& args) {
    sub.add_option("--days", args.days,
                   "Days the certificate and permissions are valid (default 365)")
        ->check(CLI::Range(1, 3650));
  };
  auto* init = security->add_subcommand(
      "init", "Create a keystore: the project CA and the signed governance document");
  add_common_options(*init, init_opts);
  init->add_option("dir", init_args.dir, "The keystore folder (created)")->required();
  on_run(*init, [] { return run_dds_security("init", init_args); });
  auto* add = security->add_subcommand(
      "add", "Add a site's or robot's identity: certificate (CN=NAME), key, signed permissions");
  add_common_options(*add, add_opts);
  add->add_option("dir", add_args.dir, "The keystore folder (from init)")->required();
  add->add_option("name", add_args.name, "The identity: a site's lexicon.site or a robot's name")
      ->required();
  add->add_option(
      "--namespace", add_args.namespaces,
      "A dds.namespace this identity may serve, or operate (repeatable; default: NAME)");
  days(*add, add_args);
  role(*add, add_args);
  on_run(*add, [] { return run_dds_security("add", add_args); });
  // A lab that keeps its key (docs/ros2.md, "Labs that keep their keys").
  auto* request = security->add_subcommand(
      "request", "At a lab: make identity NAME's key (kept here) and a signing request for the CA");
  add_common_options(*request, request_opts);
  request->add_option("dir", request_args.dir, "The lab's keystore folder (created)")->required();
  request->add_option("name", request_args.name, "The identity: the lab's lexicon.site")
      ->required();
  on_run(*request, [] { return run_dds_security("request", request_args); });
  auto* sign = security->add_subcommand(
      "sign", "At the CA: check a lab's request, issue its certificate and signed permissions");
  add_common_options(*sign, sign_opts);
  sign->add_option("dir", sign_args.dir, "The CA's keystore folder (from init)")->required();
  sign->add_option("csr", sign_args.file, "The lab's request (NAME.csr)")->required();
  sign->add_option(
      "--namespace", sign_args.namespaces,
      "A dds.namespace this identity may serve, or operate (repeatable; default: NAME)");
  days(*sign, sign_args);
  role(*sign, sign_args);
  on_run(*sign, [] { return run_dds_security("sign", sign_args); });
  auto* renew = security->add_subcommand(
      "renew", "At the CA: a new certificate and permissions for identity NAME's same key");
  add_common_options(*renew, renew_opts);
  renew->add_option("dir", renew_args.dir, "The CA's keystore folder")->required();
  renew->add_option("name", renew_args.name, "The identity")->required();
  days(*renew, renew_args);
  on_run(*renew, [] { return run_dds_security("renew", renew_args); });
  auto* revoke = security->add_subcommand(
      "revoke", "At the CA: revoke identity NAME's certificates (the CA's crl.pem)");
  add_common_options(*revoke, revoke_opts);
  revoke->add_option("dir", revoke_args.dir, "The CA's keystore folder")->required();
  revoke->add_option("name", revoke_args.name, "The identity")->required();
  on_run(*revoke, [] { return run_dds_security("revoke", revoke_args); });
  auto* install = security->add_subcommand(
      "install", "At a lab: check and install what the CA sent (its outbox/NAME folder)");
  add_common_options(*install, install_opts);
  install->add_option("dir", install_args.dir, "The lab's keystore folder (from request)")
      ->required();
  install->add_option("name", install_args.name, "The identity")->required();
  install->add_option("from", install_args.file, "The folder the CA sent")->required();
  on_run(*install, [] { return run_dds_security("install", install_args); });
  // For ROS 2 nodes (docs/ros2.md, "SROS2 keystores").
  auto* exported = security->add_subcommand(
      "export",
      "Write identity NAME as an SROS2 enclave of a ROS 2 keystore (ROS_SECURITY_KEYSTORE)");
  add_common_options(*exported, export_opts);
  exported->add_option("dir", export_args.dir, "The keystore folder holding NAME's key")
      ->required();
  exported->add_option("name", export_args.name, "The identity")->required();
  exported->add_option("keystore", export_args.file, "The SROS2 keystore folder (created)")
      ->required();
  exported->add_option("--enclave", export_args.enclave, "The enclave's name, e.g. /lab1/flipper")
      ->required();
  on_run(*exported, [] { return run_dds_security("export", export_args); });
  on_run(*cmd, [cmd] {
    if (!cmd->get_subcommands().empty()) return kExitOk;  // `dds security ...` ran instead
    return run_dds_node(opts);
  });
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
  action("passwd", "Set an account's password (from standard input); ends its logins", true);
  action("role", "Set an account's role; ends its logins", true)
      ->add_option("--role", args.role, "user, participant or admin")
      ->required()
      ->check(CLI::IsMember({"user", "participant", "admin"}));
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
