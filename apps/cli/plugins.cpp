// flipper plugins: the plugin index as a table (name, kind, version, ABI, path, status). Each
// library is actually opened and checked so the status is real; a bad plugin shows its error
// instead of crashing the listing. '*' marks the plugins the config selects.
// `flipper plugins --params` adds every plugin's declared parameters (name, type, default,
// allowed values, description) — what a config's `<section>.params` may hold; `flipper plugins
// NAME` prints only NAME's.
#include <array>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/loader.hpp"
#include "flipper/sdk/param_check.hpp"
#include "schema_text.hpp"

namespace flipper::cli {
namespace {

struct Row {
  std::string mark, name, kind, version, abi, path, status;
};

void print_table(const std::vector<Row>& rows) {
  std::size_t w[5] = {4, 4, 7, 3, 4};
  for (const auto& r : rows) {
    w[0] = std::max(w[0], r.name.size());
    w[1] = std::max(w[1], r.kind.size());
    w[2] = std::max(w[2], r.version.size());
    w[3] = std::max(w[3], r.abi.size());
    w[4] = std::max(w[4], r.path.size());
  }
  const auto line = [&](const Row& r) {
    std::cout << std::left << std::setw(2) << r.mark << std::setw(static_cast<int>(w[0] + 2))
              << r.name << std::setw(static_cast<int>(w[1] + 2)) << r.kind
              << std::setw(static_cast<int>(w[2] + 2)) << r.version
              << std::setw(static_cast<int>(w[3] + 2)) << r.abi
              << std::setw(static_cast<int>(w[4] + 2)) << r.path << r.status << "\n";
  };
  line({"", "NAME", "KIND", "VERSION", "ABI", "PATH", "STATUS"});
  for (const auto& r : rows) line(r);
}

void print_params(const kernel::LoadedPlugin& p) {
  const auto* d = p.descriptor;
  std::cout << "\n"
            << d->name << " (" << sdk::kind_name(static_cast<sdk::PluginKind>(d->kind)) << " "
            << (d->version ? d->version : "?") << ")"
            << (d->description && *d->description ? std::string(": ") + d->description : "")
            << "\n";
  const sdk::ParamSchema schema = p.schema();
  if (schema.params.empty()) {
    std::cout << "  (no parameters)\n";
    return;
  }
  TableOptions table;
  table.width = terminal_width();
  std::cout << text_table(specs_under(schema, ""), "PARAM", "  ", table);
}

// The parameter schemas of every loadable plugin, or of `only`; exit 2 when `only` is unknown
// or does not load.
int list_params(const kernel::PluginLoader& loader, const std::string& only) {
  bool found = false, ok = true;
  for (const auto& e : loader.entries()) {
    if (!e.shadowed_by.empty() || (!only.empty() && e.name != only)) continue;
    found = true;
    try {
      print_params(loader.open_entry(e, std::nullopt));
    } catch (const sdk::Error& err) {
      if (!only.empty()) {
        report_error("plugins", err.code(), "plugin '" + only + "': " + err.what(), kExitUsage);
        ok = false;
      }
    }
  }
  if (!only.empty() && !found) {
    std::vector<std::string> names;
    for (const auto& e : loader.entries()) names.push_back(e.name);
    return report_error("plugins", "plugin_not_found",
                        "no plugin named '" + only + "'" + sdk::did_you_mean(only, names),
                        kExitUsage);
  }
  return ok ? kExitOk : kExitUsage;
}

// One plugin's parameters as JSON: name, type, default (null when none), required, allowed,
// description.
nlohmann::json params_json(const kernel::LoadedPlugin& p) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : p.schema().params)
    out.push_back({{"name", s.name},
                   {"type", sdk::to_string(s.type)},
                   {"default", s.default_value ? nlohmann::json(sdk::to_string(*s.default_value))
                                               : nlohmann::json(nullptr)},
                   {"required", s.required},
                   {"allowed", allowed_text(s)},
                   {"description", s.description}});
  return out;
}

int list_plugins(const CommonOptions& opts, bool params, const std::string& only, bool json) {
  const auto config = load_config(opts);
  const kernel::PluginLoader loader(kernel::PluginLoader::search_path_for(config));
  if (!only.empty() && !json) return list_params(loader, only);
  std::vector<Row> rows;
  nlohmann::json schemas = nlohmann::json::object();
  bool selected_ok = true;
  for (const auto& e : loader.entries()) {
    Row r{
        "",        e.name, e.kind.empty() ? "?" : e.kind, e.version.empty() ? "?" : e.version, "?",
        e.library, "ok"};
    for (const auto& section : kernel::Config::plugin_sections())
      if (config.has_section(section) && config.plugin_name(section) == e.name &&
          e.shadowed_by.empty() && (e.kind.empty() || e.kind == section))
        r.mark = "*";
    if (!e.shadowed_by.empty()) {
      r.status = "shadowed by " + e.shadowed_by;
    } else {
      try {
        const kernel::LoadedPlugin p = loader.open_entry(e, std::nullopt);
        r.kind = sdk::kind_name(static_cast<sdk::PluginKind>(p.descriptor->kind));
        r.version = p.descriptor->version ? p.descriptor->version : "?";
        r.abi = std::to_string(p.descriptor->abi) + " (sdk " +
                std::to_string(p.descriptor->sdk_major) + "." +
                std::to_string(p.descriptor->sdk_minor) + ")";
        if (json && (params || e.name == only)) schemas[e.name] = params_json(p);
        (void)p.schema();
      } catch (const sdk::Error& err) {
        r.status = "error [" + err.code() + "]: " + err.what();
        if (!r.mark.empty()) selected_ok = false;
      }
    }
    rows.push_back(std::move(r));
  }
  // A selected plugin that is missing altogether is reported like any config error (with
  // --json: in the listing's "errors", so that stdout stays one JSON object).
  nlohmann::json errors = nlohmann::json::array();
  for (const auto& section : kernel::Config::plugin_sections()) {
    if (!config.has_section(section)) continue;
    const std::string name = config.plugin_name(section);
    bool present = false;
    for (const auto& r : rows) present = present || (r.mark == "*" && r.name == name);
    if (!present) {
      const std::string message = "selected " + section + " plugin '" + name + "' was not found";
      if (json)
        errors.push_back({{"code", "plugin_not_found"}, {"message", message}});
      else
        report_error("plugins", "plugin_not_found", message, kExitUsage);
      selected_ok = false;
    }
  }
  if (json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& r : rows) {
      if (!only.empty() && r.name != only) continue;
      nlohmann::json j{{"selected", r.mark == "*"}, {"name", r.name}, {"kind", r.kind},
                       {"version", r.version},      {"abi", r.abi},   {"path", r.path},
                       {"status", r.status}};
      if (schemas.contains(r.name)) j["params"] = schemas[r.name];
      list.push_back(std::move(j));
    }
    if (!only.empty() && list.empty())
      return report_error("plugins", "plugin_not_found", "no plugin named '" + only + "'",
                          kExitUsage);
    std::cout << nlohmann::json{{"ok", selected_ok},
                                {"config", config.source()},
                                {"search_path", loader.search_path()},
                                {"plugins", std::move(list)},
                                {"errors", std::move(errors)}}
                     .dump(2)
              << "\n";
    return selected_ok ? kExitOk : kExitUsage;
  }
  std::cout << "config: " << config.source() << "\nsearch path:";
  for (const auto& d : loader.search_path()) std::cout << " " << d;
  std::cout << "\n";
  print_table(rows);
  if (params && list_params(loader, "") != kExitOk) selected_ok = false;
  return selected_ok ? kExitOk : kExitUsage;
}

}  // namespace

void add_plugins_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("plugins", "List discovered plugins and whether they load");
  static CommonOptions opts;
  static bool params = false;
  static std::string only;
  static bool json = false;
  add_common_options(*cmd, opts);
  cmd->add_flag("--params", params, "Also print each plugin's parameters (name, type, default...)");
  cmd->add_flag("--json", json, "Print the listing as one JSON object");
  cmd->add_option("name", only, "Print only this plugin's parameters");
  on_run(*cmd, [] {
    try {
      return list_plugins(opts, params, only, json);
    } catch (const sdk::Error& e) {
      return report_error("plugins", e.code(), e.what(), status_for(e.code()));
    }
  });
}

}  // namespace flipper::cli
