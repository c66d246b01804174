// The original's formulas read into programs: every candidate formula the original answered for
// the dev corpus and the probes reads into the same program as the text it printed for it (an
// independent oracle: the printed text goes through normalize_original_pretty), and every formula
// users accepted or defined with reads.
#include <catch2/catch.hpp>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "flipper/corpus/original_formula.hpp"
#include "flipper/corpus/original_text.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

using namespace flipper::sdk;
using flipper::corpus::is_original_formula;
using flipper::corpus::normalize_original_pretty;
using flipper::corpus::original_formula_to_canonical;

namespace {

std::vector<nlohmann::json> lines_of(const std::string& rel) {
  std::ifstream in(std::string(FLIPPER_STUDY_DIR) + "/" + rel);
  REQUIRE(in.good());
  std::vector<nlohmann::json> out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  return out;
}

}  // namespace

TEST_CASE("original formulas: hand-checked forms", "[canonical][formula]") {
  const std::map<std::string, std::string> cases = {
      {"(: move left)", "{move left}"},
      {"(: visit (call makePoint (number 5) (number 5)))", "{visit [5,5]}"},
      {"(: visit (call makePoint (- (number 3) (number 1)) (number 4)))", "{visit [{3 - 1},4]}"},
      {"(: visitArea (call filterArea world (call allItems)))", "{visit {world containing item }}"},
      {"(: visit (call makePoint (number 9) (number 8)) room3)",
       "{visit [9,8] while avoiding room3}"},
      {"(: visitAreaCollections (call areasFromItems all_rooms (items?property red)))",
       "{visit {rooms containing item {is red}}}"},
      {"(: itemActionHandler pick (call setLimit (number -1) (and (not (items?property red)) "
       "(items?property green))))",
       "{pick every item {{not {is red}} and {is green}}}"},
      {"(: itemActionHandler drop (call setLimit (number 1) (items?color red)))",
       "{drop item {is red}}"},
      {"(:s (: move up) (: move up) (: move left))", "{{move up};{move up};{move left}}"},
      {"(:loop (number 2.500) (: move left))", "{repeat 2.5 times {move left}}"},
      {"(:if (call itemAt (items?property red) (call getRobotLocation)) (: move up))",
       "{if {item {is red} at current} {move up}}"},
      {"(:if (call itemAt (call allItems) room9) (: move left))",
       "{if {item at room9} {move left}}"},
      {"(:while (:realizable (: move right)) (: move right))",
       "{while {possible {move right}} {move right}}"},
      {"(:foreach area (call makeArray (call combineCollections (call createAreaListFromArea "
       "room1) room2)) (: visitArea (call getSelectedArea)))",
       "{foreach area in {[room1, room2]} {visit area}}"},
      {"(: visitArea (call makeArray (call combineAreas (call makePoint (number 1) (number 2)) "
       "(call makePoint (number 3) (number 4)))))",
       "{visit {[[1,2], [3,4]]}}"},
      {"(:strict (: visitArea (call getAreaWithCorners (call makePoint (number 0) (number 0)) "
       "(call makePoint (number 2) (number 2)))))",
       "{strict {visit {area with corners [0,0] and [2,2]}}}"},
  };
  for (const auto& [formula, text] : cases) {
    INFO(formula);
    CHECK(original_formula_to_canonical(formula) == text);
    CHECK_NOTHROW(read_canonical(original_formula_to_canonical(formula)));
  }
  CHECK(is_original_formula("  (: move left)"));
  CHECK_FALSE(is_original_formula("{move left}"));
  CHECK_FALSE(is_original_formula(""));
}

TEST_CASE("original formulas: what does not read is refused by name", "[canonical][formula]") {
  for (const char* bad :
       {"", "(", "(: move left", "(: move left))", "(: fly left)",
        "(:loop (number NaN) (: move left))",
        "(: itemActionHandler pick (call setLimit (number 2) (call allItems)))",
        "(: visitArea moon)", "(:s)", "(: move)", "()", "(:foreach line world (: move up))"}) {
    INFO(bad);
    try {
      original_formula_to_canonical(bad);
      FAIL("read");
    } catch (const Error& e) {
      CHECK(e.code() == std::string(codes::kBadProgram));
    }
  }
  // Depth: 256 nested forms read, 300 are refused before the recursion goes deeper.
  auto nested = [](int n) {
    std::string s;
    for (int i = 0; i < n; ++i) s += "(:strict ";
    s += "(: move up)";
    for (int i = 0; i < n; ++i) s += ")";
    return s;
  };
  CHECK_NOTHROW(original_formula_to_canonical(nested(200)));
  CHECK_THROWS_WITH(original_formula_to_canonical(nested(300)),
                    Catch::Contains("nested deeper than 256"));
}

TEST_CASE("original formulas read into the programs the original printed for them",
          "[canonical][formula][corpus]") {
  std::map<std::string, std::string> printed;  // formula -> pretty
  for (const auto& a : lines_of("dev/original-answers.jsonl"))
    for (const auto& c : a["candidates"]) printed[c["formula"]] = c["pretty"];
  for (const auto& p : lines_of("original-probes.jsonl"))
    for (const auto& c : p["candidates"]) printed[c["formula"]] = c["pretty"];
  REQUIRE(printed.size() == 535);
  int same = 0, nan = 0;
  for (const auto& [formula, pretty] : printed) {
    INFO(formula << "\n  printed: " << pretty);
    if (formula.find("NaN") != std::string::npos) {  // core-language §2 [decision]
      ++nan;
      CHECK_THROWS_AS(original_formula_to_canonical(formula), Error);
      continue;
    }
    const Program ours = read_canonical(original_formula_to_canonical(formula));
    const Program theirs = read_canonical(normalize_original_pretty(pretty));
    CHECK(equal(ours, theirs));
    same += equal(ours, theirs);
  }
  CHECK(nan == 1);
  CHECK(same == static_cast<int>(printed.size()) - nan);
}

TEST_CASE("every formula users accepted or defined with reads", "[canonical][formula][corpus]") {
  int accepts = 0, body_lines = 0, empty = 0;
  auto reads = [](const std::string& f) {
    INFO(f);
    CHECK_NOTHROW(read_canonical(original_formula_to_canonical(f)));
  };
  for (const auto& q : lines_of("dev/queries.jsonl")) {
    const std::string kind = q["kind"];
    if (kind == "accept" && q["formula"].is_string()) {
      reads(q["formula"]);
      ++accepts;
    }
    if ((kind == "def" || kind == "def_ret" || kind == "def_iso") && q["body"].is_array())
      for (const auto& b : q["body"]) {
        if (b["formula"] == "()") {  // a step without an accepted reading
          ++empty;
          continue;
        }
        reads(b["formula"]);
        ++body_lines;
      }
  }
  CHECK(accepts == 807);
  CHECK(body_lines == 320);
  CHECK(empty == 1);
}
