// `flipper replay` as a user runs it, on small corpora: every run is a new folder with a
// manifest that names what produced it (checked against independent sources: `flipper config
// print`, coreutils' sha256sum, the plugins' sidecars); a re-check from the manifest finds no
// difference in a fresh run and names a changed figure; shards merge into the unsharded run;
// --jobs 1 and --jobs 2 give the same files; the planner figures of accepted programs on hand-made
// worlds (docs/experiments.md).
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "cli_test_support.hpp"
#include "flipper/record/build_info.hpp"
#include "flipper/record/csv.hpp"
#include "flipper/record/figures.hpp"
#include "run_files.hpp"

using namespace flipper;
using clitest::contains;
using clitest::read_file;
using clitest::run_flipper;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string kSynthetic = std::string(FLIPPER_SOURCE_DIR) + "/tests/apps/replay/data";

std::string sha256sum(const std::string& path) {
  return clitest::run_shell("sha256sum '" + path + "'").out.substr(0, 64);
}

// Runs a replay with --json and returns its run folder.
std::string replay_run(const std::string& args) {
  const auto r = run_flipper("replay --json " + args, false);
  INFO("flipper replay --json " << args << "\n" << r.out);
  REQUIRE(r.status == 0);
  return json::parse(r.out)["run"].get<std::string>();
}

// A small sweep experiment on the synthetic corpus: 2 beams x 2 steps.
std::string sweep_experiment(const std::string& dir) {
  const std::string path = dir + "/sweep.yaml";
  std::ofstream(path) << "name: small sweep\ncorpus: " << kSynthetic
                      << "\nset: [induction.generalize=false]\n"
                         "sweep:\n  parser.params.beam: [5, 10]\n  scorer.params.step: [0.5, 1]\n";
  return path;
}

}  // namespace

TEST_CASE("a replay writes a new run folder whose manifest names what produced it",
          "[replay][record]") {
  const std::string out = clitest::scratch_dir("record-manifest");
  const std::string run = replay_run("--corpus tests/apps/replay/data --out " + out +
                                     " --no-plots --set induction.generalize=false");
  CHECK(fs::path(run).parent_path() == fs::path(out));
  CHECK(fs::path(run).filename().string().rfind("replay-", 0) == 0);
  const json m = json::parse(read_file(run + "/manifest.json"));
  CHECK(m["kind"] == "replay");
  CHECK(m["status"] == "complete");
  // Versions and commit: as `flipper --version` prints them and as compiled in.
  const std::string version = run_flipper("--version").out;
  CHECK(contains(version, "flipper " + m["build"]["flipper"].get<std::string>() + " (plugin SDK " +
                              m["build"]["sdk"].get<std::string>() + ")"));
  CHECK(m["build"]["commit"] == record::build_info().commit);
  CHECK(m["build"]["dirty"] == record::build_info().dirty);
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  CHECK(m["host"]["name"] == host);
  const std::regex iso(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)");
  CHECK(std::regex_match(m["started"].get<std::string>(), iso));
  CHECK(std::regex_match(m["finished"].get<std::string>(), iso));
  CHECK(m["started"].get<std::string>() <= m["finished"].get<std::string>());
  const auto argv = m["command"]["argv"];
  CHECK(argv[1] == "replay");
  CHECK(std::find(argv.begin(), argv.end(), "--out") != argv.end());
  // The corpus: every file with the checksum coreutils computes.
  CHECK(m["corpus"]["path"] == fs::canonical(kSynthetic).string());
  REQUIRE(m["corpus"]["files"].size() == 4);
  for (const auto& f : m["corpus"]["files"])
    CHECK(f["sha256"] == sha256sum(kSynthetic + "/" + f["name"].get<std::string>()));
  // The variant: its effective config as `flipper config print` shows it, its plugins with the
  // sidecar's version and the library's checksum.
  REQUIRE(m["variants"].size() == 1);
  const json& v = m["variants"][0];
  CHECK(v["name"] == "plain");
  CHECK(v["config"]["effective"] ==
        run_flipper("config print --set induction.generalize=false", false).out);
  REQUIRE(v["plugins"].size() == 6);
  std::set<std::string> sections;
  for (const auto& p : v["plugins"]) {
    sections.insert(p["section"].get<std::string>());
    const std::string file = p["file"].get<std::string>();
    CHECK(p["sha256"] == sha256sum(file));
    const std::string sidecar = read_file(
        (fs::path(file).parent_path() / (p["name"].get<std::string>() + ".flipper.yaml")).string());
    CHECK(contains(sidecar, "version: " + p["version"].get<std::string>()));
  }
  CHECK(sections ==
        std::set<std::string>{"world", "planner", "parser", "scorer", "rewriter", "similarity"});
  CHECK(v["seeds"].empty());  // no selected plugin takes a seed
  CHECK(v["mode_overrides"]["B"][1] == "lexicon.sharing=private");
  // report.md names the same.
  const std::string report = read_file(run + "/report.md");
  for (const std::string& want : std::vector<std::string>{
           "| flipper | " + m["build"]["flipper"].get<std::string>(),
           "commit `" + m["build"]["commit"].get<std::string>() + "`",
           "| planner: astar | " + v["plugins"][1]["version"].get<std::string>(),
           v["plugins"][1]["sha256"].get<std::string>(),
           m["corpus"]["files"][0]["sha256"].get<std::string>().substr(0, 16), "Seeds: none",
           m["started"].get<std::string>(), "```yaml\nworld:\n  plugin: grid2d"})
    CHECK_THAT(report, Catch::Contains(want));

  // An OMPL variant records its seed (the plugin's default, 1).
  const std::string ompl = replay_run("--corpus tests/apps/replay/data --out " + out +
                                      " --no-plots --max-queries 1 --set planner.plugin=ompl");
  const json mo = json::parse(read_file(ompl + "/manifest.json"));
  CHECK(mo["variants"][0]["seeds"] == json{{"planner.params.seed", "1"}});
  CHECK_THAT(read_file(ompl + "/report.md"), Catch::Contains("`planner.params.seed=1`"));
}

TEST_CASE("runs are never overwritten, and --out must name a parent", "[replay][record]") {
  const std::string out = clitest::scratch_dir("record-no-overwrite");
  const std::string args = "--corpus tests/apps/replay/data --out " + out + " --no-plots";
  const std::string first = replay_run(args);
  std::ofstream(first + "/my-notes.txt") << "mine\n";
  const std::string figures_before = read_file(first + "/figures.csv");
  const std::string second = replay_run(args);
  CHECK(first != second);
  CHECK(read_file(first + "/figures.csv") == figures_before);
  CHECK(read_file(first + "/my-notes.txt") == "mine\n");
  CHECK(fs::read_symlink(out + "/latest") == fs::path(second).filename());
  // A run folder given as --out is refused (it would nest a run in a run).
  const auto nested =
      run_flipper("replay --corpus tests/apps/replay/data --no-plots --out " + first);
  CHECK(nested.status == 2);
  CHECK(
      contains(nested.out, "flipper replay: [bad_request] --out '" + first + "' is a run folder"));
  const auto missing = run_flipper("replay --corpus tests/apps/replay/data");
  CHECK(missing.status == 2);
  CHECK(contains(missing.out, "flipper replay: [usage] --out PARENT is required"));
  const auto print =
      run_flipper("replay --corpus tests/apps/replay/data --out " + out + " --print nope");
  CHECK(print.status == 2);
  CHECK(contains(print.out, "--print 'nope': no such table"));
}

TEST_CASE("figures.csv holds the report's figures, tidy", "[replay][record]") {
  const std::string out = clitest::scratch_dir("record-figures");
  const std::string run = replay_run("--corpus tests/apps/replay/data --out " + out +
                                     " --no-plots --set induction.generalize=false");
  const auto figures = record::read_figures(run + "/figures.csv");
  const record::FigureTable t(figures);
  const json metrics = json::parse(read_file(run + "/plain/metrics.json"));
  // Against metrics.json (written from the same metrics by other code) and the known synthetic
  // figures (test_replay_synthetic.cpp): 11 of 12 agree, one accept matched and executed.
  CHECK(t.get("plain", "ours", "all", "agree") == 11);
  CHECK(t.get("plain", "ours", "all", "queries") == 12);
  CHECK(t.get("plain", "ours", "all", "agreement") == 100.0 * 11 / 12);
  for (const char* key : {"accepts", "matched", "executed", "compared", "all", "unexplained"}) {
    const std::string metric = std::string(key) == "accepts"       ? "accepts"
                               : std::string(key) == "all"         ? "exec_all_agree"
                               : std::string(key) == "unexplained" ? "unexplained"
                                                                   : std::string("accepts_") + key;
    INFO(metric);
    CHECK(t.get("plain", "ours", "all", metric) == metrics["execution"][key].get<double>());
  }
  CHECK(t.get("plain", "ours", "Core->core", "confusion") == 4);
  CHECK(t.get("plain", "ours", "Nothing->unparsable", "confusion") == 3);
  CHECK(t.get("plain", "paper", "A", "tokens_successful_mean") == 1150);
  // Timing figures are marked, the others are not.
  for (const auto& f : figures) {
    INFO(f.metric << " " << f.source);
    const bool timing = f.source == "ours" &&
                        f.metric != "latency_n" &&  // a count of queries, not a time
                        (f.metric.rfind("latency", 0) == 0 || f.metric.rfind("plan_cpu", 0) == 0);
    CHECK(f.timing == timing);
  }
  // The report shows figures.csv's values (its agreement line, from the table).
  CHECK_THAT(read_file(run + "/report.md"),
             Catch::Contains("Overall: 11 / 12 = 91.7 %. By group: A 3/4 (75.0 %);"));
}

TEST_CASE("a fresh run re-checks without difference, a changed figure is named",
          "[replay][record][check]") {
  const std::string dir = clitest::scratch_dir("record-check");
  const std::string run = replay_run("--experiment " + sweep_experiment(dir) + " --out " + dir +
                                     "/runs --no-plots --jobs 2");
  const auto ok = run_flipper("replay check " + run);
  INFO(ok.out);
  CHECK(ok.status == 0);
  CHECK(contains(ok.out, "re-ran 4 variant(s) from the manifest"));
  CHECK(contains(ok.out, "none differs"));
  CHECK(contains(ok.out, "result: the run reproduces"));
  CHECK_FALSE(contains(ok.out, "warning:"));

  // One figure changed in the record: exit 1, named with both values; timing apart.
  const std::string tampered = dir + "/tampered";
  fs::copy(run, tampered, fs::copy_options::recursive);
  std::string text = read_file(tampered + "/figures.csv");
  const std::string row = "\"parser.params.beam=5,scorer.params.step=0.5\",ours,all,agree,11,";
  REQUIRE(contains(text, row));
  text.replace(text.find(row), row.size(),
               "\"parser.params.beam=5,scorer.params.step=0.5\",ours,all,agree,10,");
  std::ofstream(tampered + "/figures.csv") << text;
  const auto bad = run_flipper("replay check " + tampered);
  INFO(bad.out);
  CHECK(bad.status == 1);
  CHECK(contains(bad.out, "figures: 1 of "));
  CHECK(contains(bad.out,
                 "parser.params.beam=5,scorer.params.step=0.5/ours/all/agree: recorded "
                 "10, now 11"));
  CHECK(contains(bad.out, "result: the run does NOT reproduce"));

  // Another plugin file than recorded: a warning, and the figures are still compared.
  const std::string moved = dir + "/other-plugin";
  fs::copy(run, moved, fs::copy_options::recursive);
  json m = json::parse(read_file(moved + "/manifest.json"));
  m["variants"][0]["plugins"][2]["sha256"] = "0000";
  std::ofstream(moved + "/manifest.json") << m.dump(2);
  const auto warned = run_flipper("replay check " + moved);
  INFO(warned.out);
  CHECK(warned.status == 0);
  CHECK(contains(warned.out, "warning: plugin parser 'chart' sha256 differs: recorded 0000, now "));
  CHECK(contains(warned.out, "none differs"));

  const auto none = run_flipper("replay check " + dir);
  CHECK(none.status == 2);
  CHECK(
      contains(none.out, "flipper replay check: [bad_request] '" + dir + "' is not a run folder"));
}

TEST_CASE("one job or two, and merged shards, give the same files", "[replay][record][sweep]") {
  const std::string dir = clitest::scratch_dir("record-jobs");
  const std::string experiment = sweep_experiment(dir);
  const std::string one =
      replay_run("--experiment " + experiment + " --out " + dir + "/one --jobs 1");
  const std::string two =
      replay_run("--experiment " + experiment + " --out " + dir + "/two --jobs 2");
  const auto variants = record::read_variants(one);
  REQUIRE(variants.size() == 4);
  CHECK(variants[1].name == "parser.params.beam=5,scorer.params.step=1");
  CHECK(variants[1].directory == "parser.params.beam=5+scorer.params.step=1");
  CHECK(variants[1].condition == variants[1].name);  // no seed axis: every variant its own
  // Every file but the manifest, the report (dates, durations) and the timing figures' pictures.
  const auto files = runfiles::compare_runs(one, two);
  INFO(files.text);
  CHECK(files.differing.empty());
  CHECK(files.compared >= 4 * 11 + 6);  // CSV and JSON per variant, the run's own files, plots
  CHECK(files.pictures >= 4 * 3 * 2);   // tokens, induced_core, others_self: PDF and SVG

  // Two shards, merged: the unsharded run's files.
  const std::string s0 =
      replay_run("--experiment " + experiment + " --out " + dir + "/shards --shard 0/2 --no-plots");
  const std::string s1 =
      replay_run("--experiment " + experiment + " --out " + dir + "/shards --shard 1/2 --no-plots");
  CHECK(record::read_variants(s0).size() == 2);
  CHECK(record::read_variants(s0)[1].name == "parser.params.beam=10,scorer.params.step=0.5");
  const auto merged = run_flipper("replay merge " + s1 + " " + s0 + " --out " + dir + "/merged");
  INFO(merged.out);
  REQUIRE(merged.status == 0);
  CHECK(contains(merged.out, "merged 2 shards, 4 variants"));
  const auto same = runfiles::compare_runs(one, dir + "/merged/latest");
  INFO(same.text);
  CHECK(same.differing.empty());
  const json mm = json::parse(read_file(dir + "/merged/latest/manifest.json"));
  CHECK(mm["merged_from"].size() == 2);
  CHECK(mm["shard"].is_null());

  // What merge refuses.
  auto refused = [&](const std::string& args, const std::string& why) {
    const auto r = run_flipper("replay merge " + args + " --out " + dir + "/refused");
    INFO(args << "\n" << r.out);
    CHECK(r.status == 2);
    CHECK(contains(r.out, why));
  };
  refused(s0, "shard(s) 1 of 2 missing");
  refused(s0 + " " + s0 + " " + s1, "shard 0 is given twice");
  refused(one + " " + s1, "is not a shard (it ran without --shard I/N)");
  const std::string third = replay_run("--experiment " + experiment + " --out " + dir +
                                       "/shards3 --shard 1/3 --no-plots");
  refused(s0 + " " + third, "is a shard of 3, '" + s0 + "' of 2");
  const std::string other = replay_run("--experiment " + experiment + " --out " + dir +
                                       "/other --shard 1/2 --no-plots --max-queries 2");
  refused(s0 + " " + other, "are shards of different experiments");
  CHECK_FALSE(fs::exists(dir + "/refused"));
}

TEST_CASE("planner figures of accepted programs on hand-made worlds", "[replay][planner]") {
  // Two accepts: `visit room1` around a wall (up 2, right 2: 4 cells, 1 turn) and `visit room2`
  // straight ahead (right 3: 3 cells, no turn); each plans once with A*.
  const std::string dir = clitest::scratch_dir("record-planner");
  const std::string corpus = dir + "/corpus";
  fs::create_directories(corpus);
  const json rooms = {{"room1", {{2, 2}}}, {"room2", {{3, 4}}}};
  auto world = [&](const char* id, int x, int y) {
    return json{{"world_id", id},
                {"bounds", {{"min", {0, 0}}, {"max", {4, 4}}}},
                {"robot", {{"x", x}, {"y", y}, {"holding", json::array()}}},
                {"walls", {{1, 0}, {1, 1}}},
                {"items", json::array()},
                {"rooms", rooms}};
  };
  std::ofstream(corpus + "/worlds.jsonl") << world("w1", 0, 0).dump() << "\n"
                                          << world("w2", 0, 4).dump() << "\n";
  auto command = [&](int n, const char* kind, const char* text, const char* world_id) {
    json c = {{"qid", "t/A#" + std::to_string(n)},
              {"source", "t/A"},
              {"group", "A"},
              {"session", "u"},
              {"user", "u"},
              {"participant", "u"},
              {"in_authors_tables", true},
              {"phase", "task"},
              {"kind", kind},
              {"utterance", text},
              {"world_id", world_id},
              {"next_world_id", world_id},
              {"line", n}};
    if (std::string(kind) == "q") {
      c["status"] = "Core";
      c["n_parses"] = 1;
      c["walltime_s"] = 0.05;
      c["author"] = nullptr;
    } else {
      c["formula"] = std::string("(: ") + text + ")";
      c["for_qid"] = "t/A#" + std::to_string(n - 1);
    }
    return c.dump() + "\n";
  };
  std::ofstream(corpus + "/queries.jsonl")
      << command(1, "q", "visit room1", "w1") << command(2, "accept", "visit room1", "w1")
      << command(3, "q", "visit room2", "w2") << command(4, "accept", "visit room2", "w2");
  auto answer = [](int n, const std::string& text) {
    return json{{"qid", "t/A#" + std::to_string(n)},
                {"candidates",
                 {{{"pretty", "{" + text + "}"},
                   {"formula", "(: " + text + ")"},
                   {"core_only", true}}}},
                {"accepted_rank", 0}}
               .dump() +
           "\n";
  };
  std::ofstream(corpus + "/original-answers.jsonl")
      << answer(1, "visit room1") << answer(3, "visit room2");
  std::ofstream(corpus + "/definitions.jsonl") << "";
  const std::string run = replay_run("--corpus " + corpus + " --out " + dir + "/out --no-plots");
  const record::CsvTable accepts = record::read_csv(run + "/plain/accepts.csv");
  REQUIRE(accepts.rows.size() == 2);
  auto cell = [&](std::size_t row, const char* column) {
    return accepts.rows[row][accepts.column(column, "accepts.csv")];
  };
  CHECK(cell(0, "executed") == "1");
  CHECK(cell(0, "plan_success") == "1");
  CHECK(cell(0, "path_length") == "4");
  CHECK(cell(0, "turns") == "1");
  CHECK(cell(0, "plan_calls") == "1");
  CHECK(cell(1, "path_length") == "3");
  CHECK(cell(1, "turns") == "0");
  CHECK(cell(1, "plan_calls") == "1");
  const record::FigureTable t(record::read_figures(run + "/figures.csv"));
  CHECK(t.get("plain", "ours", "all", "plan_runs") == 2);
  CHECK(t.get("plain", "ours", "all", "plan_success_rate") == 100);
  CHECK(t.get("plain", "ours", "all", "path_length_sum") == 7);
  CHECK(t.get("plain", "ours", "all", "path_length_mean") == 3.5);
  CHECK(t.get("plain", "ours", "all", "turns_mean") == 0.5);
  CHECK(t.get("plain", "ours", "all", "plan_calls") == 2);
}
