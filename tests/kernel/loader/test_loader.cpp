// Loader: discovery, checks and lifetime with the tiny test plugins, and every deliberately
// broken plugin in tests/sdk/kits/bad refused with the exact code and the file named.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include "flipper/kernel/loader.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/sdk/planner.hpp"
#include "kernel/kernel_test_support.hpp"

using namespace flipper;
using kernel::PluginLoader;
using kerneltest::require_error;

namespace {
PluginLoader test_loader() {
  return PluginLoader({kerneltest::good_dir(), kerneltest::bad_dir()});
}
}  // namespace

TEST_CASE("the index finds sidecars without loading code", "[loader]") {
  const PluginLoader loader = test_loader();
  REQUIRE(loader.search_path().size() == 2);
  bool planner = false, dup_one = false;
  for (const auto& e : loader.entries()) {
    if (e.name == "test_planner") {
      planner = true;
      CHECK(e.kind == "planner");
      CHECK(e.version == "1.0.0");
      CHECK(e.library == kerneltest::good_dir() + "/test_planner.so");
    }
    if (e.library == kerneltest::bad_dir() + "/dup_one.so") {
      dup_one = true;
      CHECK(e.name == "dup");
      CHECK(e.duplicate_of == kerneltest::bad_dir() + "/dup_two.so");
    }
  }
  CHECK(planner);
  CHECK(dup_one);
}

TEST_CASE("a world plugin's sidecar says the dims it reads, any other value is an index error",
          "[loader][world]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(FLIPPER_BINARY_DIR) / "tests/tmp/world_dims";
  fs::create_directories(dir);
  fs::copy_file(fs::path(kerneltest::good_dir()) / "test_world.so", dir / "test_world.so",
                fs::copy_options::overwrite_existing);
  const std::vector<std::pair<std::string, std::string>> sidecars = {
      {"w_none", ""}, {"w_two", "dims: 2\n"}, {"w_three", "dims: 3\n"}, {"w_four", "dims: 4\n"}};
  for (const auto& [name, dims] : sidecars) {
    std::ofstream(dir / (name + ".flipper.yaml"))
        << "name: " << name << "\nkind: world\nlibrary: test_world.so\n"
        << dims;
  }
  std::map<std::string, kernel::PluginEntry> found;
  const PluginLoader loader({dir.string()});
  for (const auto& e : loader.entries()) found[e.name] = e;
  CHECK(found.at("w_none").dims == 0);
  CHECK(found.at("w_two").dims == 2);
  CHECK(found.at("w_three").dims == 3);
  CHECK(found.at("w_three").index_error.empty());
  CHECK(found.at("w_four").index_error ==
        "sidecar '" + (dir / "w_four.flipper.yaml").string() +
            "' says dims 4 (world plugins read 2- or 3-D worlds)");
  // The in-tree world plugins declare theirs (flipper_add_plugin DIMS).
  std::map<std::string, int> built;
  const PluginLoader in_tree({FLIPPER_PLUGIN_DIR});
  for (const auto& e : in_tree.entries())
    if (e.kind == "world") built[e.name] = e.dims;
  CHECK(built.at("grid2d") == 2);
  CHECK(built.at("ros_map") == 2);
  CHECK(built.at("octomap3d") == 3);
}

TEST_CASE("a plugin is created with validated params and keeps its library loaded", "[loader]") {
  std::shared_ptr<sdk::Planner> planner;
  {
    const auto config = kerneltest::test_config();
    const PluginLoader loader(PluginLoader::search_path_for(config));
    planner = loader.create<sdk::Planner>(config, "planner").shared();
  }  // loader and config gone: the object alone keeps the code mapped
  REQUIRE(planner != nullptr);
  const sdk::Geometry g(2, {0, 0, 0}, {0, 0, 0}, {1}, {}, {});
  const sdk::Area goals{{0, 0, 0}};
  const auto r = planner->plan(g, {{0, 0, 0}, &goals, nullptr}, sdk::StopCondition{});
  CHECK(r.message == "fancy|" + kerneltest::data_dir() + "/planner.dat");
}

TEST_CASE("unknown plugin params are refused before construction", "[loader]") {
  const auto config = kerneltest::test_config({"planner.params.mdoe=plain"});
  const PluginLoader loader(PluginLoader::search_path_for(config));
  require_error([&] { (void)loader.create<sdk::Planner>(config, "planner"); }, "bad_config",
                {"planner.params.mdoe", "did you mean 'planner.params.mode'"});
}

TEST_CASE("search path: plugin_paths, then FLIPPER_PLUGIN_PATH, then beside the executable",
          "[loader]") {
  ::setenv("FLIPPER_PLUGIN_PATH", "/env/one::/env/two", 1);
  const auto path = PluginLoader::search_path_for(kerneltest::test_config());
  ::unsetenv("FLIPPER_PLUGIN_PATH");
  REQUIRE(path.size() == 5);
  CHECK(path[0] == kerneltest::good_dir());
  CHECK(path[1] == kerneltest::bad_dir());
  CHECK(path[2] == "/env/one");
  CHECK(path[3] == "/env/two");
  CHECK(path[4] == std::string(FLIPPER_BINARY_DIR) + "/lib/flipper/plugins");  // <exe>/../lib/...
  // The build tree mirrors the install layout: that directory is the build's plugin dir.
  CHECK(std::filesystem::canonical(path[4]) == std::filesystem::canonical(FLIPPER_PLUGIN_DIR));
}

TEST_CASE("an earlier directory shadows a same-named plugin in a later one", "[loader]") {
  namespace fs = std::filesystem;
  const fs::path first = fs::path(FLIPPER_BINARY_DIR) / "tests/tmp/shadow";
  fs::create_directories(first);
  for (const char* f : {"test_planner.so", "test_planner.flipper.yaml"})
    fs::copy_file(fs::path(kerneltest::good_dir()) / f, first / f,
                  fs::copy_options::overwrite_existing);
  const PluginLoader loader({first.string(), kerneltest::good_dir()});
  const auto p = loader.open("test_planner", sdk::PluginKind::planner);
  CHECK(p.entry.library == (first / "test_planner.so").string());
  bool shadowed = false;
  for (const auto& e : loader.entries())
    if (e.library == kerneltest::good_dir() + "/test_planner.so")
      shadowed = e.shadowed_by == (first / "test_planner.so").string();
  CHECK(shadowed);
}

namespace {
struct BadPlugin {
  const char* name;
  sdk::PluginKind kind;
  const char* code;
  std::vector<std::string> words;
};
}  // namespace

TEST_CASE("broken plugins are refused cleanly, naming file and values", "[loader][bad]") {
  const std::string bad = kerneltest::bad_dir();
  const std::vector<BadPlugin> cases = {
      {"no_such_plugin",
       sdk::PluginKind::planner,
       "plugin_not_found",
       {"no planner plugin named 'no_such_plugin'", "available planner plugins:", "test_planner"}},
      {"test_planner",
       sdk::PluginKind::world,
       "plugin_not_found",
       {"is a planner plugin, not a world plugin", "available world plugins: test_world"}},
      {"bad_abi",
       sdk::PluginKind::planner,
       "plugin_abi_mismatch",
       {"Wrong API version on plugin 'bad_abi' (" + bad + "/bad_abi.so).",
        "Got version 4, supported version is 3."}},
      {"bad_size",
       sdk::PluginKind::planner,
       "plugin_abi_mismatch",
       {"Wrong descriptor layout on plugin 'bad_size'", bad + "/bad_size.so", "supported size is"}},
      {"bad_sdk_major",
       sdk::PluginKind::planner,
       "plugin_abi_mismatch",
       {"Wrong SDK version on plugin 'bad_sdk_major'", "Got version 4.",  // 4.<the SDK minor>
        "supported version is 3."}},
      {"bad_sdk_minor",
       sdk::PluginKind::planner,
       "plugin_abi_mismatch",
       {"Wrong SDK version", "Got version 3.99"}},
      {"bad_fingerprint",
       sdk::PluginKind::planner,
       "plugin_abi_mismatch",
       {"Wrong build fingerprint", "bad_fingerprint.so", "cxx11abi=0",
        "supported is 'abi=3;libstdc++;cxx11abi=1;ptrsize=8'"}},
      {"no_descriptor",
       sdk::PluginKind::planner,
       "plugin_load_failed",
       {"no Flipper descriptor", bad + "/no_descriptor.so"}},
      {"dup",
       sdk::PluginKind::planner,
       "plugin_duplicate",
       {"'dup'", bad + "/dup_one.so", bad + "/dup_two.so"}},
      {"wrong_kind",
       sdk::PluginKind::world,
       "plugin_load_failed",
       {"wrong_kind.so", "is a planner plugin, but it was requested as a world plugin"}},
      {"misnamed",
       sdk::PluginKind::planner,
       "plugin_load_failed",
       {"descriptor name 'other_name'", "misnamed.flipper.yaml"}},
  };
  const PluginLoader loader = test_loader();
  for (const auto& c : cases) {
    SECTION(c.name) {
      require_error([&] { (void)loader.open(c.name, c.kind); }, c.code, c.words);
    }
  }
  SECTION("throwing constructor") {
    const auto p = loader.open("throwing", sdk::PluginKind::planner);
    require_error(
        [&] { (void)loader.instantiate(p, sdk::validate_params(p.schema(), {}, "")); },
        "plugin_error",
        {"plugin 'throwing' (" + bad + "/throwing.so): create: cannot open the planner database"});
  }
}

TEST_CASE("opening every indexed file never crashes the kernel", "[loader][bad]") {
  const PluginLoader loader = test_loader();
  int ok = 0, refused = 0;
  for (const auto& e : loader.entries()) {
    try {
      (void)loader.open_entry(e, std::nullopt);
      ++ok;
    } catch (const sdk::Error&) {
      ++refused;
    }
  }
  CHECK(ok == 5);        // four test plugins and throwing.so (which fails only when created)
  CHECK(refused == 10);  // every other bad plugin, dup_one and dup_two each
}
