// The bounds of a config document and of the files it is read from (docs/bad-input.md), and a
// document's maps as the typed values of a schema (toolkit/config/typed_values.hpp).
#include <sys/stat.h>

#include <string>

#include "config_test_support.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/toolkit/config/regular_file.hpp"
#include "flipper/toolkit/config/typed_values.hpp"
#include "flipper/toolkit/config/yaml_bounds.hpp"

namespace config = flipper::toolkit::config;
namespace sdk = flipper::sdk;
using configtest::config_error;
using configtest::write_file;

namespace {
std::string thrown_code(const std::function<void()>& f) {
  try {
    f();
  } catch (const sdk::Error& e) {
    return e.code();
  }
  return "(none)";
}
}  // namespace

TEST_CASE("a document of aliases to aliases is refused before it is walked",
          "[toolkit][config][bounds]") {
  // Ten levels of ten aliases to the level below: 10^10 nodes once expanded, a few hundred
  // bytes as text.
  std::string bomb = "l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i <= 9; ++i) {
    bomb += "l" + std::to_string(i) + ": &l" + std::to_string(i) + " [";
    for (int j = 0; j < 10; ++j) bomb += (j ? ", *l" : "*l") + std::to_string(i - 1);
    bomb += "]\n";
  }
  CHECK(config_error([&] {
          (void)config::ConfigDocument::parse(bomb, "<bomb>", "/", {}, configtest::rules());
        }) ==
        "config <bomb>: the document has more than 100000 YAML nodes once its aliases are "
        "expanded (an alias counts as the nodes it repeats); the limit for a config is "
        "100000 nodes");
  // Five levels (l4 alone expands to 111,111 nodes) are over the limit; four (12,349) are not.
  const YAML::Node four = YAML::Load(bomb.substr(0, bomb.find("l4:")));
  CHECK_NOTHROW(config::yaml_bounds::check_expanded_size(four, "four"));
  const YAML::Node five = YAML::Load(bomb.substr(0, bomb.find("l5:")));
  CHECK(thrown_code([&] { config::yaml_bounds::check_expanded_size(five, "five"); }) ==
        "bad_config");
  // Nulls dropped at every level, other values as they are.
  const YAML::Node kept = config::yaml_bounds::without_nulls(YAML::Load("a: {b: ~, c: 1}\nd: ~\n"));
  CHECK(kept.size() == 1);
  CHECK(kept["a"].size() == 1);
  CHECK(kept["a"]["c"].Scalar() == "1");
}

TEST_CASE("a config file is a regular file of at most 1 MiB", "[toolkit][config][bounds]") {
  const std::string big = write_file("big.yaml", "k: " + std::string(1 << 20, 'x') + "\n");
  CHECK(config_error([&] { (void)config::ConfigDocument::read(big, {}, configtest::rules()); }) ==
        "config file '" + big + "' has " + std::to_string((1 << 20) + 4) +
            " bytes; the limit for a config is 1048576 bytes (1 MiB)");
  const std::string dir = std::filesystem::path(big).parent_path().string();
  CHECK(config_error([&] { (void)config::ConfigDocument::read(dir, {}, configtest::rules()); }) ==
        "config file '" + dir + "' is not a regular file (only regular files are read)");
  const std::string fifo = dir + "/fifo.yaml";
  std::filesystem::remove(fifo);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);  // no writer: opening it must not wait for one
  CHECK(thrown_code([&] { (void)config::read_regular_file(fifo, 100, "world file", "nope"); }) ==
        "not_a_regular_file");
  CHECK(thrown_code([&] { config::check_regular_file(big, 100, "world file", "nope"); }) ==
        "file_too_large");
  CHECK(thrown_code([&] { (void)config::read_regular_file(dir + "/none", 100, "w", "nope"); }) ==
        "nope");
  CHECK(config::read_regular_file(write_file("small.txt", "abc"), 3, "w", "nope") == "abc");
}

TEST_CASE("a document's map as the typed values of a schema, and back",
          "[toolkit][config][typed]") {
  sdk::ParamSchema schema;
  schema.add_int("n", 1, "");
  schema.add_bool("on", false, "");
  schema.add_path("file", std::nullopt, "");
  schema.add_string_list("names", std::vector<std::string>{}, "");
  const config::PathFn path = [](const std::string& key, const std::string& text) {
    return key + ":" + text;
  };
  const YAML::Node node = YAML::Load("n: 3\non: off\nfile: a.txt\nnames: [x, y]\nodd: 1\n");
  const auto given = config::typed_values(node, schema, "p", path);
  CHECK(std::get<std::int64_t>(given.at("n")) == 3);
  CHECK(std::get<bool>(given.at("on")) == false);
  CHECK(std::get<std::string>(given.at("file")) == "p.file:a.txt");
  CHECK(std::get<std::vector<std::string>>(given.at("names")) ==
        std::vector<std::string>{"x", "y"});
  CHECK(given.count("odd") == 1);  // passed on for the engine to name
  CHECK(config_error([&] {
          (void)config::typed_values(YAML::Load("n: 2.5"), schema, "p", path);
        }) == "config key 'p.n' must be an integer, got '2.5'");
  CHECK(config_error([&] {
          (void)config::typed_values(YAML::Load("names: [x, [y]]"), schema, "", path);
        }) == "config key 'names' must be a list of strings, but an element is a list");
  const auto values = sdk::validate_params(
      schema, config::typed_values(YAML::Load("n: 03\non: yes"), schema, "", path), "");
  CHECK(config::dump_values(schema, values, YAML::Node()) == "n: 3\non: true\nnames: []\n");
  CHECK(config::parse_int("12") == 12);
  CHECK_FALSE(config::parse_int("12x"));
  CHECK(config::scalar_text(YAML::Load("{a: 1}")) == "a map");
}
