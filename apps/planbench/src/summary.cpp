// Summary tables and figures of a benchmark run's runs.csv (docs/planners.md §5).
#include "flipper/planbench/summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "flipper/planbench/intervals.hpp"
#include "stats.hpp"

namespace flipper::planbench {
namespace {

using stats::max_of;
using stats::mean;
using stats::median;
using stats::sd;

struct Run {
  std::string seed;
  std::string stopped;  // the time limit that stopped the plan (runs.csv `stopped`), or ""
  bool success = false;
  std::optional<double> length, ratio;
  double turns = 0, expansions = 0, cpu_us = 0, wall_us = 0;
  std::optional<double> peak_rss_kib, memory_kib;
};

// The runs of one world × planner, in the order they appear.
struct Group {
  std::string world, planner;
  std::vector<Run> runs;
  std::vector<std::string> seeds;  ///< in order of appearance ("" for an unseeded planner)
};

std::optional<double> number(const std::string& text) {
  if (text.empty()) return std::nullopt;
  return std::stod(text);
}

std::vector<Group> groups_of(const record::CsvTable& t) {
  const std::string where = "runs.csv";
  const std::size_t world = t.column("world", where), planner = t.column("planner", where),
                    seed = t.column("seed", where), success = t.column("success", where),
                    length = t.column("length", where), ratio = t.column("length_ratio", where),
                    turns = t.column("turns", where), expansions = t.column("expansions", where),
                    cpu = t.column("cpu_us", where), wall = t.column("wall_us", where),
                    peak = t.column("peak_rss_kib", where), memory = t.column("memory_kib", where);
  // Run folders written before the column existed have no `stopped`.
  const auto stopped_at = std::find(t.header.begin(), t.header.end(), "stopped");
  const auto stopped = static_cast<std::size_t>(stopped_at - t.header.begin());
  std::vector<Group> groups;
  for (const auto& r : t.rows) {
    auto g = std::find_if(groups.begin(), groups.end(), [&](const Group& x) {
      return x.world == r[world] && x.planner == r[planner];
    });
    if (g == groups.end()) g = groups.insert(groups.end(), Group{r[world], r[planner], {}, {}});
    if (std::find(g->seeds.begin(), g->seeds.end(), r[seed]) == g->seeds.end())
      g->seeds.push_back(r[seed]);
    Run run;
    run.seed = r[seed];
    if (stopped_at != t.header.end() && stopped < r.size()) run.stopped = r[stopped];
    run.success = r[success] == "1";
    run.length = number(r[length]);
    run.ratio = number(r[ratio]);
    run.turns = number(r[turns]).value_or(0);
    run.expansions = number(r[expansions]).value_or(0);
    run.cpu_us = number(r[cpu]).value_or(0);
    run.wall_us = number(r[wall]).value_or(0);
    run.peak_rss_kib = number(r[peak]);
    run.memory_kib = number(r[memory]);
    g->runs.push_back(run);
  }
  return groups;
}

// What the figures and tables say about some runs (a cell, or a group over its seeds).
struct Stats {
  std::size_t runs = 0, solved = 0;
  std::map<std::string, std::size_t> stopped;  // per time limit: runs it stopped
  std::vector<double> lengths, ratios, turns, expansions, cpu, wall, peak, memory;
};

Stats stats_of(const std::vector<Run>& runs, const std::string* seed = nullptr) {
  Stats s;
  for (const auto& r : runs) {
    if (seed != nullptr && r.seed != *seed) continue;
    ++s.runs;
    if (!r.stopped.empty()) ++s.stopped[r.stopped];
    s.expansions.push_back(r.expansions);
    s.cpu.push_back(r.cpu_us);
    s.wall.push_back(r.wall_us);
    if (r.peak_rss_kib) s.peak.push_back(*r.peak_rss_kib);
    if (r.memory_kib) s.memory.push_back(*r.memory_kib);
    if (!r.success) continue;
    ++s.solved;
    if (r.length) {
      s.lengths.push_back(*r.length);
      s.turns.push_back(r.turns);
    }
    if (r.ratio) s.ratios.push_back(*r.ratio);
  }
  return s;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// A duration in µs as a table shows it: µs below 1 ms, then ms, then s.
std::string duration(double us) {
  if (us < 1000) return fixed(us, us < 10 ? 2 : 1) + " µs";
  if (us < 1e6) return fixed(us / 1000, 2) + " ms";
  return fixed(us / 1e6, 2) + " s";
}

// "–", or the runs each time limit stopped: "2 cpu_budget, 1 wall_backstop".
std::string stopped_text(const Stats& s) {
  std::string out;
  for (const auto& [cause, n] : s.stopped)
    out += (out.empty() ? "" : ", ") + std::to_string(n) + " " + cause;
  return out.empty() ? "–" : out;
}

std::string variant_name(const std::string& world, const std::string& planner,
                         const std::string& seed) {
  return "world=" + world + ",planner=" + planner + (seed.empty() ? "" : ",seed=" + seed);
}

// "70.0 % [39.7, 89.2]": a success rate and its Wilson interval, in percent.
std::string rate_text(std::size_t solved, std::size_t runs) {
  const auto ci = wilson_interval(solved, runs);
  if (!ci) return "–";
  return fixed(100.0 * static_cast<double>(solved) / static_cast<double>(runs), 1) + " % [" +
         fixed(100 * ci->low, 1) + ", " + fixed(100 * ci->high, 1) + "]";
}

// "1.023 [1.000, 1.048]": the mean of per-seed values and its t interval, its low end no
// lower than `floor` (a length / shortest is at least 1, a length at least 0); "[–]" for one
// seed, "–" for none.
std::string mean_text(const std::vector<double>& per_seed, int decimals, double floor) {
  if (per_seed.empty()) return "–";
  const auto ci = t_interval(per_seed);
  return fixed(mean(per_seed), decimals) + (ci ? " [" + fixed(std::max(floor, ci->low), decimals) +
                                                     ", " + fixed(ci->high, decimals) + "]"
                                               : " [–]");
}

// "[1.20 ms, 1.31 ms]": the t interval of the seeds' median CPU times, or "–".
std::string duration_interval(const std::vector<double>& per_seed) {
  const auto ci = t_interval(per_seed);
  if (!ci) return "–";
  return "[" + duration(std::max(0.0, ci->low)) + ", " + duration(ci->high) + "]";
}

}  // namespace

std::string intervals_table(const record::CsvTable& runs) {
  std::string out =
      "| world | planner | seeds | plans | success [95 % Wilson] | length / shortest: mean "
      "over seeds [95 % t] | length: mean over seeds [95 % t] |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const auto& g : groups_of(runs)) {
    const Stats s = stats_of(g.runs);
    std::vector<double> ratios, lengths;  // per seed, over its successful plans
    for (const auto& seed : g.seeds) {
      const Stats one = stats_of(g.runs, &seed);
      if (!one.ratios.empty()) ratios.push_back(mean(one.ratios));
      if (!one.lengths.empty()) lengths.push_back(mean(one.lengths));
    }
    const bool seeded = !(g.seeds.size() == 1 && g.seeds.front().empty());
    out += "| " + g.world + " | " + g.planner + " | " +
           (seeded ? std::to_string(g.seeds.size()) : "–") + " | " + std::to_string(s.runs) +
           " | " + rate_text(s.solved, s.runs) + " | " + mean_text(ratios, 3, 1.0) + " | " +
           mean_text(lengths, 2, 0.0) + " |\n";
  }
  return out;
}

std::string results_table(const record::CsvTable& runs) {
  std::string out =
      "| world | planner | seeds | runs | success | length (mean) | length / shortest (mean) | "
      "(worst) | turns (mean) | expansions (median) | stopped for time |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& g : groups_of(runs)) {
    const Stats s = stats_of(g.runs);
    const double rate =
        s.runs ? 100.0 * static_cast<double>(s.solved) / static_cast<double>(s.runs) : 0.0;
    const bool seeded = !(g.seeds.size() == 1 && g.seeds.front().empty());
    out += "| " + g.world + " | " + g.planner + " | " +
           (seeded ? std::to_string(g.seeds.size()) : "–") + " | " + std::to_string(s.runs) +
           " | " + fixed(rate, 1) + " % (" + std::to_string(s.solved) + ") | " +
           (s.lengths.empty() ? "–" : fixed(mean(s.lengths), 2)) + " | " +
           (s.ratios.empty() ? "–" : fixed(mean(s.ratios), 3)) + " | " +
           (s.ratios.empty() ? "–" : fixed(max_of(s.ratios), 3)) + " | " +
           (s.turns.empty() ? "–" : fixed(mean(s.turns), 2)) + " | " +
           fixed(median(s.expansions), 0) + " | " + stopped_text(s) + " |\n";
  }
  return out;
}

std::string timing_table(const record::CsvTable& runs) {
  std::string out =
      "| world | planner | plan CPU (median) | over seeds: mean ± sd of medians | [95 % t] | "
      "CPU (max) | wall (median) | memory growth (max) | peak RSS (max) |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& g : groups_of(runs)) {
    const Stats s = stats_of(g.runs);
    std::vector<double> medians;
    for (const auto& seed : g.seeds) medians.push_back(median(stats_of(g.runs, &seed).cpu));
    out += "| " + g.world + " | " + g.planner + " | " + duration(median(s.cpu)) + " | " +
           (medians.size() > 1 ? duration(mean(medians)) + " ± " + duration(sd(medians)) : "–") +
           " | " + duration_interval(medians) + " | " + duration(max_of(s.cpu)) + " | " +
           duration(median(s.wall)) + " | " +
           (s.memory.empty() ? "–" : fixed(max_of(s.memory), 0) + " KiB") + " | " +
           (s.peak.empty() ? "–" : fixed(max_of(s.peak) / 1024, 1) + " MiB") + " |\n";
  }
  return out;
}

BenchFigures bench_figures(const record::CsvTable& runs) {
  BenchFigures out;
  for (const auto& g : groups_of(runs))
    for (const auto& seed : g.seeds) {
      const std::string name = variant_name(g.world, g.planner, seed);
      const Stats s = stats_of(g.runs, &seed);
      out.variants.push_back({name,
                              "",
                              variant_name(g.world, g.planner, ""),
                              seed.empty() ? "" : "seed=" + seed,
                              {{"world", g.world}, {"planner", g.planner}, {"seed", seed}}});
      auto add = [&](const std::string& metric, double value, const std::string& unit,
                     bool timing = false) {
        out.figures.push_back({name, "ours", "all", metric, value, unit, timing});
      };
      add("tasks", static_cast<double>(s.runs), "plans");
      add("solved", static_cast<double>(s.solved), "plans");
      add("success",
          s.runs ? 100.0 * static_cast<double>(s.solved) / static_cast<double>(s.runs) : 0.0, "%");
      add("length_mean", mean(s.lengths), "steps");
      add("length_ratio_mean", mean(s.ratios), "");
      add("length_ratio_max", max_of(s.ratios), "");
      add("turns_mean", mean(s.turns), "turns");
      add("expansions_median", median(s.expansions), "");
      add("cpu_us_median", median(s.cpu), "µs", true);
      add("cpu_us_max", max_of(s.cpu), "µs", true);
      add("wall_us_median", median(s.wall), "µs", true);
      if (!s.peak.empty()) add("peak_rss_kib_max", max_of(s.peak), "KiB", true);
      if (!s.memory.empty()) add("memory_kib_max", max_of(s.memory), "KiB", true);
    }
  return out;
}

std::string intervals_csv(const BenchFigures& f) {
  const record::FigureTable table(f.figures);
  std::vector<std::pair<std::string, std::vector<std::string>>> conditions;  // in run order
  for (const auto& v : f.variants) {
    auto c = std::find_if(conditions.begin(), conditions.end(),
                          [&](const auto& x) { return x.first == v.condition; });
    if (c == conditions.end()) c = conditions.insert(conditions.end(), {v.condition, {}});
    c->second.push_back(v.name);
  }
  std::string out = "condition,metric,seeds,mean,low,high,method,timing\n";
  auto line = [&](const std::string& condition, const std::string& metric, std::size_t seeds,
                  double mean_value, const std::optional<Interval>& ci, const char* method,
                  bool timing) {
    out +=
        record::csv_line({condition, metric, std::to_string(seeds),
                          record::exact_number(mean_value), ci ? record::exact_number(ci->low) : "",
                          ci ? record::exact_number(ci->high) : "", method, timing ? "1" : "0"}) +
        "\n";
  };
  for (const auto& [condition, names] : conditions) {
    double solved = 0, tasks = 0;
    for (const auto& n : names) {
      solved += table.get(n, "ours", "all", "solved");
      tasks += table.get(n, "ours", "all", "tasks");
    }
    auto ci = wilson_interval(static_cast<std::size_t>(solved), static_cast<std::size_t>(tasks));
    if (ci) ci = Interval{100 * ci->low, 100 * ci->high};
    line(condition, "success", names.size(), tasks > 0 ? 100 * solved / tasks : 0.0, ci, "wilson",
         false);
    // The low end no lower than the figure can be: a length / shortest 1, turns and time 0.
    for (const auto& [metric, floor] : {std::pair<std::string, double>{"length_ratio_mean", 1.0},
                                        {"turns_mean", 0.0},
                                        {"cpu_us_median", 0.0}}) {
      std::vector<double> values;
      values.reserve(names.size());
      for (const auto& n : names) values.push_back(table.get(n, "ours", "all", metric));
      auto t = t_interval(values);
      if (t) t->low = std::max(floor, t->low);
      line(condition, metric, names.size(), mean(values), t, "t", metric == "cpu_us_median");
    }
  }
  return out;
}

}  // namespace flipper::planbench
