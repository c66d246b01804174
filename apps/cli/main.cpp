// build/bin/flipper: the command-line front door of the kernel.
#include <iostream>
#include <string>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/version.hpp"
#include "frontends.hpp"

namespace {

// "lexicon import": the subcommands parsed so far, for error messages.
std::string command_path(const CLI::App& app) {
  std::string path;
  for (const CLI::App* at = &app;;) {
    const auto subs = at->get_subcommands();
    if (subs.empty()) break;
    at = subs.front();
    path += (path.empty() ? "" : " ") + at->get_name();
  }
  return path;
}

std::string version_text() {
  return "flipper " FLIPPER_VERSION " (plugin SDK " + std::to_string(FLIPPER_SDK_VERSION_MAJOR) +
         "." + std::to_string(FLIPPER_SDK_VERSION_MINOR) + "." +
         std::to_string(FLIPPER_SDK_VERSION_PATCH) + ")";
}

}  // namespace

int main(int argc, char** argv) {
  flipper::cli::enter(argc, argv);
  CLI::App app{"Flipper: precise but natural specifications for robot tasks"};
  app.set_version_flag("--version", version_text(), "Print the version and exit");
  app.require_subcommand(1);
  flipper::cli::add_plugins_command(app);
  flipper::cli::add_config_command(app);
  flipper::cli::add_run_command(app);
  flipper::cli::add_session_command(app);
  flipper::cli::add_repl_command(app);
  flipper::cli::add_replay_command(app);
  flipper::cli::add_lexicon_command(app);
  flipper::cli::add_serve_command(app);
  flipper::cli::add_dds_command(app);
  flipper::cli::add_accounts_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and version exit 0 with CLI11's own output; CLI misuse exits with status 2.
    if (e.get_exit_code() == 0) return app.exit(e);
    std::string message = e.what();
    if (message.empty()) message = e.get_name();
    flipper::cli::report_error(command_path(app), "usage", message + " (see --help)", 2);
    return 2;
  } catch (const flipper::sdk::Error& e) {
    return flipper::cli::report_error(command_path(app), e.code(), e.what(),
                                      flipper::cli::status_for(e.code()));
  } catch (const std::exception& e) {
    return flipper::cli::report_error(command_path(app), "internal", e.what(), 1);
  }
  return 0;
}
