// Protocol 2 (docs/protocol.md § "Protocol versions"): world versions and change-only worlds. The
// oracle is the world plugin itself: every world a session answers with (the world op's, each
// candidate's, each accept's, the state's) must equal the plugin's own text for that state, in the
// full form, and a client that applies the change-only answers must rebuild exactly that world —
// over every request of the whole dev corpus.
#include <catch2/catch.hpp>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "dev_stream.hpp"
#include "session_fixture.hpp"

using flipper::kernel::Json;
using flipper::testsupport::ask;
using flipper::testsupport::dev_stream;
using flipper::testsupport::error_code;
using Plain = nlohmann::json;  // key order does not matter when comparing worlds

namespace {

// What a protocol-2 client keeps: the geometry of each version it was sent.
struct Client {
  std::map<std::uint64_t, Plain> geometry;
  std::uint64_t current = 0;
  // Takes the version (and geometry) of an answer; false when it names an unknown version.
  bool take(const Plain& answer) {
    if (!answer.contains("world_version")) return false;
    current = answer["world_version"].get<std::uint64_t>();
    if (answer.contains("geometry")) geometry[current] = answer["geometry"];
    return geometry.count(current) == 1;
  }
  Plain rebuild(const Plain& changes) const {
    Plain w = geometry.at(current);
    for (const auto& [k, v] : changes.items()) w[k] = v;
    return w;
  }
};

Plain plugin_text(flipper::kernel::Session& s, const flipper::sdk::WorldState& state) {
  return Plain::parse(s.runtime().world.borrow()->save(state));
}

}  // namespace

TEST_CASE("change-only answers rebuild the plugin's worlds over the whole dev corpus",
          "[session][protocol2][corpus]") {
  const auto stream = dev_stream();
  REQUIRE(stream.size() > 8000);
  auto full = flipper::wiring::open_session(std::nullopt, flipper::testsupport::test_overrides());
  auto changes =
      flipper::wiring::open_session(std::nullopt, flipper::testsupport::test_overrides());
  REQUIRE(ask(*changes, R"({"op":"hello","protocol":2})")["protocol"] == 2);
  Client client;
  std::size_t worlds_checked = 0, geometries_sent = 0;
  for (const auto& line : stream) {
    INFO(line.substr(0, 200));
    Plain a = Plain::parse(full->handle_line(line));
    Plain b = Plain::parse(changes->handle_line(line));
    REQUIRE(a["ok"] == b["ok"]);
    if (a["ok"] != true) {
      CHECK(a["error"]["code"] == b["error"]["code"]);
      continue;
    }
    const std::string op = a["op"];
    CHECK_FALSE(a.contains("world_version"));  // protocol 1 answers are unchanged
    if (op == "world" || op == "state" || op == "accept") {
      if (b.contains("geometry")) ++geometries_sent;
      REQUIRE(client.take(b));
      const Plain expected = plugin_text(*full, full->world());
      CHECK(a["world"] == expected);
      CHECK(client.rebuild(b["world"]) == expected);
      CHECK_FALSE(b["world"].contains("walls"));
      ++worlds_checked;
    } else if (op == "query") {
      REQUIRE(a["candidates"].size() == b["candidates"].size());
      if (a["candidates"].empty()) continue;
      REQUIRE(client.take(b));
      const auto& shown = full->last_query()->shown;
      for (std::size_t i = 0; i < shown.size(); ++i) {
        const Plain expected = plugin_text(*full, shown[i].outcome.world);
        CHECK(a["candidates"][i]["world"] == expected);
        CHECK(client.rebuild(b["candidates"][i]["world"]) == expected);
        CHECK_FALSE(b["candidates"][i]["world"].contains("walls"));
        CHECK(a["candidates"][i]["formula"] == b["candidates"][i]["formula"]);
        ++worlds_checked;
      }
    }
  }
  CHECK(worlds_checked > 7000);
  // The corpus uses a handful of maps: geometry goes out once per map (and on each `state`),
  // not with every world op.
  CHECK(geometries_sent < worlds_checked / 20);
}

TEST_CASE("hello selects the protocol and refuses unknown versions", "[session][protocol2]") {
  auto s = flipper::testsupport::bare_session();
  Json a = ask(*s, R"({"op":"hello"})");
  CHECK(a["protocol"] == 1);
  CHECK(a["protocols"] == Json::parse("[1,2]"));
  CHECK(error_code(ask(*s, R"({"op":"hello","protocol":3})")) == "bad_request");
  CHECK(ask(*s, R"({"op":"hello"})")["protocol"] == 1);  // a refused hello changes nothing
  CHECK(ask(*s, R"({"op":"hello","protocol":2})")["protocol"] == 2);
}

TEST_CASE("a world version is kept for the same map and renewed for another",
          "[session][protocol2]") {
  auto s = flipper::testsupport::bare_session();
  ask(*s, R"({"op":"hello","protocol":2})");
  const std::string map1 =
      R"({"walls":[[0,0],[1,0],[2,0],[0,2],[1,2],[2,2]],"items":[],"robot":{"x":1,"y":1,"holding":[]}})";
  // Same walls, another robot cell and an item: the same version, no geometry again.
  const std::string map1b =
      R"({"walls":[[0,0],[1,0],[2,0],[0,2],[1,2],[2,2]],"items":[{"x":2,"y":1,"color":"red","shape":"circle"}],"robot":{"x":0,"y":1,"holding":[]}})";
  const std::string map2 =
      R"({"walls":[[0,0],[1,0],[2,0],[0,2],[1,2]],"items":[],"robot":{"x":1,"y":1,"holding":[]}})";
  Json a = ask(*s, R"({"op":"world","world":)" + map1 + "}");
  REQUIRE(a["ok"] == true);
  CHECK(a["geometry"]["walls"].size() == 6);
  CHECK(a["world"] == Json::parse(R"({"items":[],"robot":{"x":1,"y":1,"holding":[]}})"));
  const auto v1 = a["world_version"];
  Json b = ask(*s, R"({"op":"world","world":)" + map1b + "}");
  CHECK(b["world_version"] == v1);
  CHECK_FALSE(b.contains("geometry"));
  CHECK(b["world"]["robot"]["x"] == 0);
  Json c = ask(*s, R"({"op":"world","world":)" + map2 + "}");
  CHECK(c["world_version"] != v1);
  CHECK(c["geometry"]["walls"].size() == 5);
  // state always carries the geometry (a client resyncs with it).
  Json d = ask(*s, R"({"op":"state"})");
  CHECK(d["world_version"] == c["world_version"]);
  CHECK(d["geometry"] == c["geometry"]);
}

TEST_CASE("protocol 1 answers carry no world version", "[session][protocol2]") {
  auto s = flipper::testsupport::bare_session();
  Json a = ask(*s, R"({"op":"state"})");
  CHECK_FALSE(a.contains("world_version"));
  CHECK_FALSE(a.contains("geometry"));
  CHECK(a["world"].contains("walls"));
}
