// Naturalization over a store other writers share (docs/naturalization.md §5): heads with '$'
// tokens refused, bad stored rules quarantined instead of locking everyone out, hidden rules answer
// not_found, and an accept whose lexicon transaction fails applies nothing (a retry applies it
// once).
#include <sqlite3.h>
#include <nlohmann/json.hpp>

#include <catch2/catch.hpp>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "naturalize_fixture.hpp"

using namespace flipper;
using namespace flipper::naturalizetest;
using kernel::Json;

namespace {

/// Another process's write lock on the store, held until destroyed.
struct LockHolder {
  sqlite3* db = nullptr;
  explicit LockHolder(const std::string& path) {
    REQUIRE(sqlite3_open(path.c_str(), &db) == SQLITE_OK);
    REQUIRE(sqlite3_exec(db, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr) == SQLITE_OK);
  }
  ~LockHolder() {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
};

naturalization::StoredRule stored_rule(std::vector<std::string> rhs, std::string semantics) {
  naturalization::StoredRule r;
  r.lhs = "$Action";
  r.rhs = std::move(rhs);
  r.semantics = std::move(semantics);
  r.author = "mallory";
  r.head = "glorb red";
  r.body = {"move left"};
  r.how = "simple";
  return r;
}

}  // namespace

TEST_CASE("a head token starting with $ is refused and the store stays usable",
          "[naturalize][writers]") {
  const std::string store = scratch_path("dollar") + ".sqlite";
  {
    auto s = open(store);
    user(*s, "mallory");
    for (const std::string head : {"glorb $Color", "$", "$1 zed", "go $Action now"}) {
      INFO(head);
      const Json a = define(*s, head, {"move left"});
      CHECK(error_code(a) == "head_reserved_token");
      CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains("starts with '$'"));
    }
    CHECK(s->handle({{"op", "rules"}})["rules"].empty());
  }
  naturalization::LexiconStore reopened(store);
  CHECK(reopened.definitions().empty());
  auto again = open(store);  // everyone can still open it
  user(*again, "ana");
  CHECK(define(*again, "go west", {"move left"})["ok"] == true);
}

TEST_CASE("a stored rule that no longer loads is quarantined with a warning naming it",
          "[naturalize][writers]") {
  const std::string store = scratch_path("quarantine") + ".sqlite";
  {
    naturalization::LexiconStore raw(store);
    raw.add_definition({0, "glorb red", {"move left"}, "mallory", 1},
                       {stored_rule({"glorb", "$Bogus"}, "{move left}")});
    raw.add_definition({0, "fnord", {"move left"}, "mallory", 2},
                       {stored_rule({"fnord"}, "{move {{{")});
  }
  std::shared_ptr<kernel::Runtime> rt =
      kernel::make_runtime(kernel::Config::load(std::nullopt, {"lexicon.path=" + store}));
  auto options = naturalization::NaturalizeOptions::from_config(rt->config);
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  auto nat = std::make_shared<naturalization::Naturalizer>(rt, options);  // opens: no throw
  auto s = std::make_unique<kernel::Session>(rt);
  naturalization::install_naturalization(*s, nat);
  REQUIRE(warnings.size() == 2);
  CHECK_THAT(warnings[0], Catch::Contains("rule r1") && Catch::Contains("quarantined") &&
                              Catch::Contains("$Bogus") && Catch::Contains(store));
  CHECK_THAT(warnings[1], Catch::Contains("rule r2") && Catch::Contains("quarantined"));
  REQUIRE(nat->quarantined().size() == 2);
  CHECK(nat->quarantined()[0].stored.id == "r1");
  CHECK(nat->induced_rules().empty());  // not served
  user(*s, "ana");
  CHECK(status(*s, "fnord") == "unparsable");
  CHECK(define(*s, "go west", {"move left"})["ok"] == true);  // the store works on
  CHECK(status(*s, "go west") == "induced");
  naturalization::LexiconStore reopened(store);
  CHECK(reopened.rules().size() == 3);  // the quarantined rules stay in the file
  CHECK(naturalization::quarantine_reason(reopened.rules()[0]).has_value());
  CHECK_FALSE(naturalization::quarantine_reason(reopened.rules()[2]).has_value());
  std::ostringstream exported;
  reopened.export_jsonl(exported, naturalization::quarantine_reason);
  const std::string text = exported.str();
  CHECK(std::count(text.begin(), text.end(), '\n') == 6);
  CHECK_THAT(text, Catch::Contains("\"id\":\"r1\"") &&
                       Catch::Contains("\"quarantined\":\"unknown category '$Bogus'"));
}

TEST_CASE("private mode: deleting a rule hidden from the user answers not_found",
          "[naturalize][writers]") {
  const std::string store = scratch_path("hidden") + ".sqlite";
  auto s = open(store, {"lexicon.sharing=private"});
  user(*s, "ana");
  const Json a = define(*s, "go west", {"move left"});
  REQUIRE(a["rules"].size() == 1);
  const std::string id = a["rules"][0]["id"];
  user(*s, "bob");
  const Json d = s->handle({{"op", "delete_rule"}, {"rule", id}});
  CHECK(error_code(d) == "not_found");
  CHECK_THAT(d["error"]["message"].get<std::string>(), !Catch::Contains("ana"));
  user(*s, "ana");
  CHECK(status(*s, "go west") == "induced");  // still there for its author
  CHECK(s->handle({{"op", "delete_rule"}, {"rule", id}})["ok"] == true);
}

TEST_CASE("an accept whose lexicon transaction fails applies nothing, and a retry applies it once",
          "[naturalize][writers]") {
  const std::string store = scratch_path("accept") + ".sqlite";
  auto s = open(store, {"lexicon.busy_timeout_ms=100"});
  user(*s, "ana");
  REQUIRE(define(*s, "go west", {"move left"})["ok"] == true);
  const Json before = s->handle({{"op", "state"}})["world"];
  const std::string weights = s->runtime().scorer.borrow()->save_state();
  const Json q = s->handle({{"op", "query"}, {"text", "go west"}});
  REQUIRE(q["status"] == "induced");
  const Json expected = q["candidates"][0]["world"];
  REQUIRE(expected != before);
  auto uses = [&] {
    int n = 0;
    const Json listed = s->handle({{"op", "rules"}});
    for (const auto& r : listed["rules"]) n += r["uses"].get<int>();
    return n;
  };
  {
    LockHolder other(store);
    const Json failed = s->handle({{"op", "accept"}, {"rank", 0}});
    CHECK(error_code(failed) == "lexicon_busy");
    CHECK_THAT(failed["error"]["message"].get<std::string>(), Catch::Contains(store));
    CHECK(s->handle({{"op", "state"}})["world"] == before);        // world unchanged
    CHECK(s->runtime().scorer.borrow()->save_state() == weights);  // nothing learned
  }
  CHECK(uses() == 0);
  const Json retried = s->handle({{"op", "accept"}, {"rank", 0}});
  REQUIRE(retried["ok"] == true);
  CHECK(s->handle({{"op", "state"}})["world"] == expected);  // applied exactly once
  // One reading: the scorer has nothing to learn (a softmax over one candidate); the use
  // counter below shows the accept counted once.
  CHECK(s->runtime().scorer.borrow()->save_state() == weights);
  CHECK(uses() == 1);
  CHECK(error_code(s->handle({{"op", "accept"}, {"rank", 0}})) == "no_query");
  naturalization::LexiconStore reopened(store);
  CHECK(reopened.rules()[0].uses_by_author == 1);
}
