// The researcher's lexicon page over HTTP against the real binary (docs/studio.md §7 "Lexicon",
// docs/naturalization.md §5 "Moderation"): in a study with `moderation: hold_new` a participant's
// definition is held and changes no other participant's answers until the researcher approves
// it; a rejected one changes nothing; approving and rejecting need the researcher's login (a
// participant or a plain user gets 403 `forbidden`, no login 401 `login_required`); the page's
// history shows every step, and the audit names the researcher.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

namespace fs = std::filesystem;

std::string text_of(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// One shared group (C), no preload, definitions held for the researcher.
std::string moderated_study(const std::string& dir) {
  const std::string world = text_of(fs::path(FLIPPER_SOURCE_DIR) / "configs/worlds/study2018.json");
  std::ofstream(dir + "/start.json") << world;
  std::ofstream(dir + "/study.yaml")
      << "name: m\ngroups: [C]\nrecord: rec\nmoderation: hold_new\ntasks:\n"
         "  - {name: one, text: anything, start: start.json}\n";
  return "serve.study=" + dir + "/study.yaml";
}

struct Person {
  httplib::Client& http;
  httplib::Headers headers;
  std::string session;
  json send(const json& request) {
    Reply r = post(http, session, request.dump(), headers, session.empty() ? "C" : "");
    if (!r.session.empty()) session = r.session;
    if (!r.set_cookie.empty()) headers = cookie(r.set_cookie.substr(0, r.set_cookie.find(';')));
    return r.body;
  }
  /// The query's answer without its timings (compared whole before and after).
  json ask(const std::string& text) {
    json a = send({{"op", "query"}, {"text", text}});
    a.erase("ms");
    return a;
  }
};

json post_to(httplib::Client& http, const std::string& path, const httplib::Headers& who,
             const json& body, int* status) {
  auto res = http.Post(path.c_str(), who, body.dump(), "application/json");
  REQUIRE(res);
  *status = res->status;
  return json::parse(res->body, nullptr, false);
}

std::string first_formula(const json& answer) {
  if (!answer.value("ok", false) || answer["candidates"].empty()) return "(none)";
  return answer["candidates"][0].value("formula", std::string());
}

}  // namespace

TEST_CASE("the researcher approves or rejects held definitions and nobody else can") {
  const std::string dir = fresh_dir("study-lexicon");
  StudioServer server(dir, {moderated_study(dir)});
  server.add_account("mod", "moderator password", "admin");
  server.add_account("ana", "ana's password");
  auto http = server.client();
  Person p1{http, {}, ""}, p2{http, {}, ""};
  REQUIRE(p1.send({{"op", "state"}})["ok"] == true);
  REQUIRE(p2.send({{"op", "state"}})["ok"] == true);
  const json zap_before = p2.ask("zap red");
  const json hop_before = p2.ask("hop twice");
  CHECK(first_formula(zap_before) == "(none)");

  const json held =
      p1.send({{"op", "define"}, {"head", "zap blue"}, {"body", {"pick item is blue"}}});
  INFO(held.dump());
  REQUIRE(held["ok"] == true);
  CHECK(held["held"] == "h1");
  CHECK(held["stored"] == false);
  CHECK(p2.ask("zap red") == zap_before);                // held: P2's answers are those of before
  CHECK(first_formula(p1.ask("zap blue")) == "(none)");  // nor does the author use it

  // Only the researcher: no login 401, a plain user or a participant 403 `forbidden`.
  const auto mod = cookie(login(http, json{{"name", "mod"}, {"password", "moderator password"}}));
  const auto ana = cookie(login(http, json{{"name", "ana"}, {"password", "ana's password"}}));
  const json approve_h1 = {{"group", "C"}, {"id", "h1"}};
  int status = 0;
  json a = post_to(http, "/api/v1/study/lexicon/approve", {}, approve_h1, &status);
  CHECK(status == 401);
  CHECK(a["error"]["code"] == "login_required");
  a = post_to(http, "/api/v1/study/lexicon/approve", ana, approve_h1, &status);
  CHECK(status == 403);
  CHECK(a["error"]["code"] == "forbidden");
  a = post_to(http, "/api/v1/study/lexicon/approve", p1.headers, approve_h1, &status);
  CHECK(status == 403);
  CHECK(a["error"]["code"] == "forbidden");
  CHECK(http.Get("/api/v1/study/lexicon?group=C", ana)->status == 403);
  CHECK(p2.ask("zap red") == zap_before);

  // The page's view: the queue with the held rules, the history.
  auto res = http.Get("/api/v1/study/lexicon?group=C", mod);
  REQUIRE(res->status == 200);
  json page = json::parse(res->body);
  CHECK(page["moderation"] == "hold_new");
  REQUIRE(page["pending"].size() == 1);
  CHECK(page["pending"][0]["id"] == "h1");
  CHECK(page["pending"][0]["author"] == "P1");
  CHECK(page["pending"][0]["head"] == "zap blue");
  REQUIRE(page["pending"][0]["rules"].size() == 3);
  CHECK(page["pending"][0]["rules"][0]["rhs"] == json{"zap", "$Color"});
  CHECK(http.Get("/api/v1/study/lexicon?group=Q", mod)->status == 404);

  // Bad requests: another group, an id that is not held.
  a = post_to(http, "/api/v1/study/lexicon/approve", mod, {{"group", "Q"}, {"id", "h1"}}, &status);
  CHECK(status == 404);
  CHECK(a["error"]["code"] == "unknown_group");
  a = post_to(http, "/api/v1/study/lexicon/approve", mod, {{"group", "C"}, {"id", "h9"}}, &status);
  CHECK(status == 404);
  CHECK(a["error"]["code"] == "not_found");
  a = post_to(http, "/api/v1/study/lexicon/approve", mod, {{"id", "h1"}}, &status);
  CHECK(status == 400);

  // Rejected: nothing changes.
  REQUIRE(p1.send({{"op", "define"}, {"head", "hop twice"}, {"body", {"move up", "move up"}}})
              .value("held", "") == "h2");
  a = post_to(http, "/api/v1/study/lexicon/reject", mod,
              {{"group", "C"}, {"id", "h2"}, {"reason", "say it with numbers"}}, &status);
  REQUIRE(status == 200);
  CHECK(p2.ask("hop twice") == hop_before);
  CHECK(p2.ask("zap red") == zap_before);

  // Approved: P2's answer changes.
  a = post_to(http, "/api/v1/study/lexicon/approve", mod, approve_h1, &status);
  INFO(a.dump());
  REQUIRE(status == 200);
  CHECK(a["rules"] == json{"r1", "r2", "r3"});
  CHECK(first_formula(p2.ask("zap red")) == "{pick item {is red}}");
  CHECK(p2.ask("hop twice") == hop_before);
  a = post_to(http, "/api/v1/study/lexicon/approve", mod, approve_h1, &status);
  CHECK(status == 404);  // once

  // The history, newest first: every step and who took it.
  page = json::parse(http.Get("/api/v1/study/lexicon?group=C", mod)->body);
  CHECK(page["pending"].empty());
  std::vector<std::string> steps;
  for (const auto& e : page["history"])
    steps.push_back(e["action"].get<std::string>() + " " + e["author"].get<std::string>() + " " +
                    e["note"].get<std::string>());
  CHECK(steps == std::vector<std::string>{"induce P1 ", "induce P1 ", "induce P1 ", "define P1 ",
                                          "approve mod h1", "reject mod h2: say it with numbers",
                                          "hold P1 h2", "hold P1 h1"});
  CHECK(page["history_total"] == 8);

  // The researcher's audit: the approval and the rejection, by account.
  server.stop();
  std::istringstream audit(text_of(fs::path(dir) / "rec" / "audit.jsonl"));
  std::vector<std::string> actions;
  for (std::string line; std::getline(audit, line);) {
    const json e = json::parse(line);
    CHECK(e["account"] == "mod");
    actions.push_back(e["action"].get<std::string>() + " " + e["id"].get<std::string>());
  }
  CHECK(actions == std::vector<std::string>{"reject h2", "approve h1"});

  // The recording keeps the two moderations that took effect (not the refused attempts) among
  // the exchanges, where they happened, and the study replays byte for byte (docs/studio.md §7).
  std::istringstream exchanges(text_of(fs::path(dir) / "rec" / "exchanges.jsonl"));
  std::vector<std::string> moderations;
  std::size_t count = 0;
  for (std::string line; std::getline(exchanges, line); ++count) {
    const json e = json::parse(line);
    if (e["origin"] != "researcher") continue;
    CHECK(e["participant"].is_null());
    CHECK(e["user"] == "mod");
    moderations.push_back(e["request"].get<std::string>() + " -> " +
                          e["answer"].get<std::string>());
  }
  CHECK(
      moderations ==
      std::vector<std::string>{
          R"({"id":"h2","op":"reject","reason":"say it with numbers"} -> {"id":"h2","ok":true,"op":"reject"})",
          R"({"id":"h1","op":"approve"} -> {"id":"h1","ok":true,"op":"approve","rules":["r1","r2","r3"]})"});
  const CliRun verify = run_flipper("replay verify " + dir + "/rec", dir);
  INFO(verify.out);
  CHECK(verify.status == 0);
  CHECK(verify.out ==
        std::to_string(count) + " exchanges, every answer equal byte for byte (ms excluded)\n");
}

}  // namespace flipper::studiotest
