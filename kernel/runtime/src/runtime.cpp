// make_runtime: config -> loaded plugins, core grammar, default world. Everything a request
// needs is built here, once, before the first request (fail fast, as Nav2 and gz do).
#include "flipper/kernel/runtime.hpp"

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <optional>

#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/keys.hpp"
#include "flipper/kernel/limits.hpp"
#include "flipper/kernel/loader.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/sdk/world_format.hpp"

namespace flipper::kernel {

namespace fs = std::filesystem;
using sdk::Error;
namespace codes = sdk::codes;

namespace {

std::uint64_t cells_of(const sdk::Cell& lo, const sdk::Cell& hi) {
  auto extent = [](std::int64_t a, std::int64_t b) {
    return b < a ? std::uint64_t{0} : static_cast<std::uint64_t>(b - a) + 1;
  };
  return extent(lo.x, hi.x) * extent(lo.y, hi.y) * extent(lo.z, hi.z);
}

void refuse_large(std::uint64_t cells, std::uint64_t limit) {
  if (cells > limit)
    throw Error(codes::kWorldTooLarge,
                "the world has " + std::to_string(cells) +
                    " cells; the limit is world.max_cells = " + std::to_string(limit));
}

// The discoverable world plugins that read `dims`-D worlds (each instantiated with its default
// params; one that needs params of its own is left out). Only asked on an error path.
std::vector<std::string> world_plugins_of(const Config& config, int dims) {
  std::vector<std::string> names;
  const PluginLoader loader(PluginLoader::search_path_for(config));
  for (const auto& e : loader.entries()) {
    if (!e.shadowed_by.empty() || (!e.kind.empty() && e.kind != "world")) continue;
    try {
      const LoadedPlugin p = loader.open_entry(e, sdk::PluginKind::world);
      const auto object = loader.instantiate(p, sdk::validate_params(p.schema(), {}, ""));
      const auto* w = dynamic_cast<const sdk::World*>(object.get());
      if (w != nullptr && w->dims() == dims) names.push_back(e.name);
    } catch (const std::exception&) {  // a hint: plugins that do not load are not offered
    }
  }
  return names;
}

// A world of the other dimension (a 3-D world for a 2-D plugin, or the reverse) fails inside the
// plugin with a message about one point; say what is wrong instead, and which plugin reads it.
void refuse_other_dims(const Error& error, const Config& config, const std::string& text,
                       int dims) {
  if (error.code() != codes::kBadWorld) return;
  const int other = dims == 2 ? 3 : 2;
  try {
    sdk::world_format::parse_world(text, other);
  } catch (const std::exception&) {
    return;  // not a world of the other dimension either: the plugin's message stands
  }
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

sdk::WorldState load_world(const PluginRef<sdk::World>& world, const Config& config,
                           const std::string& text, const std::string& base_dir) {
  const InputLimits limits = InputLimits::from_config(config);
  // The shared part of the format gives the explicit or default bounds: a 110-byte world can
  // name a box of 16382^2 cells, which the plugin would allocate before anything else.
  // A world plugin with a format of its own may refuse what the shared reader cannot read: then
  // only the check after loading applies.
  const int dims = world.call("dims", [](const sdk::World& w) { return w.dims(); });
  std::optional<sdk::world_format::Bounds> box;
  try {
    box = sdk::world_format::effective_bounds(sdk::world_format::parse_world(text, dims));
  } catch (const Error&) {
  }
  if (box) refuse_large(cells_of(box->min, box->max), limits.max_world_cells);
  sdk::WorldState state;
  try {
    state = world.call("load", [&](const sdk::World& w) { return w.load(text, base_dir); });
  } catch (const Error& e) {
    refuse_other_dims(e, config, text, dims);
    throw;
  }
  // The plugin may grow the box (an octree's extent): check what it built as well.
  if (state.geometry) refuse_large(state.geometry->cell_count(), limits.max_world_cells);
  return state;
}

sdk::WorldState load_world_path(const PluginRef<sdk::World>& world, const Config& config,
                                const std::string& path_or_json) {
  const auto first = path_or_json.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && path_or_json[first] == '{')
    return load_world(world, config, path_or_json, fs::current_path().string());
  const std::string text =
      read_regular_file(path_or_json, InputLimits::from_config(config).max_file_bytes, "world file",
                        codes::kBadWorld);
  return load_world(world, config, text, fs::absolute(path_or_json).parent_path().string());
}

// A missing file named by a path key: the message names the resolved path and the rule that
// resolved it (a copied config otherwise fails with a puzzling "cannot read").
void require_file(const Config& config, const std::string& key, const char* code,
                  const char* what) {
  const std::string path = config.get_path(key);
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
  std::vector<std::string> chosen = config.get_string_list("grammar.directions");
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
  // docs/plugins-untrusted.md §6: plan and tour in a child process each, when so configured.
  const std::string isolation = config.get(keys::kPluginIsolation);
  rt->planner = rt->planner.with_isolation(isolation == "auto" ? g_auto_isolation.load()
                                                               : isolation_from_name(isolation));
  rt->parser = loader.create<sdk::Parser>(config, "parser");
  rt->scorer = loader.create<sdk::Scorer>(config, "scorer");
  if (config.has_section("rewriter"))
    rt->rewriter = loader.create<sdk::Rewriter>(config, "rewriter");
  if (config.has_section("similarity"))
    rt->similarity = loader.create<sdk::Similarity>(config, "similarity");

  const std::string world_name = config.plugin_name("world");
  const std::string planner_name = config.plugin_name("planner");
  const int dims = rt->world.call("dims", [](const sdk::World& w) { return w.dims(); });
  const sdk::PlannerTraits traits =
      rt->planner.call("traits", [](const sdk::Planner& p) { return p.traits(); });
  if ((dims == 3 && !traits.supports_3d) || (dims == 2 && !traits.supports_2d))
    throw Error(codes::kBadConfig, "planner '" + planner_name + "' does not support the " +
                                       std::to_string(dims) + "-D worlds of world plugin '" +
                                       world_name + "'; choose a planner with " +
                                       (dims == 3 ? "supports_3d" : "supports_2d"));

  // The world first: its direction words are the grammar's (a world swap is one line).
  require_file(config, "world.file", codes::kBadWorld, "world file");
  rt->default_world = load_world_path(rt->world, config, config.get_path("world.file"));

  require_file(config, "grammar.file", codes::kBadGrammar, "grammar file");
  const std::string grammar_file = config.get_path("grammar.file");
  check_regular_file(grammar_file, InputLimits::from_config(config).max_file_bytes, "grammar file",
                     codes::kBadGrammar);
  rt->core_grammar = std::make_shared<const sdk::Grammar>(sdk::load_grammar_file(
      config.get_path("grammar.file"), config.get_string_list("grammar.colors"),
      config.get_string_list("grammar.shapes"),
      direction_words(config, world_name, rt->default_world)));
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
