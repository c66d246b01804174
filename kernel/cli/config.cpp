// flipper config check [FILE]: validates the config (kernel keys and every plugin's params),
// instantiates all plugins, loads grammar and default world, then prints the effective config.
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::cli {

void add_config_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("config", "Inspect and check configurations");
  cmd->require_subcommand(1);
  auto* check = cmd->add_subcommand("check", "Validate a config and instantiate its plugins");
  static CommonOptions opts;
  static std::string positional;
  add_common_options(*check, opts);
  check->add_option("file", positional, "Config file (same as --config)");
  check->callback([] {
    if (!positional.empty() && !opts.config_file.empty() && positional != opts.config_file)
      throw CLI::ValidationError("config check", "give the config file once (FILE or --config)");
    const std::string file = positional.empty() ? opts.config_file : positional;
    try {
      const auto config = kernel::Config::load(
          file.empty() ? std::nullopt : std::optional<std::string>(file), opts.overrides);
      const auto runtime = kernel::make_runtime(config);
      std::cout << "config ok: " << config.source() << "\n" << config.dump();
    } catch (const sdk::Error& e) {
      // Any problem found while checking is a config problem for the caller: exit 2.
      std::cerr << "flipper: error [" << e.code() << "]: " << e.what() << "\n";
      throw CLI::RuntimeError(kExitUsage);
    }
  });
}

}  // namespace flipper::cli
