// Runtime: a config becomes loaded plugins, grammar (handed to the parser) and default world;
// incompatible world/planner pairs and bad worlds are refused.
#include "flipper/kernel/runtime.hpp"
#include "kernel_test_support.hpp"

using namespace flipper;
using kerneltest::require_error;

TEST_CASE("make_runtime loads plugins, grammar and the default world", "[runtime]") {
  const auto rt = kernel::make_runtime(kerneltest::test_config());
  REQUIRE(rt->world != nullptr);
  REQUIRE(rt->planner != nullptr);
  REQUIRE(rt->parser != nullptr);
  REQUIRE(rt->scorer != nullptr);
  CHECK(rt->rewriter == nullptr);
  CHECK(rt->similarity == nullptr);
  REQUIRE(rt->core_grammar != nullptr);
  CHECK(rt->core_grammar->rules.size() == 4);
  // The test parser reports the number of rules it was given as `derivations`.
  sdk::ParseRequest req;
  req.scorer = rt->scorer.get();
  CHECK(rt->parser->parse(req).derivations == 4);
  REQUIRE(rt->default_world.geometry != nullptr);
  CHECK(rt->default_world.geometry->size_x() == 4);  // world.params.size from the config
  CHECK(rt->world->dims() == 2);
}

TEST_CASE("a 3-D world needs a planner that supports 3-D", "[runtime]") {
  require_error(
      [] { (void)kernel::make_runtime(kerneltest::test_config({"world.params.dims=3"})); },
      "bad_config", {"planner 'test_planner'", "3-D", "test_world", "supports_3d"});
  const auto rt = kernel::make_runtime(
      kerneltest::test_config({"world.params.dims=3", "planner.params.supports_3d=true"}));
  CHECK(rt->default_world.geometry->dims() == 3);
}

TEST_CASE("world loading errors keep the world plugin's code", "[runtime]") {
  const auto rt = kernel::make_runtime(kerneltest::test_config());
  require_error([&] { (void)kernel::load_world_file(*rt, R"({"bad": 1})"); }, "bad_world",
                {"entry 'bad'"});
  require_error([&] { (void)kernel::load_world_file(*rt, "/nonexistent/world.json"); }, "bad_world",
                {"/nonexistent/world.json"});
  CHECK(kernel::load_world_file(*rt, kerneltest::data_dir() + "/tiny_world.json").geometry !=
        nullptr);
  require_error(
      [] { (void)kernel::make_runtime(kerneltest::test_config({"world.file=missing.json"})); },
      "bad_world", {"missing.json"});
}

TEST_CASE("runtime errors name the failing plugin", "[runtime]") {
  require_error(
      [] { (void)kernel::make_runtime(kerneltest::test_config({"parser.plugin=chartt"})); },
      "plugin_not_found", {"no parser plugin named 'chartt'", "test_parser"});
  require_error(
      [] { (void)kernel::make_runtime(kerneltest::test_config({"planner.plugin=throwing"})); },
      "plugin_error", {"plugin 'throwing'", "cannot open the planner database"});
  require_error(
      [] { (void)kernel::make_runtime(kerneltest::test_config({"grammar.file=nope.grammar"})); },
      "bad_grammar", {"nope.grammar"});
}
