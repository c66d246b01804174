// Nothing fails silently (docs/naturalization.md §5 "Quarantine", "Community lexicon"): a stored
// rule that does not load — an unknown category, a template that does not read, a row whose
// lists do not decode, an empty or single-category right-hand side — is quarantined with a
// warning naming it at every start, from the rows and from the rule snapshot alike, and shows
// in `flipper lexicon list`; a preloaded definition that does not load is a warning naming it
// and why, and a row that `lexicon list` and `export` show.
#include <algorithm>
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "cli_test_support.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "naturalize_fixture.hpp"
#include "product_schema.hpp"
#include "store_sql.hpp"

using namespace flipper;
using namespace flipper::naturalizetest;

namespace {

/// A naturalizer over `store` with snapshots from one rule on, its warnings collected.
struct Started {
  std::shared_ptr<kernel::Runtime> rt;
  std::shared_ptr<naturalization::Naturalizer> nat;
  std::vector<std::string> warnings;
  explicit Started(const std::string& store, const std::string& preload = "") {
    rt = kernel::make_runtime(kernel::Config::load(std::nullopt, {"lexicon.path=" + store}));
    auto options = naturalization::NaturalizeOptions::from_config(rt->config);
    options.snapshot_min_rules = 1;
    options.preload = preload;
    options.warn = [this](const std::string& w) { warnings.push_back(w); };
    nat = std::make_shared<naturalization::Naturalizer>(rt, options);
  }
  std::vector<std::string> quarantined_ids() const {
    std::vector<std::string> out;
    for (const auto& q : nat->quarantined()) out.push_back(q.stored.id);
    std::sort(out.begin(), out.end());
    return out;
  }
  std::vector<std::string> served_ids() const {
    std::vector<std::string> out;
    for (const auto& r : nat->induced_rules()) out.push_back(r->id);
    return out;
  }
  /// The warning that names rule `id`, or "" when none does.
  std::string warning_for(const std::string& id) const {
    for (const auto& w : warnings)
      if (w.find("rule " + id + " ") != std::string::npos) return w;
    return "";
  }
};

naturalization::StoredRule rule(const std::string& lhs, std::vector<std::string> rhs,
                                const std::string& semantics, const std::string& head) {
  naturalization::StoredRule r;
  r.lhs = lhs;
  r.rhs = std::move(rhs);
  r.semantics = semantics;
  r.author = "ana";
  r.head = head;
  r.body = {"repeat 3 times pick item"};
  r.how = "best";
  return r;
}

/// Rules r1..r3 load; r4..r10 do not, each for its own reason (the expected excerpt).
const std::vector<std::pair<std::string, std::string>> kBad = {
    {"r4", "$ROOT"},                                          // an older version's statement hole
    {"r5", "$Nope"},                                          // an unknown category
    {"r6", "template"},                                       // a template that does not read
    {"r7", "has an empty right-hand side"},                   // rhs = '[]'
    {"r8", "column 'rhs' holds 'not json'"},                  // rhs is not JSON
    {"r9", "column 'body' holds '{\"a\":1}'"},                // body is JSON, but not a list
    {"r10", "has a single category as its right-hand side"},  // rhs = '["$Action"]'
};

std::string store_with_bad_rules() {
  const std::string path = scratch_path("quarantine") + ".sqlite";
  {
    naturalization::LexiconStore s(path);
    const std::string rep = "{repeat 3 times {pick item}}";
    auto add = [&](naturalization::StoredRule r) {
      s.add_definition({0, r.head, r.body, "ana", 1}, {r});
    };
    add(rule("$Action", {"zig", "zag"}, "{move up}", "zig zag"));                        // r1
    add(rule("$Action", {"$Number", "zigs"}, "{repeat $1 times {move up}}", "3 zigs"));  // r2
    add(rule("$Action", {"go", "west"}, "{move left}", "go west"));                      // r3
    add(rule("$Action", {"$ROOT", "thrice"}, "{repeat 3 times $1}", "move up thrice"));  // r4
    add(rule("$Action", {"$Nope", "x"}, rep, "nope x"));                                 // r5
    add(rule("$Action", {"bad", "template"}, "{repeat 3 times", "bad template"));        // r6
    add(rule("$Action", {"a", "b"}, rep, "empty rhs"));                                  // r7
    add(rule("$Action", {"c", "d"}, rep, "rhs not json"));                               // r8
    add(rule("$Action", {"e", "f"}, rep, "body not a list"));                            // r9
    add(rule("$Action", {"g", "h"}, rep, "single category"));                            // r10
  }
  sql(path, "UPDATE rules SET rhs = '[]' WHERE id = 'r7'");
  sql(path, "UPDATE rules SET rhs = 'not json' WHERE id = 'r8'");
  sql(path, "UPDATE rules SET body = '{\"a\":1}' WHERE id = 'r9'");
  sql(path, "UPDATE rules SET rhs = '[\"$Action\"]' WHERE id = 'r10'");
  return path;
}

void check_quarantined(const Started& s) {
  std::vector<std::string> want;
  for (const auto& [id, why] : kBad) {
    want.push_back(id);
    const std::string w = s.warning_for(id);
    INFO("rule " << id << ", warnings:\n"
                 << [&] {
                      std::string all;
                      for (const auto& x : s.warnings) all += x + "\n";
                      return all;
                    }());
    CHECK_THAT(w, Catch::Contains("is quarantined, not served") && Catch::Contains(why));
  }
  std::sort(want.begin(), want.end());
  CHECK(s.quarantined_ids() == want);
  CHECK(s.served_ids() == std::vector<std::string>{"r1", "r2", "r3"});
}

std::string status_of(const Started& s, const std::string& text) {
  kernel::Session session(s.rt);
  naturalization::install_naturalization(session, s.nat);
  return status(session, text);
}

}  // namespace

TEST_CASE("a stored rule that does not load is quarantined at every start, rows or snapshot",
          "[naturalize][quarantine]") {
  const std::string store = store_with_bad_rules();
  {
    // First start: from the rows (no snapshot yet); it leaves a snapshot holding every live row.
    Started first(store);
    CHECK_FALSE(first.nat->startup().from_snapshot);
    CHECK(first.nat->startup().snapshot_saved);
    check_quarantined(first);
    CHECK(status_of(first, "zig zag") == "induced");
    CHECK(status_of(first, "4 zigs") == "induced");
  }
  {
    // Second start: from the snapshot. The bad rules are in it and must be named again.
    Started second(store);
    REQUIRE(second.nat->startup().from_snapshot);
    CHECK(second.nat->startup().snapshot_rules == 10);
    check_quarantined(second);
    CHECK(status_of(second, "go west") == "induced");
    CHECK(status_of(second, "c d") == "unparsable");
    // The history has one `quarantine` entry per rule and reason, though two starts met them
    // (docs/naturalization.md §5 "History and governance").
    std::vector<std::string> noted;
    for (const auto& e : second.nat->store().history())
      if (e.action == "quarantine") noted.push_back(e.rule);
    std::sort(noted.begin(), noted.end());
    CHECK(noted == second.quarantined_ids());
  }
  // `flipper lexicon list` names every one of them, and the export flags them.
  const auto list = clitest::run_flipper("lexicon list --set lexicon.path=" + store);
  CHECK(list.status == 0);
  for (const auto& [id, why] : kBad) {
    INFO(list.out);
    CHECK_THAT(list.out, Catch::Contains("QUARANTINED " + id + " ") && Catch::Contains(why));
  }
  CHECK_THAT(list.out, Catch::Contains("3 rules in") && Catch::Contains("7 quarantined"));
  const auto exported = clitest::run_flipper("lexicon export - --set lexicon.path=" + store, false);
  REQUIRE(exported.status == 0);
  std::istringstream lines(exported.out);
  int flagged = 0;
  for (std::string line; std::getline(lines, line);)
    if (kernel::Json::parse(line).contains("quarantined")) ++flagged;
  CHECK(flagged == 7);
}

TEST_CASE("a definition row whose body does not decode is flagged, never blocks the store",
          "[naturalize][quarantine]") {
  const std::string store = scratch_path("bad-definition") + ".sqlite";
  {
    naturalization::LexiconStore s(store);
    s.add_definition({0, "zig zag", {"move up"}, "ana", 1},
                     {rule("$Action", {"zig", "zag"}, "{move up}", "zig zag")});
  }
  sql(store, "UPDATE definitions SET body = 'oops' WHERE id = 1");
  naturalization::LexiconStore s(store);
  const auto defs = s.definitions();
  REQUIRE(defs.size() == 1);
  CHECK(defs[0].body.empty());
  CHECK_THAT(defs[0].decode_error, Catch::Contains("column 'body' holds 'oops'"));
  std::ostringstream out;
  s.export_jsonl(out);
  CHECK_THAT(out.str(), Catch::Contains("\"quarantined\":\"the row does not decode"));
  Started started(store);
  CHECK(started.served_ids() == std::vector<std::string>{"r1"});
}

TEST_CASE("preloaded definitions that do not load are named in a warning, the list and export",
          "[naturalize][preload]") {
  const std::string store = scratch_path("preload-report") + ".sqlite";
  const std::string preload = scratch_path("preload") + ".jsonl";
  std::ofstream(preload)
      << R"({"head":"zig zag","body":["move up","move right"],"author":"expert"})"
      << "\n"
      << R"({"head":"move left","body":["move right"],"author":"expert"})"
      << "\n\n"
      << R"({"head":"glorb","body":["fly to the moon"],"author":"eve"})"
      << "\n";
  auto check_failures = [&](const Started& s) {
    const auto& failures = s.nat->preload_report().failures;
    REQUIRE(failures.size() == 2);
    CHECK(failures[0].line == 2);
    CHECK(failures[0].head == "move left");
    CHECK(failures[0].code == "head_is_core");
    CHECK(failures[1].line == 4);
    CHECK(failures[1].author == "eve");
    CHECK(failures[1].code == "body_unparsable");
    REQUIRE(s.warnings.size() == 2);
    CHECK_THAT(s.warnings[0], Catch::Contains("line 2: definition 'move left' (author 'expert') "
                                              "was not loaded: head_is_core"));
    CHECK_THAT(s.warnings[1], Catch::Contains("line 4: definition 'glorb' (author 'eve') was not "
                                              "loaded: body_unparsable"));
    naturalization::LexiconStore copy(store);
    const auto rows = copy.preload_failures();
    REQUIRE(rows.size() == 2);  // replaced at each start, never duplicated
    CHECK(rows[0].file == preload);
    CHECK(rows[0].line == 2);
    CHECK(rows[1].code == "body_unparsable");
  };
  {
    Started first(store, preload);
    CHECK(first.nat->preload_report().replayed == 1);
    check_failures(first);
  }
  {
    Started again(store, preload);  // the good one is stored: skipped; the others fail again
    CHECK(again.nat->preload_report().already_stored == 1);
    check_failures(again);
  }
  const auto list = clitest::run_flipper("lexicon list --set lexicon.path=" + store);
  CHECK(list.status == 0);
  CHECK_THAT(list.out, Catch::Contains("PRELOAD FAILED " + preload +
                                       " line 2 'move left' "
                                       "(author 'expert'): head_is_core"));
  CHECK_THAT(list.out, Catch::Contains("line 4 'glorb' (author 'eve'): body_unparsable"));
  CHECK_THAT(list.out, Catch::Contains("2 preloaded definition(s) not loaded"));
  const auto exported = clitest::run_flipper("lexicon export - --set lexicon.path=" + store, false);
  int reported = 0;
  std::istringstream lines(exported.out);
  for (std::string line; std::getline(lines, line);)
    if (kernel::Json::parse(line).value("type", "") == "preload_failure") ++reported;
  CHECK(reported == 2);

  // Once the file loads, the report is cleared.
  std::ofstream(preload)
      << R"({"head":"zig zag","body":["move up","move right"],"author":"expert"})"
      << "\n";
  Started fixed(store, preload);
  CHECK(fixed.warnings.empty());
  CHECK(naturalization::LexiconStore(store).preload_failures().empty());
}
