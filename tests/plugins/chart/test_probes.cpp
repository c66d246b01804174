// Differential test against the original system's answers to the 277 probes
// (data/study2018/original-probes.jsonl): for every probe our candidate set must equal the
// original's de-duplicated set after normalising its printing, except where a [decision] differs.
#include <catch2/catch.hpp>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "parse_support.hpp"

using namespace flipper;

namespace {

// `(+ (number 2) (number 1))` -> `{2 + 1}` (the original printed arithmetic in prefix form).
std::string sexpr(const std::string& s, std::size_t& i) {
  auto skip = [&] {
    while (i < s.size() && s[i] == ' ') ++i;
  };
  auto atom = [&] {
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ' && s[i] != ')') ++i;
    return s.substr(b, i - b);
  };
  ++i;  // (
  skip();
  const std::string head = atom();
  skip();
  std::string out;
  if (head == "number") {
    out = atom();
  } else {
    std::string a = s[i] == '(' ? sexpr(s, i) : atom();
    skip();
    std::string b = s[i] == '(' ? sexpr(s, i) : atom();
    out = "{" + a + " " + head + " " + b + "}";
  }
  skip();
  ++i;  // )
  return out;
}

std::size_t matching_brace(const std::string& s, std::size_t open) {
  int depth = 0;
  for (std::size_t i = open; i < s.size(); ++i) {
    if (s[i] == '{') ++depth;
    if (s[i] == '}' && --depth == 0) return i;
  }
  return std::string::npos;
}

}  // namespace

/// The original's pretty text -> our canonical text.
std::string normalise_original(std::string s) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    if (s[i] == '(')
      out += sexpr(s, i);
    else
      out += s[i++];
  }
  s = std::regex_replace(out, std::regex(R"((-?\d+)\.0(?![0-9]))"), "$1");
  // `{item at {is red}room3}` -> `{item {is red} at room3}` (the original's misprint of I at P).
  for (std::size_t p = s.find("{item at "); p != std::string::npos;
       p = s.find("{item at ", p + 1)) {
    const std::size_t close = matching_brace(s, p);
    std::size_t q = p + 9;
    std::string filter;
    if (s[q] == '{') {
      const std::size_t fe = matching_brace(s, q);
      filter = s.substr(q, fe - q + 1);
      q = fe + 1;
    }
    const std::string loc = s.substr(q, close - q);
    s = s.substr(0, p) + "{item " + filter + " at " + loc + "}" + s.substr(close + 1);
  }
  return s;
}

TEST_CASE("normalising the original's printing") {
  CHECK(normalise_original("{visit [(+ (number 2) (number 1)),4.0]}") == "{visit [{2 + 1},4]}");
  CHECK(normalise_original("{if {item at {is red}[7.0,4.0]} {move left}}") ==
        "{if {item {is red} at [7,4]} {move left}}");
  CHECK(normalise_original("{if {item at room9} {move left}}") ==
        "{if {item  at room9} {move left}}");
}

TEST_CASE("every probe of the original yields the expected candidate set") {
  auto& st = parsetest::shared_stack();
  std::ifstream in(std::string(FLIPPER_STUDY_DIR) + "/original-probes.jsonl");
  REQUIRE(in);
  // [decision]s: Java number syntax is not a number; number words are case-insensitive;
  // `has color/shape` is a synonym of `is`. Probes the kernel refuses (limits) are skipped.
  const std::set<std::string> java_numbers = {"L17", "L24", "N3", "N4", "N5", "N10"};
  const std::map<std::string, std::string> decided = {
      {"L2", "{repeat 3 times {move right}}"}, {"L30", "{repeat 2 times {move right}}"},
      {"N9", "{repeat 0 times {move right}}"}, {"L22", "{pick item {is red}}"},
      {"Q3", "{pick item {is circle}}"},       {"Q4", "{visit {world containing item {is red}}}"}};
  const std::set<std::string> refused = {"LIM30", "LIMCH", "Z1"};
  int probes = 0, sets_equal = 0, scored = 0, scores_equal = 0;
  std::string line;
  while (std::getline(in, line)) {
    const auto j = nlohmann::json::parse(line);
    const std::string id = j["id"];
    if (refused.count(id)) continue;
    ++probes;
    const std::string program = j["program"];
    std::vector<sdk::Program> expected;
    std::vector<double> expected_scores;
    if (java_numbers.count(id)) {
      // expected stays empty
    } else if (decided.count(id)) {
      expected.push_back(sdk::read_canonical(decided.at(id)));
      expected_scores.push_back(-1);
    } else {
      for (const auto& c : j["candidates"]) {
        auto p = sdk::read_canonical(normalise_original(c["pretty"]));
        if (!sdk::loop_variables_bound(p)) continue;  // [decision] §3.7
        bool dup = false;
        for (std::size_t k = 0; k < expected.size(); ++k)
          if (sdk::equal(expected[k], p)) {
            expected_scores[k] = std::max(expected_scores[k], c["score"].get<double>());
            dup = true;
          }
        if (!dup) {
          expected.push_back(p);
          expected_scores.push_back(c["score"].get<double>());
        }
      }
    }
    sdk::ParseResult r;
    REQUIRE_NOTHROW(r = st.parse(program));
    INFO("probe " << id << ": " << program);
    bool same = r.candidates.size() == expected.size();
    for (const auto& c : r.candidates) {
      bool found = false;
      for (std::size_t k = 0; k < expected.size(); ++k)
        if (sdk::equal(expected[k], c.program)) {
          found = true;
          if (expected_scores[k] >= 0) {
            ++scored;
            if (c.score == expected_scores[k])
              ++scores_equal;
            else
              std::cout << "score differs: " << id << " " << sdk::render(c.program) << " ours "
                        << c.score << " original " << expected_scores[k] << "\n";
          }
        }
      if (!found) {
        same = false;
        UNSCOPED_INFO("unexpected candidate " << sdk::render(c.program));
      }
    }
    for (const auto& e : expected) UNSCOPED_INFO("expected " << sdk::render(e));
    CHECK(same);
    if (same) ++sets_equal;
    // Status: every probe's interpretation is core language here.
    for (const auto& c : r.candidates) CHECK(c.core_only);
  }
  std::cout << "probes: " << sets_equal << "/" << probes << " candidate sets equal; initial scores "
            << scores_equal << "/" << scored << " equal to the original's\n";
  CHECK(sets_equal == probes);
  // Every candidate the original scored (all but the [decision] probes above) has its initial
  // score exactly: measured 248/248.
  CHECK(scored == 248);
  CHECK(scores_equal == scored);
}
