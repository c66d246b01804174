// flipper config check [FILE] [--json]: validates the config (kernel keys and every plugin's
// params), instantiates all plugins, loads grammar and default world, then prints the effective
// config (YAML, or one JSON object with --json).
// flipper config print [FILE]: the effective config, kernel keys validated, no plugin loaded.
// flipper config explain [KEY|SECTION] [--markdown]: the kernel's keys as declared (type,
// default, allowed values, description), from the schema that validates them; --markdown prints
// the table docs/config.md carries.
#include <yaml-cpp/yaml.h>

#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/param_check.hpp"
#include "schema_text.hpp"

namespace flipper::cli {
namespace {

// YAML as JSON: maps and lists as they are; scalars that read as bool or number become those.
nlohmann::json to_json(const YAML::Node& node) {
  if (node.IsMap()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& kv : node) out[kv.first.Scalar()] = to_json(kv.second);
    return out;
  }
  if (node.IsSequence()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& e : node) out.push_back(to_json(e));
    return out;
  }
  if (!node.IsScalar()) return nullptr;
  const std::string& text = node.Scalar();
  if (node.Tag() != "!") {  // unquoted
    bool b = false;
    std::int64_t i = 0;
    double d = 0;
    if (text == "true" || text == "false") return YAML::convert<bool>::decode(node, b) && b;
    if (YAML::convert<std::int64_t>::decode(node, i)) return i;
    if (YAML::convert<double>::decode(node, d)) return d;
  }
  return text;
}

struct CheckArgs {
  CommonOptions opts;
  std::string positional;
  bool json = false;
};

std::optional<std::string> file_of(const CheckArgs& a);

int check(const CheckArgs& a) {
  try {
    const auto config = kernel::Config::load(file_of(a), a.opts.overrides);
    const auto runtime = kernel::make_runtime(config);
    if (a.json)
      std::cout << nlohmann::json{{"ok", true},
                                  {"source", config.source()},
                                  {"config", to_json(YAML::Load(config.dump()))}}
                       .dump(2)
                << "\n";
    else
      std::cout << "config ok: " << config.source() << "\n" << config.dump();
    return kExitOk;
  } catch (const sdk::Error& e) {
    // Any problem found while checking is a config problem for the caller: exit 2.
    if (a.json)
      std::cout << nlohmann::json{{"ok", false},
                                  {"error", {{"code", e.code()}, {"message", e.what()}}}}
                       .dump(2)
                << "\n";
    return report_error("config check", e.code(), e.what(), kExitUsage);
  }
}

std::optional<std::string> file_of(const CheckArgs& a) {
  const std::string file = a.positional.empty() ? a.opts.config_file : a.positional;
  return file.empty() ? std::nullopt : std::optional<std::string>(file);
}

int print(const CheckArgs& a) {
  try {
    std::cout << kernel::Config::load(file_of(a), a.opts.overrides).dump();
    return kExitOk;
  } catch (const sdk::Error& e) {
    return report_error("config print", e.code(), e.what(), kExitUsage);
  }
}

struct ExplainArgs {
  std::string key;
  bool markdown = false;
};

int explain(const ExplainArgs& a) {
  const sdk::ParamSchema& schema = kernel::Config::schema();
  if (a.markdown) {
    std::cout << markdown_table(schema);
    return kExitOk;
  }
  const auto specs = specs_under(schema, a.key);
  if (specs.empty()) {
    std::vector<std::string> names;
    for (const auto& p : schema.params) names.push_back(p.name);
    for (const auto& s : schema.sections) names.push_back(s.name);
    return report_error("config explain", "bad_config",
                        "no config key or section '" + a.key + "'" +
                            sdk::did_you_mean(a.key, names) +
                            " (flipper config explain lists them all)",
                        kExitUsage);
  }
  if (const sdk::ParamSection* s = schema.find_section(a.key))
    std::cout << s->name << ": " << s->description << (s->optional ? " (optional)" : "") << "\n";
  std::cout << text_table(specs, "KEY", "");
  return kExitOk;
}

}  // namespace

void add_config_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("config", "Inspect and check configurations");
  cmd->require_subcommand(1);
  auto* check_cmd = cmd->add_subcommand("check", "Validate a config and instantiate its plugins");
  static CheckArgs args;
  add_common_options(*check_cmd, args.opts);
  check_cmd->add_option("file", args.positional, "Config file (same as --config)");
  check_cmd->add_flag("--json", args.json, "Print the effective config as one JSON object");
  on_run(*check_cmd, [] {
    if (!args.positional.empty() && !args.opts.config_file.empty() &&
        args.positional != args.opts.config_file)
      return report_error("config check", "usage", "give the config file once (FILE or --config)",
                          kExitUsage);
    return check(args);
  });

  auto* print_cmd =
      cmd->add_subcommand("print", "Print the effective config (kernel keys checked, no plugins)");
  static CheckArgs print_args;
  add_common_options(*print_cmd, print_args.opts);
  print_cmd->add_option("file", print_args.positional, "Config file (same as --config)");
  on_run(*print_cmd, [] { return print(print_args); });

  auto* explain_cmd =
      cmd->add_subcommand("explain", "Describe the kernel's config keys (type, default, range)");
  static ExplainArgs explain_args;
  explain_cmd->add_option("key", explain_args.key, "A key or section (default: all)");
  explain_cmd->add_flag("--markdown", explain_args.markdown,
                        "The Markdown table of docs/config.md");
  on_run(*explain_cmd, [] { return explain(explain_args); });
}

}  // namespace flipper::cli
