// world / user / state / query / accept on the study map, through the protocol.
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "flipper/sdk/canonical.hpp"
#include "session_fixture.hpp"

using flipper::kernel::Json;
using flipper::testsupport::ask;
using flipper::testsupport::error_code;

namespace {

const char* kSmallWorld = R"({"walls":[[0,0],[1,0],[2,0],[0,1],[2,1],[0,2],[1,2],[2,2]],
  "items":[{"x":1,"y":1,"color":"red","shape":"circle"}],
  "robot":{"x":1,"y":1,"holding":[]},"rooms":{}})";

Json robot_cell(const Json& world) {
  return Json::array({world["robot"]["x"], world["robot"]["y"]});
}

}  // namespace

TEST_CASE("world replaces the current world and answers it normalised", "[session][ops]") {
  auto s = flipper::testsupport::bare_session();
  Json a = ask(*s, Json{{"op", "world"}, {"world", Json::parse(kSmallWorld)}, {"id", 1}}.dump());
  REQUIRE(a["ok"] == true);
  const Json& w = a["world"];
  CHECK(robot_cell(w) == Json::parse("[1,1]"));
  REQUIRE(w["items"].size() == 1);
  CHECK(w["items"][0].contains("id"));  // ids are assigned
  CHECK(w.contains("bounds"));
  CHECK(ask(*s, R"({"op":"state"})")["world"] == w);

  // From a file: the same world comes back.
  std::string path = flipper::testsupport::scratch_path("world") + ".json";
  std::ofstream(path) << kSmallWorld;
  Json b = ask(*s, Json{{"op", "world"}, {"file", path}}.dump());
  REQUIRE(b["ok"] == true);
  CHECK(b["world"] == w);
}

TEST_CASE("a malformed world is bad_world and the old world stays", "[session][ops]") {
  auto s = flipper::testsupport::bare_session();
  const Json before = ask(*s, R"({"op":"state"})")["world"];
  Json on_wall = Json::parse(kSmallWorld);
  on_wall["robot"]["x"] = 0;
  Json a = ask(*s, Json{{"op", "world"}, {"world", on_wall}}.dump());
  CHECK(a["ok"] == false);
  CHECK(error_code(a) == "bad_world");
  a = ask(*s, R"({"op":"world","file":"/nonexistent/world.json"})");
  CHECK(error_code(a) == "bad_world");
  CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains("/nonexistent/world.json"));
  CHECK(ask(*s, R"({"op":"state"})")["world"] == before);
}

TEST_CASE("user sets the current user, default anonymous", "[session][ops]") {
  auto s = flipper::testsupport::bare_session();
  CHECK(s->user() == "anonymous");
  Json a = ask(*s, R"({"op":"user","name":"ana","id":"u"})");
  CHECK(a == Json::parse(R"({"ok":true,"op":"user","id":"u","name":"ana"})"));
  CHECK(s->user() == "ana");
}

TEST_CASE("query answers carry every field, planned on a copy", "[session][ops]") {
  auto s = flipper::testsupport::bare_session();
  const Json before = ask(*s, R"({"op":"state"})")["world"];
  const auto t0 = std::chrono::steady_clock::now();
  Json a = ask(*s, R"({"op":"query","text":"visit world containing item is red","id":3})");
  const double elapsed_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  REQUIRE(a["ok"] == true);
  CHECK(a["id"] == 3);
  CHECK(a["status"] == "core");
  // `ms` is the query's own time in milliseconds: within what the caller measured around it.
  REQUIRE(a["ms"].is_number());
  CHECK(a["ms"].get<double>() <= elapsed_ms);
  const Json& cands = a["candidates"];
  REQUIRE(!cands.empty());
  CHECK(cands.size() <= 3);
  double prob_sum = 0, last_prob = 2;
  for (std::size_t i = 0; i < cands.size(); ++i) {
    const Json& c = cands[i];
    for (const char* key : {"rank", "score", "prob", "formula", "induced", "rules", "authors",
                            "realizable", "trace", "world", "warnings"})
      CHECK(c.contains(key));
    CHECK(c["rank"] == i);
    CHECK(c["induced"] == false);
    CHECK(c["rules"].empty());
    // The formula is canonical text that reads back to itself.
    const std::string formula = c["formula"].get<std::string>();
    CHECK(flipper::sdk::render(flipper::sdk::read_canonical(formula)) == formula);
    prob_sum += c["prob"].get<double>();
    CHECK(c["prob"].get<double>() <= last_prob + 1e-12);
    last_prob = c["prob"].get<double>();
  }
  CHECK(prob_sum <= 1.0 + 1e-9);
  // Example 1 of core-language §10: five steps east to (7,4).
  const Json& best = cands[0];
  CHECK(best["formula"] == "{visit {world containing item {is red}}}");
  CHECK(best["realizable"] == true);
  REQUIRE(best["trace"].size() == 5);
  CHECK(best["trace"][0] == Json::parse(R"({"act":"move","to":[3,4]})"));
  CHECK(best["trace"][4] == Json::parse(R"({"act":"move","to":[7,4]})"));
  CHECK(robot_cell(best["world"]) == Json::parse("[7,4]"));
  // Planning happened on a copy.
  CHECK(ask(*s, R"({"op":"state"})")["world"] == before);

  Json k1 = ask(*s, R"({"op":"query","text":"visit world containing item is red","k":1})");
  CHECK(k1["candidates"].size() == 1);
}

TEST_CASE("an utterance that does not parse is unparsable", "[session][ops]") {
  auto s = flipper::testsupport::bare_session();
  Json a = ask(*s, R"({"op":"query","text":"make me a sandwich please"})");
  REQUIRE(a["ok"] == true);
  CHECK(a["status"] == "unparsable");
  CHECK(a["candidates"].empty());
}

TEST_CASE("accept executes the candidate on the current world", "[session][ops]") {
  auto s = flipper::testsupport::bare_session();
  Json q =
      ask(*s, R"({"op":"query","text":"visit world containing item is red ; pick item is red"})");
  REQUIRE(q["ok"] == true);
  REQUIRE(!q["candidates"].empty());
  Json a = ask(*s, R"({"op":"accept","rank":0,"id":9})");
  REQUIRE(a["ok"] == true);
  CHECK(a["id"] == 9);
  CHECK(a["world"] == q["candidates"][0]["world"]);
  CHECK(a["trace"] == q["candidates"][0]["trace"]);
  CHECK(a["warnings"].empty());
  const Json& last = a["trace"].back();
  CHECK(last["act"] == "pick");
  CHECK(last["item"]["color"] == "red");
  CHECK(a["world"]["robot"]["holding"].size() == 1);
  CHECK(ask(*s, R"({"op":"state"})")["world"] == a["world"]);
}

TEST_CASE("handle_line and handle give the same answers (worlds spliced as text)",
          "[session][ops]") {
  auto line_session = flipper::testsupport::bare_session();
  auto tree_session = flipper::testsupport::bare_session();
  for (const char* text :
       {R"({"op":"query","text":"visit room1 or room2 containing item","k":5,"id":"\u0001w1:0"})",
        R"({"op":"accept","rank":1})", R"({"op":"state"})",
        R"({"op":"query","text":"move down ; move down"})"}) {
    INFO(text);
    Json from_line = ask(*line_session, text);
    Json from_tree = tree_session->handle(Json::parse(text));
    from_line.erase("ms");
    from_tree.erase("ms");
    CHECK(from_line == from_tree);
    CHECK(from_line["ok"] == true);
  }
}
