// flipper replay: placeholder until its module lands (owner replaces this file).
#include <iostream>

#include "commands.hpp"
#include "common.hpp"

namespace flipper::cli {
void add_replay_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("replay", "(not available yet)");
  static CommonOptions opts;
  add_common_options(*cmd, opts);
  cmd->callback([] {
    std::cerr << "flipper replay: not available in this build yet\n";
    std::exit(2);
  });
}
}  // namespace flipper::cli
