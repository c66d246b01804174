// flipper repl: the interactive terminal front end (apps/repl), a client of the session ops.
#include <unistd.h>

#include <iostream>

#include "commands.hpp"
#include "common.hpp"
#include "dds_services.hpp"
#include "flipper/repl/repl.hpp"
#include "flipper/wiring/session_factory.hpp"

namespace flipper::cli {
void add_repl_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("repl", "Interactive terminal: give tasks, choose plans, teach");
  static CommonOptions opts;
  add_common_options(*cmd, opts);
  on_run(*cmd, [] {
    wiring::SessionHost host = wiring::open_host(config_file(opts), opts.overrides);
    const DdsServices dds = DdsServices::start(host);  // publish.plans, lexicon.replication
    auto session = dds.open(host);
    // Readline only on a terminal; piped input is read line by line without prompts.
    bool terminal = isatty(STDIN_FILENO) != 0;
    auto reader = repl::make_line_reader(std::cin, terminal,
                                         terminal ? repl::default_history_file() : std::string());
    return repl::run(*session, *reader, std::cout);
  });
}
}  // namespace flipper::cli
