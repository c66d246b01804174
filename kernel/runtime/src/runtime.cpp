// make_runtime: config -> loaded plugins, core grammar, default world. Everything a request
// needs is built here, once, before the first request (fail fast, as Nav2 and gz do).
#include "flipper/kernel/runtime.hpp"

#include <algorithm>
#include <atomic>
#include <filesystem>

#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/keys.hpp"
#include "flipper/kernel/limits.hpp"
#include "flipper/kernel/loader.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world_format.hpp"
#include "flipper/toolkit/config/regular_file.hpp"

namespace flipper::kernel {

namespace fs = std::filesystem;
using sdk::Error;
namespace codes = sdk::codes;

namespace {

// The world plugins whose sidecars say they read `dims`-D worlds (no code loaded). Only asked on
// an error path.
std::vector<std::string> world_plugins_of(const Config& config, int dims) {
  std::vector<std::string> names;
  const PluginLoader loader(PluginLoader::search_path_for(config));
  for (const auto& e : loader.entries())
    if (e.shadowed_by.empty() && e.index_error.empty() && e.kind == "world" && e.dims == dims)
      names.push_back(e.name);
  return names;
}

// A world of the other dimension (a 3-D world for a 2-D plugin, or the reverse): the plugin says
// so (sdk::OtherDimsError); name the plugins that read it.
[[noreturn]] void refuse_other_dims(const sdk::OtherDimsError& error, const Config& config,
                                    int dims) {
  const int other = error.world_dims();
  const auto plugins = world_plugins_of(config, other);
  std::string which;
  for (const auto& n : plugins) which += (which.empty() ? "" : " or ") + n;
  throw Error(
      codes::kBadWorld,
      "this is a " + std::to_string(other) + "-D world (its points have " + std::to_string(other) +
          " coordinates), but world plugin '" + config.plugin_name("world") + "' reads " +
          std::to_string(dims) + "-D worlds: " +
          (which.empty() ? "select a " + std::to_string(other) + "-D world plugin"
                         : "select " + which + " (--set world.plugin=" + plugins.front() + ")") +
          " (" + error.what() + ")");
}

// The plugin reads the world once, within the limits (docs/worlds.md § "Limits").
sdk::WorldState load_world(const PluginRef<sdk::World>& world, const Config& config,
                           const std::string& text, const std::string& base_dir) {
  const InputLimits input = InputLimits::from_config(config);
  const sdk::WorldLimits limits{input.max_world_cells, input.max_file_bytes};
  sdk::WorldState state;
  try {
    state = world.call("load", [&](const sdk::World& w) { return w.load(text, base_dir, limits); });
  } catch (const sdk::OtherDimsError& e) {
    if (e.world_dims() == 2 || e.world_dims() == 3)
      refuse_other_dims(e, config,
                        world.call("dims", [](const sdk::World& w) { return w.dims(); }));
    throw;
  }
  // A plugin is untrusted: what it built is checked against the limit as well.
  if (state.geometry) sdk::world_format::check_cells(state.geometry->cell_count(), limits);
  return state;
}

sdk::WorldState load_world_path(const PluginRef<sdk::World>& world, const Config& config,
                                const std::string& path_or_json) {
  const auto first = path_or_json.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && path_or_json[first] == '{')
    return load_world(world, config, path_or_json, fs::current_path().string());
  const std::string text = toolkit::config::read_regular_file(
      path_or_json, InputLimits::from_config(config).max_file_bytes, "world file",
      codes::kBadWorld);
  return load_world(world, config, text, fs::absolute(path_or_json).parent_path().string());
}

// A missing file named by a path key: the message names the resolved path and the rule that
// resolved it (a copied config otherwise fails with a puzzling "cannot read").
void require_file(const Config& config, const sdk::param::Path& key, const char* code,
                  const char* what) {
  const std::string path = config.get(key);
  std::error_code ec;
  // Existence only: what kind of file it is (regular, within the size limit) is checked when it
  // is read, with its own codes (not_a_regular_file, file_too_large).
  if (!fs::exists(path, ec))
    throw Error(code,
                std::string("no ") + what + " at '" + path + "' (" + config.path_origin(key) + ")");
}

// The grammar's direction words: the world's own (grid2d: up, down, left, right; octomap3d also
// ascend, descend), or the subset `grammar.directions` names. A word the world does not know is
// a config error now, not an execution error at the first `move`.
std::vector<std::string> direction_words(const Config& config, const std::string& world_name,
                                         const sdk::WorldState& world) {
  if (!world.geometry)
    throw Error(codes::kBadWorld,
                "world plugin '" + world_name + "' loaded a world without geometry");
  std::vector<std::string> known;
  for (const auto& [word, offset] : world.geometry->directions()) known.push_back(word);
  std::vector<std::string> chosen = config.get(keys::kGrammarDirections);
  if (chosen.empty()) return known;
  for (const auto& word : chosen)
    if (std::find(known.begin(), known.end(), word) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw Error(codes::kBadConfig, "grammar.directions names '" + word +
                                         "', which world plugin '" + world_name +
                                         "' does not know (its directions: " + list +
                                         "); leave grammar.directions empty to use the world's");
    }
  return chosen;
}

}  // namespace

namespace {
std::atomic<Isolation> g_auto_isolation{Isolation::in_process};
}  // namespace

void set_auto_isolation(Isolation isolation) {
  g_auto_isolation.store(isolation);
}

std::unique_ptr<Runtime> make_runtime(const Config& config) {
  const PluginLoader loader(PluginLoader::search_path_for(config));
  auto rt = std::make_unique<Runtime>(config);
  rt->world = loader.create<sdk::World>(config, "world");
  rt->planner = loader.create<sdk::Planner>(config, "planner");
  // docs/plugins-untrusted.md §6: plan, tour, parse (its scorer calls with it) and learn in a
  // child process each, when so configured.
  const keys::PluginIsolation setting = config.get(keys::kPluginIsolation);
  const Isolation isolation = setting == keys::PluginIsolation::automatic ? g_auto_isolation.load()
                              : setting == keys::PluginIsolation::process ? Isolation::process
                                                                          : Isolation::in_process;
  rt->planner = rt->planner.with_isolation(isolation);
  rt->parser = loader.create<sdk::Parser>(config, "parser").with_isolation(isolation);
  rt->scorer = loader.create<sdk::Scorer>(config, "scorer").with_isolation(isolation);
  if (config.has_section("rewriter"))
    rt->rewriter = loader.create<sdk::Rewriter>(config, "rewriter");
  if (config.has_section("similarity"))
    rt->similarity = loader.create<sdk::Similarity>(config, "similarity");

  const std::string world_name = config.plugin_name("world");
  const std::string planner_name = config.plugin_name("planner");
  const int dims = rt->world.call("dims", [](const sdk::World& w) { return w.dims(); });
  for (const auto& e : loader.entries())  // the sidecar's dims name this plugin in hints
    if (e.name == world_name && e.shadowed_by.empty() && e.dims != 0 && e.dims != dims)
      throw Error(codes::kPluginLoadFailed, "world plugin '" + world_name +
                                                "': its sidecar says dims " +
                                                std::to_string(e.dims) + " but it reads " +
                                                std::to_string(dims) + "-D worlds");
  const sdk::PlannerTraits traits =
      rt->planner.call("traits", [](const sdk::Planner& p) { return p.traits(); });
  if ((dims == 3 && !traits.supports_3d) || (dims == 2 && !traits.supports_2d))
    throw Error(codes::kBadConfig, "planner '" + planner_name + "' does not support the " +
                                       std::to_string(dims) + "-D worlds of world plugin '" +
                                       world_name + "'; choose a planner with " +
                                       (dims == 3 ? "supports_3d" : "supports_2d"));

  // The world first: its direction words are the grammar's (a world swap is one line).
  require_file(config, keys::kWorldFile, codes::kBadWorld, "world file");
  rt->default_world = load_world_path(rt->world, config, config.get(keys::kWorldFile));

  require_file(config, keys::kGrammarFile, codes::kBadGrammar, "grammar file");
  const std::string grammar_file = config.get(keys::kGrammarFile);
  toolkit::config::check_regular_file(grammar_file, InputLimits::from_config(config).max_file_bytes,
                                      "grammar file", codes::kBadGrammar);
  rt->core_grammar = std::make_shared<const sdk::Grammar>(sdk::load_grammar_file(
      config.get(keys::kGrammarFile), config.get(keys::kGrammarColors),
      config.get(keys::kGrammarShapes), direction_words(config, world_name, rt->default_world)));
  rt->parser.call("set_grammar", [&](sdk::Parser& p) { p.set_grammar(rt->core_grammar); });
  return rt;
}

sdk::WorldState load_world_file(const Runtime& rt, const std::string& path) {
  return load_world_path(rt.world, rt.config, path);
}

sdk::WorldState load_world_text(const Runtime& rt, const std::string& text,
                                const std::string& base_dir) {
  return load_world(rt.world, rt.config, text, base_dir);
}

}  // namespace flipper::kernel
