// The plots (apps/plots, docs/experiments.md §5) checked through what they plotted, not pixels:
// each figure's .plotdata.json against the run's CSV files (exact values), and the rules — axes
// fitted to the data (zoomed where bars differ by a little), value labels, error bars over seeds,
// µs below 1 ms, full-width panels — on a hand-made run folder whose figures trigger each rule.
// Pictures are deterministic; without matplotlib the run succeeds and says how to get them.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"
#include "flipper/record/figures.hpp"
#include "flipper/record/manifest.hpp"

using namespace flipper;
using clitest::contains;
using clitest::read_file;
using clitest::run_flipper;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Two conditions (p=a, p=b) over two seeds each.
const std::vector<std::string> kVariants = {"p=a,seed=1", "p=a,seed=2", "p=b,seed=1", "p=b,seed=2"};

// A run folder with the figures the plots read: agreement close together (zoom), tokens far
// apart (no zoom), plan CPU times below 1 ms (µs).
std::string hand_made_run(const std::string& name) {
  const std::string dir = clitest::scratch_dir(name);
  std::vector<record::Figure> f;
  const double agreement[4][4] = {{97.0, 98.0, 96.5, 97.2},
                                  {97.5, 98.0, 96.0, 97.3},
                                  {98.5, 99.0, 95.5, 97.9},
                                  {99.0, 99.5, 95.0, 98.1}};
  std::vector<record::VariantInfo> variants;
  for (std::size_t v = 0; v < kVariants.size(); ++v) {
    const std::string& n = kVariants[v];
    variants.push_back({n, "v" + std::to_string(v), n.substr(0, 3), n.substr(4), {{"p", "x"}}});
    const char* groups[] = {"A", "B", "C", "all"};
    for (int g = 0; g < 4; ++g)
      f.push_back({n, "ours", groups[g], "agreement", agreement[v][g], "%", false});
    for (const char* g : {"A", "B", "C"}) {
      f.push_back({n, "ours", g, "tokens_successful_mean", 100.0 * (1 + static_cast<double>(v)),
                   "tokens", false});
      f.push_back({n, "original", g, "tokens_successful_mean", 90, "tokens", false});
      f.push_back({n, "ours", g, "tokens_all_mean", 500, "tokens", false});
    }
    f.push_back({n, "ours", "all", "accepts_matched", 785, "accepts", false});
    f.push_back(
        {n, "ours", "all", "accepted_first", 780.0 + static_cast<double>(v), "accepts", false});
    f.push_back({n, "ours", "all", "accepted_top3", 785, "accepts", false});
    f.push_back({n, "ours", "all", "plan_success_rate", 92.9, "%", false});
    f.push_back(
        {n, "ours", "all", "path_length_mean", 7.5 + static_cast<double>(v), "cells", false});
    f.push_back({n, "ours", "all", "turns_mean", 2.25, "turns", false});
    f.push_back(
        {n, "ours", "all", "plan_cpu_p50", 0.004 + 0.001 * static_cast<double>(v), "ms", true});
  }
  record::write_figures(dir + "/figures.csv", f);
  record::write_variants(dir, variants);
  record::write_manifest(dir, {{"kind", "replay"}});
  for (std::size_t v = 0; v < kVariants.size(); ++v)
    fs::create_directories(dir + "/v" + std::to_string(v));
  return dir;
}

json plotdata(const std::string& path) {
  return json::parse(read_file(path));
}

// The mean and sample sd over seeds as the plot script computes them (sum from 0, in order).
std::pair<double, double> over_seeds(double a, double b) {
  const double mean = (0.0 + a + b) / 2;
  const double sd = std::sqrt((0.0 + (a - mean) * (a - mean) + (b - mean) * (b - mean)) / 1);
  return {mean, sd};
}

}  // namespace

TEST_CASE("plots show exactly the run's figures, by the rules", "[replay][plots]") {
  const std::string run = hand_made_run("plots-rules");
  const auto drawn = run_flipper("replay plot " + run);
  INFO(drawn.out);
  REQUIRE(drawn.status == 0);
  CHECK(contains(drawn.out, "plots: "));
  for (const char* f : {"variants", "planner"})
    for (const char* ext : {".pdf", ".svg", ".plotdata.json"})
      CHECK(fs::exists(run + "/" + f + ext));

  const json variants = plotdata(run + "/variants.plotdata.json");
  REQUIRE(variants["panels"].size() == 4);
  // Status agreement: per condition the mean over its two seeds, sd error bars; bars differ by a
  // few points, so the axis is zoomed onto them (and the title says so), not 0-100.
  const json& agree = variants["panels"][0];
  CHECK(agree["unit"] == "%");
  CHECK(agree["categories"] == json{"A", "B", "C", "all"});
  REQUIRE(agree["series"].size() == 2);
  CHECK(agree["series"][0]["label"] == "p=a");
  CHECK(agree["series"][1]["label"] == "p=b");
  double lowest = 1e9, highest = 0;
  const double agreement[2][2][4] = {{{97.0, 98.0, 96.5, 97.2}, {97.5, 98.0, 96.0, 97.3}},
                                     {{98.5, 99.0, 95.5, 97.9}, {99.0, 99.5, 95.0, 98.1}}};
  for (int c = 0; c < 2; ++c)
    for (int g = 0; g < 4; ++g) {
      const auto [mean, sd] = over_seeds(agreement[c][0][g], agreement[c][1][g]);
      const json& s = agree["series"][c];
      CHECK(s["values"][g].get<double>() == mean);
      CHECK(s["errors"][0][g].get<double>() == sd);
      CHECK(s["errors"][1][g].get<double>() == sd);
      char label[16];
      std::snprintf(label, sizeof label, "%.1f", mean);
      CHECK(s["value_labels"][g] == label);
      lowest = std::min(lowest, mean - sd);
      highest = std::max(highest, mean + sd);
    }
  CHECK(agree["zoomed"] == true);
  CHECK(contains(agree["title"].get<std::string>(), "axis zoomed"));
  CHECK(agree["ylim"][0].get<double>() > 80);  // not from 0
  CHECK(agree["ylim"][0].get<double>() <= lowest);
  CHECK(agree["ylim"][1].get<double>() >= highest);
  CHECK(agree["ylim"][1].get<double>() <= highest + 0.6 * (highest - lowest) + 1e-9);
  // Tokens differ by a factor of 4: from 0, and the axis ends just above the largest bar.
  const json& tokens = variants["panels"][1];
  CHECK(tokens["zoomed"] == false);
  CHECK(tokens["ylim"][0].get<double>() == 0);
  const double top = tokens["series"][1]["values"][0].get<double>() +
                     tokens["series"][1]["errors"][1][0].get<double>();
  CHECK(top == 350 + std::sqrt(5000.0));  // p=b: 300 and 400 tokens
  CHECK(tokens["ylim"][1].get<double>() == Approx(top * 1.12));
  // Full-width panels, all of one width.
  for (const auto& p : variants["panels"]) {
    CHECK(p["width_fraction"].get<double>() >= 0.8);
    CHECK(p["width_fraction"] == variants["panels"][0]["width_fraction"]);
  }

  // The planner: plan CPU times below 1 ms are drawn in µs, the CSV's ms times 1000.
  const json planner = plotdata(run + "/planner.plotdata.json");
  REQUIRE(planner["panels"].size() == 4);
  const json& cpu = planner["panels"][3];
  CHECK(cpu["unit"] == "µs");
  CHECK(cpu["timing"] == true);
  CHECK(cpu["categories"] == json{"p=a", "p=b"});
  const auto [cpu_a, sd_a] = over_seeds(0.004 * 1000.0, 0.005 * 1000.0);
  CHECK(cpu["series"][0]["values"][0].get<double>() == cpu_a);
  CHECK(cpu["series"][0]["errors"][0][0].get<double>() == sd_a);
  CHECK(cpu["series"][0]["value_labels"][0] == "4.5");
  // Planner success is the same everywhere: no zoom onto equal bars.
  CHECK(planner["panels"][0]["zoomed"] == false);
  CHECK(planner["panels"][0]["series"][0]["values"][0].get<double>() == 92.9);
  // A percentage axis ends at 100 (92.9 × 1.12 would pass it).
  CHECK(planner["panels"][0]["ylim"][1].get<double>() == 100.0);

  // Per variant: the tokens figure's bars are the CSV's values.
  const json t0 = plotdata(run + "/v0/tokens.plotdata.json");
  CHECK(t0["panels"][0]["series"][0]["values"] == json{90.0, 90.0, 90.0});
  CHECK(t0["panels"][0]["series"][1]["values"] == json{100.0, 100.0, 100.0});
  CHECK(t0["panels"][0]["series"][1]["value_labels"] == json{"100", "100", "100"});

  // Deterministic: drawn again, every picture has the same bytes.
  const std::string svg = read_file(run + "/variants.svg"), pdf = read_file(run + "/planner.pdf");
  CHECK(contains(svg, "p=a"));  // text stays text
  REQUIRE(run_flipper("replay plot " + run).status == 0);
  CHECK(read_file(run + "/variants.svg") == svg);
  CHECK(read_file(run + "/planner.pdf") == pdf);
}

TEST_CASE("without matplotlib a run succeeds and says how to get its plots", "[replay][plots]") {
  const std::string dir = clitest::scratch_dir("plots-missing");
  // A Python that cannot import Debian's matplotlib (-S: no site packages).
  const std::string python = dir + "/python";
  std::ofstream(python) << "#!/bin/sh\nexec /usr/bin/python3 -S \"$@\"\n";
  fs::permissions(python, fs::perms::owner_all);
  for (const std::string& env :
       {"FLIPPER_PYTHON=" + python, std::string("FLIPPER_PYTHON=/no/such/python3")}) {
    const auto r = clitest::run_shell(env + " " + FLIPPER_BINARY_DIR +
                                      "/bin/flipper replay --corpus tests/apps/replay/data --out " +
                                      dir + "/out 2>&1");
    INFO(env << "\n" << r.out);
    CHECK(r.status == 0);
    CHECK(contains(r.out, "flipper replay: note: plots skipped: no Python with matplotlib"));
    CHECK(contains(r.out, "apt-get install python3-matplotlib"));
    CHECK(contains(r.out, "flipper replay plot "));
    CHECK(fs::exists(dir + "/out/latest/figures.csv"));
    CHECK_FALSE(fs::exists(dir + "/out/latest/plain/tokens.svg"));
    CHECK(contains(read_file(dir + "/out/latest/report.md"), "Plots: plots skipped"));
  }
}
