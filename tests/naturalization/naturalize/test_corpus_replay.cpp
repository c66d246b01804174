// Real definitions (corpus/dev/definitions.jsonl) replayed per run through the session protocol:
// how many are accepted, and how many heads parse right after their definition. Each run gets a
// fresh lexicon with its group's sharing mode (A core, B private, C shared) and alignment off,
// as the 2018 study ran; preloaded expert definitions come first; every definition is made in
// the world it was made in. Floors are the figures measured when this test was written.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "naturalize_fixture.hpp"

using namespace flipper;
using namespace flipper::naturalizetest;
using kernel::Json;

namespace {

std::vector<Json> read_jsonl(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::vector<Json> out;
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) out.push_back(Json::parse(line));
  return out;
}

Json world_object(const Json& w) {
  Json out;
  for (const char* k : {"walls", "items", "robot", "rooms", "bounds"})
    if (w.contains(k)) out[k] = w[k];
  return out;
}

}  // namespace

TEST_CASE("replay of the corpus definitions", "[naturalize][corpus]") {
  const std::string dir = std::string(FLIPPER_STUDY_DIR) + "/dev/";
  std::map<std::string, Json> worlds;
  for (auto& w : read_jsonl(dir + "worlds.jsonl")) worlds[w["world_id"]] = world_object(w);

  // Runs in first-appearance order; within a run the preloaded definitions first, then file order.
  std::vector<std::string> runs;
  std::map<std::string, std::vector<Json>> by_run;
  for (auto& d : read_jsonl(dir + "definitions.jsonl")) {
    const std::string run = d["source"];
    if (!by_run.count(run)) runs.push_back(run);
    by_run[run].push_back(d);
  }

  int total = 0, accepted = 0, head_parses = 0;
  std::map<std::string, int> classes;
  for (const auto& run : runs) {
    auto defs = by_run[run];
    std::stable_partition(defs.begin(), defs.end(),
                          [](const Json& d) { return d["origin"] == "preloaded"; });
    std::string group = "B";
    for (const auto& d : defs)
      if (d["group"] != "expert") group = d["group"];
    const std::string sharing = group == "A" ? "core" : group == "C" ? "shared" : "private";
    auto s = open(scratch_path("replay") + ".sqlite",
                  {"lexicon.sharing=" + sharing, "induction.alignment=false"});
    for (const auto& d : defs) {
      ++total;
      if (d.contains("world_id") && d["world_id"].is_string() && worlds.count(d["world_id"]))
        REQUIRE(s->handle({{"op", "world"}, {"world", worlds[d["world_id"]]}})["ok"] == true);
      user(*s, d["user"]);
      std::vector<std::string> body;
      for (const auto& line : d["body"]) body.push_back(line["utterance"]);
      const Json a = define(*s, d["head"], body);
      if (a["ok"] != true) {
        classes["refused: " + error_code(a)]++;
        if (std::getenv("REPLAY_VERBOSE"))
          std::cout << run << " | " << d["head"] << " := " << Json(body).dump() << " -> "
                    << a["error"]["message"] << "\n";
        continue;
      }
      ++accepted;
      const std::string st = status(*s, d["head"]);
      if (st == "induced") {
        ++head_parses;
      } else if (a["rules"].empty()) {
        classes["accepted, no rule (packings over 4 categories, or duplicates), head " + st]++;
        if (std::getenv("REPLAY_VERBOSE"))
          std::cout << run << " | " << d["head"] << " := " << Json(body).dump() << " (no rule)\n";
      } else if (sharing == "core") {
        classes["accepted, core mode hides induced rules"]++;
      } else {
        classes["accepted, head " + st]++;
      }
    }
  }
  std::cout << "corpus replay: " << total << " definitions, " << accepted << " accepted, "
            << head_parses << " heads parse right after their definition\n";
  for (const auto& [k, v] : classes) std::cout << "  " << v << "  " << k << "\n";
  CHECK(total == 300);
  // Measured: 274 accepted, 273 heads parse. Refused: 24 body_unparsable (body lines using
  // phrases no core rule or earlier definition of the run covers, e.g. `pick every red item`,
  // `visit empty space`, `get all red items`: the original fell back to the client's formula),
  // 2 head_is_core. The one accepted head that does not parse packs 6 categories.
  CHECK(accepted >= 274);
  CHECK(head_parses >= 273);
}
