// Corpus coverage: every `q` of the dev corpus that was Core in the original parses as core here
// (both property syntaxes), and every group-A `Nothing` is unparsable here. Rates are printed;
// the floors below are the measured rates.
#include <catch2/catch.hpp>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "parse_support.hpp"

using namespace flipper;

TEST_CASE("dev corpus: original Core queries parse as core, group A Nothing stays unparsable") {
  auto& st = parsetest::shared_stack();
  std::ifstream in(std::string(FLIPPER_STUDY_DIR) + "/dev/queries.jsonl");
  REQUIRE(in);
  int core_total = 0, core_ok = 0, nothing_total = 0, nothing_ok = 0;
  std::map<std::string, int> failures;
  std::string line;
  while (std::getline(in, line)) {
    const auto j = nlohmann::json::parse(line);
    if (j.value("kind", "") != "q" || !j["utterance"].is_string()) continue;
    const std::string status = j.value("status", "");
    const std::string u = j["utterance"];
    if (status == "Core") {
      ++core_total;
      auto r = st.parse(u);
      if (!r.candidates.empty() && r.candidates.front().core_only)
        ++core_ok;
      else {
        ++failures["core not parsed: " + j.value("syntax", "")];
        std::cout << "core query not parsed: " << u << "\n";
      }
    } else if (status == "Nothing" && j.value("group", "") == "A") {
      ++nothing_total;
      auto r = st.parse(u);
      if (r.candidates.empty())
        ++nothing_ok;
      else {
        ++failures["nothing parsed: " + j.value("syntax", "")];
        std::cout << "group-A Nothing parsed: " << u << "  =>  "
                  << sdk::render(r.candidates.front().program) << "\n";
      }
    }
  }
  std::cout << "corpus: Core parsed as core " << core_ok << "/" << core_total
            << "; group-A Nothing unparsable " << nothing_ok << "/" << nothing_total << "\n";
  for (const auto& [k, v] : failures) std::cout << "  " << k << ": " << v << "\n";
  REQUIRE(core_total > 1000);
  REQUIRE(nothing_total > 100);
  CHECK(core_ok == core_total);  // measured: 2059/2059
  // measured 192/193: the one left mixes `has color` and `is` ([decision] synonyms).
  CHECK(nothing_ok + 1 >= nothing_total);
}
