#pragma once
// Options every subcommand shares, loading the config they name, and the uniform exit.
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/sdk/stop.hpp"
#include "flipper/wiring/config_schema.hpp"

namespace flipper::cli {

struct CommonOptions {
  std::string config_file;             ///< empty: the embedded default (configs/default.yaml)
  std::vector<std::string> overrides;  ///< "key.path=value", applied after the file
};

/// Adds --config and --set to a subcommand.
inline void add_common_options(CLI::App& cmd, CommonOptions& opts) {
  cmd.add_option("--config", opts.config_file, "YAML config file (default: the embedded default)");
  cmd.add_option("--set", opts.overrides,
                 "Override a config key: --set key.path=value (repeatable)")
      ->take_all()
      ->allow_extra_args(false);
}

/// The --config file, or nothing for the embedded default.
inline std::optional<std::string> config_file(const CommonOptions& opts) {
  if (opts.config_file.empty()) return std::nullopt;
  return opts.config_file;
}

/// The validated config the options name (throws sdk::Error(bad_config)).
inline kernel::Config load_config(const CommonOptions& opts) {
  return wiring::load_config(config_file(opts), opts.overrides);
}

/// Exit codes.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;
inline constexpr int kExitUsage = 2;

/// Whether the command line asked for --json: then every outcome, errors included, is one JSON
/// object on standard output (main sets it before parsing, so usage errors obey it too).
inline bool& json_output() {
  static bool on = false;
  return on;
}

/// The one error format of every subcommand: `flipper <cmd>: [code] message` on stderr, or with
/// --json `{"ok":false,"command":CMD,"error":{"code","message"}}` on stdout and nothing on stderr;
/// a deadline_exceeded error also has `stopped` ("cpu_budget" | "wall_backstop", docs/protocol.md).
/// Returns `status` so callers can `return report_error(...)`.
/// `more`: members the JSON object also carries (`run`'s "repair"); the text form has none.
inline int report_error(const std::string& cmd, const std::string& code, const std::string& message,
                        int status, sdk::StopCause stopped = sdk::StopCause::none,
                        const nlohmann::json& more = nlohmann::json::object()) {
  if (json_output()) {
    nlohmann::json error{{"code", code}, {"message", message}};
    if (stopped != sdk::StopCause::none) error["stopped"] = sdk::to_string(stopped);
    nlohmann::json out{{"ok", false}, {"command", cmd}, {"error", error}};
    out.update(more);
    std::cout << out.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n"
              << std::flush;
    return status;
  }
  std::cerr << "flipper" << (cmd.empty() ? "" : " " + cmd) << ": [" << code << "] " << message
            << "\n";
  return status;
}

/// Exit status for a kernel error code: problems of the caller's config, request or plugins are
/// misuse (2); anything else means the work itself failed (1).
inline int status_for(const std::string& code) {
  return code == "bad_config" || code == "bad_request" || code == "bad_grammar" ||
                 code == "bad_world" || code.rfind("plugin_", 0) == 0
             ? kExitUsage
             : kExitFailed;
}

/// Runs `action`; an sdk::Error it throws is reported as subcommand `cmd` (report_error) with its
/// code's exit status (status_for).
inline int reporting_errors(const char* cmd, const std::function<int()>& action) {
  try {
    return action();
  } catch (const sdk::Error& e) {
    return report_error(cmd, e.code(), e.what(), status_for(e.code()));
  }
}

/// Makes `action` the subcommand's callback; a non-zero status ends the process with exactly that
/// status (a CLI::RuntimeError would reach main's handler, which maps every failure to 2).
inline void on_run(CLI::App& cmd, std::function<int()> action) {
  cmd.callback([action = std::move(action)] {
    if (const int rc = action(); rc != kExitOk) std::exit(rc);
  });
}

}  // namespace flipper::cli
