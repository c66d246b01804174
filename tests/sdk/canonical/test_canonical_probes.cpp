// Every interpretation the original printed for the probe programs reads back (after rewriting
// the original's number and arithmetic printing), and renders to the same text.
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "flipper/corpus/original_text.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

using namespace flipper::sdk;
using flipper::corpus::normalize_original_pretty;

TEST_CASE("normalising the original's printing", "[canonical][probes]") {
  CHECK(normalize_original_pretty("{visit [9.0,8.0] while avoiding room3}") ==
        "{visit [9,8] while avoiding room3}");
  CHECK(normalize_original_pretty("{visit [(+ (number 2) (number 1)),4.0]}") ==
        "{visit [{2 + 1},4]}");
  CHECK(normalize_original_pretty("{repeat (- (number 3) (number 1)) times {move left}}") ==
        "{repeat {3 - 1} times {move left}}");
  CHECK(normalize_original_pretty("{if {item at {is red}room3} {move left}}") ==
        "{if {item {is red} at room3} {move left}}");
  CHECK(normalize_original_pretty("{if {item at {is red}{room3 or room1}} {move left}}") ==
        "{if {item {is red} at {room3 or room1}} {move left}}");
  CHECK(normalize_original_pretty("{if {item at room9} {move left}}") ==
        "{if {item at room9} {move left}}");
  CHECK(normalize_original_pretty("{repeat 2.5 times {move left}}") ==
        "{repeat 2.5 times {move left}}");
}

TEST_CASE("every probe interpretation reads and round-trips", "[canonical][probes]") {
  std::ifstream in(std::string(FLIPPER_STUDY_DIR) + "/original-probes.jsonl");
  REQUIRE(in.good());
  std::set<std::string> texts;
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    auto j = nlohmann::json::parse(line);
    for (const auto& c : j["candidates"]) texts.insert(c["pretty"].get<std::string>());
  }
  REQUIRE(texts.size() > 200);
  int read = 0, exact = 0, nan = 0;
  for (const auto& original : texts) {
    const std::string text = normalize_original_pretty(original);
    INFO(original << "\n  normalised: " << text);
    if (text.find("NaN") != std::string::npos) {  // §2 [decision]: NaN is not a number
      ++nan;
      CHECK_THROWS_AS(read_canonical(text), Error);
      continue;
    }
    Program p;
    REQUIRE_NOTHROW(p = read_canonical(text));
    ++read;
    const std::string again = render(p);
    CHECK(equal(read_canonical(again), p));
    // The original nested sequences left-associatively; Flipper's are flat. Otherwise the texts
    // agree character for character.
    if (again == text) {
      ++exact;
    } else {
      // Only braces may differ: the same tokens otherwise, in the same order.
      auto unbraced = [](const std::string& t) {
        std::vector<std::string> out;
        for (auto& tok : tokenize(t))
          if (tok != "{" && tok != "}") out.push_back(tok);
        return out;
      };
      CHECK(text.find("{{{") != std::string::npos);
      CHECK(unbraced(again) == unbraced(text));
    }
  }
  CHECK(nan == 1);
  CHECK(read == static_cast<int>(texts.size()) - nan);
  CHECK(exact > read * 9 / 10);
}
