// Study mode over HTTP against the real binary (docs/studio.md §7): every record kind with its
// fields, participants enrolled as accounts and resumed by their login cookie, the researcher's
// endpoints (401/403/200, downloads, close), page events, a restart that continues the
// numbering, one kernel per group under concurrent participants, and `flipper replay verify` on
// the recording (equal, one byte changed, a bad folder).
#include <sys/inotify.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "flipper/corpus/answer_digest.hpp"
#include "flipper/record/checksum.hpp"
#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The SHA-256 of `text` by coreutils' sha256sum: an implementation independent of the libsodium
// the server and flipper_record hash with.
std::string coreutils_sha256(const std::string& text, const fs::path& scratch) {
  const fs::path file = scratch / "sha256-input";
  std::ofstream(file, std::ios::binary) << text;
  const CliRun r = run_shell("sha256sum '" + file.string() + "'");
  REQUIRE(r.status == 0);
  REQUIRE(r.out.size() >= 64);
  return r.out.substr(0, 64);
}

std::vector<json> read_jsonl(const fs::path& path) {
  std::vector<json> out;
  std::istringstream in(read_file(path));
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(json::parse(line));
  return out;
}

json world_file() {
  return json::parse(read_file(fs::path(FLIPPER_SOURCE_DIR) / "configs/worlds/study2018.json"));
}

// A study with groups B and C in `dir`: task 0's goal is the start with the robot one step right.
std::string make_study(const std::string& dir) {
  json start = world_file();
  json goal = start;
  goal["robot"] = {{"x", 3}, {"y", 4}, {"holding", json::array()}};
  std::ofstream(dir + "/start.json") << start.dump();
  std::ofstream(dir + "/goal.json") << goal.dump();
  std::ofstream(dir + "/experts.jsonl")
      << json{{"head", "go to red"}, {"body", {"visit world containing item is red"}}}.dump()
      << "\n";
  std::ofstream(dir + "/study.yaml")
      << "name: t\ngroups: [B, C]\npreload: experts.jsonl\nrecord: rec\ntasks:\n"
         "  - {name: one, text: right, start: start.json, goal: goal.json}\n"
         "  - {name: two, text: more, start: start.json}\n";
  return "serve.study=" + dir + "/study.yaml";
}

struct Participant {
  httplib::Client& http;
  httplib::Headers headers;  ///< the login cookie once enrolled
  std::string session;
  std::string group;
  std::string goal = {};  ///< the last reply's Flipper-Goal header
  Reply send(const json& request) {
    Reply r = post(http, session, request.dump(), headers, group);
    if (!r.session.empty()) session = r.session;
    if (!r.set_cookie.empty()) headers = cookie(r.set_cookie.substr(0, r.set_cookie.find(';')));
    goal = r.goal;
    return r;
  }
  json info() {
    auto res = http.Get(("/api/v1/info?session=" + session).c_str(), headers);
    REQUIRE(res);
    return json::parse(res->body);
  }
  int event(const json& body) {
    auto res = http.Post(("/api/v1/study/event?session=" + session).c_str(), headers, body.dump(),
                         "application/json");
    REQUIRE(res);
    return res->status;
  }
};

std::vector<json> of_kind(const std::vector<json>& lines, const std::string& kind) {
  std::vector<json> out;
  for (const auto& l : lines)
    if (l["kind"] == kind) out.push_back(l);
  return out;
}

TEST_CASE("answer_for_digest removes the ms members only") {
  CHECK(corpus::answer_for_digest(R"({"ok":true,"ms":12.5,"x":1})") == R"({"ok":true,"x":1})");
  CHECK(corpus::answer_for_digest(R"({"a":{"b":2,"ms":-1e-3},"ms":7})") == R"({"a":{"b":2}})");
  // Inside a string the quotes are escaped: kept.
  CHECK(corpus::answer_for_digest(R"({"t":"x\",\"ms\":5"})") == R"({"t":"x\",\"ms\":5"})");
  CHECK(corpus::answer_for_digest(R"({"ms":3,"a":1})") == R"({"ms":3,"a":1})");  // no comma
  CHECK(corpus::answer_for_digest(R"({"a":1,"ms":"x"})") == R"({"a":1,"ms":"x"})");
}

// `flipper serve` with `sets`, bounded by `timeout` in case a regression lets it start serving:
// its exit status and output.
CliRun serve_refusal(const std::string& dir, const std::string& sets) {
  return run_shell("cd " + dir + " && timeout 60 " + std::string(FLIPPER_BINARY_DIR) +
                   "/bin/flipper serve --set serve.port=0 --set lexicon.path=:memory: " + sets +
                   " </dev/null 2>&1");
}

TEST_CASE("a study file or task world that is no bounded regular file is refused bad_config") {
  const std::string dir = fresh_dir("study-bounds");
  const auto started = std::chrono::steady_clock::now();
  CliRun r = serve_refusal(dir, "--set serve.study=/dev/zero");
  CHECK(r.status == 2);
  CHECK_THAT(r.out, Catch::Contains("[bad_config]") && Catch::Contains("study file") &&
                        Catch::Contains("/dev/zero"));
  // An alias bomb: 9 levels of 10 aliases expand to 10^9 nodes.
  {
    std::ofstream bomb(dir + "/bomb.yaml");
    bomb << "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
    for (int i = 1; i <= 9; ++i) {
      bomb << "a" << i << ": &a" << i << " [";
      for (int j = 0; j < 10; ++j) bomb << (j ? ", " : "") << "*a" << (i - 1);
      bomb << "]\n";
    }
  }
  r = serve_refusal(dir, "--set serve.study=" + dir + "/bomb.yaml");
  CHECK(r.status == 2);
  CHECK_THAT(r.out, Catch::Contains("[bad_config]") && Catch::Contains("100000 nodes"));
  // A task whose start world is a device.
  std::ofstream(dir + "/study.yaml") << "name: t\ngroups: [B]\ntasks:\n"
                                        "  - {name: one, text: x, start: /dev/zero}\n";
  r = serve_refusal(dir, "--set serve.study=" + dir + "/study.yaml");
  CHECK(r.status == 2);
  CHECK_THAT(r.out, Catch::Contains("[bad_config]") && Catch::Contains("/dev/zero") &&
                        Catch::Contains("regular file"));
  // Each refusal is immediate, not a read of an endless device or an expansion of 10^9 nodes.
  CHECK(std::chrono::steady_clock::now() - started < std::chrono::seconds(30));
}

TEST_CASE("a study records every participant action with its fields and replays byte for byte") {
  const std::string dir = fresh_dir("study-record");
  const std::string study = make_study(dir);
  const fs::path rec = fs::path(dir) / "rec";
  {
    StudioServer server(dir, {study});
    auto http = server.client();
    Participant p1{http, {}, "", "B"};
    // A guest is enrolled as account P1 with a login cookie.
    Reply r = p1.send({{"op", "world"},
                       {"world", world_file()},
                       {"studio", {{"why", "task_start"}, {"task", 0}}}});
    REQUIRE(r.body["ok"] == true);
    CHECK(r.user == "P1");
    REQUIRE(p1.headers.size() == 1);
    CHECK(p1.send({{"op", "query"}, {"text", "move right"}}).body["status"] == "core");
    REQUIRE(p1.send({{"op", "accept"}, {"rank", 0}}).body["ok"] == true);
    CHECK(p1.goal == "reached");
    REQUIRE(p1.send({{"op", "define"}, {"head", "hop"}, {"body", {"move up"}}}).body["ok"] == true);
    REQUIRE(p1.send({{"op", "define"},
                     {"head", "hop"},
                     {"body", {{{"text", "move left"}, {"formula", "{move left}"}}}}})
                .body["ok"] == true);
    r = p1.send({{"op", "query"}, {"text", "hop"}, {"studio", {{"why", "live"}}}});
    REQUIRE(r.body["candidates"].size() == 2);
    CHECK(r.body["candidates"][1]["formula"] == "{move up}");
    r = p1.send(
        {{"op", "define"}, {"head", "zig"}, {"body", {"move right", "hop"}}, {"ranks", {0, 1}}});
    REQUIRE(r.body["ok"] == true);
    CHECK(r.body["rules"][0]["semantics"] == "{{move right};{move up}}");
    const std::string zig_rule = r.body["rules"][0]["id"];
    r = p1.send({{"op", "query"}, {"text", "zig"}, {"studio", {{"why", "rerun"}}}});
    CHECK(r.body["status"] == "induced");
    CHECK(p1.event({{"kind", "flip"}, {"rank", 0}, {"formula", "{{move right};{move up}}"}}) ==
          200);
    CHECK(p1.event({{"kind", "reject"}}) == 200);
    REQUIRE(p1.send({{"op", "delete_rule"}, {"rule", zig_rule}}).body["ok"] == true);
    REQUIRE(p1.send({{"op", "query"}, {"text", "move up"}}).body["ok"] == true);
    REQUIRE(p1.send({{"op", "accept"}, {"rank", 0}}).body["ok"] == true);
    CHECK(p1.goal.empty());  // reached before: said once
    REQUIRE(p1.send({{"op", "world"}, {"world", world_file()}, {"studio", {{"why", "undo"}}}})
                .body["ok"] == true);
    // info: the participant's place, not the condition.
    const json info = p1.info();
    CHECK(info["sharing"].is_null());
    CHECK_FALSE(info["study"].contains("group"));
    CHECK_FALSE(info["study"].contains("sharing"));
    CHECK(info["study"]["participant"] == "P1");
    CHECK(info["study"]["teaching"] == true);
    CHECK(info["study"]["task"] == 0);
    CHECK(info["study"]["goal_reached"] == true);
    REQUIRE(info["study"]["history"].size() == 1);  // two accepts, one undone
    CHECK(info["study"]["history"][0]["utterance"] == "move right");
    CHECK(info["study"]["history"][0]["world"]["robot"]["x"] == 3);
    // Next task without the goal of task 1: task_start only; then a skip of task 1.
    REQUIRE(p1.send({{"op", "world"},
                     {"world", world_file()},
                     {"studio", {{"why", "task_start"}, {"task", 1}}}})
                .body["ok"] == true);
    Participant p2{http, {}, "", "C"};
    CHECK(p2.send({{"op", "query"}, {"text", "go to green"}}).body["status"] == "induced");
    CHECK(p2.send({{"op", "query"}, {"text", "move lfet"}}).body["status"] == "unparsable");
    CHECK(p2.event({{"kind", "page_load"}, {"reloaded", true}}) == 200);
    for (int task : {0, 1})  // task 0 left without its goal: skipped
      REQUIRE(p2.send({{"op", "world"},
                       {"world", world_file()},
                       {"studio", {{"why", "task_start"}, {"task", task}}}})
                  .body["ok"] == true);
  }
  const auto lines = read_jsonl(rec / "queries.jsonl");
  std::vector<std::string> kinds;
  for (const auto& l : lines)
    if (l["participant"] == "P1") kinds.push_back(l["kind"]);
  CHECK(kinds == std::vector<std::string>{"session_start", "task_start", "q", "accept", "goal",
                                          "def", "def", "live", "def", "rerun", "flip", "reject",
                                          "delete", "q", "accept", "undo", "task_start"});
  for (std::size_t i = 0; i < lines.size(); ++i) {
    INFO(lines[i].dump());
    CHECK(lines[i]["line"] == i + 1);
    CHECK(lines[i]["qid"] == lines[i]["source"].get<std::string>() + "#" + std::to_string(i + 1));
    for (const char* key : {"participant", "group", "task", "time", "phase", "account", "exchange"})
      CHECK(lines[i].contains(key));
  }
  const auto defs = of_kind(lines, "def");
  REQUIRE(defs.size() == 3);
  CHECK(defs[0]["body"] == json::parse(R"([{"utterance":"move up","formula":"","rank":0}])"));
  CHECK(defs[1]["body"] == json::parse(R"([{"utterance":"move left","formula":"{move left}"}])"));
  CHECK(defs[2]["body"][1] == json::parse(R"({"utterance":"hop","formula":"","rank":1})"));
  const auto del = of_kind(lines, "delete");
  REQUIRE(del.size() == 1);
  CHECK(del[0]["def_id"] == defs[2]["def_id"]);
  CHECK(del[0]["rule_pos"] == 0);
  const auto goal = of_kind(lines, "goal");
  REQUIRE(goal.size() == 1);
  CHECK(goal[0]["task"] == 0);
  CHECK(goal[0]["for_qid"] == of_kind(lines, "accept")[0]["qid"]);
  // P1 reached task 0's goal before the next task: no skip; P2 did not.
  const auto skips = of_kind(lines, "task_skip");
  REQUIRE(skips.size() == 1);
  CHECK(skips[0]["participant"] == "P2");
  CHECK(skips[0]["task"] == 0);
  const auto reject = of_kind(lines, "reject");
  REQUIRE(reject.size() == 1);
  CHECK(reject[0]["utterance"] == "zig");
  CHECK(reject[0]["formulas"] == json::array({"{{move right};{move up}}"}));
  CHECK(reject[0]["exchange"].is_null());
  CHECK(of_kind(lines, "page_load").at(0)["reloaded"] == true);
  const auto q = of_kind(lines, "q");
  REQUIRE(q.size() == 4);  // the live check and the re-run are not participant queries
  CHECK(q[2]["participant"] == "P2");
  CHECK(q[2]["phase"] == "tutorial");
  CHECK(q[2]["task"] == -1);
  CHECK(q[0]["task_name"] == "one");
  // definitions.jsonl: the induced rules with their semantics.
  const auto definitions = read_jsonl(rec / "definitions.jsonl");
  bool zig_found = false;
  for (const auto& d : definitions)
    if (d["head"] == "zig") {
      zig_found = true;
      CHECK(d["induced_rules"][0]["semantics"] == "{{move right};{move up}}");
    }
  CHECK(zig_found);
  // exchanges.jsonl: every request, the SHA-256 of the answer without ms (coreutils' sha256sum,
  // an implementation independent of the server's libsodium).
  const auto exchanges = read_jsonl(rec / "exchanges.jsonl");
  CHECK(exchanges.size() == 17);  // P1: 13 requests; P2: 4
  for (std::size_t i = 0; i < exchanges.size(); ++i) {
    CHECK(exchanges[i]["n"] == i + 1);
    CHECK(exchanges[i]["sha256"] ==
          coreutils_sha256(corpus::answer_for_digest(exchanges[i]["answer"].get<std::string>()),
                           dir));
  }
  CHECK(exchanges[1]["qid"] == q[0]["qid"]);
  CHECK(json::parse(exchanges[1]["request"].get<std::string>())["text"] == "move right");
  // participants.json: both, with counts.
  const json parts = json::parse(read_file(rec / "participants.json"));
  REQUIRE(parts["participants"].size() == 2);
  CHECK(parts["participants"][0]["counts"]["q"] == 2);
  CHECK(parts["participants"][0]["counts"]["live"] == 1);
  CHECK(parts["participants"][0]["task"] == 1);
  CHECK(parts["participants"][1]["group"] == "C");

  // flipper replay verify: equal; one answer byte changed; the change with its hash redone.
  const CliRun ok = run_flipper("replay verify " + rec.string(), dir);
  INFO(ok.out);
  CHECK(ok.status == 0);
  CHECK(ok.out.find("17 exchanges, every answer equal byte for byte") != std::string::npos);
  auto corrupt = [&](const std::string& name, bool rehash) {
    const fs::path copy = fs::path(dir) / name;
    fs::copy(rec, copy, fs::copy_options::recursive);
    auto ex = read_jsonl(copy / "exchanges.jsonl");
    std::string answer = ex[1]["answer"];
    const auto at = answer.find("\"core\"");
    REQUIRE(at != std::string::npos);
    answer[at + 1] = 'k';  // "kore"
    ex[1]["answer"] = answer;
    if (rehash) ex[1]["sha256"] = record::sha256_text(corpus::answer_for_digest(answer));
    std::ofstream out(copy / "exchanges.jsonl", std::ios::trunc);
    for (const auto& e : ex) out << e.dump() << "\n";
    return copy;
  };
  CliRun bad = run_flipper("replay verify " + corrupt("changed", false).string(), dir);
  CHECK(bad.status == 1);
  CHECK(bad.out.find("exchange 2 (participant P1, group B") != std::string::npos);
  CHECK(bad.out.find("does not match its recorded sha256") != std::string::npos);
  bad = run_flipper("replay verify " + corrupt("rehashed", true).string(), dir);
  CHECK(bad.status == 1);
  CHECK(bad.out.find("exchange 2 (participant P1, group B, qid \"studio/t/B#3\", op query) differs "
                     "at byte 34") != std::string::npos);
  CHECK(bad.out.find("differs at byte") != std::string::npos);
  CHECK(bad.out.find("live:    {\"ok\":true,\"op\":\"query\",\"status\":\"kore\"") !=
        std::string::npos);
  CHECK(bad.out.find("replay:  {\"ok\":true,\"op\":\"query\",\"status\":\"core\"") !=
        std::string::npos);
  const CliRun missing = run_flipper("replay verify " + dir + "/nothing-here", dir);
  CHECK(missing.status == 2);
  CHECK(missing.out.find("[bad_corpus]") != std::string::npos);
}

TEST_CASE("participants resume by their login, and the researcher sees and closes the study") {
  const std::string dir = fresh_dir("study-resume");
  const std::string study = make_study(dir);
  httplib::Headers p1_cookie;
  {
    StudioServer server(dir, {study});
    server.add_account("mod", "moderator password", "admin");
    server.add_account("ana", "ana's password");
    auto http = server.client();
    Participant p1{http, {}, "", "C"};
    REQUIRE(p1.send({{"op", "world"},
                     {"world", world_file()},
                     {"studio", {{"why", "task_start"}, {"task", 0}}}})
                .body["ok"] == true);
    REQUIRE(p1.send({{"op", "query"}, {"text", "move up"}}).body["ok"] == true);
    REQUIRE(p1.send({{"op", "accept"}, {"rank", 0}}).body["ok"] == true);
    p1_cookie = p1.headers;
    // Another tab: no session token, the same cookie -> the same participant and world.
    Participant again{http, p1.headers, "", "", ""};
    Reply r = again.send({{"op", "state"}});
    CHECK(r.user == "P1");
    CHECK(r.session != p1.session);
    CHECK(r.body["world"]["robot"]["y"] == 5);  // moved up from (2,4)
    CHECK(again.info()["study"]["task"] == 0);
    CHECK(again.info()["study"]["history"].size() == 1);
    // The old session's rules stay the participant's own (same account).
    // The researcher: 401 without a login, 403 for a user, 200 for an admin.
    CHECK(http.Get("/api/v1/study/overview")->status == 401);
    const auto ana = cookie(login(http, json{{"name", "ana"}, {"password", "ana's password"}}));
    CHECK(http.Get("/api/v1/study/overview", ana)->status == 403);
    const auto mod = cookie(login(http, json{{"name", "mod"}, {"password", "moderator password"}}));
    auto res = http.Get("/api/v1/study/overview", mod);
    REQUIRE(res->status == 200);
    const json o = json::parse(res->body);
    CHECK(o["study"]["open"] == true);
    REQUIRE(o["participants"].size() == 1);
    CHECK(o["participants"][0]["participant"] == "P1");
    CHECK(o["participants"][0]["group"] == "C");
    CHECK(o["participants"][0]["task_name"] == "one");
    CHECK(o["participants"][0]["online"] == true);
    CHECK(o["participants"][0]["counts"]["accept"] == 1);
    // Downloads: the allowlist only.
    res = http.Get("/api/v1/study/recording/queries.jsonl", mod);
    REQUIRE(res->status == 200);
    CHECK(res->get_header_value("Content-Disposition") == "attachment; filename=\"queries.jsonl\"");
    CHECK(res->get_header_value("Content-Type") == "application/x-ndjson");
    CHECK(res->body == read_file(fs::path(dir) / "rec" / "queries.jsonl"));
    for (const char* name : {"lexicon-C.sqlite", "..%2Fstudy.yaml", "../study.yaml", "x"})
      CHECK(http.Get((std::string("/api/v1/study/recording/") + name).c_str(), mod)->status == 404);
    CHECK(http.Get("/api/v1/study/recording/queries.jsonl", ana)->status == 403);
    // Events: shape, session and login checked.
    CHECK(p1.event({{"kind", "shout"}}) == 400);
    CHECK(p1.event({{"kind", "flip"}}) == 400);  // no rank
    Participant stranger{http, {}, "nosuchtoken", ""};
    CHECK(stranger.event({{"kind", "reject"}}) == 404);
    Participant thief{http, {}, p1.session, ""};
    CHECK(thief.event({{"kind", "reject"}}) == 401);
    // Close: a new participant is refused, a known one still resumes.
    res = http.Post("/api/v1/study/close", mod, R"({"open":false})", "application/json");
    REQUIRE(res->status == 200);
    CHECK(json::parse(res->body)["study"]["open"] == false);
    CHECK(http.Post("/api/v1/study/close", ana, R"({"open":true})", "application/json")->status ==
          403);
    Participant late{http, {}, "", ""};
    r = late.send({{"op", "state"}});
    CHECK(r.status == 403);
    CHECK(r.body["error"]["code"] == "study_closed");
    // Another device: the researcher's code logs in as P1 (no new participant, even closed).
    res = http.Post("/api/v1/study/invite", mod, R"({"participant":"P1"})", "application/json");
    REQUIRE(res->status == 200);
    const json code = json::parse(res->body);
    CHECK(code["url"] == "/?code=" + code["code"].get<std::string>());
    Participant device{http, cookie(login(http, json{{"code", code["code"]}})), "", "", ""};
    CHECK(device.send({{"op", "state"}}).user == "P1");
    CHECK(http.Post("/api/v1/study/invite", mod, R"({"participant":"mod"})", "application/json")
              ->status == 409);  // never a code for a researcher's account
    CHECK(http.Post("/api/v1/study/invite", ana, R"({"participant":"P1"})", "application/json")
              ->status == 403);
    Participant back{http, p1.headers, "", "", ""};
    CHECK(back.send({{"op", "state"}}).user == "P1");
    REQUIRE(http.Post("/api/v1/study/close", mod, R"({"open":true})", "application/json")->status ==
            200);
  }
  // The researcher's own actions, in order, each by its account and address (docs/studio.md §7
  // "Audit"): refusals (ana's 403s, the 404 downloads, the 409 invitation) are not actions; the
  // invitation's code, a secret, is not written.
  const auto audit = read_jsonl(fs::path(dir) / "rec" / "audit.jsonl");
  REQUIRE(audit.size() == 4);
  const std::vector<std::string> actions{"download", "close", "invite", "reopen"};
  for (std::size_t i = 0; i < audit.size(); ++i) {
    CHECK(audit[i]["action"] == actions[i]);
    CHECK(audit[i]["account"] == "mod");
    CHECK(audit[i]["peer"] == "127.0.0.1");
    const std::string time = audit[i]["time"].get<std::string>();  // 2026-11-29T12:00:00.000 (UTC)
    CHECK((time.size() == 23 && time[10] == 'T' && time[19] == '.'));
    CHECK_FALSE(audit[i].contains("code"));
  }
  CHECK(audit[0]["file"] == "queries.jsonl");
  CHECK(audit[2]["participant"] == "P1");
  CHECK(audit[2]["known"] == true);
  // A restart: qids, participant ids and the preload continue; the cookie still resumes.
  const auto before = read_jsonl(fs::path(dir) / "rec" / "queries.jsonl");
  {
    StudioServer server(dir, {study});
    auto http = server.client();
    Participant p2{http, {}, "", ""};
    Reply r = p2.send({{"op", "query"}, {"text", "move up"}});
    CHECK(r.user == "P2");
    Participant p1{http, p1_cookie, "", "", ""};
    r = p1.send({{"op", "state"}});
    CHECK(r.user == "P1");
    CHECK(r.body["world"]["robot"]["y"] == 5);
  }
  const auto after = read_jsonl(fs::path(dir) / "rec" / "queries.jsonl");
  REQUIRE(after.size() > before.size());
  for (std::size_t i = 0; i < after.size(); ++i) CHECK(after[i]["line"] == i + 1);
  int preloaded = 0;
  for (const auto& d : read_jsonl(fs::path(dir) / "rec" / "definitions.jsonl"))
    preloaded += d["origin"] == "preloaded";
  CHECK(preloaded == 1);
  const CliRun ok = run_flipper("replay verify " + (fs::path(dir) / "rec").string(), dir);
  INFO(ok.out);
  CHECK(ok.status == 0);
}

TEST_CASE("a study owns its accounts: a second study starts at P1, the first's login is nobody") {
  // docs/studio.md §7 "A study's accounts": accounts.sqlite in each study's recording folder.
  const std::string dir = fresh_dir("study-accounts");
  make_study(dir);
  for (const char* n : {"1", "2"})
    std::ofstream(dir + "/s" + n + ".yaml")
        << "name: s" << n << "\ngroups: [B]\nrecord: rec" << n
        << "\ntasks:\n  - {name: one, text: right, start: start.json}\n";
  httplib::Headers first_login;
  {
    StudioServer server(dir, {"serve.study=" + dir + "/s1.yaml"});
    auto http = server.client();
    Participant p{http, {}, "", ""};
    REQUIRE(p.send({{"op", "state"}}).user == "P1");
    first_login = p.headers;
    server.add_account("mod", "moderator password", "admin");  // `flipper accounts` agrees
    CHECK(login(http, json{{"name", "mod"}, {"password", "moderator password"}})
              .find("flipper_login=") == 0);
  }
  CHECK(fs::is_regular_file(fs::path(dir) / "rec1" / "accounts.sqlite"));
  CHECK_FALSE(fs::exists(fs::path(dir) / "accounts.sqlite"));  // not beside the lexicon
  StudioServer server(dir, {"serve.study=" + dir + "/s2.yaml"});
  auto http = server.client();
  Participant fresh{http, {}, "", ""};
  CHECK(fresh.send({{"op", "state"}}).user == "P1");      // numbered in its own study
  Participant returning{http, first_login, "", ""};       // the same browser as study 1's P1
  CHECK(returning.send({{"op", "state"}}).user == "P2");  // a new participant here
  CHECK(fs::is_regular_file(fs::path(dir) / "rec2" / "accounts.sqlite"));
  // Study 1's researcher is no account of study 2.
  int status = 0;
  CHECK(login(http, json{{"name", "mod"}, {"password", "moderator password"}}, &status).empty());
  CHECK(status == 401);
}

TEST_CASE("the server reads the study file once at start: its accounts come from that read") {
  // docs/studio.md §7 "A study's accounts": the accounts store is found from the study the server
  // loaded, not from a second read of the file. The oracle is the kernel's count of the file's
  // opens (inotify); IN_CLOSE_NOWRITE is watched too, so two opens are never coalesced into one
  // event (inotify merges identical events that follow each other unread).
  const std::string dir = fresh_dir("study-read-once");
  make_study(dir);
  const std::string study = dir + "/once.yaml";
  std::ofstream(study) << "name: once\ngroups: [B]\nrecord: rec\ntasks:\n"
                          "  - {name: one, text: right, start: start.json}\n";
  const int watch = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  REQUIRE(watch >= 0);
  REQUIRE(::inotify_add_watch(watch, study.c_str(), IN_OPEN | IN_CLOSE_NOWRITE) >= 0);
  {
    StudioServer server(dir, {"serve.study=" + study});
    auto http = server.client();
    Participant p{http, {}, "", ""};
    REQUIRE(p.send({{"op", "state"}}).user == "P1");  // enrolled: the study's accounts work
  }
  int opens = 0;
  alignas(inotify_event) char buffer[4096];
  for (ssize_t n; (n = ::read(watch, buffer, sizeof buffer)) > 0;)
    for (ssize_t at = 0; at < n;) {
      const auto* e = reinterpret_cast<const inotify_event*>(buffer + at);
      opens += (e->mask & IN_OPEN) != 0;
      at += static_cast<ssize_t>(sizeof(inotify_event) + e->len);
    }
  ::close(watch);
  CHECK(opens == 1);
  CHECK(fs::is_regular_file(fs::path(dir) / "rec" / "accounts.sqlite"));
}

TEST_CASE("a shared computer takes the next participant: the page's next, the researcher's end") {
  // docs/studio.md §7 "Shared computers".
  const std::string dir = fresh_dir("study-next");
  StudioServer server(dir, {make_study(dir)});
  server.add_account("mod", "moderator password", "admin");
  auto http = server.client();
  Participant p1{http, {}, "", "B"};
  REQUIRE(p1.send({{"op", "state"}}).user == "P1");
  // Without a participant's login, nothing to end.
  auto res = http.Post("/api/v1/study/next", httplib::Headers{}, "", "application/json");
  CHECK(res->status == 401);
  CHECK(json::parse(res->body)["error"]["code"] == "login_required");
  // The page's "next participant": this login ends, the browser's cookie with it.
  res = http.Post("/api/v1/study/next", p1.headers, "", "application/json");
  REQUIRE(res->status == 200);
  CHECK(json::parse(res->body) == json{{"ok", true}, {"participant", "P1"}});
  CHECK(res->get_header_value("Set-Cookie") ==
        "flipper_login=; Path=/; HttpOnly; SameSite=Strict; Max-Age=0");
  CHECK(p1.send({{"op", "state"}}).status == 401);  // P1's old session is P1's no more
  Participant p2{http, {}, "", "B"};                // the same computer, reloaded
  REQUIRE(p2.send({{"op", "state"}}).user == "P2");
  // The researcher ends P2's logins from the researcher's view.
  const auto mod = cookie(login(http, json{{"name", "mod"}, {"password", "moderator password"}}));
  // "next" ends only a participant's own login: the researcher's page keeps its login (used below).
  res = http.Post("/api/v1/study/next", mod, "", "application/json");
  CHECK(res->status == 401);
  CHECK(json::parse(res->body)["error"]["code"] == "login_required");
  res = http.Post("/api/v1/study/end", p2.headers, R"({"participant":"P2"})", "application/json");
  CHECK(res->status == 403);  // a participant is no researcher
  res = http.Post("/api/v1/study/end", mod, R"({"participant":"P9"})", "application/json");
  CHECK(res->status == 404);
  CHECK(json::parse(res->body)["error"]["code"] == "not_a_participant");
  res = http.Post("/api/v1/study/end", mod, R"({"participant":"P2"})", "application/json");
  REQUIRE(res->status == 200);
  CHECK(json::parse(res->body) == json{{"ok", true}, {"participant", "P2"}, {"logins", 1}});
  Reply r = p2.send({{"op", "state"}});
  CHECK(r.status == 401);
  CHECK(r.body["error"]["code"] == "login_required");
  Participant p3{http, {}, "", "B"};
  CHECK(p3.send({{"op", "state"}}).user == "P3");
  const auto audit = read_jsonl(fs::path(dir) / "rec" / "audit.jsonl");
  REQUIRE(audit.size() == 1);
  CHECK(audit[0]["action"] == "end");
  CHECK(audit[0]["participant"] == "P2");
  CHECK(audit[0]["logins"] == 1);
}

TEST_CASE("participants of one group teaching at once are recorded in the order they ran") {
  // docs/studio.md §5: one kernel per study group, recorded inside its lock. Two participants of
  // shared group C each teach words and query the other's: a record written after the kernel
  // let go could come after a query that already used its rule, and the replay would diverge.
  const std::string dir = fresh_dir("study-order");
  const std::string study = make_study(dir);
  {
    StudioServer server(dir, {study, "serve.kernels=4"});
    auto worker = [&](const std::string& me, const std::string& other) {
      auto http = server.client();
      Participant p{http, {}, "", "C"};
      for (int i = 0; i < 25; ++i) {
        p.send({{"op", "define"},
                {"head", me + std::to_string(i)},
                {"body", {i % 2 ? "move up" : "move left"}}});
        p.send({{"op", "query"}, {"text", other + std::to_string(i)}});
        p.send({{"op", "rules"}});
      }
    };
    std::thread a(worker, "zork", "blip"), b(worker, "blip", "zork");
    a.join();
    b.join();
  }
  const CliRun ok = run_flipper("replay verify " + dir + "/rec", dir);
  INFO(ok.out);
  CHECK(ok.status == 0);
  CHECK(ok.out.find("150 exchanges") != std::string::npos);
}

}  // namespace
}  // namespace flipper::studiotest
