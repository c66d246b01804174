// sdk::kind_name / sdk::parse_kind over every PluginKind: the names the loader's refusals and
// sidecars use, and the numbers plugins are built with (docs/sdk-migration.md, enumerators).
#include <catch2/catch.hpp>
#include <cstdint>
#include <string>

#include "flipper/sdk/frontend.hpp"
#include "flipper/sdk/plugin.hpp"

using flipper::sdk::PluginKind;

TEST_CASE("plugin kinds: names and numbers both ways, frontend included, 0 and 8 unknown") {
  const std::pair<std::uint32_t, std::string> kinds[] = {
      {1, "world"},    {2, "planner"},    {3, "parser"},   {4, "scorer"},
      {5, "rewriter"}, {6, "similarity"}, {7, "frontend"},
  };
  for (const auto& [number, name] : kinds) {
    INFO(name);
    CHECK(flipper::sdk::kind_name(static_cast<PluginKind>(number)) == name);
    PluginKind parsed{};
    REQUIRE(flipper::sdk::parse_kind(name.c_str(), parsed));
    CHECK(static_cast<std::uint32_t>(parsed) == number);
  }
  CHECK(flipper::sdk::kind_name(PluginKind::frontend) == std::string("frontend"));
  CHECK(flipper::sdk::kFrontendKind == PluginKind::frontend);
  CHECK(flipper::sdk::kind_name(static_cast<PluginKind>(0)) == std::string("unknown"));
  CHECK(flipper::sdk::kind_name(static_cast<PluginKind>(8)) == std::string("unknown"));
  PluginKind untouched = PluginKind::world;
  CHECK_FALSE(flipper::sdk::parse_kind("frontends", untouched));
  CHECK(untouched == PluginKind::world);
}
