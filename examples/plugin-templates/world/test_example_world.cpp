// example_world's own tests, beside the conformance kits: the plugin created as the kernel
// creates it (testing::load_plugin validates its parameters against its schema).
#include <catch2/catch.hpp>
#include <flipper/sdk/errors.hpp>
#include <flipper/sdk/world.hpp>
#include <flipper/testing/plugin_factory.hpp>

namespace {

const char* kField = R"({"bounds": {"min": [0, 0], "max": [3, 2]}, "robot": {"x": 1, "y": 1}})";

}  // namespace

TEST_CASE("example_world: a 4 x 3 field, 4 or 8 neighbours, max_cells") {
  using flipper::testing::load_plugin;
  const auto four = load_plugin<flipper::sdk::World>("example_world")->load(kField, ".");
  CHECK(four.geometry->cell_count() == 12);
  CHECK(four.geometry->free_cells().size() == 12);
  CHECK(four.geometry->neighbour_offsets().size() == 4);
  const auto eight = load_plugin<flipper::sdk::World>("example_world", {{"diagonal", true}});
  CHECK(eight->load(kField, ".").geometry->neighbour_offsets().size() == 8);
  // 12 cells are allowed with max_cells = 12, not with 11.
  CHECK_NOTHROW(load_plugin<flipper::sdk::World>("example_world", {{"max_cells", std::int64_t{12}}})
                    ->load(kField, "."));
  CHECK_THROWS_WITH(
      load_plugin<flipper::sdk::World>("example_world", {{"max_cells", std::int64_t{11}}})
          ->load(kField, "."),
      Catch::Contains("12 cells; the limit is max_cells = 11"));
  // No walls in an open field.
  CHECK_THROWS_AS(load_plugin<flipper::sdk::World>("example_world")
                      ->load(R"({"robot": {"x": 0, "y": 0}, "walls": [[1, 1]]})", "."),
                  flipper::sdk::Error);
}
