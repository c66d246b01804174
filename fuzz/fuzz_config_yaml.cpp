// Fuzz target: config YAML and --set values (kernel/config), then each selected plugin's params
// validated against the schema the real plugin declares (as the loader does before construction).
// Input: the YAML file, optionally followed by a line `%%` and one `--set` assignment per line.
// Oracle: loading either throws sdk::Error (bad_config, or plugin_* for unknown plugin names) or
// gives a config whose typed keys, dump and plugin params can all be read.
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/keys.hpp"
#include "flipper/kernel/loader.hpp"
#include "flipper/language/keys.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/wiring/config_schema.hpp"
#include "support/fuzz_support.hpp"

namespace fz = flipper::fuzz;
namespace sdk = flipper::sdk;
using flipper::kernel::Config;
using flipper::kernel::LoadedPlugin;
using flipper::kernel::PluginLoader;

namespace {

std::unique_ptr<PluginLoader> g_loader;
std::map<std::string, LoadedPlugin> g_opened;  // "kind/name" -> plugin (loaded once)

const LoadedPlugin& open_plugin(const std::string& section, const std::string& name) {
  const std::string key = section + "/" + name;
  auto it = g_opened.find(key);
  if (it == g_opened.end()) {
    sdk::PluginKind kind{};
    if (!sdk::parse_kind(section.c_str(), kind)) std::abort();  // sections are plugin kinds
    it = g_opened.emplace(key, g_loader->open(name, kind)).first;
  }
  return it->second;
}

void read_everything(Config& config) {
  namespace keys = flipper::kernel::keys;
  namespace exec = flipper::language::keys;
  (void)config.dump();
  for (const auto* key :
       {&exec::kActionBudget, &exec::kStepBudget, &exec::kExecCpuBudgetMs, &exec::kExecDeadlineMs,
        &exec::kWhileLimit, &keys::kMaxChars, &keys::kSessionK})
    (void)config.get(*key);
  (void)config.get(keys::kGrammarColors);
  (void)config.get(keys::kGrammarShapes);
  (void)config.get(keys::kGrammarDirections);
  (void)config.get(keys::kGrammarFile);
  (void)config.get(flipper::naturalization::keys::kLexiconPath);
  for (const std::string& section : Config::plugin_sections()) {
    if (!config.has_section(section)) continue;
    const LoadedPlugin& plugin = open_plugin(section, config.plugin_name(section));
    (void)config.plugin_params(section, plugin.schema());
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  flipper::wiring::install_config_schema();  // the product's keys, as `flipper` loads them
  g_loader =
      std::make_unique<PluginLoader>(PluginLoader::search_path_for(Config::embedded_default()));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto parts = fz::split_sections(fz::as_text(data, size), "%%", 2);
  const std::string file = fz::scratch_dir() + "/config.yaml";
  fz::write_file(file, parts[0]);
  std::vector<std::string> overrides;
  if (parts.size() > 1)
    for (std::string_view line : fz::split_lines(parts[1], 8))
      if (!line.empty()) overrides.emplace_back(line);
  try {
    Config config = Config::load(file, overrides);
    read_everything(config);
  } catch (const sdk::Error&) {
    // the documented outcome for a bad config or an unknown plugin
  }
  return 0;
}
