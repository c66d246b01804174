#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/similarity.hpp"
#include "flipper/testing/loader.hpp"
#include "flipper/testing/similarity_conformance.hpp"
#include "plugin_fixture.hpp"

using flipper::sdk::Error;
using flipper::sdk::Params;
using flipper::sdk::Similarity;
using flipper::testsupport::load_plugin;

namespace {

std::string write_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "similarity_data";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

// 3-d vectors with known cosines: red ⟂ blue, red ∥ crimson, triangle = -red.
const char* kVectors =
    "red 1 0 0\n"
    "crimson 2 0 0\n"
    "blue 0 1 0\n"
    "triangle -1 0 0\n"
    "visit 0 0 1\n";

std::shared_ptr<Similarity> glove(const std::string& path) {
  return load_plugin<Similarity>("glove", Params({{"path", path}}));
}

}  // namespace

TEST_CASE("glove: cosine of averaged vectors", "[glove]") {
  auto sim = glove(write_file("small.txt", kVectors));
  CHECK(sim->similarity({"red"}, {"crimson"}) == Approx(1.0));
  CHECK(sim->similarity({"red"}, {"blue"}) == Approx(0.0).margin(1e-12));
  CHECK(sim->similarity({"red"}, {"triangle"}) == Approx(-1.0));
  // avg(red, blue) = (.5,.5,0) vs visit (0,0,1): orthogonal; vs blue: cos 45°.
  CHECK(sim->similarity({"red", "blue"}, {"blue"}) == Approx(std::sqrt(0.5)));
  // Unknown words contribute zero vectors: direction unchanged.
  CHECK(sim->similarity({"red", "blorp"}, {"blue", "red"}) == Approx(std::sqrt(0.5)));
}

TEST_CASE("glove: unknown and empty inputs give 0, never NaN", "[glove]") {
  auto sim = glove(write_file("small.txt", kVectors));
  CHECK(sim->similarity({"blorp"}, {"red"}) == 0.0);
  CHECK(sim->similarity({}, {"red"}) == 0.0);
  CHECK(sim->similarity({}, {}) == 0.0);
  // red + triangle cancel out: an all-zero average.
  CHECK(sim->similarity({"red", "triangle"}, {"red"}) == 0.0);
}

TEST_CASE("glove: word2vec header line is skipped", "[glove]") {
  auto sim = glove(write_file("w2v.txt", std::string("5 3\n") + kVectors));
  CHECK(sim->similarity({"red"}, {"crimson"}) == Approx(1.0));
  CHECK(sim->similarity({"5"}, {"red"}) == 0.0);
}

TEST_CASE("glove: max_words keeps only the first words", "[glove]") {
  auto sim = load_plugin<Similarity>("glove", Params({{"path", write_file("small.txt", kVectors)},
                                                      {"max_words", std::int64_t{2}}}));
  CHECK(sim->similarity({"red"}, {"crimson"}) == Approx(1.0));
  CHECK(sim->similarity({"red"}, {"blue"}) == 0.0);  // blue not loaded
}

TEST_CASE("glove: bad files are config errors naming the problem", "[glove]") {
  auto code_of = [](const std::string& path) {
    try {
      glove(path);
    } catch (const Error& e) {
      return e.code() + ": " + e.what();
    }
    return std::string("no error");
  };
  CHECK_THAT(code_of(write_file("ragged.txt", "red 1 0 0\nblue 0 1\n")),
             Catch::Contains("bad_config") && Catch::Contains("ragged.txt:2") &&
                 Catch::Contains("expected 3 components"));
  CHECK_THAT(code_of(write_file("nan.txt", "red 1 zero 0\n")),
             Catch::Contains("bad_config") && Catch::Contains("'zero' is not a number"));
  CHECK_THAT(code_of("/nonexistent/vectors.txt"),
             Catch::Contains("bad_config") && Catch::Contains("/nonexistent/vectors.txt"));
  CHECK_THAT(code_of(write_file("empty.txt", "")), Catch::Contains("no word vectors"));
}

TEST_CASE("glove: similarity conformance", "[glove][conformance]") {
  auto sim = glove(write_file("small.txt", kVectors));
  flipper::testing::check_similarity_conformance(
      *sim, {{"red"}, {"blue", "visit"}, {"red", "triangle"}, {"crimson", "blorp"}, {"visit"}});
}

// The loader-layer kit every in-tree plugin passes (tests/sdk/kits), here because glove's required
// `path` has no default the generic kit could pass: opened through the SDK's host loader like the
// kernel does, with a vectors file for `path`.
TEST_CASE("glove: loader conformance through the host loader", "[glove][conformance][loader]") {
  flipper::testing::check_loader_conformance(
      std::string(FLIPPER_PLUGIN_DIR) + "/glove.so",
      {{"path", flipper::sdk::ParamValue{write_file("small.txt", kVectors)}}});
}
