// Runtime: a config becomes loaded plugins, grammar (handed to the parser) and default world;
// incompatible world/planner pairs and bad worlds are refused.
#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "kernel/kernel_test_support.hpp"

using namespace flipper;
using kerneltest::require_error;

TEST_CASE("make_runtime loads plugins, grammar and the default world", "[runtime]") {
  const auto rt = kernel::make_runtime(kerneltest::test_config());
  REQUIRE(rt->world);
  REQUIRE(rt->planner);
  REQUIRE(rt->parser);
  REQUIRE(rt->scorer);
  CHECK_FALSE(rt->rewriter);
  CHECK_FALSE(rt->similarity);
  REQUIRE(rt->core_grammar != nullptr);
  CHECK(rt->core_grammar->rules.size() == 4);
  // The test parser reports the number of rules it was given as `derivations`.
  sdk::ParseRequest req;
  req.scorer = rt->scorer.borrow();
  CHECK(rt->parser.borrow()->parse(req).derivations == 4);
  REQUIRE(rt->default_world.geometry != nullptr);
  CHECK(rt->default_world.geometry->size_x() == 4);  // world.params.size from the config
  CHECK(rt->world.borrow()->dims() == 2);
  CHECK(rt->planner.id().name == "test_planner");
  CHECK(rt->planner.id().file == kerneltest::good_dir() + "/test_planner.so");
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

TEST_CASE("the grammar's direction words come from the world plugin", "[runtime]") {
  // The test world knows one direction, `right`.
  const auto rt = kernel::make_runtime(kerneltest::test_config());
  CHECK(rt->core_grammar->directions == std::vector<std::string>{"right"});
  CHECK(kernel::make_runtime(kerneltest::test_config({"grammar.directions=[right]"}))
            ->core_grammar->directions == std::vector<std::string>{"right"});
  // A word the world does not know is a config error, before anything runs.
  require_error(
      [] {
        (void)kernel::make_runtime(kerneltest::test_config({"grammar.directions=[right, up]"}));
      },
      "bad_config",
      {"grammar.directions names 'up', which world plugin 'test_world' does not know (its "
       "directions: right)"});
}

// Per-user weights are the scorer's (docs/naturalization.md §5 "Learned state"): a scorer without
// the per_user param asked for them is refused, never silently global.
TEST_CASE("lexicon.weights = per_user with a scorer that has no per-user weights is bad_config",
          "[runtime][per_user]") {
  kernel::Config c = kerneltest::test_config({"lexicon.weights=per_user"});
  naturalization::apply_weights_switch(c);
  require_error([&] { (void)kernel::make_runtime(c); }, "bad_config",
                {"scorer.params.per_user", "unknown"});
  // Without the switch the same config runs (the refusal is the switch's, nothing else's).
  CHECK_NOTHROW(kernel::make_runtime(kerneltest::test_config()));
  // The switch against an explicit scorer.params.per_user: false.
  kernel::Config both =
      kerneltest::test_config({"lexicon.weights=per_user", "scorer.params.per_user=false"});
  require_error([&] { naturalization::apply_weights_switch(both); }, "bad_config",
                {"lexicon.weights = per_user", "scorer.params.per_user is false"});
  // A config that skipped the switch: the naturalization's options refuse it.
  const kernel::Config skipped = kerneltest::test_config({"lexicon.weights=per_user"});
  require_error([&] { (void)naturalization::NaturalizeOptions::from_config(skipped); },
                "bad_config", {"scorer's per_user param is not set"});
}
