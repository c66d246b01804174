// flipper config check [FILE] [--json]: validates the config (kernel keys and every plugin's
// params), instantiates all plugins, loads grammar and default world, then prints the effective
// config (YAML, or one JSON object with --json).
// flipper config print [FILE]: the effective config, kernel keys validated, no plugin loaded.
// flipper config explain [KEY|SECTION] [--markdown]: the kernel's keys as declared (type,
// default, allowed values, description), from the schema that validates them, then the params of
// the plugins the config selects, as each plugin declares them; --markdown prints the table
// docs/config.md carries (kernel keys only: plugin params depend on the config).
#include <yaml-cpp/yaml.h>

#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/loader.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/wiring/config_schema.hpp"
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
    const auto config = wiring::load_config(file_of(a), a.opts.overrides);
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
    // Any problem found while checking is a config problem for the caller: exit 2 (with --json
    // report_error prints the JSON object).
    return report_error("config check", e.code(), e.what(), kExitUsage);
  }
}

std::optional<std::string> file_of(const CheckArgs& a) {
  const std::string file = a.positional.empty() ? a.opts.config_file : a.positional;
  return file.empty() ? std::nullopt : std::optional<std::string>(file);
}

int print(const CheckArgs& a) {
  try {
    std::cout << wiring::load_config(file_of(a), a.opts.overrides).dump();
    return kExitOk;
  } catch (const sdk::Error& e) {
    return report_error("config print", e.code(), e.what(), kExitUsage);
  }
}

struct ExplainArgs {
  CommonOptions opts;
  std::string key;
  bool markdown = false;
};

// The params of the plugin a section selects, as `flipper plugins NAME` declares them.
struct PluginParams {
  std::string section, plugin, heading;
  sdk::ParamSchema schema;
  std::string error;  ///< set when the plugin does not load: its schema is unknown
};

std::vector<PluginParams> selected_plugin_params(const kernel::Config& config) {
  std::vector<PluginParams> out;
  const kernel::PluginLoader loader(kernel::PluginLoader::search_path_for(config));
  for (const auto& section : kernel::Config::plugin_sections()) {
    if (!config.has_section(section)) continue;
    PluginParams p;
    p.section = section;
    p.plugin = config.plugin_name(section);
    try {
      const kernel::PluginEntry* entry = nullptr;
      for (const auto& e : loader.entries())
        if (e.name == p.plugin && e.shadowed_by.empty()) entry = &e;
      if (entry == nullptr) throw sdk::Error("plugin_not_found", "not found on the search path");
      const kernel::LoadedPlugin loaded = loader.open_entry(*entry, std::nullopt);
      p.schema = loaded.schema();
      const auto* d = loaded.descriptor;
      p.heading = section + ".params: plugin " + p.plugin + " " + (d->version ? d->version : "?") +
                  (d->description && *d->description ? std::string(", ") + d->description : "");
    } catch (const sdk::Error& e) {
      p.heading = section + ".params: plugin " + p.plugin;
      p.error = e.what();
    }
    out.push_back(std::move(p));
  }
  return out;
}

// `config explain [KEY]`: the kernel's keys under KEY, then the params of the selected plugins
// under it (`planner`, `planner.params`, `planner.params.heuristic`, or everything).
int explain(const ExplainArgs& a) {
  wiring::install_config_schema();
  const sdk::ParamSchema& schema = kernel::Config::schema();
  if (a.markdown) {
    std::cout << markdown_table(schema);
    return kExitOk;
  }
  std::optional<kernel::Config> config;
  try {
    config = load_config(a.opts);
  } catch (const sdk::Error& e) {
    return report_error("config explain", e.code(), e.what(), kExitUsage);
  }
  TableOptions table;
  table.schema = &schema;
  table.width = terminal_width();
  std::string text;
  std::vector<std::string> names;  // every key and section explain knows, for the hint
  const auto kernel_specs = specs_under(schema, a.key);
  for (const auto& p : schema.params) names.push_back(p.name);
  for (const auto& s : schema.sections) names.push_back(s.name);
  if (const sdk::ParamSection* s = schema.find_section(a.key))
    text += s->name + ": " + s->description + (s->optional ? " (optional)" : "") + "\n";
  if (!kernel_specs.empty()) text += text_table(kernel_specs, "KEY", "", table);
  for (const auto& p : selected_plugin_params(*config)) {
    const std::string prefix = p.section + ".params.";
    for (const auto& spec : p.schema.params) names.push_back(prefix + spec.name);
    // KEY selects this plugin's params when it is the section, its params, or one param.
    const bool all = a.key.empty() || a.key == p.section || a.key == p.section + ".params";
    const std::string param = a.key.rfind(prefix, 0) == 0 ? a.key.substr(prefix.size()) : "";
    const auto specs = all ? specs_under(p.schema, "") : specs_under(p.schema, param);
    if (!all && (param.empty() || specs.empty())) continue;
    const auto heading = wrap_words(p.heading, table.width > 2 ? table.width - 2 : table.width);
    text += "\n";
    for (std::size_t i = 0; i < heading.size(); ++i) text += (i ? "  " : "") + heading[i] + "\n";
    if (!p.error.empty()) {
      text += "  (its params are unknown: " + p.error + ")\n";
      continue;
    }
    if (specs.empty()) {
      text += "  (no parameters)\n";
      continue;
    }
    TableOptions params = table;
    params.schema = &p.schema;
    params.name_prefix = prefix;
    text += text_table(specs, "KEY", "  ", params);
  }
  if (text.empty())
    return report_error("config explain", "bad_config",
                        "no config key or section '" + a.key + "'" +
                            sdk::did_you_mean(a.key, names) +
                            " (flipper config explain lists them all)",
                        kExitUsage);
  std::cout << text;
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

  auto* explain_cmd = cmd->add_subcommand(
      "explain",
      "Describe the config keys and the selected plugins' params (type, default, range)");
  static ExplainArgs explain_args;
  add_common_options(*explain_cmd, explain_args.opts);
  explain_cmd->add_option("key", explain_args.key,
                          "A key, section or plugin param such as planner.params.heuristic "
                          "(default: all, with the selected plugins' params)");
  explain_cmd->add_flag("--markdown", explain_args.markdown,
                        "The Markdown table of docs/config.md");
  on_run(*explain_cmd, [] { return explain(explain_args); });
}

}  // namespace flipper::cli
