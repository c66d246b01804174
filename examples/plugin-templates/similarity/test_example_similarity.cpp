// example_similarity's own tests, beside the conformance kits: the plugin created as the kernel
// creates it (testing::load_plugin validates its parameters).
#include <catch2/catch.hpp>
#include <flipper/sdk/similarity.hpp>
#include <flipper/testing/plugin_factory.hpp>

TEST_CASE("example_similarity: Jaccard overlap after the ignored words") {
  using flipper::testing::load_plugin;
  const auto sim = load_plugin<flipper::sdk::Similarity>("example_similarity");
  CHECK(sim->similarity({"go", "to", "the", "red", "box"}, {"go", "red", "box"}) == 1.0);
  CHECK(sim->similarity({"red", "box"}, {"red", "ball"}) == 1.0 / 3.0);  // {red} of 3 words
  CHECK(sim->similarity({"the"}, {"the"}) == 0.0);                       // nothing left
  const auto strict = load_plugin<flipper::sdk::Similarity>(
      "example_similarity", {{"ignore", std::vector<std::string>{}}});
  CHECK(strict->similarity({"go", "to", "the", "red", "box"}, {"go", "red", "box"}) == 0.6);
}
