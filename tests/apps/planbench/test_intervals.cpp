// Confidence intervals over seeds (docs/planners.md §5, "Intervals"): the quantiles, the Wilson
// score interval and Student's t interval against numbers computed by hand (and with Python's
// statistics.NormalDist for the digits past the fourth), and the report's intervals table.
#include <catch2/catch.hpp>
#include <cmath>

#include "flipper/planbench/intervals.hpp"
#include "flipper/planbench/measure.hpp"
#include "flipper/planbench/summary.hpp"

using namespace flipper;
using namespace flipper::planbench;
using Catch::Detail::Approx;

TEST_CASE("intervals: the normal and t quantiles of a 95 % interval") {
  CHECK(normal_quantile(0.95) == Approx(1.959963984540054).epsilon(1e-12));
  // Student's t in closed form for 1 and 2 degrees of freedom (p = 0.975): tan(π(p − ½)) =
  // 12.706205 and (2p − 1)·sqrt(2 / (4p(1 − p))) = 4.302653; 30 from the printed table, 2.0423.
  const double p = 0.975, pi = std::acos(-1.0);
  CHECK(t_quantile(0.95, 1) == Approx(std::tan(pi * (p - 0.5))).epsilon(1e-12));
  CHECK(t_quantile(0.95, 2) ==
        Approx((2 * p - 1) * std::sqrt(2 / (4 * p * (1 - p)))).epsilon(1e-12));
  CHECK(t_quantile(0.95, 1) == Approx(12.706204736174696).epsilon(1e-12));
  CHECK(t_quantile(0.95, 2) == Approx(4.302652729749461).epsilon(1e-12));
  CHECK(t_quantile(0.95, 30) == Approx(2.0423).margin(5e-5));
}

TEST_CASE("intervals: Wilson score interval of a success rate") {
  // 7 of 10: p = 0.7, z² = 3.8415; centre (0.7 + 0.19207) / 1.38415 = 0.64449, half-width
  // 1.96 · sqrt(0.021 + 0.0096037) / 1.38415 = 0.24772: [0.3968, 0.8922].
  auto ci = wilson_interval(7, 10);
  REQUIRE(ci);
  CHECK(ci->low == Approx(0.39677814746114537).margin(1e-12));
  CHECK(ci->high == Approx(0.8922087325936989).margin(1e-12));
  CHECK(std::round(ci->low * 1e4) / 1e4 == 0.3968);
  CHECK(std::round(ci->high * 1e4) / 1e4 == 0.8922);
  // The boundaries: none or all (the interval stays inside [0, 1] and is not [p, p]).
  ci = wilson_interval(0, 10);
  REQUIRE(ci);
  CHECK(ci->low == Approx(0).margin(1e-12));
  CHECK(ci->high == Approx(0.27753279986288915).margin(1e-12));
  ci = wilson_interval(10, 10);
  REQUIRE(ci);
  CHECK(ci->low == Approx(0.7224672001371109).margin(1e-12));
  CHECK(ci->high == Approx(1.0).margin(1e-12));
  CHECK(ci->high <= 1.0);
  ci = wilson_interval(1, 1);
  REQUIRE(ci);
  CHECK(ci->low == Approx(0.20654931437723745).margin(1e-12));
  CHECK_FALSE(wilson_interval(0, 0));
  // Another level: 99 % (z = 2.5758) is wider: [0.3200, 0.9204].
  ci = wilson_interval(7, 10, 0.99);
  REQUIRE(ci);
  CHECK(ci->low == Approx(0.3200246792011026).margin(1e-12));
  CHECK(ci->high == Approx(0.9204336834769342).margin(1e-12));
}

TEST_CASE("intervals: Student's t interval of a mean over seeds") {
  // 1, 2, 3: mean 2, sd 1, t(0.975; 2) = 4.302653: 2 ± 4.302653 / sqrt(3) = 2 ± 2.484138.
  auto ci = t_interval({1, 2, 3});
  REQUIRE(ci);
  CHECK(ci->low == Approx(-0.4841377117503294).margin(1e-12));
  CHECK(ci->high == Approx(4.484137711750329).margin(1e-12));
  // Two seeds: 1 and 3, sd sqrt(2): 2 ± 12.706205.
  ci = t_interval({1, 3});
  REQUIRE(ci);
  CHECK(ci->low == Approx(2 - 12.706204736174696).margin(1e-12));
  CHECK(ci->high == Approx(2 + 12.706204736174696).margin(1e-12));
  // Equal values: no spread, the interval is the point.
  ci = t_interval({5, 5, 5});
  REQUIRE(ci);
  CHECK(ci->low == 5);
  CHECK(ci->high == 5);
  // One seed or none: no interval.
  CHECK_FALSE(t_interval({4}));
  CHECK_FALSE(t_interval({}));
}

namespace {

std::vector<std::string> row(const std::string& planner, const std::string& seed,
                             const std::string& task, bool success, std::size_t length,
                             std::size_t shortest) {
  RunRow r;
  r.world = "w";
  r.planner = planner;
  r.plugin = planner;
  r.seed = seed;
  r.task = task;
  r.status = success ? "found" : "no_path";
  r.success = success;
  if (success) r.length = length;
  r.shortest = shortest;
  return row_fields(r);
}

}  // namespace

TEST_CASE("intervals: the report's table, per world × planner over its seeds") {
  record::CsvTable table;
  table.header = run_columns();
  // p, seed 1: lengths 4 and 6 of shortest 4 (ratios 1 and 1.5); seed 2: 4 of 4 and a failure.
  table.rows = {row("p", "1", "a", true, 4, 4), row("p", "1", "b", true, 6, 4),
                row("p", "2", "a", true, 4, 4), row("p", "2", "b", false, 0, 4),
                row("q", "", "a", true, 3, 3)};
  // p: 3 of 4 solved, Wilson [0.3006, 0.9544]; ratio per seed 1.25 and 1, mean 1.125, sd
  // 0.125·sqrt(2), t(0.975; 1) = 12.706205: 1.125 ± 1.588276 = [-0.463, 2.713]; length per seed
  // 5 and 4: 4.5 ± 6.353102 = [-1.85, 10.85]. The low ends are cut at what a ratio (1) and a
  // length (0) can be. q: one plan, one seed: Wilson of 1 of 1, no t.
  CHECK(intervals_table(table) ==
        "| world | planner | seeds | plans | success [95 % Wilson] | length / shortest: mean over "
        "seeds [95 % t] | length: mean over seeds [95 % t] |\n"
        "|---|---|---|---|---|---|---|\n"
        "| w | p | 2 | 4 | 75.0 % [30.1, 95.4] | 1.125 [1.000, 2.713] | 4.50 [0.00, 10.85] |\n"
        "| w | q | – | 1 | 100.0 % [20.7, 100.0] | 1.000 [–] | 3.00 [–] |\n");
}

TEST_CASE("intervals: intervals.csv, the plots' error bars, from the seeds' figures") {
  record::CsvTable table;
  table.header = run_columns();
  table.rows = {row("p", "1", "a", true, 4, 4), row("p", "1", "b", true, 6, 4),
                row("p", "2", "a", true, 4, 4), row("p", "2", "b", false, 0, 4),
                row("q", "", "a", true, 3, 3)};
  const auto csv = record::parse_csv(intervals_csv(bench_figures(table)), "intervals.csv");
  REQUIRE(csv.header == std::vector<std::string>{"condition", "metric", "seeds", "mean", "low",
                                                 "high", "method", "timing"});
  REQUIRE(csv.rows.size() == 8);  // 2 conditions × success, ratio, turns, CPU
  auto at = [&](std::size_t r, std::size_t c) { return std::stod(csv.rows[r][c]); };
  // p's success: 3 of 4 plans, Wilson in % [30.0642, 95.4413].
  CHECK(csv.rows[0][0] == "world=w,planner=p");
  CHECK(csv.rows[0][1] == "success");
  CHECK(csv.rows[0][2] == "2");
  CHECK(at(0, 3) == 75);
  CHECK(at(0, 4) == Approx(30.0641842582402).margin(1e-9));
  CHECK(at(0, 5) == Approx(95.44127391902995).margin(1e-9));
  CHECK(csv.rows[0][6] == "wilson");
  // p's length / shortest: the seeds' figures 1.25 and 1, 1.125 ± 1.588276, the low end cut at 1.
  CHECK(csv.rows[1][1] == "length_ratio_mean");
  CHECK(at(1, 3) == 1.125);
  CHECK(at(1, 4) == 1.0);
  CHECK(at(1, 5) == Approx(2.713275592021837).margin(1e-9));
  CHECK(csv.rows[1][6] == "t");
  // Turns and CPU time are 0 in every row here: the interval is [0, 0]; CPU time is timing.
  CHECK(csv.rows[2][1] == "turns_mean");
  CHECK((at(2, 4) == 0 && at(2, 5) == 0));
  CHECK(csv.rows[3][1] == "cpu_us_median");
  CHECK(csv.rows[3][7] == "1");
  CHECK(csv.rows[2][7] == "0");
  // q: one seed: Wilson of 1 of 1 in %, no t interval (low and high empty).
  CHECK(csv.rows[4][0] == "world=w,planner=q");
  CHECK(at(4, 4) == Approx(20.654931437723745).margin(1e-9));
  CHECK(at(4, 5) == 100);
  CHECK(csv.rows[5][1] == "length_ratio_mean");
  CHECK(csv.rows[5][2] == "1");
  CHECK(csv.rows[5][4].empty());
  CHECK(csv.rows[5][5].empty());
}
