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

}  // namespace flipper::cli
