// build/bin/flipper: the command-line front door of the kernel.
#include <iostream>

#include "commands.hpp"
#include "flipper/sdk/errors.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Flipper: precise but natural specifications for robot tasks"};
  app.require_subcommand(1);
  flipper::cli::add_plugins_command(app);
  flipper::cli::add_config_command(app);
  flipper::cli::add_run_command(app);
  flipper::cli::add_session_command(app);
  flipper::cli::add_repl_command(app);
  flipper::cli::add_replay_command(app);
  flipper::cli::add_lexicon_command(app);
  flipper::cli::add_serve_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI misuse exits with status 2 (help and version requests exit 0).
    int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  } catch (const flipper::sdk::Error& e) {
    std::cerr << "flipper: error [" << e.code() << "]: " << e.what() << "\n";
    return e.code() == "bad_config" || e.code().rfind("plugin_", 0) == 0 ? 2 : 1;
  } catch (const std::exception& e) {
    std::cerr << "flipper: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
