// `flipper replay check` on a run whose figures.csv was edited (docs/experiments.md §4): a figure
// the record lacks, a figure only the record has, and a changed one each make the check fail
// (exit 1), named in its account; the untouched run reproduces (exit 0).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"

using namespace flipper;
using clitest::contains;
using clitest::read_file;
using clitest::run_flipper;
namespace fs = std::filesystem;

namespace {

const std::string kSynthetic = std::string(FLIPPER_SOURCE_DIR) + "/tests/apps/replay/data";

// A copy of `run` named `name` whose figures.csv is `edit`ed.
std::string edited_copy(const std::string& run, const std::string& name,
                        const std::function<void(std::string&)>& edit) {
  const std::string copy = fs::path(run).parent_path().parent_path().string() + "/" + name;
  fs::copy(run, copy, fs::copy_options::recursive);
  std::string text = read_file(copy + "/figures.csv");
  edit(text);
  std::ofstream(copy + "/figures.csv", std::ios::trunc) << text;
  return copy;
}

}  // namespace

TEST_CASE("replay check fails on a missing, an extra and a changed figure",
          "[replay][record][check]") {
  const std::string dir = clitest::scratch_dir("replay-check-figures");
  const std::string experiment = dir + "/one.yaml";
  std::ofstream(experiment) << "name: one\ncorpus: " << kSynthetic
                            << "\nset: [induction.generalize=false]\n"
                               "variants:\n  - name: plain\n";
  const auto made = run_flipper(
      "replay --json --experiment " + experiment + " --out " + dir + "/runs --no-plots", false);
  INFO(made.out);
  REQUIRE(made.status == 0);
  const std::string run = nlohmann::json::parse(made.out)["run"].get<std::string>();
  // The row every edit starts from: the agreement of the whole corpus (11 of 12, hand-counted in
  // test_run_record.cpp), not a timing figure.
  const std::string row = "plain,ours,all,agree,11,";
  REQUIRE(contains(read_file(run + "/figures.csv"), "\n" + row));

  const auto ok = run_flipper("replay check " + run);
  INFO(ok.out);
  CHECK(ok.status == 0);
  CHECK(contains(ok.out, "result: the run reproduces"));

  const auto line_of = [&](const std::string& text) {
    const auto at = text.find("\n" + row) + 1;
    return std::make_pair(at, text.find('\n', at) + 1 - at);
  };
  // The record lacks the figure: only the re-run has it.
  const std::string missing = edited_copy(run, "missing", [&](std::string& text) {
    const auto [at, size] = line_of(text);
    text.erase(at, size);
  });
  const auto lacks = run_flipper("replay check " + missing);
  INFO(lacks.out);
  CHECK(lacks.status == 1);
  CHECK(contains(lacks.out, "  plain/ours/all/agree: not in the recorded run\n"));
  CHECK(contains(lacks.out, "result: the run does NOT reproduce"));

  // The record has a figure the re-run does not make.
  const std::string extra = edited_copy(run, "extra", [&](std::string& text) {
    const auto [at, size] = line_of(text);
    std::string invented = text.substr(at, size);
    invented.replace(0, row.size(), "plain,ours,all,agree_twice,11,");
    text.insert(at, invented);
  });
  const auto more = run_flipper("replay check " + extra);
  INFO(more.out);
  CHECK(more.status == 1);
  CHECK(contains(more.out, "  plain/ours/all/agree_twice: missing in the re-run\n"));
  CHECK(contains(more.out, "result: the run does NOT reproduce"));

  // A changed figure: named with both values.
  const std::string changed = edited_copy(run, "changed", [&](std::string& text) {
    const auto [at, size] = line_of(text);
    text.replace(at, row.size(), "plain,ours,all,agree,10,");
  });
  const auto differs = run_flipper("replay check " + changed);
  INFO(differs.out);
  CHECK(differs.status == 1);
  CHECK(contains(differs.out, "plain/ours/all/agree: recorded 10, now 11"));
  CHECK(contains(differs.out, "result: the run does NOT reproduce"));
  fs::remove_all(dir);
}
