// flipper plugins: the plugin index as a table (name, kind, version, ABI, path, status). Each
// library is actually opened and checked so the status is real; a bad plugin shows its error
// instead of crashing the listing. '*' marks the plugins the config selects.
#include <iomanip>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/loader.hpp"

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

int list_plugins(const CommonOptions& opts) {
  const auto config = kernel::Config::load(
      opts.config_file.empty() ? std::nullopt : std::optional<std::string>(opts.config_file),
      opts.overrides);
  const kernel::PluginLoader loader(kernel::PluginLoader::search_path_for(config));
  std::vector<Row> rows;
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
        (void)p.schema();
      } catch (const sdk::Error& err) {
        r.status = "error [" + err.code() + "]: " + err.what();
        if (!r.mark.empty()) selected_ok = false;
      }
    }
    rows.push_back(std::move(r));
  }
  std::cout << "config: " << config.source() << "\nsearch path:";
  for (const auto& d : loader.search_path()) std::cout << " " << d;
  std::cout << "\n";
  print_table(rows);
  // A selected plugin that is missing altogether is reported like any config error.
  for (const auto& section : kernel::Config::plugin_sections()) {
    if (!config.has_section(section)) continue;
    const std::string name = config.plugin_name(section);
    bool present = false;
    for (const auto& r : rows) present = present || (r.mark == "*" && r.name == name);
    if (!present) {
      std::cerr << "flipper: selected " << section << " plugin '" << name << "' was not found\n";
      selected_ok = false;
    }
  }
  return selected_ok ? kExitOk : kExitUsage;
}

}  // namespace

void add_plugins_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("plugins", "List discovered plugins and whether they load");
  static CommonOptions opts;
  add_common_options(*cmd, opts);
  cmd->callback([] {
    const int rc = list_plugins(opts);
    if (rc != kExitOk) throw CLI::RuntimeError(rc);
  });
}

}  // namespace flipper::cli
