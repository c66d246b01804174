#include <catch2/catch.hpp>
#include <cmath>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/similarity.hpp"
#include "flipper/testing/similarity_conformance.hpp"
#include "plugin_fixture.hpp"

using flipper::sdk::Params;
using flipper::sdk::Similarity;
using flipper::testsupport::load_plugin;

namespace {
// The default path is Debian's wordnet-base (/usr/share/wordnet), installed by the setup script.
std::shared_ptr<Similarity> wordnet() {
  return load_plugin<Similarity>("wordnet");
}
}  // namespace

TEST_CASE("wordnet: synonyms score high, unrelated words lower", "[wordnet]") {
  auto sim = wordnet();
  const double car_automobile = sim->similarity({"car"}, {"automobile"});
  CHECK(car_automobile >= 0.9);
  const double dog_cat = sim->similarity({"dog"}, {"cat"});
  const double dog_idea = sim->similarity({"dog"}, {"idea"});
  CHECK(dog_cat > dog_idea);
  CHECK(dog_cat > 0.5);
  CHECK(dog_cat < 1.0);
  // Colours share "chromatic colour", shapes share "plane figure".
  CHECK(sim->similarity({"red"}, {"green"}) > sim->similarity({"red"}, {"triangle"}));
  CHECK(sim->similarity({"triangle"}, {"circle"}) > sim->similarity({"triangle"}, {"dog"}));
}

TEST_CASE("wordnet: inflected forms reach their base form", "[wordnet]") {
  auto sim = wordnet();
  CHECK(sim->similarity({"items"}, {"item"}) == 1.0);   // rule s -> ""
  CHECK(sim->similarity({"mice"}, {"mouse"}) == 1.0);   // exception list
  CHECK(sim->similarity({"picked"}, {"pick"}) == 1.0);  // verb rule ed -> ""
}

TEST_CASE("wordnet: identical words 1, unknown words 0, never NaN", "[wordnet]") {
  auto sim = wordnet();
  CHECK(sim->similarity({"blorptastic"}, {"blorptastic"}) == 1.0);
  CHECK(sim->similarity({"blorptastic"}, {"car"}) == 0.0);
  CHECK(sim->similarity({"3"}, {"[", "]"}) == 0.0);
  CHECK(sim->similarity({}, {"car"}) == 0.0);
  // Average best match in both directions: {car} vs {car, blorptastic} = (1 + (1+0)/2) / 2.
  CHECK(sim->similarity({"car"}, {"car", "blorptastic"}) == Approx(0.75));
  for (const auto* w : {"up", "left", "every", "3", "{", "the", "a", "is"}) {
    const double s = sim->similarity({w}, {"visit", "red", "triangle"});
    CHECK(std::isfinite(s));
  }
}

TEST_CASE("wordnet: missing dictionary is a config error", "[wordnet]") {
  try {
    load_plugin<Similarity>("wordnet", Params({{"path", std::string("/nonexistent/wn")}}));
    FAIL("expected an error");
  } catch (const flipper::sdk::Error& e) {
    CHECK(e.code() == "bad_config");
    CHECK_THAT(e.what(), Catch::Contains("/nonexistent/wn") && Catch::Contains("wordnet-base"));
  }
}

TEST_CASE("wordnet: similarity conformance", "[wordnet][conformance]") {
  auto sim = wordnet();
  flipper::testing::check_similarity_conformance(*sim, {{"visit", "red", "triangle"},
                                                        {"move", "right"},
                                                        {"pick", "every", "blue"},
                                                        {"drop", "3", "items"},
                                                        {"car"},
                                                        {"automobile", "dog"}});
}
