// The replay end to end on tests/apps/replay/data: a core run with an accept, a private run with a
// definition and its deletion, a shared run with a preloaded expert definition. Every figure is
// known exactly.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "flipper/record/figures.hpp"
#include "flipper/replay/corpus.hpp"
#include "flipper/replay/experiment.hpp"
#include "flipper/replay/metrics.hpp"
#include "flipper/replay/replayer.hpp"

using namespace flipper::replay;

namespace {
const Corpus& corpus() {
  static const Corpus c = load_corpus(FLIPPER_SOURCE_DIR "/tests/apps/replay/data");
  return c;
}
ReplayResult run(const std::vector<std::string>& runs = {}) {
  ReplayOptions o;
  o.sets = {"induction.generalize=false"};
  o.runs = runs;
  return replay(corpus(), o);
}
}  // namespace

TEST_CASE("the synthetic corpus loads with runs and groups") {
  const Corpus& c = corpus();
  REQUIRE(c.runs.size() == 3);
  CHECK(c.find_run("test/B")->group == "B");
  CHECK(c.preloaded("test/C").size() == 1);
  CHECK(c.worlds.size() == 3);
}

TEST_CASE("synthetic replay: statuses, accept, definitions, deletion") {
  const ReplayResult r = run();
  REQUIRE(r.queries.size() == 12);
  std::vector<std::string> ours;
  for (const auto& q : r.queries) ours.push_back(q.ours);
  CHECK(ours == std::vector<std::string>{"core", "unparsable", "core", "core",               // A
                                         "unparsable", "induced", "unparsable",              // B
                                         "induced", "core", "induced", "induced", "core"});  // C
  CHECK(r.queries[7].our_author == "other");  // the expert's rule
  CHECK(r.queries[9].our_author == "self");
  CHECK(r.queries[10].our_author == "other");  // c2 uses c1's rule (shared)

  REQUIRE(r.accepts.size() == 1);
  CHECK(r.accepts[0].matched);
  CHECK(r.accepts[0].rank == 0);
  CHECK(r.accepts[0].executed);
  CHECK(r.accepts[0].compared);
  CHECK((r.accepts[0].robot && r.accepts[0].held && r.accepts[0].floor));
  CHECK(r.accepts[0].diff == "agree");

  REQUIRE(r.defines.size() == 3);
  for (const auto& d : r.defines) CHECK(d.ok);
  REQUIRE(r.deletes.size() == 1);
  CHECK(r.deletes[0].definition == "d:test/B#2");
  CHECK(r.deletes[0].deleted.size() == 1);

  const Metrics m = compute_metrics(r);
  CHECK(m.overall.n == 12);
  CHECK(m.overall.agree == 11);
  CHECK(m.overall.confusion.at("Core").at("core") == 4);
  CHECK(m.overall.confusion.at("Nothing").at("core") == 1);
  CHECK(m.overall.confusion.at("Nothing").at("unparsable") == 3);
  CHECK(m.overall.confusion.at("Induced").at("induced") == 4);
  // Tokens per participant (task, in tables): A a1 6 all, ours 4 successful, original 2.
  CHECK(m.ours.tokens_all_sum.at("A") == 6);
  CHECK(m.ours.tokens_successful_sum.at("A") == 4);
  CHECK(m.original.tokens_successful_sum.at("A") == 2);
  CHECK(m.ours.tokens_successful_sum.at("B") == 2);
  CHECK(m.ours.tokens_successful.at("C").mean == Approx(4.0));  // c1 6, c2 2 (c3 not counted)
  CHECK(m.ours.induced.at("C").mean == Approx(1.5));
  CHECK(m.ours.induced.at("C").min == 1);
  CHECK(m.ours.induced.at("C").max == 2);
  CHECK(m.ours.core.at("C").mean == Approx(0.5));
  CHECK(m.ours.induced.at("B").mean == Approx(1.0));
  CHECK(m.ours.others.mean == Approx(1.0));
  CHECK(m.ours.self.mean == Approx(0.5));
  CHECK(m.original.others.mean == Approx(1.0));
  CHECK(m.original.self.mean == Approx(0.5));
  CHECK(m.exec.all == 1);
  CHECK(m.original_latency.histogram[7] == 12);  // every walltime is 50 ms
  CHECK(m.preloaded_ok == 1);
  CHECK(m.defines_ok == 2);
  CHECK(m.rules_deleted == 1);
}

TEST_CASE("replay is deterministic and --max-queries stops each run") {
  ReplayOptions o;
  o.sets = {"induction.generalize=false"};
  o.max_queries = 1;
  const ReplayResult a = replay(corpus(), o), b = replay(corpus(), o);
  REQUIRE(a.queries.size() == 3);  // one per run
  CHECK(a.accepts.size() == 1);    // A's accept follows its first query
  for (std::size_t i = 0; i < a.queries.size(); ++i) CHECK(a.queries[i].ours == b.queries[i].ours);
  CHECK_THROWS(run({"no/such-run"}));
}

TEST_CASE("an experiment writes a run folder: metrics, CSV, figures and the report") {
  namespace fs = std::filesystem;
  const fs::path out = fs::path(FLIPPER_BINARY_DIR) / "replay-test-out";
  fs::remove_all(out);
  Experiment e;
  e.corpus = FLIPPER_SOURCE_DIR "/tests/apps/replay/data";
  e.sets = {"induction.generalize=false"};
  e.variants = {{"plain", {}}, {"beam5", {"parser.params.beam=5"}}};
  RunOptions options;
  options.out = out.string();
  options.plots = false;
  const RunSummary s = run_experiment(e, options);
  REQUIRE(s.variants.size() == 2);
  CHECK(fs::path(s.run_dir).parent_path() == out);
  for (const char* f : {"metrics.json", "queries.csv", "participants.csv", "groups.csv",
                        "accepts.csv", "definitions.csv", "figures.csv"})
    CHECK(fs::exists(fs::path(s.run_dir) / "plain" / f));
  for (const char* f :
       {"manifest.json", "figures.csv", "variants.csv", "settings.csv", "report.md"})
    CHECK(fs::exists(fs::path(s.run_dir) / f));
  std::ifstream report(fs::path(s.run_dir) / "report.md");
  const std::string text((std::istreambuf_iterator<char>(report)), {});
  CHECK(text.find("## Variants compared") != std::string::npos);
  CHECK(text.find("plain/tokens.svg") != std::string::npos);
  CHECK(text.find("| `agree` | 1 | agree |") != std::string::npos);  // the class table
  CHECK(text.find("Unexplained: 0.") != std::string::npos);
  // The synthetic corpus's figures (see above): 11 of 12 statuses agree, in every variant.
  const flipper::record::FigureTable t(s.figures);
  for (const auto& v : s.variants) {
    CHECK(t.get(v.name, "ours", "all", "agree") == 11);
    CHECK(t.get(v.name, "ours", "all", "queries") == 12);
  }
}

TEST_CASE("experiment files are validated") {
  namespace fs = std::filesystem;
  const fs::path f = fs::path(FLIPPER_BINARY_DIR) / "replay-bad-experiment.yaml";
  std::ofstream(f) << "corpus: x\nvariant: []\n";
  CHECK_THROWS_WITH(load_experiment(f.string()), Catch::Contains("unknown key 'variant'"));
  const Experiment e = load_experiment(FLIPPER_SOURCE_DIR "/configs/experiments/ablation.yaml");
  CHECK(e.variants.size() == 5);
  // Relative to the file (configs/experiments/): two levels up is the repository's root.
  const fs::path root = fs::weakly_canonical(FLIPPER_SOURCE_DIR);
  CHECK(e.corpus == (root / "data" / "study2018" / "dev").string());
}

TEST_CASE("a sweep's grid: names, conditions, seeds, and parameters a plugin lacks",
          "[replay][sweep]") {
  Experiment e;
  e.name = "sweep";
  e.corpus = FLIPPER_SOURCE_DIR "/tests/apps/replay/data";
  e.variants = {{"chart", {"parser.plugin=chart"}}};
  e.sweep = {{"planner.plugin", {"astar", "ompl"}}, {"planner.params.seed", {"1", "2"}}};
  const auto planned = plan_variants(e);
  REQUIRE(planned.size() == 4);
  CHECK(planned[0].info.name == "chart,planner.plugin=astar,planner.params.seed=1");
  CHECK(planned[0].info.directory == "chart+planner.plugin=astar+planner.params.seed=1");
  CHECK(planned[3].info.name == "chart,planner.plugin=ompl,planner.params.seed=2");
  // The condition is the name without the seed; the seed is what the spread is taken over.
  CHECK(planned[0].info.condition == "chart,planner.plugin=astar");
  CHECK(planned[3].info.condition == "chart,planner.plugin=ompl");
  CHECK(planned[3].info.seed == "planner.params.seed=2");
  // astar declares no seed: left out, with a note; ompl takes it.
  CHECK(planned[0].sets == std::vector<std::string>{"parser.plugin=chart", "planner.plugin=astar"});
  REQUIRE(planned[0].notes.size() == 1);
  CHECK_THAT(planned[0].notes[0],
             Catch::Contains("`planner.params.seed=1` left out: plugin 'astar' (planner) "
                             "declares no parameter 'seed'"));
  CHECK(planned[3].sets == std::vector<std::string>{"parser.plugin=chart", "planner.plugin=ompl",
                                                    "planner.params.seed=2"});
  CHECK(planned[3].notes.empty());
  // A parameter no variant's plugin declares is a typo, not a silent no-op.
  e.sweep = {{"planner.plugin", {"astar", "ompl"}}, {"planner.params.sed", {"1"}}};
  CHECK_THROWS_WITH(plan_variants(e), Catch::Contains("sweep key 'planner.params.sed': no "
                                                      "variant's planner plugin declares a "
                                                      "parameter 'sed'"));
  // Sweep files: a map of lists; a repeated value is refused.
  namespace fs = std::filesystem;
  const fs::path f = fs::path(FLIPPER_BINARY_DIR) / "replay-sweep-experiment.yaml";
  std::ofstream(f) << "corpus: x\nsweep: {planner.params.seed: [1, 2, 1]}\n";
  CHECK_THROWS_WITH(load_experiment(f.string()),
                    Catch::Contains("sweep key 'planner.params.seed' lists '1' twice"));
  std::ofstream(f) << "corpus: x\nsweep: [1, 2]\n";
  CHECK_THROWS_WITH(load_experiment(f.string()), Catch::Contains("'sweep' must be a map"));
  std::ofstream(f) << "corpus: x\nsweep: {planner.params.seed: [1, 2], parser.params.beam: 5}\n";
  const Experiment loaded = load_experiment(f.string());
  REQUIRE(loaded.sweep.size() == 2);
  CHECK(loaded.sweep[0].values == std::vector<std::string>{"1", "2"});
  CHECK(loaded.sweep[1].values == std::vector<std::string>{"5"});
}
