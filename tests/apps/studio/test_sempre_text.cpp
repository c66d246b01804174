// /sempre answers are written without JSON trees (docs/sempre.md § "Answers"): each candidate once,
// where it is made, and the body from the candidates' texts. Their bytes must be the ones the
// trees they replaced dumped; each writer is compared with that tree on fixed odd values and on
// many generated ones (escapes, control characters, unicode, invalid UTF-8, NaN and infinities).
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/execution.hpp"
#include "sempre.hpp"
#include "sempre_session.hpp"
#include "sempre_value.hpp"

namespace {

using nlohmann::json;
namespace studio = flipper::studio;
namespace sdk = flipper::sdk;

std::string tree_dump(const json& j) {
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

// The candidate tree the endpoint used to build.
json candidate_tree(const std::string& formula, double score, double prob,
                    const std::string& value) {
  return json{{"formula", formula}, {"prettyString", formula}, {"score", score},
              {"prob", prob},       {"value", value},          {"anchored", true}};
}

std::string random_string(std::mt19937_64& rng) {
  static const std::vector<std::string> pieces = {
      "a",
      "Z",
      " ",
      "\"",
      "\\",
      "/",
      "\n",
      "\t",
      "\r",
      "\b",
      "\f",
      std::string(1, '\0'),
      "\x01",
      "\x1f",
      "\x7f",
      "é",
      "ünï",
      "€",
      "😀",
      "\xff",
      "\xc3",
      "\xe2\x82",
      "\xed\xa0\x80",
      "(:s (: move left))",
      "{\"path\":[[1,2,\"path\",\"null\",\"null\",true]],\"status\":\"\"}"};
  std::string s;
  const auto n = rng() % 6;
  for (std::uint64_t i = 0; i < n; ++i) s += pieces[rng() % pieces.size()];
  return s;
}

double random_double(std::mt19937_64& rng) {
  switch (rng() % 4) {
    case 0: {
      const std::uint64_t bits = rng();
      double d = 0;
      std::memcpy(&d, &bits, sizeof d);
      return d;  // any exponent, NaN and infinities included
    }
    case 1:
      return std::uniform_real_distribution<double>(-30, 30)(rng);
    case 2:
      return std::uniform_real_distribution<double>(0, 1)(rng);
    default:
      return static_cast<double>(rng() % 5);
  }
}

}  // namespace

TEST_CASE("a candidate's text is its tree's dump", "[sempre][writer]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(studio::candidate_text("(: move left)", 0.0, 1.0, R"({"path":[],"status":""})") ==
        R"x({"anchored":true,"formula":"(: move left)","prettyString":"(: move left)","prob":1.0,)x"
        R"x("score":0.0,"value":"{\"path\":[],\"status\":\"\"}"})x");
  CHECK(
      studio::candidate_text("x", nan, -0.0, "") ==
      R"({"anchored":true,"formula":"x","prettyString":"x","prob":-0.0,"score":null,"value":""})");
  std::mt19937_64 rng(50);
  for (int i = 0; i < 20000; ++i) {
    const std::string formula = random_string(rng), value = random_string(rng);
    const double score = random_double(rng), prob = random_double(rng);
    REQUIRE(studio::candidate_text(formula, score, prob, value) ==
            tree_dump(candidate_tree(formula, score, prob, value)));
  }
}

TEST_CASE("an answer's body is its tree's dump", "[sempre][writer]") {
  std::mt19937_64 rng(2018);
  for (int i = 0; i < 3000; ++i) {
    studio::SempreAnswer a;
    json candidates = json::array();
    const auto n = rng() % 4;
    for (std::uint64_t c = 0; c < n; ++c) {
      const std::string formula = random_string(rng), value = random_string(rng);
      const double score = random_double(rng), prob = random_double(rng);
      a.candidates.push_back(studio::candidate_text(formula, score, prob, value));
      candidates.push_back(candidate_tree(formula, score, prob, value));
    }
    for (std::uint64_t l = rng() % 3; l > 0; --l) a.lines.push_back(random_string(rng));
    if (rng() % 2) a.stats["size"] = rng() % 60;
    if (rng() % 2) a.stats["status"] = random_string(rng);
    if (rng() % 2) a.stats["author"] = nullptr;
    const std::string type = random_string(rng);
    const std::uint64_t count = rng();
    const double seconds = random_double(rng);
    const std::string code = rng() % 3 == 0 ? random_string(rng) : std::string();
    // What the endpoint's body was: the stats with the endpoint's members, the whole tree dumped.
    json stats = a.stats;
    stats["type"] = type;
    stats["count"] = count;
    stats["walltime"] = seconds;
    json tree{{"stats", stats}, {"lines", a.lines}, {"candidates", candidates}};
    if (!code.empty())
      tree["error"] = json{{"code", code}, {"message", a.lines.empty() ? "" : a.lines[0]}};
    REQUIRE(studio::sempre_body(type, count, seconds, a, code) == tree_dump(tree));
  }
}

TEST_CASE("a value's text is the dump of its path tree", "[sempre][writer]") {
  using Act = sdk::TraceStep::Act;
  // A program of one statement: its value is written from the whole trace.
  const sdk::Program move =
      sdk::make(sdk::Kind::Move, {sdk::make_word(sdk::Kind::Direction, "left")});
  sdk::WorldState start;
  start.robot = {3, 4, 0};
  class NoRuns : public sdk::ExecutionService {
   public:
    sdk::Outcome run(const sdk::Program&, const sdk::WorldState&) const override { return {}; }
  } exec;
  std::mt19937_64 rng(5);
  for (int i = 0; i < 2000; ++i) {
    sdk::Outcome whole;
    for (auto n = rng() % 6; n > 0; --n) {
      sdk::TraceStep s;
      s.act = static_cast<Act>(rng() % 3);
      s.cell = {static_cast<std::int32_t>(rng() % 41) - 20, static_cast<std::int32_t>(rng()), 0};
      if (s.act != Act::move) s.item = {static_cast<std::int64_t>(rng() % 9), "", ""};
      // Item names and warnings as a valid world gives them (any UTF-8, escapes): invalid UTF-8
      // cannot come from a parsed world and threw when the tree was dumped.
      if (s.act != Act::move) {
        s.item.color = rng() % 2 ? "red" : "r\"e\\d\n é";
        s.item.shape = rng() % 2 ? "circle" : "\x01\x7f 😀";
      }
      whole.trace.push_back(s);
    }
    if (rng() % 3 == 0) whole.warnings.push_back(rng() % 2 ? "blocked \"x\"" : "ünï \t");
    const std::string text = studio::sempre_value(move, start, whole, exec);
    const json parsed = json::parse(text);
    REQUIRE(parsed.dump() == text);  // the canonical dump of the tree it describes
    REQUIRE(parsed.at("path").is_array());
    REQUIRE(parsed.at("status") == (whole.warnings.empty() ? "" : whole.warnings.back()));
  }
  // Invalid UTF-8 in an item's name throws nlohmann's error, as dumping the tree did.
  sdk::Outcome bad;
  bad.trace.push_back({Act::pick, {1, 1, 0}, {1, "re\xff", "circle"}});
  CHECK_THROWS_AS(studio::sempre_value(move, start, bad, exec), json::type_error);
}
