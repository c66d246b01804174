// `--set parser.plugin=floating` and `--set scorer.plugin=perceptron` in every front end of
// build/bin/flipper: run, session (with the perceptron's state persisted in the lexicon), repl
// and replay; and the parser x scorer experiment writing the cross-variant figure.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"
#include "flipper/record/figures.hpp"
#include "flipper/replay/experiment.hpp"

using namespace flipper;
using clitest::contains;
using clitest::run_flipper;

namespace {

const std::string kSwap = " --set parser.plugin=floating --set scorer.plugin=perceptron";

std::vector<nlohmann::json> answers(const std::string& out) {
  std::vector<nlohmann::json> a;
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] == '{') a.push_back(nlohmann::json::parse(line));
  return a;
}

// A fresh output directory under build/tests/tmp/cli.
std::string scratch_dir(const std::string& name) {
  const std::string dir = std::string(FLIPPER_BINARY_DIR) + "/tests/tmp/cli/" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

}  // namespace

TEST_CASE("run: floating + perceptron read extra words, chart refuses them") {
  const auto r =
      run_flipper("run --set lexicon.path=:memory:" + kSwap + " 'please visit room1 now'");
  INFO(r.out);
  CHECK(r.status == 0);
  CHECK(contains(r.out, "interpretation: {visit room1}"));
  const auto chart = run_flipper("run --set lexicon.path=:memory: 'please visit room1 now'");
  CHECK(chart.status == 1);
  CHECK(contains(chart.out, "cannot understand"));
}

TEST_CASE("session: floating readings, definitions, perceptron state across sessions") {
  const std::string lexicon = clitest::scratch("floating-perceptron.sqlite");
  const std::string ambiguous = "visit room1 or room2 containing item is red or is blue";
  const std::string script1 = clitest::write_file(
      "floating-session1.jsonl",
      "{\"op\":\"query\",\"text\":\"please visit room1 now\"}\n"
      "{\"op\":\"accept\",\"rank\":0}\n"
      "{\"op\":\"define\",\"head\":\"move up twice\",\"body\":[\"move up; move up\"]}\n"
      "{\"op\":\"query\",\"text\":\"please move up twice\"}\n"
      "{\"op\":\"query\",\"text\":\"" +
          ambiguous + "\",\"k\":10}\n{\"op\":\"accept\",\"rank\":1}\n");
  const auto r1 = run_flipper("session " + script1 + " --set lexicon.path=" + lexicon + kSwap);
  INFO(r1.out);
  REQUIRE(r1.status == 0);
  const auto a = answers(r1.out);
  REQUIRE(a.size() == 6);
  for (const auto& x : a) CHECK(x.value("ok", false));
  // A floating reading: not core, no rules.
  CHECK(a[0]["status"] == "induced");
  CHECK(a[0]["candidates"][0]["formula"] == "{visit room1}");
  CHECK(a[0]["candidates"][0]["rules"].empty());
  // `move up twice` floats to `move up`, yet it is not core: the definition is accepted.
  CHECK_FALSE(a[2]["rules"].empty());
  // The rule is `$Action twice` (a statement hole is never $ROOT, docs/naturalization.md), which
  // scores below the floating `{move up}` reading: the rule's reading is offered, not necessarily
  // first.
  bool rule_reading = false;
  for (const auto& c : a[3]["candidates"])
    rule_reading = rule_reading || (c["formula"] == "{{move up};{move up}}" && !c["rules"].empty());
  CHECK(rule_reading);
  REQUIRE(a[4]["candidates"].size() >= 2);
  const std::string second = a[4]["candidates"][1]["formula"];

  // The perceptron's weights were saved with the lexicon: a new session ranks the accepted
  // program first (a fresh model ranks it second, as the first session saw).
  const std::string script2 = clitest::write_file(
      "floating-session2.jsonl", "{\"op\":\"query\",\"text\":\"" + ambiguous + "\"}\n");
  const auto r2 = run_flipper("session " + script2 + " --set lexicon.path=" + lexicon + kSwap);
  const auto b = answers(r2.out);
  REQUIRE(b.size() == 1);
  CHECK(b[0]["candidates"][0]["formula"] == second);
  const auto fresh =
      answers(run_flipper("session " + script2 + " --set lexicon.path=:memory:" + kSwap).out);
  REQUIRE(fresh.size() == 1);
  CHECK(fresh[0]["candidates"][0]["formula"] != second);
}

TEST_CASE("repl: a floating reading is shown and chosen") {
  const std::string input =
      clitest::write_file("floating-repl.txt", "please visit room1 now\n1\n:quit\n");
  const auto r = run_flipper("repl --set lexicon.path=:memory:" + kSwap + " < " + input);
  INFO(r.out);
  CHECK(r.status == 0);
  CHECK(contains(r.out, "[1] {visit room1}"));
  CHECK(contains(r.out, "leaves words out"));
  CHECK(contains(r.out, "Robot at [9,0]"));  // as `flipper run "visit room1"` ends
}

TEST_CASE("replay: floating + perceptron on the synthetic corpus") {
  const std::string out = scratch_dir("floating-replay");
  const auto r = run_flipper("replay --corpus tests/apps/replay/data --out " + out +
                             " --set induction.generalize=false" + kSwap);
  INFO(r.out);
  CHECK(r.status == 0);
  CHECK(std::filesystem::exists(out + "/latest/report.md"));  // the run's folder under --out
  const auto m = nlohmann::json::parse(clitest::read_file(out + "/latest/plain/metrics.json"));
  CHECK(m["agreement"]["n"] == 12);
  CHECK(m.contains("floating_top"));
}

TEST_CASE("the parser x scorer experiment writes the cross-variant section") {
  const auto e =
      replay::load_experiment(FLIPPER_SOURCE_DIR "/configs/experiments/parser-scorer.yaml");
  REQUIRE(e.variants.size() == 4);
  auto small = e;
  small.corpus = FLIPPER_SOURCE_DIR "/tests/apps/replay/data";
  const std::string out = scratch_dir("floating-experiment");
  replay::RunOptions options;
  options.out = out;
  options.plots = false;
  const auto run = replay::run_experiment(small, options);
  REQUIRE(run.variants.size() == 4);
  const std::string report = clitest::read_file(run.run_dir + "/report.md");
  CHECK(contains(report, "## Variants compared"));
  CHECK(contains(report, "![variants](variants.svg)"));
  // The synthetic corpus has every figure known (tests/apps/replay/test_replay_synthetic.cpp):
  // 11/12 agree and the one accept's program ranks first, whichever parser and scorer.
  const record::FigureTable t(run.figures);
  for (const auto& v : run.variants) {
    INFO(v.name);
    CHECK(t.get(v.name, "ours", "all", "agree") == 11);
    CHECK(t.get(v.name, "ours", "all", "accepted_first") == 1);
    CHECK(contains(report, "| " + v.name + " | 91.7 / "));
  }
}
