// Config: the embedded default, schema defaults, --set, dump, paths, and table-driven bad
// configs asserting the exact code and the key words of each message.
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <functional>

#include "flipper/dds/config_keys.hpp"
#include "flipper/kernel/limits.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "flipper/studio/config_keys.hpp"

#include "kernel/kernel_test_support.hpp"

using namespace flipper;
using kernel::Config;
using kerneltest::require_error;

TEST_CASE("embedded default config has the documented values", "[config]") {
  const Config c = Config::embedded_default();
  CHECK(c.source() == "<embedded default>");
  CHECK(c.plugin_name("world") == "grid2d");
  CHECK(c.plugin_name("planner") == "astar");
  CHECK(c.plugin_name("parser") == "chart");
  CHECK(c.plugin_name("scorer") == "loglinear");
  CHECK(c.plugin_name("rewriter") == "rewrites");
  CHECK(c.plugin_name("similarity") == "wordnet");
  CHECK(c.get_path("world.file") ==
        std::string(FLIPPER_SOURCE_DIR) + "/configs/worlds/study2018.json");
  CHECK(c.get_path("grammar.file") ==
        std::string(FLIPPER_SOURCE_DIR) + "/configs/grammars/core.grammar");
  CHECK(c.get_string_list("grammar.colors").size() == 9);
  CHECK(c.get_string_list("grammar.shapes") ==
        std::vector<std::string>{"triangle", "circle", "square"});
  CHECK(c.get_string_list("grammar.directions").empty());  // the world plugin's words
  CHECK(c.get_string("lexicon.sharing") == "shared");
  CHECK(c.get_string("lexicon.weights") == "global");
  CHECK(c.get_string("lexicon.preload").empty());
  CHECK(c.get_path("lexicon.path") ==
        std::string(std::getenv("HOME")) + "/.local/share/flipper/lexicon.sqlite");
  CHECK(c.get_bool("induction.alignment"));
  CHECK(c.get_bool("induction.generalize"));
  CHECK(c.get_int("induction.perturbed_checks") == 0);
  CHECK(c.get_int("execution.action_budget") == 100000);
  CHECK(c.get_int("execution.step_budget") == 1000000);
  CHECK(c.get_int("execution.cpu_budget_ms") == 2000);
  CHECK(c.get_int("execution.deadline_ms") == 300000);
  CHECK(c.get_int("session.cpu_budget_ms") == 5000);
  CHECK(c.get_int("session.deadline_ms") == 600000);
  CHECK(c.get_int("execution.while_limit") == 20);
  CHECK(c.get_int("input.max_chars") == 2000);
  CHECK(c.get_int("input.max_semicolons") == 30);
  CHECK(c.get_int("session.k") == 3);
  CHECK(c.get_string_list("plugin_paths").empty());
}

TEST_CASE("the embedded default is configs/default.yaml", "[config]") {
  const Config file = Config::load(std::string(FLIPPER_SOURCE_DIR) + "/configs/default.yaml", {});
  CHECK(file.dump() == Config::embedded_default().dump());
  CHECK(file.base_dir() == std::string(FLIPPER_SOURCE_DIR) + "/configs");
}

TEST_CASE("a small file gets schema defaults, optional sections stay absent", "[config]") {
  const auto path = kerneltest::write_temp("small.yaml", "session: {k: 5}\n");
  const Config c = Config::load(path, {});
  CHECK(c.get_int("session.k") == 5);
  CHECK(c.get_int("execution.while_limit") == 20);
  CHECK(c.plugin_name("planner") == "astar");
  CHECK_FALSE(c.has_section("rewriter"));
  CHECK_FALSE(c.has_section("similarity"));
  CHECK(c.resolve_path("worlds/x.json") ==
        (std::filesystem::path(path).parent_path() / "worlds/x.json").string());
}

TEST_CASE("overrides (--set) apply after the file and are validated the same way", "[config]") {
  const auto path = kerneltest::write_temp("set.yaml", "session: {k: 5}\n");
  const Config c = Config::load(path, {"session.k=7", "plugin_paths=[a, /b]",
                                       "planner.params.heuristic=manhattan", "rewriter.plugin=rw"});
  CHECK(c.get_int("session.k") == 7);
  CHECK(c.get_string_list("plugin_paths") == std::vector<std::string>{"a", "/b"});
  CHECK(c.get_string("planner.params.heuristic") == "manhattan");
  CHECK(c.plugin_name("rewriter") == "rw");
  const Config removed = Config::load(std::nullopt, {"rewriter=null", "session.k=~"});
  CHECK_FALSE(removed.has_section("rewriter"));
  CHECK(removed.get_int("session.k") == 3);  // null restores the default

  Config later = Config::embedded_default();
  later.set("execution.while_limit=5");
  CHECK(later.get_int("execution.while_limit") == 5);
  require_error([&] { later.set("execution.while_limit=-1"); }, "bad_config",
                {"execution.while_limit", "out of range"});
  CHECK(later.get_int("execution.while_limit") == 5);  // a failed set changes nothing
}

TEST_CASE("dump is the effective config and loads back to itself", "[config]") {
  const Config c = Config::load(std::nullopt, {"session.k=9"});
  const std::string text = c.dump();
  CHECK(text.find("k: 9") != std::string::npos);
  CHECK(text.find("action_budget: 100000") != std::string::npos);
  const auto path = kerneltest::write_temp("dumped.yaml", text);
  CHECK(Config::load(path, {}).dump() == text);
}

namespace {
struct BadCase {
  const char* what;
  const char* file_text;  // null: embedded default
  std::vector<std::string> overrides;
  std::vector<std::string> words;
};
}  // namespace

TEST_CASE("bad configs are refused with bad_config and a precise message", "[config]") {
  const std::vector<BadCase> cases = {
      {"unknown top-level key",
       "planer: {plugin: astar}\n",
       {},
       {"unknown config key 'planer'", "did you mean 'planner'"}},
      {"unknown nested key",
       "execution: {action_budgt: 5}\n",
       {},
       {"unknown config key 'execution.action_budgt'", "did you mean 'execution.action_budget'"}},
      {"unknown key without a close match",
       "lexicon: {colour_scheme: 1}\n",
       {},
       {"unknown config key 'lexicon.colour_scheme'"}},
      {"wrong type (int)",
       "execution: {action_budget: lots}\n",
       {},
       {"execution.action_budget", "must be an integer", "'lots'"}},
      {"wrong type (bool)",
       "induction: {alignment: maybe}\n",
       {},
       {"induction.alignment", "boolean"}},
      {"wrong type (list)", "grammar: {colors: red}\n", {}, {"grammar.colors", "list of strings"}},
      {"section is not a map", "world: grid2d\n", {}, {"'world' must be a map"}},
      {"out of range", "session: {k: 0}\n", {}, {"session.k", "out of range", "[1, 1000]"}},
      {"bad enum",
       "lexicon: {sharing: public}\n",
       {},
       {"lexicon.sharing", "'public'", "shared, private, core"}},
      {"bad enum with hint",
       "lexicon: {weights: per-user}\n",
       {},
       {"lexicon.weights", "did you mean 'per_user'"}},
      {"optional section without plugin",
       "rewriter: {params: {}}\n",
       {},
       {"rewriter", "missing", "rewriter.plugin"}},
      {"YAML syntax error", "world: [\n", {}, {"kernel_bad.yaml:"}},
      {"config is not a map", "- a\n- b\n", {}, {"must be a YAML map"}},
      {"--set without =",
       nullptr,
       {"execution.action_budget"},
       {"malformed --set", "key.path=value"}},
      {"--set with bad YAML",
       nullptr,
       {"plugin_paths=[a,"},
       {"malformed --set 'plugin_paths=[a,'"}},
      {"--set with a bad key", nullptr, {"a..b=1"}, {"malformed --set", "not a dotted key path"}},
      {"--set with empty value", nullptr, {"session.k="}, {"malformed --set", "empty"}},
      {"--set unknown key",
       nullptr,
       {"execution.budget=3"},
       {"unknown config key 'execution.budget'"}},
      {"--set wrong type", nullptr, {"session.k=abc"}, {"session.k", "must be an integer"}},
  };
  for (const auto& c : cases) {
    SECTION(c.what) {
      std::optional<std::string> file;
      if (c.file_text != nullptr) file = kerneltest::write_temp("kernel_bad.yaml", c.file_text);
      require_error([&] { (void)Config::load(file, c.overrides); }, "bad_config", c.words);
    }
  }
  SECTION("missing config file") {
    require_error([] { (void)Config::load(std::string("/nonexistent/flipper.yaml"), {}); },
                  "bad_config", {"cannot read config file", "/nonexistent/flipper.yaml"});
  }
}

TEST_CASE("plugin params are validated against the plugin's schema", "[config][params]") {
  sdk::ParamSchema schema;
  schema.add_string("heuristic", "octile", "", {"octile", "manhattan"});
  schema.add_int("max_expansions", 1000, "", 1, 1000000);
  schema.add_double("weight", 1.0, "", 0.0, 5.0);
  schema.add_path("map", std::nullopt, "", true);
  schema.add_string_list("tags", {}, "");
  const auto with = [&](const std::string& params) {
    const auto path =
        kerneltest::write_temp("params.yaml", "planner: {plugin: p, params: " + params + "}\n");
    return Config::load(path, {}).plugin_params("planner", schema);
  };

  const sdk::Params ok = with("{map: maps/a.bt, weight: 2, tags: [x, y]}");
  CHECK(ok.get_string("heuristic") == "octile");
  CHECK(ok.get_int("max_expansions") == 1000);
  CHECK(ok.get_double("weight") == 2.0);
  CHECK(ok.get_string_list("tags") == std::vector<std::string>{"x", "y"});
  CHECK(ok.get_string("map") ==
        (std::filesystem::path(FLIPPER_BINARY_DIR) / "tests/tmp/maps/a.bt").string());

  require_error(
      [&] { (void)with("{map: m, heuristc: manhattan}"); }, "bad_config",
      {"unknown config key 'planner.params.heuristc'", "did you mean 'planner.params.heuristic'",
       "keys in 'planner.params': heuristic, max_expansions, weight, map, tags"});
  require_error([&] { (void)with("{map: m, max_expansions: many}"); }, "bad_config",
                {"planner.params.max_expansions", "must be an integer"});
  require_error([&] { (void)with("{map: m, max_expansions: 0}"); }, "bad_config",
                {"planner.params.max_expansions", "out of range"});
  require_error([&] { (void)with("{map: m, weight: 9.5}"); }, "bad_config",
                {"planner.params.weight", "out of range", "[0, 5]"});
  require_error([&] { (void)with("{map: m, heuristic: euclid}"); }, "bad_config",
                {"planner.params.heuristic", "one of: octile, manhattan"});
  require_error([&] { (void)with("{}"); }, "bad_config",
                {"missing required config key 'planner.params.map'"});
  require_error([&] { (void)with("{map: m, tags: x}"); }, "bad_config",
                {"planner.params.tags", "list of strings"});
}

namespace {
struct SetCase {
  const char* assignment;
  const char* key;
  const char* expected;  // get_string after the assignment
};
}  // namespace

TEST_CASE("set overrides take text keys verbatim unless quoted, other keys are YAML",
          "[config][set]") {
  const std::vector<SetCase> cases = {
      {"lexicon.path=:memory:", "lexicon.path", ":memory:"},
      {"lexicon.path=\":memory:\"", "lexicon.path", ":memory:"},
      {"lexicon.path='it''s here'", "lexicon.path", "it's here"},
      {"lexicon.path=a: b", "lexicon.path", "a: b"},
      {"lexicon.path=a #b", "lexicon.path", "a #b"},
      {"lexicon.path=[x]", "lexicon.path", "[x]"},
      {"lexicon.path=\"null\"", "lexicon.path", "null"},
      {"lexicon.preload=", "lexicon.preload", ""},
      {"lexicon.preload=''", "lexicon.preload", ""},
      {"world.file=w: 1.json", "world.file", "w: 1.json"},
      {"lexicon.sharing=private", "lexicon.sharing", "private"},
      {"planner.plugin=astar", "planner.plugin", "astar"},
      {"planner.params.label=:x:", "planner.params.label", ":x:"},
      {"planner.params.label=", "planner.params.label", ""},
      {"planner.params.label=\"a: b\"", "planner.params.label", "a: b"},
  };
  for (const auto& c : cases) {
    SECTION(c.assignment) {
      const Config config = Config::load(std::nullopt, {c.assignment});
      CHECK(config.get_string(c.key) == c.expected);
      // The effective config written out loads back to the same value.
      const auto path = kerneltest::write_temp("set_dump.yaml", config.dump());
      CHECK(Config::load(path, {}).get_string(c.key) == c.expected);
    }
  }
  SECTION("a null word still unsets a text key (restoring its default)") {
    const Config c = Config::load(std::nullopt, {"lexicon.sharing=private", "lexicon.sharing=~"});
    CHECK(c.get_string("lexicon.sharing") == "shared");
    CHECK(Config::load(std::nullopt, {"lexicon.path=x", "lexicon.path=null"}).dump() ==
          Config::embedded_default().dump());
  }
  SECTION("enum text keys are still checked") {
    require_error([] { (void)Config::load(std::nullopt, {"lexicon.sharing=:all:"}); }, "bad_config",
                  {"lexicon.sharing", "':all:'", "shared, private, core"});
  }
  SECTION("non-text keys keep YAML parsing") {
    const Config c = Config::load(
        std::nullopt, {"plugin_paths=[a, 'b c']", "session.k=4", "induction.alignment=off"});
    CHECK(c.get_string_list("plugin_paths") == std::vector<std::string>{"a", "b c"});
    CHECK(c.get_int("session.k") == 4);
    CHECK_FALSE(c.get_bool("induction.alignment"));
    require_error([] { (void)Config::load(std::nullopt, {"session.k=:3:"}); }, "bad_config",
                  {"session.k", "must be an integer"});
  }
  SECTION("Config::set follows the same rule") {
    Config c = Config::embedded_default();
    c.set("lexicon.path=:memory:");
    CHECK(c.get_string("lexicon.path") == ":memory:");
  }
}

TEST_CASE("set overrides of plugin params: String/Path verbatim, other types as before",
          "[config][set]") {
  sdk::ParamSchema schema;
  schema.add_string("label", "none", "");
  schema.add_path("map", std::string("maps/default.bt"), "");
  schema.add_int("max_expansions", 1000, "", 1, 1000000);
  schema.add_bool("diagonal", true, "");
  schema.add_string_list("tags", {}, "");
  const auto params = [&](std::vector<std::string> sets) {
    return Config::load(std::nullopt, std::move(sets)).plugin_params("planner", schema);
  };
  const sdk::Params p = params({"planner.params.label=a: b #c", "planner.params.map=/m/:x:.bt",
                                "planner.params.max_expansions=12", "planner.params.diagonal=false",
                                "planner.params.tags=[x, 'y z']"});
  CHECK(p.get_string("label") == "a: b #c");
  CHECK(p.get_string("map") == "/m/:x:.bt");
  CHECK(p.get_int("max_expansions") == 12);
  CHECK_FALSE(p.get_bool("diagonal"));
  CHECK(p.get_string_list("tags") == std::vector<std::string>{"x", "y z"});
  CHECK(params({"planner.params.label="}).get_string("label").empty());
  CHECK(params({"planner.params.label='[x]'"}).get_string("label") == "[x]");
  CHECK(params({"planner.params.label=x", "planner.params.label=null"}).get_string("label") ==
        "none");
  require_error([&] { (void)params({"planner.params.max_expansions=a: b"}); }, "bad_config",
                {"planner.params.max_expansions", "must be an integer", "'a: b'"});
  require_error([&] { (void)params({"planner.params.tags=x"}); }, "bad_config",
                {"planner.params.tags", "list of strings"});
  require_error([&] { (void)params({"planner.params.tags=[x,"}); }, "bad_config",
                {"malformed --set 'planner.params.tags=[x,'"});
}

// --- one engine, one wording: kernel keys and plugin params --------------------------------

namespace {
// The whole message of the bad_config `f` throws.
std::string config_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const sdk::Error& e) {
    CHECK(e.code() == "bad_config");
    return e.what();
  }
  return "(no error: the config was accepted)";  // differs from every expected message
}
std::string load_error(const std::string& name, const std::string& text) {
  const std::string path = kerneltest::write_temp(name, text);
  return config_error([&] { (void)Config::load(path, {}); });
}
std::string tmp(const std::string& name) {
  return (std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / name).string();
}
}  // namespace

TEST_CASE("a bad kernel key is refused naming the file, the key and what is wrong",
          "[config][schema]") {
  // Expected texts written from the declared ranges and choices (keys.hpp, keys.cpp).
  CHECK(load_error("named/unknown.yaml", "execution: {action_budgt: 5}\n") ==
        "config " + tmp("named/unknown.yaml") +
            ": unknown config key 'execution.action_budgt' (did you mean "
            "'execution.action_budget'?); keys in 'execution': action_budget, step_budget, "
            "while_limit, cpu_budget_ms, deadline_ms");
  // A retired key says what replaced it, from a file and from --set alike.
  const std::string retired = load_error("named/retired.yaml", "execution: {time_budget_ms: 5}\n");
  CHECK_THAT(retired,
             Catch::StartsWith("config " + tmp("named/retired.yaml") +
                               ": config key 'execution.time_budget_ms' is retired: it was "
                               "a wall-clock budget") &&
                 Catch::Contains("execution.step_budget") &&
                 Catch::Contains("execution.deadline_ms"));
  try {
    (void)Config::load(std::nullopt, {"execution.time_budget_ms=60000"});
    FAIL("a retired key was accepted");
  } catch (const sdk::Error& e) {
    CHECK(e.code() == sdk::codes::kBadConfig);
    CHECK_THAT(e.what(), Catch::Contains("'execution.time_budget_ms' is retired"));
  }
  CHECK(load_error("named/type.yaml", "session: {k: lots}\n") ==
        "config " + tmp("named/type.yaml") +
            ": config key 'session.k' must be an integer, got 'lots'");
  CHECK(load_error("named/range.yaml", "input: {max_tokens: 65535}\n") ==
        "config " + tmp("named/range.yaml") +
            ": config key 'input.max_tokens' = 65535 is out of range [1, 65534]");
  CHECK(load_error("named/big.yaml", "input: {max_file_bytes: 1099511627777}\n") ==
        "config " + tmp("named/big.yaml") +
            ": config key 'input.max_file_bytes' = 1099511627777 is out of range [1, "
            "1099511627776]");
  CHECK(load_error("named/enum.yaml", "lexicon: {weights: per-user}\n") ==
        "config " + tmp("named/enum.yaml") +
            ": config key 'lexicon.weights' = 'per-user' must be one of: global, per_user (did you "
            "mean 'per_user'?)");
  // The top-level keys: the kernel's, then each layer's.
  CHECK(load_error("named/top.yaml", "sesion: {k: 3}\n") ==
        "config " + tmp("named/top.yaml") +
            ": unknown config key 'sesion' (did you mean 'session'?); top-level keys: world, "
            "planner, parser, scorer, rewriter, similarity, grammar, execution, input, session, "
            "plugin_paths, plugins, lexicon, induction, serve, publish, dds, nav2");
  CHECK(load_error("named/numbers.yaml", "world: {origin: [1, x]}\n") ==
        "config " + tmp("named/numbers.yaml") +
            ": config key 'world.origin' must be a list of numbers, but an element is 'x'");
  CHECK(load_error("named/optional.yaml", "similarity: {params: {}}\n") ==
        "config " + tmp("named/optional.yaml") +
            ": missing required config key 'similarity.plugin': the optional section "
            "'similarity' is given, so it needs one");
  // The boundaries themselves are accepted.
  const std::string edge =
      kerneltest::write_temp("named/edge.yaml", "input: {max_tokens: 65534}\nsession: {k: 1}\n");
  CHECK(Config::load(edge, {}).get_int("input.max_tokens") == 65534);
}

TEST_CASE("plugin params get the same wording as kernel keys", "[config][schema][params]") {
  sdk::ParamSchema schema;
  schema.add_double("weight", 1.0, "", 0.0, 5.0);
  schema.add_string("mode", "fast", "", {"fast", "exact"});
  schema.add_int("search.depth", 3, "", 1, 9);  // a nested section, written as YAML nesting
  const auto error = [&](const std::string& name, const std::string& params) {
    const std::string path =
        kerneltest::write_temp(name, "planner: {plugin: p, params: " + params + "}\n");
    return config_error([&] { (void)Config::load(path, {}).plugin_params("planner", schema); });
  };
  CHECK(error("pnamed/range.yaml", "{weight: 9.5}") ==
        "config " + tmp("pnamed/range.yaml") +
            ": config key 'planner.params.weight' = 9.5 is out of range [0, 5]");
  CHECK(error("pnamed/type.yaml", "{weight: heavy}") ==
        "config " + tmp("pnamed/type.yaml") +
            ": config key 'planner.params.weight' must be a number, got 'heavy'");
  CHECK(error("pnamed/enum.yaml", "{mode: exakt}") ==
        "config " + tmp("pnamed/enum.yaml") +
            ": config key 'planner.params.mode' = 'exakt' must be one of: fast, exact (did you "
            "mean 'exact'?)");
  CHECK(error("pnamed/nested.yaml", "{search: {dept: 4}}") ==
        "config " + tmp("pnamed/nested.yaml") +
            ": unknown config key 'planner.params.search.dept' (did you mean "
            "'planner.params.search.depth'?); keys in 'planner.params.search': depth");
  const std::string ok = kerneltest::write_temp(
      "pnamed/ok.yaml", "planner: {plugin: p, params: {search: {depth: 7}}}\n");
  CHECK(Config::load(ok, {}).plugin_params("planner", schema).get_int("search.depth") == 7);
}

TEST_CASE("the option structs start from the schema's defaults", "[config][schema][defaults]") {
  const sdk::ParamSchema& schema = Config::schema();
  const auto def = [&](const char* key) {
    const sdk::ParamSpec* spec = schema.find(key);
    REQUIRE(spec != nullptr);
    REQUIRE(spec->default_value.has_value());
    return std::get<std::int64_t>(*spec->default_value);
  };
  const kernel::InputLimits input;
  CHECK(static_cast<std::int64_t>(input.max_line_bytes) == def("input.max_line_bytes"));
  CHECK(input.max_json_depth == def("input.max_json_depth"));
  CHECK(static_cast<std::int64_t>(input.max_tokens) == def("input.max_tokens"));
  CHECK(static_cast<std::int64_t>(input.max_body_lines) == def("input.max_body_lines"));
  CHECK(static_cast<std::int64_t>(input.max_file_bytes) == def("input.max_file_bytes"));
  CHECK(static_cast<std::int64_t>(input.max_world_cells) == def("world.max_cells"));
  CHECK(input.cpu_budget.count() == def("session.cpu_budget_ms"));
  CHECK(input.deadline.count() == def("session.deadline_ms"));
  const kernel::ExecLimits exec;
  CHECK(static_cast<std::int64_t>(exec.action_budget) == def("execution.action_budget"));
  CHECK(static_cast<std::int64_t>(exec.step_budget) == def("execution.step_budget"));
  CHECK(exec.cpu_budget.count() == def("execution.cpu_budget_ms"));
  CHECK(exec.deadline.count() == def("execution.deadline_ms"));
  CHECK(exec.while_limit == def("execution.while_limit"));
  const kernel::SessionOptions session;
  CHECK(session.k == def("session.k"));
  CHECK(static_cast<std::int64_t>(session.max_chars) == def("input.max_chars"));
  CHECK(session.max_semicolons == def("input.max_semicolons"));
  // from_config of a config that sets nothing gives the same structs.
  const Config empty = Config::load(kerneltest::write_temp("defaults/none.yaml", "{}\n"), {});
  const kernel::SessionOptions read = kernel::SessionOptions::from_config(empty);
  CHECK(read.k == session.k);
  CHECK(read.limits.action_budget == exec.action_budget);
  CHECK(read.limits.while_limit == exec.while_limit);
  CHECK(read.input.max_tokens == input.max_tokens);
  CHECK(read.input.deadline == input.deadline);
}

TEST_CASE("every declared key is in the effective config and has a description",
          "[config][schema]") {
  const Config c = Config::embedded_default();
  const YAML::Node dumped = YAML::Load(c.dump());
  for (const auto& spec : Config::schema().params) {
    INFO(spec.name);
    CHECK(!spec.description.empty());
    if (sdk::is_retired(spec)) {  // declared only to be refused with its hint
      CHECK_FALSE(c.has(spec.name));
      continue;
    }
    CHECK(c.has(spec.name));  // the embedded default sets both optional sections
    YAML::Node node = YAML::Clone(dumped);
    std::size_t start = 0;
    for (std::size_t dot;; start = dot + 1) {
      dot = spec.name.find('.', start);
      node = YAML::Node(node[spec.name.substr(start, dot - start)]);
      if (dot == std::string::npos) break;
    }
    CHECK(node.IsDefined());
  }
}

// --- extends: overlays ------------------------------------------------------------------------

namespace {
std::string configs_dir() {
  return std::string(FLIPPER_SOURCE_DIR) + "/configs";
}
}  // namespace

TEST_CASE("swap configs are overlays with the effective config of their old full copies",
          "[config][extends]") {
  CHECK(Config::embedded_default().dump() ==
        Config::load(kerneltest::data_dir() + "/swap-full/default.yaml", {"grammar.directions=[]"})
            .dump());
  for (const char* name : {"grid-ompl", "octomap-astar", "octomap-ompl"}) {
    INFO(name);
    const Config overlay = Config::load(configs_dir() + "/" + name + ".yaml", {});
    // The old copies listed the world's direction words, which now come from the world plugin.
    const Config full = Config::load(kerneltest::data_dir() + "/swap-full/" + name + ".yaml",
                                     {"grammar.directions=[]"});
    CHECK(overlay.dump() == full.dump());
    // Paths written in default.yaml resolve against default.yaml's directory.
    CHECK(overlay.get_path("grammar.file") == configs_dir() + "/grammars/core.grammar");
  }
  const Config octo = Config::load(configs_dir() + "/octomap-ompl.yaml", {});
  CHECK(octo.get_path("world.file") == configs_dir() + "/worlds/two-floors.json");
  CHECK(octo.plugin_name("planner") == "ompl");
  CHECK(octo.plugin_name("rewriter") == "rewrites");
}

TEST_CASE("an overlay's paths resolve against its own file, the base's against the base's",
          "[config][extends]") {
  const std::string base = kerneltest::write_temp(
      "extends/base/base.yaml",
      "world: {plugin: test_world, file: base-world.json, params: {size: 3}}\n"
      "planner: {plugin: test_planner, params: {mode: fancy, data: base.dat}}\n"
      "parser: {plugin: test_parser}\nscorer: {plugin: test_scorer}\n"
      "grammar: {file: base.grammar}\nsession: {k: 7}\n");
  const std::string overlay = kerneltest::write_temp("extends/top/overlay.yaml",
                                                     "extends: ../base/base.yaml\n"
                                                     "grammar: {file: top.grammar}\n"
                                                     "planner: {params: {data: top.dat}}\n"
                                                     "world: {params: {dims: 3}}\n");
  const std::string base_dir = std::filesystem::path(base).parent_path().string();
  const std::string top_dir = std::filesystem::path(overlay).parent_path().string();
  const Config c = Config::load(overlay, {});
  CHECK(c.get_path("world.file") == base_dir + "/base-world.json");
  CHECK(c.get_path("grammar.file") == top_dir + "/top.grammar");
  CHECK(c.get_int("session.k") == 7);
  CHECK(c.base_dir() == top_dir);
  CHECK_THAT(c.path_origin(kernel::keys::kWorldFile),
             Catch::Equals("world.file 'base-world.json' from " + base + " (extended by " +
                           overlay + "): relative to its directory " + base_dir));
  // Same plugin: params merge key by key, each path from its own file.
  sdk::ParamSchema planner;
  planner.add_string("mode", "plain", "");
  planner.add_path("data", std::nullopt, "");
  const sdk::Params p = c.plugin_params("planner", planner);
  CHECK(p.get_string("mode") == "fancy");
  CHECK(p.get_string("data") == top_dir + "/top.dat");
  sdk::ParamSchema world;
  world.add_int("size", 5, "");
  world.add_int("dims", 2, "");
  const sdk::Params w = c.plugin_params("world", world);
  CHECK(w.get_int("size") == 3);
  CHECK(w.get_int("dims") == 3);
  // --set still resolves against the current directory.
  CHECK(Config::load(overlay, {"world.file=x.json"}).get_path("world.file") ==
        (std::filesystem::current_path() / "x.json").string());
}

TEST_CASE("an overlay that swaps a plugin starts that plugin's params afresh",
          "[config][extends]") {
  const std::string base = kerneltest::write_temp(
      "extends/swap/base.yaml", "planner: {plugin: astar, params: {heuristic: manhattan}}\n");
  const std::string overlay = kerneltest::write_temp(
      "extends/swap/overlay.yaml", "extends: base.yaml\nplanner: {plugin: ompl}\n");
  const Config c = Config::load(overlay, {});
  CHECK(c.plugin_name("planner") == "ompl");
  CHECK_FALSE(c.has(std::string("planner.params.heuristic")));
  const std::string same = kerneltest::write_temp("extends/swap/same.yaml",
                                                  "extends: base.yaml\nplanner: {plugin: astar}\n");
  CHECK(Config::load(same, {}).get_string("planner.params.heuristic") == "manhattan");
}

// Cycles, missing bases and deep chains are the document's: tests/toolkit/config.
TEST_CASE("a bad value in an extended file is refused naming that file", "[config][extends]") {
  // A bad value written in the base names the base file; set again by the overlay, the overlay.
  const std::string range_base =
      kerneltest::write_temp("extends/range/base.yaml", "session: {k: 0}\n");
  const std::string range_top = kerneltest::write_temp(
      "extends/range/top.yaml", "extends: base.yaml\ninput: {max_tokens: 10}\n");
  CHECK(config_error([&] { (void)Config::load(range_top, {}); }) ==
        "config " + range_base + " (extended by " + range_top +
            "): config key 'session.k' = 0 is out of range [1, 1000]");
  const std::string again =
      kerneltest::write_temp("extends/range/again.yaml", "extends: base.yaml\nsession: {k: -1}\n");
  CHECK(config_error([&] { (void)Config::load(again, {}); }) ==
        "config " + again + ": config key 'session.k' = -1 is out of range [1, 1000]");
  CHECK(config_error([&] { (void)Config::load(range_top, {"session.k=2000"}); }) ==
        "config " + range_top + ": config key 'session.k' = 2000 is out of range [1, 1000]");
  // An overlay is validated as any config: a typo is refused with a hint.
  const std::string typo =
      kerneltest::write_temp("extends/typo.yaml", "extends: good/base.yaml\nsesion: {k: 3}\n");
  (void)kerneltest::write_temp("extends/good/base.yaml", "session: {k: 3}\n");
  require_error([&] { (void)Config::load(typo, {}); }, "bad_config",
                {"unknown config key 'sesion'", "did you mean 'session'"});
}

TEST_CASE("configs/default.yaml restates no schema default", "[config][defaults]") {
  // A leaf it sets to the value a config that sets nothing gets would be a second copy.
  const std::string empty = kerneltest::write_temp("defaults/empty.yaml", "{}\n");
  const YAML::Node schema_only = YAML::Load(Config::load(empty, {}).dump());
  const auto emit = [](const YAML::Node& n) {
    YAML::Emitter out;
    out.SetSeqFormat(YAML::Flow);
    out.SetMapFormat(YAML::Flow);
    out << n;
    return std::string(out.c_str());
  };
  std::vector<std::string> restated;
  std::function<void(const YAML::Node&, const YAML::Node&, const std::string&)> walk =
      [&](const YAML::Node& mine, const YAML::Node& theirs, const std::string& key) {
        if (!theirs.IsDefined() || theirs.IsNull()) return;  // not a schema default
        if (mine.IsMap() && mine.size() > 0 && theirs.IsMap()) {
          for (const auto& kv : mine) {
            const std::string name = kv.first.Scalar();
            walk(kv.second, theirs[name], key.empty() ? name : key + "." + name);
          }
          return;
        }
        if (emit(mine) == emit(theirs)) restated.push_back(key);
      };
  walk(YAML::LoadFile(configs_dir() + "/default.yaml"), schema_only, "");
  INFO("restated: " << Catch::Detail::stringify(restated));
  CHECK(restated.empty());
  // The old default.yaml restated nearly everything: the check sees it.
  restated.clear();
  walk(YAML::LoadFile(kerneltest::data_dir() + "/swap-full/default.yaml"), schema_only, "");
  CHECK(restated.size() > 40);
}

// docs/config.md "Who declares a key": the kernel's fragment holds its own sections only, each
// layer's fragment its own, and the installed schema is their composition in that order.
TEST_CASE("each layer declares its own keys, the host composes them", "[config][schema][layers]") {
  const auto sections_of = [](const sdk::ParamSchema& s) {
    std::vector<std::string> out;
    for (const auto& spec : s.params) {
      const std::string top = spec.name.substr(0, spec.name.find('.'));
      if (out.empty() || out.back() != top) out.push_back(top);
    }
    return out;
  };
  CHECK(sections_of(Config::kernel_schema()) ==
        std::vector<std::string>{"world", "planner", "parser", "scorer", "rewriter", "similarity",
                                 "grammar", "execution", "input", "session", "plugin_paths",
                                 "plugins"});
  CHECK(sections_of(naturalization::keys::config_schema()) ==
        std::vector<std::string>{"lexicon", "induction"});
  CHECK(sections_of(studio::keys::config_schema()) == std::vector<std::string>{"serve"});
  CHECK(sections_of(dds::keys::config_schema()) ==
        std::vector<std::string>{"publish", "dds", "nav2"});
  const sdk::ParamSchema& installed = Config::schema();
  CHECK(installed.params.size() == Config::kernel_schema().params.size() +
                                       naturalization::keys::config_schema().params.size() +
                                       studio::keys::config_schema().params.size() +
                                       dds::keys::config_schema().params.size());
  // The keys of docs/config.md's table: 88 before the split, then `plugins.isolation`, then
  // serve.tls.cert, serve.tls.key and serve.behind_proxy, then nav2.execute, nav2.distro,
  // nav2.action and nav2.behavior_tree, then dds.security.crl, then dds.security.enclave and
  // dds.security.protection, then lexicon.moderation, then lexicon.group_commit, then
  // induction.alignment_mode and induction.view.
  CHECK(installed.params.size() == 103);
  CHECK(Config::kernel_schema().params.size() ==
        38);  // 6 world, 2 x 5 plugins, 4 grammar, 6 + 7 + 3, 1, 1 plugins
  // A lexicon key is the naturalization's: a config reads it through its handle...
  const Config c =
      Config::load(std::nullopt, {"lexicon.path=:memory:", "lexicon.weights=per_user"});
  CHECK(c.text(naturalization::keys::kLexiconPath) == ":memory:");
  CHECK(c.get(naturalization::keys::kWeights) == naturalization::keys::Weights::per_user);
  CHECK(c.get(naturalization::keys::kSharing) == naturalization::Sharing::shared);
  // ... and a schema without the kernel's keys is refused.
  sdk::ParamSchema partial = naturalization::keys::config_schema();
  try {
    Config::install_schema(partial);
    FAIL("a schema without the kernel's keys was installed");
  } catch (const std::logic_error& e) {
    CHECK(std::string(e.what()) == "the config schema lacks the kernel key 'world.plugin'");
  }
}
