// make_runtime: config -> loaded plugins, core grammar, default world. Everything a request
// needs is built here, once, before the first request (fail fast, as Nav2 and gz do).
#include "flipper/kernel/runtime.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "flipper/kernel/loader.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::kernel {

namespace fs = std::filesystem;
using sdk::Error;
namespace codes = sdk::codes;

namespace {

// Runs a plugin call; sdk::Errors keep their code (a world plugin's bad_world), anything else
// becomes plugin_error naming the plugin.
template <class F>
auto guarded(const std::string& who, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(codes::kPluginError, "plugin '" + who + "': " + e.what());
  } catch (...) {
    throw Error(codes::kPluginError, "plugin '" + who + "': unknown exception");
  }
}

std::string read_file(const std::string& path, const char* code, const char* what) {
  std::ifstream in(path);
  if (!in) throw Error(code, std::string("cannot read ") + what + " '" + path + "'");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

sdk::WorldState load_world(const sdk::World& world, const std::string& who,
                           const std::string& path_or_json) {
  std::string text = path_or_json;
  std::string base_dir = fs::current_path().string();
  const auto first = path_or_json.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || path_or_json[first] != '{') {
    text = read_file(path_or_json, codes::kBadWorld, "world file");
    base_dir = fs::absolute(path_or_json).parent_path().string();
  }
  return guarded(who, [&] { return world.load(text, base_dir); });
}

// A missing file named by a path key: the message names the resolved path and the rule that
// resolved it (a copied config otherwise fails with a puzzling "cannot read").
void require_file(const Config& config, const std::string& key, const char* code,
                  const char* what) {
  const std::string path = config.get_path(key);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw Error(code, std::string("no ") + what + " at '" + path + "' (" +
                          config.path_origin(key) + ")");
}

}  // namespace

std::unique_ptr<Runtime> make_runtime(const Config& config) {
  const PluginLoader loader(PluginLoader::search_path_for(config));
  auto rt = std::unique_ptr<Runtime>(new Runtime{config, {}, {}, {}, {}, {}, {}, {}, {}});
  rt->world = loader.create<sdk::World>(config, "world");
  rt->planner = loader.create<sdk::Planner>(config, "planner");
  rt->parser = loader.create<sdk::Parser>(config, "parser");
  rt->scorer = loader.create<sdk::Scorer>(config, "scorer");
  if (config.has_section("rewriter"))
    rt->rewriter = loader.create<sdk::Rewriter>(config, "rewriter");
  if (config.has_section("similarity"))
    rt->similarity = loader.create<sdk::Similarity>(config, "similarity");

  const std::string world_name = config.plugin_name("world");
  const std::string planner_name = config.plugin_name("planner");
  const int dims = guarded(world_name, [&] { return rt->world->dims(); });
  const sdk::PlannerTraits traits = guarded(planner_name, [&] { return rt->planner->traits(); });
  if ((dims == 3 && !traits.supports_3d) || (dims == 2 && !traits.supports_2d))
    throw Error(codes::kBadConfig, "planner '" + planner_name + "' does not support the " +
                                       std::to_string(dims) + "-D worlds of world plugin '" +
                                       world_name + "'; choose a planner with " +
                                       (dims == 3 ? "supports_3d" : "supports_2d"));

  require_file(config, "grammar.file", codes::kBadGrammar, "grammar file");
  rt->core_grammar = std::make_shared<const sdk::Grammar>(sdk::load_grammar_file(
      config.get_path("grammar.file"), config.get_string_list("grammar.colors"),
      config.get_string_list("grammar.shapes"), config.get_string_list("grammar.directions")));
  guarded(config.plugin_name("parser"), [&] { rt->parser->set_grammar(rt->core_grammar); });

  require_file(config, "world.file", codes::kBadWorld, "world file");
  rt->default_world = load_world(*rt->world, world_name, config.get_path("world.file"));
  return rt;
}

sdk::WorldState load_world_file(const Runtime& rt, const std::string& path) {
  return load_world(*rt.world, rt.config.plugin_name("world"), path);
}

}  // namespace flipper::kernel
