// define with body lines that carry their program (docs/protocol.md § define:
// {"text", "formula"}): the formula decides the line's reading, whatever the text parses to.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "naturalize_fixture.hpp"

using namespace flipper;
using namespace flipper::naturalizetest;
using kernel::Json;

namespace {

Json define_lines(kernel::Session& s, const std::string& head, const Json& body,
                  const Json& ranks = nullptr) {
  Json request{{"op", "define"}, {"head", head}, {"body", body}};
  if (!ranks.is_null()) request["ranks"] = ranks;
  return s.handle(request);
}

Json line(const std::string& text, const std::string& formula) {
  return Json{{"text", text}, {"formula", formula}};
}

std::string top(kernel::Session& s, const std::string& text) {
  return s.handle({{"op", "query"}, {"text", text}})["candidates"][0]["formula"];
}

// A rule list without what differs between two stores (ids, authors).
Json shapes(Json rules) {
  for (auto& r : rules) {
    r.erase("id");
    r.erase("author");
  }
  return rules;
}

const std::string kAmbiguous = "visit room3 or room5 containing item is red";

}  // namespace

TEST_CASE("a line's formula is its program even when its text does not parse to it",
          "[naturalize][formula]") {
  auto s = open(scratch_path("lex") + ".sqlite");
  // The text parses to nothing: as plain text the line is refused, with its formula it is read.
  CHECK(error_code(define(*s, "hop north", {"hop up"})) == "body_unparsable");
  Json a = define_lines(*s, "hop north", Json::array({line("hop up", "{move up}"), "move right"}));
  REQUIRE(a["ok"] == true);
  CHECK(a["rules"][0]["semantics"] == "{{move up};{move right}}");
  CHECK(top(*s, "hop north") == "{{move up};{move right}}");
  // The text parses, to another program: the formula wins.
  a = define_lines(*s, "hop south", Json::array({line("move up", "{move down}")}));
  REQUIRE(a["ok"] == true);
  CHECK(top(*s, "hop south") == "{move down}");
}

TEST_CASE("a formula names one reading of an ambiguous line, over its rank",
          "[naturalize][formula]") {
  auto s = open(scratch_path("lex") + ".sqlite");
  const Json q = s->handle({{"op", "query"}, {"text", kAmbiguous}});
  REQUIRE(q["total"] == 2);
  const std::string first = q["candidates"][0]["formula"], second = q["candidates"][1]["formula"];
  REQUIRE(first != second);
  // The second reading by formula, with ranks naming the first: the formula decides.
  REQUIRE(define_lines(*s, "scoot over", Json::array({line(kAmbiguous, second)}),
                       Json::array({0}))["ok"] == true);
  CHECK(top(*s, "scoot over") == second);
  // The same definition by rank 1 gives the same rules (the reading's derivation serves
  // alignment either way), in a store of its own.
  auto by_formula = open(scratch_path("lex") + ".sqlite");
  auto by_rank = open(scratch_path("lex") + ".sqlite");
  const Json f = define_lines(*by_formula, "scoot about", Json::array({line(kAmbiguous, second)}));
  const Json r = define_lines(*by_rank, "scoot about", Json::array({kAmbiguous}), Json::array({1}));
  REQUIRE(f["ok"] == true);
  REQUIRE(r["ok"] == true);
  CHECK(shapes(f["rules"]) == shapes(r["rules"]));
  // And a one-line body whose formula is its top reading induces what the plain line does,
  // alignment rules included.
  auto plain = open(scratch_path("lex") + ".sqlite");
  auto formula = open(scratch_path("lex") + ".sqlite");
  const Json p = define(*plain, "visit red spots now", {"visit world containing item is red"});
  const Json g = define_lines(*formula, "visit red spots now",
                              Json::array({line("visit world containing item is red",
                                                "{visit {world containing item {is red}}}")}));
  REQUIRE(p["ok"] == true);
  CHECK(shapes(g["rules"]) == shapes(p["rules"]));
  bool aligned = false;
  for (const auto& rule : p["rules"]) aligned |= rule["how"] == "alignment";
  CHECK(aligned);
}

TEST_CASE("body lines of the wrong shape and formulas that do not read are refused by line",
          "[naturalize][formula]") {
  auto s = open(scratch_path("lex") + ".sqlite");
  Json a = define_lines(*s, "hop", Json::array({"move up", line("move up", "{fly up}")}));
  CHECK(error_code(a) == "bad_program");
  CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains("body line 2"));
  for (const Json& bad :
       {Json::array({Json{{"text", "move up"}}}), Json::array({Json{{"formula", "{move up}"}}}),
        Json::array({Json{{"text", "move up"}, {"formula", 3}}}), Json::array({5}),
        Json("move up")}) {
    INFO(bad.dump());
    CHECK(error_code(define_lines(*s, "hop", bad)) == "bad_request");
  }
  CHECK(error_code(s->handle({{"op", "define"}, {"head", "hop"}})) == "missing_field");
  CHECK(s->handle({{"op", "rules"}})["rules"].empty());  // nothing was added by the failures
}
