// One error format everywhere (`flipper <cmd>: [code] message`), --version, --json listings,
// `lexicon delete`, and `run` reading phrases of the user's lexicon.
#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"
#include "flipper/sdk/version.hpp"

using namespace flipper::clitest;

using nlohmann::json;

TEST_CASE("errors have one format and the documented exit status", "[cli][format]") {
  const Run version = run_flipper("--version");
  CHECK(version.status == 0);
  CHECK(version.out == "flipper 0.1.0 (plugin SDK " + std::to_string(FLIPPER_SDK_VERSION_MAJOR) +
                           "." + std::to_string(FLIPPER_SDK_VERSION_MINOR) + "." +
                           std::to_string(FLIPPER_SDK_VERSION_PATCH) + ")\n");

  const Run unknown = run_flipper("bogus");
  CHECK(unknown.status == 2);
  CHECK(contains(unknown.out, "flipper: [usage] "));
  const Run missing = run_flipper("run");
  CHECK(missing.status == 2);
  CHECK(contains(missing.out, "flipper run: [usage] program is required"));
  const Run bad_program = run_flipper("run --set lexicon.path=:memory: 'zorp blah'");
  CHECK(bad_program.status == 1);
  CHECK(contains(bad_program.out, "flipper run: [bad_program] cannot understand 'zorp blah'"));
  // The repair (docs/protocol.md "Repairs") on the same line: what it understood instead.
  const Run repaired = run_flipper("run --set lexicon.path=:memory: 'move up xyzzy'");
  CHECK(repaired.status == 1);
  CHECK(contains(repaired.out,
                 "; nearest understood: 'move up' (drop 'xyzzy'); understood: "
                 "'move up'; not understood: 'xyzzy' (unknown) (teach a phrase"));
  const Run bad_key = run_flipper("config check --set session.kk=3");
  CHECK(bad_key.status == 2);
  CHECK(contains(bad_key.out,
                 "flipper config check: [bad_config] config <embedded default>: unknown config key "
                 "'session.kk' (did you mean 'session.k'?)"));
  const Run no_store = run_flipper("lexicon list --set lexicon.path=/nonexistent/x.sqlite");
  CHECK(no_store.status == 2);
  CHECK(contains(no_store.out,
                 "flipper lexicon list: [bad_config] no lexicon store at "
                 "'/nonexistent/x.sqlite'"));
  const Run no_plugin = run_flipper("plugins astarr");
  CHECK(no_plugin.status == 2);
  CHECK(contains(no_plugin.out,
                 "flipper plugins: [plugin_not_found] no plugin named 'astarr' "
                 "(did you mean 'astar'?)"));
}

TEST_CASE("json output (--json) of plugins, config check, lexicon list and replay",
          "[cli][format]") {
  const Run plugins = run_flipper("plugins --json", false);
  REQUIRE(plugins.status == 0);
  const json p = json::parse(plugins.out);
  bool astar_selected = false;
  for (const auto& e : p["plugins"])
    if (e["name"] == "astar") astar_selected = e["selected"].get<bool>() && e["status"] == "ok";
  CHECK(astar_selected);
  const json one = json::parse(run_flipper("plugins astar --json", false).out);
  REQUIRE(one["plugins"].size() == 1);
  CHECK(one["plugins"][0]["params"].size() >= 4);

  const Run check = run_flipper("config check --json --set session.k=7", false);
  REQUIRE(check.status == 0);
  const json c = json::parse(check.out);
  CHECK(c["config"]["session"]["k"] == 7);
  CHECK(c["config"]["planner"]["plugin"] == "astar");
  CHECK(c["config"]["induction"]["alignment"] == true);

  const std::string store = scratch("json-list.sqlite");
  const std::string script = write_file("json-list.jsonl", R"({"op":"user","name":"ana"}
{"op":"define","head":"pick 3 items","body":["repeat 3 times pick item"]}
)");
  REQUIRE(run_flipper("session --set lexicon.path=" + store + " " + script).status == 0);
  const json l =
      json::parse(run_flipper("lexicon list --json --set lexicon.path=" + store, false).out);
  REQUIRE(l["rules"].size() == 2);  // pick 3 items, and its $ItemAct generalisation
  CHECK(l["rules"][0]["id"] == "r1");
  CHECK(l["rules"][0]["author"] == "ana");

  const std::string out = scratch_dir("json-replay");
  const Run replay = run_flipper("replay --json --corpus " + std::string(FLIPPER_STUDY_DIR) +
                                     "/dev --runs sep2018/TuesdayAfternoon --max-queries 3 "
                                     "--out " +
                                     out,
                                 false);
  INFO(replay.out);
  REQUIRE(replay.status == 0);
  const json r = json::parse(replay.out);
  CHECK(r["variants"][0]["variant"] == "plain");
  // A new run folder under --out, named after the experiment ("replay" without one).
  const std::string run = r["run"].get<std::string>();
  CHECK(run.rfind(out + "/replay-", 0) == 0);
  CHECK(r["report"] == run + "/report.md");
  CHECK(r["figures"] == run + "/figures.csv");
}

TEST_CASE("lexicon delete checks authorship, and run reads the user's phrases", "[cli][format]") {
  const std::string store = scratch("delete.sqlite");
  const std::string script = write_file("delete.jsonl", R"({"op":"user","name":"ana"}
{"op":"define","head":"pick 3 items","body":["repeat 3 times pick item"]}
)");
  REQUIRE(run_flipper("session --set lexicon.path=" + store + " " + script).status == 0);
  const std::string set = " --set lexicon.path=" + store;

  // run with the lexicon: ana's phrase parses; with private sharing bob does not see it.
  const Run ana = run_flipper("run --user ana 'pick 3 items'" + set);
  INFO(ana.out);
  CHECK(ana.status == 0);
  CHECK(contains(ana.out, "interpretation: {repeat 3 times {pick item }}"));
  const Run bob = run_flipper("run --user bob 'pick 3 items' --set lexicon.sharing=private" + set);
  CHECK(bob.status == 1);
  CHECK(contains(bob.out, "flipper run: [bad_program] cannot understand 'pick 3 items'"));
  // Several readings: the top one is taken, and run says so.
  const Run two = run_flipper("run 'visit room3 or room5 containing item is red'" + set);
  CHECK(two.status == 0);
  CHECK(contains(two.out, "flipper run: note: took the top of 2 readings (p=0.50)"));

  const Run forbidden = run_flipper("lexicon delete r1 --user bob" + set);
  CHECK(forbidden.status == 1);
  CHECK(contains(forbidden.out, "flipper lexicon delete: [forbidden] "));
  const Run unknown = run_flipper("lexicon delete r99 --user ana" + set);
  CHECK(unknown.status == 1);
  CHECK(contains(unknown.out, "flipper lexicon delete: [not_found] "));
  const Run deleted = run_flipper("lexicon delete r1 --user ana" + set);
  INFO(deleted.out);
  CHECK(deleted.status == 0);
  CHECK(contains(deleted.out, "deleted rule r1 of ana"));
  const json l = json::parse(run_flipper("lexicon list --json" + set, false).out);
  REQUIRE(l["rules"].size() == 1);
  CHECK(l["rules"][0]["id"] == "r2");
}
