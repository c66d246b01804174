// Tidy figures: exact CSV round trips, differences (timing apart), spread over seeds, comparison.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "flipper/record/compare.hpp"
#include "flipper/record/csv.hpp"
#include "flipper/record/figures.hpp"
#include "flipper/sdk/errors.hpp"
#include "record_scratch.hpp"

using namespace flipper::record;
namespace fs = std::filesystem;

namespace {
using recordtest::scratch;
}  // namespace

TEST_CASE("CSV fields are quoted exactly when they must be, and read back", "[record][csv]") {
  CHECK(csv_field("plain") == "plain");
  CHECK(csv_field("a,b") == "\"a,b\"");
  CHECK(csv_field("say \"hi\"") == "\"say \"\"hi\"\"\"");
  CHECK(csv_field("two\nlines") == "\"two\nlines\"");
  const CsvTable t = parse_csv("x,y\n\"a,b\",\"say \"\"hi\"\"\"\n\"two\nlines\",\n", "t");
  REQUIRE(t.rows.size() == 2);
  CHECK(t.rows[0] == std::vector<std::string>{"a,b", "say \"hi\""});
  CHECK(t.rows[1] == std::vector<std::string>{"two\nlines", ""});
  CHECK(t.column("y", "t") == 1);
  CHECK_THROWS_WITH(t.column("z", "t"), Catch::Contains("no column 'z'"));
  CHECK_THROWS_WITH(parse_csv("x,y\n1\n", "f.csv"),
                    Catch::Contains("f.csv: row 1 has 1 fields, the header 2"));
  CHECK_THROWS_WITH(parse_csv("x\n\"open\n", "f.csv"), Catch::Contains("unterminated quote"));
}

TEST_CASE("figure values survive the CSV bit for bit", "[record][figures]") {
  const std::vector<double> values = {0.1,    1.0 / 3, 3830, 97.0 / 3950 * 100,  1e-300,
                                      5e-324, -2.5,    0.0,  123456789.123456789};
  std::vector<Figure> figures;
  for (std::size_t i = 0; i < values.size(); ++i)
    figures.push_back({"v,1", "ours", "g" + std::to_string(i), "m", values[i], "%", i % 2 == 1});
  const fs::path dir = scratch("roundtrip");
  write_figures((dir / "figures.csv").string(), figures);
  const auto back = read_figures((dir / "figures.csv").string());
  REQUIRE(back.size() == values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    CHECK(back[i].variant == "v,1");    // quoted in the file
    CHECK(back[i].value == values[i]);  // exact, not approximately
    CHECK(back[i].timing == (i % 2 == 1));
  }
  CHECK(exact_number(0.1) == "0.1");
  CHECK(exact_number(3830) == "3830");
  const FigureTable t(back);
  CHECK(t.get("v,1", "ours", "g0", "m") == 0.1);
  CHECK_FALSE(t.find("v,1", "ours", "g0", "other"));
  CHECK_THROWS_WITH(t.get("v,1", "ours", "g0", "other"), Catch::Contains("v,1/ours/g0/other"));
}

TEST_CASE("differences: deterministic figures count, timing figures are apart",
          "[record][figures]") {
  const std::vector<Figure> a = {{"v", "ours", "all", "agree", 3830, "", false},
                                 {"v", "ours", "all", "latency_p50", 0.02, "ms", true},
                                 {"v", "ours", "all", "gone", 1, "", false},
                                 {"v", "ours", "A", "same", 7, "", false}};
  const std::vector<Figure> b = {{"v", "ours", "all", "agree", 3829, "", false},
                                 {"v", "ours", "all", "latency_p50", 0.03, "ms", true},
                                 {"v", "ours", "A", "same", 7, "", false},
                                 {"v", "ours", "all", "new", 2, "", false}};
  const FigureDiff d = diff_figures(a, b);
  REQUIRE(d.changed.size() == 1);
  CHECK(describe(d.changed[0].key) == "v/ours/all/agree");
  CHECK(d.changed[0].a == 3830);
  CHECK(d.changed[0].b == 3829);
  REQUIRE(d.timing.size() == 1);
  CHECK(describe(d.timing[0].key) == "v/ours/all/latency_p50");
  CHECK(d.only_a.size() == 1);
  CHECK(d.only_b.size() == 1);
  CHECK(d.compared == 2);  // agree and same; the timing figure is not counted
  // The smallest change of a double is a difference.
  const FigureDiff tiny = diff_figures({{"v", "s", "g", "m", 0.1, "", false}},
                                       {{"v", "s", "g", "m", std::nextafter(0.1, 1.0), "", false}});
  CHECK(tiny.changed.size() == 1);
}

TEST_CASE("spread over seeds: mean, sample sd, min, max per condition", "[record][figures]") {
  // Seeds 1, 2, 4 of condition c: mean 7/3, sd sqrt(((1-7/3)^2 + (2-7/3)^2 + (4-7/3)^2) / 2)
  // = sqrt(7/3); a condition of one variant has sd 0.
  const std::vector<VariantInfo> variants = {{"c,seed=1", "d1", "c", "seed=1", {}},
                                             {"c,seed=2", "d2", "c", "seed=2", {}},
                                             {"c,seed=3", "d3", "c", "seed=3", {}},
                                             {"alone", "d4", "alone", "", {}}};
  const std::vector<Figure> figures = {{"c,seed=1", "ours", "all", "m", 1, "", false},
                                       {"c,seed=2", "ours", "all", "m", 2, "", false},
                                       {"c,seed=3", "ours", "all", "m", 4, "", false},
                                       {"alone", "ours", "all", "m", 5, "", false}};
  const auto s = spread_over_seeds(figures, variants);
  REQUIRE(s.size() == 2);
  CHECK(s[0].condition == "c");
  CHECK(s[0].n == 3);
  CHECK(s[0].mean == Approx(7.0 / 3));
  CHECK(s[0].sd == Approx(std::sqrt(7.0 / 3)));
  CHECK(s[0].min == 1);
  CHECK(s[0].max == 4);
  CHECK(s[1].condition == "alone");
  CHECK(s[1].n == 1);
  CHECK(s[1].sd == 0);
}

TEST_CASE("compare puts two runs side by side, over seeds, timing apart", "[record][compare]") {
  const std::vector<VariantInfo> variants = {{"p=a,seed=1", "x", "p=a", "seed=1", {}},
                                             {"p=a,seed=2", "y", "p=a", "seed=2", {}}};
  RunFigures a{"A-run",
               {{"p=a,seed=1", "ours", "all", "len", 10, "cells", false},
                {"p=a,seed=2", "ours", "all", "len", 12, "cells", false},
                {"p=a,seed=1", "ours", "all", "same", 3, "", false},
                {"p=a,seed=2", "ours", "all", "same", 3, "", false},
                {"p=a,seed=1", "ours", "all", "cpu", 1, "ms", true},
                {"p=a,seed=2", "ours", "all", "cpu", 1, "ms", true}},
               variants};
  RunFigures b = a;
  b.label = "B-run";
  b.figures[1].value = 14;  // len over seeds: A 10, 12; B 10, 14
  b.figures[5].value = 3;   // a timing figure
  const std::string text = compare_runs(a, b, false);
  INFO(text);
  CHECK_THAT(text, Catch::Contains("# A-run (A) and B-run (B)"));
  CHECK_THAT(text, Catch::Contains("## p=a (over seeds: 2 in A, 2 in B)"));
  // A: mean 11, sd sqrt(2); B: mean 12, sd sqrt(8); the difference of the means +1.
  CHECK_THAT(text, Catch::Contains("| ours / all / len (cells) | 11 ± 1.414 (10–12, n=2) | "
                                   "12 ± 2.828 (10–14, n=2) | +1 |"));
  CHECK_THAT(text, Catch::Contains("Timing figures"));
  CHECK_THAT(text, Catch::Contains("1 of 2 figures differ; timing figures (not compared): 1."));
  CHECK_FALSE(Catch::Contains("same").match(text));  // unchanged figures only with --all
  CHECK_THAT(compare_runs(a, b, true),
             Catch::Contains("| ours / all / same | 3 ± 0 (3–3, n=2) | 3 ± 0 (3–3, n=2) | 0 |"));
}

TEST_CASE("compare orders numbers as numbers and says when it compared nothing",
          "[record][compare]") {
  const std::vector<VariantInfo> one = {{"v", "v", "v", "", {}}};
  RunFigures a{"A",
               {{"v", "ours", "all", "rank_10", 1, "", false},
                {"v", "ours", "all", "rank_2", 1, "", false},
                {"v", "ours", "all", "rank_1", 1, "", false},
                {"v", "ours", "all", "rank_02x", 1, "", false}},
               one};
  RunFigures b = a;
  for (auto& f : b.figures) f.value = 2;
  ComparisonCounts counts;
  const std::string text = compare_runs(a, b, false, &counts);
  INFO(text);
  CHECK(counts.compared == 4);
  CHECK(counts.differing == 4);
  const auto at = [&](const char* metric) {
    return text.find(std::string("all / ") + metric + " |");
  };
  CHECK(at("rank_1") < at("rank_2"));
  CHECK(at("rank_2") < at("rank_02x"));
  CHECK(at("rank_02x") < at("rank_10"));
  CHECK(at("rank_10") != std::string::npos);
  // Runs with no condition in common: nothing compared, said in words.
  RunFigures c{"C", {{"w", "ours", "all", "rank_1", 1, "", false}}, {{"w", "w", "w", "", {}}}};
  const std::string none = compare_runs(a, c, false, &counts);
  CHECK(counts.compared == 0);
  CHECK_THAT(none, Catch::Contains("Nothing compared: A and B share no figure of one condition."));
  CHECK_FALSE(Catch::Contains("0 of 0").match(none));
  CHECK(show_value(123456.75) == "123456.8");
  CHECK(show_value(1234.25) == "1234");
  CHECK(show_value(0.0125) == "0.0125");
}
