// build/bin/flipper: the command-line front door of the kernel.
#include <algorithm>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/sdk/version.hpp"

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

// `flipper runn`: CLI11 would say "A subcommand is required"; name the unknown command and the
// closest one instead (only within a typo's distance, see sdk::did_you_mean).
std::optional<std::string> unknown_command(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return std::nullopt;
  const std::string word = argv[1];
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  if (std::find(names.begin(), names.end(), word) != names.end()) return std::nullopt;
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return "unknown command '" + word + "'" + flipper::sdk::did_you_mean(word, names) +
         "; the commands are " + list + " (see --help)";
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc && std::string(argv[i]) != "--"; ++i)
    if (std::string(argv[i]) == "--json") flipper::cli::json_output() = true;
  CLI::App app{"Flipper: precise but natural specifications for robot tasks"};
  app.set_version_flag("--version", version_text(), "Print the version and exit");
  app.require_subcommand(1);
  flipper::cli::add_plugins_command(app);
  flipper::cli::add_plugin_command(app);
  flipper::cli::add_config_command(app);
  flipper::cli::add_run_command(app);
  flipper::cli::add_session_command(app);
  flipper::cli::add_repl_command(app);
  flipper::cli::add_replay_command(app);
  flipper::cli::add_bench_command(app);
  flipper::cli::add_runs_command(app);
  flipper::cli::add_lexicon_command(app);
  flipper::cli::add_serve_command(app);
  flipper::cli::add_dds_command(app);
  flipper::cli::add_accounts_command(app);
  flipper::cli::add_frontend_command(app);
  if (const auto unknown = unknown_command(app, argc, argv))
    return flipper::cli::report_error("", "usage", *unknown, 2);
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
