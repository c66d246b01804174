#pragma once
// Options every subcommand shares, and the uniform error exit.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

namespace flipper::cli {

struct CommonOptions {
  std::string config_file;            ///< empty: the embedded default (configs/default.yaml)
  std::vector<std::string> overrides; ///< "key.path=value", applied after the file
};

/// Adds --config and --set to a subcommand.
inline void add_common_options(CLI::App& cmd, CommonOptions& opts) {
  cmd.add_option("--config", opts.config_file, "YAML config file (default: the embedded default)");
  cmd.add_option("--set", opts.overrides, "Override a config key: --set key.path=value (repeatable)")
      ->take_all()
      ->allow_extra_args(false);
}

/// Exit codes.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;
inline constexpr int kExitUsage = 2;

}  // namespace flipper::cli
