// Typed plugin parameter handles (flipper/sdk/config_handles.hpp): the schema a plugin declares
// from them, and what `get` reads — from params the SDK validated, and from hand-made ones
// (defaults, and refusals naming the parameter).
#include <catch2/catch.hpp>
#include <cstdint>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/param_check.hpp"

using namespace flipper;
namespace param = sdk::param;

namespace {

enum class Shape { box, sphere };

constexpr param::Int<int> kBeam{"beam", 50, 1, 100000, "derivations kept"};
constexpr param::Int<std::uint64_t> kBudget{"budget", 0, 0, std::nullopt, "0: none"};
constexpr param::Double kRate{"rate", 0.5, 0.0, 1.0, "step"};
constexpr param::Bool kFast{"fast", true, "go fast"};
constexpr param::Text kLabel{"label", "x", "a label"};
constexpr param::Choice<Shape, 2> kShape{"shape", Shape::box, {"box", "sphere"}, "body"};
constexpr param::Path kFile{"file", "", "a file", true};
constexpr param::Path kDir{"dir", "/usr/share", "a folder"};
constexpr param::TextList<2> kWords{"words", {"a", "b"}, "words"};
constexpr param::Subset<3> kParts{"parts", {"one", "two", "three"}, "parts used"};

sdk::ParamSchema schema() {
  return param::schema(kBeam, kBudget, kRate, kFast, kLabel, kShape, kFile, kDir, kWords, kParts);
}

template <class Handle>
std::string refusal(const sdk::Params& p, const Handle& h) {
  try {
    (void)param::get(p, h);
  } catch (const sdk::Error& e) {
    CHECK(e.code() == sdk::codes::kBadConfig);
    return e.what();
  }
  return "(accepted)";
}

}  // namespace

TEST_CASE("params: the schema holds each handle's name, type, default, range and choices") {
  const sdk::ParamSchema s = schema();
  REQUIRE(s.params.size() == 10);
  const sdk::ParamSpec* beam = s.find("beam");
  REQUIRE(beam != nullptr);
  CHECK(beam->type == sdk::ParamType::Int);
  CHECK(std::get<std::int64_t>(*beam->default_value) == 50);
  CHECK(*beam->min == 1);
  CHECK(*beam->max == 100000);
  CHECK(beam->description == "derivations kept");
  CHECK_FALSE(s.find("budget")->max.has_value());
  CHECK(s.find("rate")->type == sdk::ParamType::Double);
  CHECK(std::get<double>(*s.find("rate")->default_value) == 0.5);
  CHECK(s.find("shape")->one_of == std::vector<std::string>{"box", "sphere"});
  CHECK(std::get<std::string>(*s.find("shape")->default_value) == "box");
  CHECK(s.find("file")->required);
  CHECK_FALSE(s.find("file")->default_value.has_value());
  CHECK(std::get<std::string>(*s.find("dir")->default_value) == "/usr/share");
  CHECK(std::get<std::vector<std::string>>(*s.find("parts")->default_value) ==
        std::vector<std::string>{"one", "two", "three"});
}

TEST_CASE("params: get reads validated values, and defaults where a hand-made Params has none") {
  const sdk::Params validated =
      sdk::validate_params(schema(),
                           {{"beam", std::int64_t{7}},
                            {"shape", std::string("sphere")},
                            {"file", std::string("/tmp/f")},
                            {"parts", std::vector<std::string>{"three", "one"}}},
                           "plugin.params");
  CHECK(param::get(validated, kBeam) == 7);
  CHECK(param::get(validated, kShape) == Shape::sphere);
  CHECK(param::get(validated, kFile) == "/tmp/f");
  CHECK(param::get(validated, kParts) == std::array<bool, 3>{true, false, true});
  CHECK(param::get(validated, kRate) == 0.5);  // defaults filled in by the validation
  const sdk::Params empty;
  CHECK(param::get(empty, kBeam) == 50);
  CHECK(param::get(empty, kBudget) == 0u);
  CHECK(param::get(empty, kFast));
  CHECK(param::get(empty, kLabel) == "x");
  CHECK(param::get(empty, kShape) == Shape::box);
  CHECK(param::get(empty, kDir) == "/usr/share");
  CHECK(param::get(empty, kWords) == std::vector<std::string>{"a", "b"});
  CHECK(param::get(empty, kParts) == std::array<bool, 3>{true, true, true});
  CHECK(param::name_of(kShape, Shape::sphere) == "sphere");
  // The SDK's validation refuses what the handles declare out of range.
  CHECK_THROWS_AS(
      sdk::validate_params(schema(), {{"beam", std::int64_t{0}}, {"file", std::string("f")}},
                           "plugin.params"),
      sdk::Error);
}

TEST_CASE("params: get refuses, naming the parameter, what a hand-made Params gets wrong") {
  // The declared range binds a host that did not validate too: [1, 100000] at N and N+1.
  CHECK(param::get(sdk::Params({{"beam", std::int64_t{100000}}}), kBeam) == 100000);
  CHECK(refusal(sdk::Params({{"beam", std::int64_t{100001}}}), kBeam) ==
        "param 'beam' = 100001 is out of range [1, 100000]");
  CHECK(param::get(sdk::Params({{"beam", std::int64_t{1}}}), kBeam) == 1);
  CHECK(refusal(sdk::Params({{"beam", std::int64_t{0}}}), kBeam) ==
        "param 'beam' = 0 is out of range [1, 100000]");
  CHECK(refusal(sdk::Params({{"budget", std::int64_t{-1}}}), kBudget) ==
        "param 'budget' = -1 is out of range [0, inf]");
  CHECK(param::get(sdk::Params({{"rate", 1.0}}), kRate) == 1.0);
  CHECK(refusal(sdk::Params({{"rate", 1.5}}), kRate) ==
        "param 'rate' = 1.5 is out of range [0, 1]");
  // Without a range an int parameter holds what its type holds: 2^31 - 1 fits, 2^31 does not.
  constexpr param::Int<int> kWide{"wide", 0, std::nullopt, std::nullopt, "any int"};
  CHECK(param::get(sdk::Params({{"wide", std::int64_t{2147483647}}}), kWide) == 2147483647);
  CHECK(refusal(sdk::Params({{"wide", std::int64_t{2147483648}}}), kWide) ==
        "param 'wide' = 2147483648 does not fit its type");
  CHECK(refusal(sdk::Params({{"shape", std::string("cube")}}), kShape) ==
        "param 'shape' = \"cube\" is not one of box, sphere");
  CHECK(refusal(sdk::Params({{"parts", std::vector<std::string>{"two", "four"}}}), kParts) ==
        "param 'parts' has 'four', which is not one of one, two, three");
  CHECK(refusal(sdk::Params(), kFile) == "param 'file' is required");
}

TEST_CASE("params: list handles declare and read lists of paths and numbers") {
  constexpr param::PathList<2> kDirs{"dirs", {"a", "/b"}, "folders"};
  constexpr param::DoubleList<3> kOrigin{"origin", {0.5, -1, 2}, "metres"};
  const sdk::ParamSchema s = param::schema(kDirs, kOrigin);
  REQUIRE(s.params.size() == 2);
  CHECK(s.params[0].type == sdk::ParamType::PathList);
  CHECK(s.params[1].type == sdk::ParamType::DoubleList);
  const sdk::Params defaults = sdk::validate_params(s, {}, "");
  CHECK(param::get(defaults, kDirs) == std::vector<std::string>{"a", "/b"});
  CHECK(param::get(defaults, kOrigin) == std::vector<double>{0.5, -1, 2});
  CHECK(param::get(sdk::Params{}, kOrigin) == std::vector<double>{0.5, -1, 2});
}

TEST_CASE("params: compose joins fragments in order and refuses a key two of them declare") {
  constexpr param::Int<int> kA{"one.a", 1, 0, 9, "a"};
  constexpr param::Bool kB{"two.b", false, "b"};
  sdk::ParamSchema first = param::schema(kA);
  first.add_section("one", "the first");
  sdk::ParamSchema second = param::schema(kB);
  second.add_section("two", "the second");
  const sdk::ParamSchema both = param::compose({&first, &second});
  REQUIRE(both.params.size() == 2);
  CHECK(both.params[0].name == "one.a");
  CHECK(both.params[1].name == "two.b");
  REQUIRE(both.sections.size() == 2);
  CHECK(both.sections[1].name == "two");
  try {
    (void)param::compose({&first, &second, &first});
    FAIL("a key declared twice was accepted");
  } catch (const std::logic_error& e) {
    CHECK(std::string(e.what()) == "config section 'one' is declared twice");
  }
  const sdk::ParamSchema again = param::schema(kA);  // the key without its section
  try {
    (void)param::compose({&first, &again});
    FAIL("a key declared twice was accepted");
  } catch (const std::logic_error& e) {
    CHECK(std::string(e.what()) == "config key 'one.a' is declared twice");
  }
}

TEST_CASE("params: a retired key is the flag, not its description's words") {
  sdk::ParamSchema s;
  s.add_retired("old", "use new");
  sdk::ParamSpec lookalike;
  lookalike.name = "lookalike";
  lookalike.description = "retired: only words";
  s.add(lookalike);
  REQUIRE(s.find("old") != nullptr);
  CHECK(sdk::is_retired(*s.find("old")));
  CHECK(s.find("old")->has(sdk::ParamFlag::retired));
  CHECK_FALSE(sdk::is_retired(*s.find("lookalike")));
  try {
    (void)sdk::validate_params(s, {{"old", std::string("x")}}, "p");
    FAIL("a retired key was accepted");
  } catch (const sdk::Error& e) {
    CHECK(std::string(e.what()) == "config key 'p.old' is retired: use new");
  }
  const sdk::Params p = sdk::validate_params(s, {{"lookalike", std::string("x")}}, "p");
  CHECK(p.get_string("lookalike") == "x");
}

TEST_CASE("params: a list of numbers holds numbers, and a list of texts is not one") {
  sdk::ParamSchema s;
  s.add_double_list("origin", {0.25, 2}, "metres");
  const sdk::Params defaults = sdk::validate_params(s, {}, "");
  CHECK(defaults.get_double_list("origin") == std::vector<double>{0.25, 2});
  CHECK(sdk::to_string(defaults.values().at("origin")) == "[0.25, 2]");
  CHECK_THROWS_AS(sdk::validate_params(s, {{"origin", std::vector<std::string>{"0.25", "2"}}}, "w"),
                  sdk::Error);
  CHECK_THROWS_AS(defaults.get_string_list("origin"), sdk::Error);
}
