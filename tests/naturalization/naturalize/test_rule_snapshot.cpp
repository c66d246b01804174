// The rule snapshot (docs/naturalization.md §5 "Start-up at scale"): a start-up from it serves
// exactly the rules (and parses) a start-up from the rows serves, on the dev corpus's induced
// rules; a snapshot left stale by other writers is completed from the rows after its mark (or
// rebuilt when much changed); a damaged, undecodable or inconsistent one is rebuilt, never served.
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/naturalization/rule_snapshot.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "naturalize_fixture.hpp"
#include "product_schema.hpp"
#include "store_sql.hpp"

using namespace flipper;
using namespace flipper::naturalizetest;
using kernel::Json;

namespace {

/// A naturalizer (and a session wired to it) over `store`; snapshots from `min_rules` rules on.
struct Started {
  std::shared_ptr<kernel::Runtime> rt;
  std::shared_ptr<naturalization::Naturalizer> nat;
  std::unique_ptr<kernel::Session> session;
  std::vector<std::string> warnings;
  Started(const std::string& store, std::int64_t min_rules) {
    rt = kernel::make_runtime(kernel::Config::load(std::nullopt, {"lexicon.path=" + store}));
    auto options = naturalization::NaturalizeOptions::from_config(rt->config);
    options.snapshot_min_rules = min_rules;
    options.warn = [this](const std::string& w) { warnings.push_back(w); };
    nat = std::make_shared<naturalization::Naturalizer>(rt, options);
    session = std::make_unique<kernel::Session>(rt);
    naturalization::install_naturalization(*session, nat);
  }
};

/// Everything a served rule carries, as one comparable line.
std::vector<std::string> served(const naturalization::Naturalizer& nat) {
  std::vector<std::string> out;
  for (const auto& r : nat.induced_rules()) {
    std::string line = r->id + "|" + std::to_string(r->created) + "|" + r->lhs + " ->";
    for (const auto& s : r->rhs)
      line += " " + std::to_string(static_cast<int>(s.type)) + ":" + s.text;
    line += " => " + sdk::render(r->sem) + "|" + r->author + "|" + r->head + "|" +
            sdk::to_string(r->how) + "|" + (r->induced ? "induced" : "core");
    for (const auto& b : r->body) line += "|" + b;
    out.push_back(line);
  }
  return out;
}

/// The live rule ids as the store's rows say (the independent oracle).
std::vector<std::string> live_ids(const std::string& store) {
  naturalization::LexiconStore s(store);
  std::vector<std::string> out;
  for (const auto& r : s.rules()) out.push_back(r.id);
  return out;
}

std::vector<std::string> ids(const naturalization::Naturalizer& nat) {
  std::vector<std::string> out;
  for (const auto& r : nat.induced_rules()) out.push_back(r->id);
  return out;
}

naturalization::StoredRule rule(const std::string& token, const std::string& author) {
  naturalization::StoredRule r;
  r.lhs = "$Action";
  r.rhs = {token, "$Number"};
  r.semantics = "{repeat $1 times {pick item}}";
  r.author = author;
  r.head = token + " 3";
  r.body = {"pick item", "pick item"};
  r.how = "simple";
  return r;
}

/// A store with `n` one-rule definitions ("tok0" .. ), by ana.
std::string store_with(int n, const std::string& stem) {
  const std::string path = scratch_path(stem) + ".sqlite";
  naturalization::LexiconStore s(path);
  for (int i = 0; i < n; ++i)
    s.add_definition({0, "tok" + std::to_string(i) + " 3", {"pick item"}, "ana", i},
                     {rule("tok" + std::to_string(i), "ana")});
  return path;
}

std::vector<Json> read_jsonl(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::vector<Json> out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(Json::parse(line));
  return out;
}

}  // namespace

TEST_CASE("a snapshot blob reads back exactly, and a damaged one hands out nothing",
          "[naturalize][snapshot]") {
  naturalization::StoredRule a = rule("glorp", "ana");
  a.id = "r7";
  a.created = 7;
  a.definition = 3;
  naturalization::StoredRule b = rule("with \"quotes\" and \\ é", "bob");
  b.id = "r9";
  b.created = 9;
  b.definition = 4;
  b.body = {};
  b.how = "alignment";
  b.decode_error = "the row does not decode: column 'body' holds 'x', not a JSON list of strings";
  naturalization::RuleSnapshotWriter w;
  w.add(a);
  w.add(b);
  const std::string blob = w.finish();
  std::vector<naturalization::StoredRule> back;
  REQUIRE(naturalization::read_rule_snapshot(
      blob, [&](const naturalization::StoredRuleView& r) { back.push_back(r.materialize()); }));
  REQUIRE(back.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& want = i == 0 ? a : b;
    CHECK(back[i].id == want.id);
    CHECK(back[i].created == want.created);
    CHECK(back[i].definition == want.definition);
    CHECK(back[i].lhs == want.lhs);
    CHECK(back[i].rhs == want.rhs);
    CHECK(back[i].semantics == want.semantics);
    CHECK(back[i].author == want.author);
    CHECK(back[i].head == want.head);
    CHECK(back[i].body == want.body);
    CHECK(back[i].how == want.how);
    CHECK(back[i].decode_error == want.decode_error);
  }
  // Truncated, one byte too many, a count that promises more, the format before this one
  // (without decode_error): nothing at all is handed out.
  REQUIRE(naturalization::kRuleSnapshotFormat == 2);
  for (const std::string& bad : {blob.substr(0, blob.size() - 1), blob + "x",
                                 blob.substr(0, 8) + std::string("\x03", 1) + blob.substr(9),
                                 std::string("FLXS\x01\0\0\0", 8) + blob.substr(8)}) {
    int handed = 0;
    CHECK_FALSE(naturalization::read_rule_snapshot(
        bad, [&](const naturalization::StoredRuleView&) { ++handed; }));
    CHECK(handed == 0);
  }
  CHECK(naturalization::snapshot_checksum(blob) !=
        naturalization::snapshot_checksum(blob.substr(1) + "F"));
}

TEST_CASE("the dev corpus's induced rules: the same rules and parses with and without a snapshot",
          "[naturalize][snapshot][corpus]") {
  const std::string dir = std::string(FLIPPER_STUDY_DIR) + "/dev/";
  const std::string store = scratch_path("snapshot-corpus") + ".sqlite";
  {
    auto s = open(store);
    for (const auto& d : read_jsonl(dir + "definitions.jsonl")) {
      user(*s, d["user"].get<std::string>());
      std::vector<std::string> body;
      for (const auto& line : d["body"]) body.push_back(line["utterance"].get<std::string>());
      (void)define(*s, d["head"].get<std::string>(), body);  // some are refused, as in the study
    }
  }
  const std::vector<std::string> oracle = live_ids(store);
  REQUIRE(oracle.size() > 100);

  Started rows(store, 0);  // no snapshot read or written
  CHECK_FALSE(rows.nat->startup().from_snapshot);
  CHECK_FALSE(rows.nat->startup().snapshot_saved);
  Started first(store, 1);  // reads the rows, leaves a snapshot
  CHECK_FALSE(first.nat->startup().from_snapshot);
  CHECK(first.nat->startup().snapshot_saved);
  Started snap(store, 1);
  REQUIRE(snap.nat->startup().from_snapshot);
  CHECK(snap.nat->startup().snapshot_rules == static_cast<std::int64_t>(oracle.size()));

  CHECK(ids(*rows.nat) == oracle);
  CHECK(served(*snap.nat) == served(*rows.nat));
  CHECK(snap.warnings == rows.warnings);

  // Every corpus utterance parses to the same answer (candidates, scores, statuses).
  std::set<std::string> seen;
  int compared = 0;
  user(*rows.session, "BP1");
  user(*snap.session, "BP1");
  for (const auto& q : read_jsonl(dir + "queries.jsonl")) {
    if (q.value("kind", "") != "q" || !q["utterance"].is_string()) continue;
    const std::string text = q["utterance"];
    if (!seen.insert(text).second || seen.size() > 400) continue;
    Json a = rows.session->handle({{"op", "query"}, {"text", text}});
    Json b = snap.session->handle({{"op", "query"}, {"text", text}});
    a.erase("ms");
    b.erase("ms");
    INFO(text);
    CHECK(a == b);
    ++compared;
  }
  CHECK(compared > 300);
}

TEST_CASE("a snapshot left stale by other writers is completed from the rows after its mark",
          "[naturalize][snapshot]") {
  const std::string store = store_with(40, "snapshot-stale");
  {
    Started first(store, 1);
    REQUIRE(first.nat->startup().snapshot_saved);
  }
  {
    // Another process: two new rules (bob's, ana's), one of ana's snapshotted rules deleted.
    naturalization::LexiconStore other(store);
    other.add_definition({0, "zork 3", {"pick item"}, "bob", 50}, {rule("zork", "bob")});
    other.add_definition({0, "quux 3", {"pick item"}, "ana", 51}, {rule("quux", "ana")});
    REQUIRE(other.delete_rule("r5", "ana", 52, {}).status == naturalization::DeleteStatus::deleted);
    other.record_accept({{"r7", 2, 1}}, "", std::string());
  }
  const std::vector<std::string> oracle = live_ids(store);
  REQUIRE(oracle.size() == 41);
  Started snap(store, 1);
  REQUIRE(snap.nat->startup().from_snapshot);
  CHECK(snap.nat->startup().snapshot_rules == 40);
  CHECK(ids(*snap.nat) == oracle);
  CHECK(ids(*snap.nat).back() == "r42");
  CHECK_FALSE(snap.nat->find_rule("r5"));
  const auto uses = snap.rt->usage->uses("r7");  // counters are read fresh, not snapshotted
  CHECK(uses.by_author == 2);
  CHECK(uses.by_others == 1);
  Started rows(store, 0);
  CHECK(served(*snap.nat) == served(*rows.nat));
  user(*snap.session, "carl");
  CHECK(status(*snap.session, "zork 3") == "induced");

  // Much changed since (more than an eighth of its rules): rebuilt from the rows, mark moved on.
  {
    naturalization::LexiconStore other(store);
    for (int i = 0; i < 12; ++i)
      other.add_definition({0, "more" + std::to_string(i) + " 3", {"pick item"}, "bob", 60 + i},
                           {rule("more" + std::to_string(i), "bob")});
  }
  Started rebuilt(store, 1);
  CHECK_FALSE(rebuilt.nat->startup().from_snapshot);
  CHECK(rebuilt.nat->startup().snapshot_saved);
  CHECK(ids(*rebuilt.nat) == live_ids(store));
  CHECK(sql_int(store, "SELECT created_mark FROM rule_snapshot") == 54);
  Started again(store, 1);
  CHECK(again.nat->startup().from_snapshot);
  CHECK(again.nat->startup().snapshot_rules == 53);
}

TEST_CASE("a damaged, undecodable or inconsistent snapshot is rebuilt, never served",
          "[naturalize][snapshot]") {
  const std::string store = store_with(30, "snapshot-damaged");
  { Started first(store, 1); }
  const std::vector<std::string> oracle = live_ids(store);

  SECTION("a changed byte: the checksum no longer matches") {
    sql(store,
        "UPDATE rule_snapshot SET data = substr(data, 1, 100) || x'41' || substr(data, 102)");
    Started s(store, 1);
    CHECK_FALSE(s.nat->startup().from_snapshot);
    REQUIRE(s.warnings.size() == 1);
    CHECK_THAT(s.warnings[0], Catch::Contains("checksum") && Catch::Contains(store));
    CHECK(ids(*s.nat) == oracle);
    CHECK(s.nat->startup().snapshot_saved);
  }
  SECTION("a blob that matches its checksum but does not decode") {
    naturalization::RuleSnapshotWriter w;
    w.add(rule("x", "ana"));
    std::string blob = w.finish();
    blob.pop_back();
    std::ostringstream hex;
    for (unsigned char c : blob) hex << std::hex << (c >> 4) << (c & 15);
    sql(store,
        "UPDATE rule_snapshot SET data = x'" + hex.str() + "', checksum = " +
            std::to_string(static_cast<std::int64_t>(naturalization::snapshot_checksum(blob))));
    Started s(store, 1);
    CHECK_FALSE(s.nat->startup().from_snapshot);
    REQUIRE(s.warnings.size() == 1);
    CHECK_THAT(s.warnings[0], Catch::Contains("does not decode"));
    CHECK(ids(*s.nat) == oracle);
  }
  SECTION("rows imported below its mark make it inconsistent") {
    naturalization::LexiconStore other(store);
    std::istringstream line(
        R"({"type":"rule","id":"imported","lhs":"$Action","rhs":["blarg","$Number"],)"
        R"("semantics":"{repeat $1 times {pick item}}","author":"zed","how":"simple","created":0})"
        "\n");
    REQUIRE(other.import_jsonl(line) == 1);
    Started s(store, 1);
    CHECK_FALSE(s.nat->startup().from_snapshot);
    CHECK(s.warnings.empty());
    CHECK(s.nat->find_rule("imported"));
    CHECK(ids(*s.nat).size() == oracle.size() + 1);
  }
  SECTION("another format is ignored") {
    sql(store, "UPDATE rule_snapshot SET format = 99");
    Started s(store, 1);
    CHECK_FALSE(s.nat->startup().from_snapshot);
    CHECK(s.warnings.empty());
    CHECK(ids(*s.nat) == oracle);
  }
  Started after(store, 1);  // whatever happened, the rebuilt snapshot serves the next start
  CHECK(after.nat->startup().from_snapshot);
  CHECK(ids(*after.nat) == live_ids(store));
}

namespace {
/// Makes the definitions table's root page unreadable (its b-tree page type byte), a page the
/// rule start-up itself never reads: only SQLite's page check, or a statement on that table, sees
/// it.
void damage_definitions_page(const std::string& store) {
  const std::int64_t page_size = sql_int(store, "PRAGMA page_size");
  const std::int64_t root =
      sql_int(store, "SELECT rootpage FROM sqlite_master WHERE name = 'definitions'");
  REQUIRE(root > 1);
  std::fstream f(store, std::ios::in | std::ios::out | std::ios::binary);
  REQUIRE(f);
  f.seekp((root - 1) * page_size);
  f.put(static_cast<char>(0x55));  // not a b-tree page type
  REQUIRE(f);
}
}  // namespace

TEST_CASE("a damaged page is lexicon_corrupt: at start-up without a snapshot, else when read",
          "[naturalize][snapshot][faults]") {
  SECTION("no snapshot: the page check at start-up finds it") {
    const std::string store = store_with(40, "snapshot-page");
    damage_definitions_page(store);
    try {
      Started s(store, 1);
      FAIL("started on a damaged store");
    } catch (const flipper::sdk::Error& e) {
      CHECK(std::string(e.code()) == "lexicon_corrupt");
      CHECK_THAT(e.what(), Catch::Contains(store));
    }
  }
  SECTION("a valid snapshot vouches for the rules; the damaged table answers lexicon_corrupt") {
    const std::string store = store_with(40, "snapshot-page-later");
    { Started first(store, 1); }
    damage_definitions_page(store);
    Started s(store, 1);
    REQUIRE(s.nat->startup().from_snapshot);
    CHECK(ids(*s.nat).size() == 40);
    user(*s.session, "ana");
    const Json a = define(*s.session, "zorp left", {"move left"});
    CHECK(error_code(a) == "lexicon_corrupt");
  }
}

TEST_CASE("after a start from the snapshot a rule already held is not induced again",
          "[naturalize][snapshot]") {
  const std::string store = scratch_path("snapshot-duplicate") + ".sqlite";
  {
    auto s = open(store);
    user(*s, "ana");
    for (int i = 0; i < 20; ++i)
      REQUIRE(define(*s, "zorble" + std::to_string(i) + " left", {"move left"})["rules"].size() ==
              1);
  }
  { Started first(store, 1); }
  Started s(store, 1);
  REQUIRE(s.nat->startup().from_snapshot);
  user(*s.session, "ana");
  // `zorble7 $Direction => {move $1}` is held: nothing new; a new head induces its one rule.
  CHECK(define(*s.session, "zorble7 left", {"move left"})["rules"].empty());
  CHECK(define(*s.session, "fnord left", {"move left"})["rules"].size() == 1);
  CHECK(define(*s.session, "fnord left", {"move left"})["rules"].empty());
  CHECK(s.nat->induced_rules().size() == 21);
}
