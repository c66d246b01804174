// The planner benchmark's parts (docs/planners.md §5): the breadth-first oracle, turns, path
// checks, random tasks, task files, experiment files and one cell's rows with stub planners.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include "flipper/planbench/experiment.hpp"
#include "flipper/planbench/measure.hpp"
#include "flipper/planbench/summary.hpp"
#include "flipper/planbench/tasks.hpp"
#include "flipper/sdk/errors.hpp"

using namespace flipper;
using namespace flipper::planbench;
using sdk::Cell;
namespace fs = std::filesystem;

namespace {

// A 2-D grid from rows of text, top row first ('#' a wall), y up, 4-neighbourhood in the
// grid's tie order (right, left, up, down).
std::shared_ptr<const sdk::Geometry> grid(const std::vector<std::string>& rows) {
  const int h = static_cast<int>(rows.size()), w = static_cast<int>(rows[0].size());
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      mask[static_cast<std::size_t>(y * w + x)] =
          rows[static_cast<std::size_t>(h - 1 - y)][static_cast<std::size_t>(x)] == '#' ? 0 : 1;
  return std::make_shared<const sdk::Geometry>(
      2, Cell{0, 0, 0}, Cell{w - 1, h - 1, 0}, std::move(mask),
      std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
      std::vector<std::pair<std::string, Cell>>{});
}

// y=2  . . .
// y=1  . # .
// y=0  . # .   and a pocket: none here (see `walled`)
const auto kRing = grid({"...", ".#.", ".#."});

// The test's files, in a folder of this process removed at exit.
struct TempDir {
  fs::path path =
      fs::temp_directory_path() / ("flipper-test-planbench-" + std::to_string(::getpid()));
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string write_temp(const std::string& name, const std::string& text) {
  static const TempDir temp;
  const fs::path& dir = temp.path;
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return (dir / name).string();
}

// A planner stub answering what the test gives it.
class StubPlanner : public sdk::Planner {
 public:
  std::vector<sdk::PathResult> answers;  ///< one per call, the last repeated
  mutable std::size_t calls = 0;
  bool throws = false;  ///< plan throws std::runtime_error
  /// plan runs until its stop condition fires (burning CPU, or waiting: no CPU), then `stopped`
  enum class Until { answer, cpu_spent, waited } until = Until::answer;

 protected:
  sdk::PathResult do_plan(const sdk::Geometry&, const sdk::PathRequest&,
                          const sdk::StopCondition& stop) const override {
    if (throws) throw std::runtime_error("out of luck");
    if (until != Until::answer) {
      // Bounded by the cell's limits, which the test sets to a few ms.
      while (!stop.expired())
        if (until == Until::waited) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      sdk::PathResult r;
      r.status = sdk::PlanStatus::stopped;
      return r;
    }
    const auto& a = answers[std::min(calls, answers.size() - 1)];
    ++calls;
    return a;
  }
  sdk::TourResult do_tour(const sdk::Geometry&, Cell, const std::vector<Cell>&,
                          const sdk::StopCondition&) const override {
    return {};
  }
  sdk::PlannerTraits do_traits() const override { return {}; }
};

sdk::PathResult found(std::vector<Cell> path) {
  sdk::PathResult r;
  r.status = sdk::PlanStatus::found;
  r.target = path.empty() ? Cell{} : path.back();
  r.path = std::move(path);
  r.expansions = 7;
  return r;
}

}  // namespace

TEST_CASE("the oracle's shortest steps, unreachable goals and walls") {
  CHECK(shortest_steps(*kRing, {0, 0, 0}, {2, 0, 0}) == 6u);  // up, over the top, down
  CHECK(shortest_steps(*kRing, {0, 0, 0}, {0, 0, 0}) == 0u);
  CHECK(shortest_steps(*kRing, {0, 0, 0}, {0, 1, 0}) == 1u);
  CHECK_FALSE(shortest_steps(*kRing, {0, 0, 0}, {1, 0, 0}));  // a wall
  CHECK_FALSE(shortest_steps(*kRing, {0, 0, 0}, {3, 0, 0}));  // outside
  const auto walled = grid({".#.", ".#."});
  CHECK_FALSE(shortest_steps(*walled, {0, 0, 0}, {2, 1, 0}));
}

// Which paths are valid is the kernel's check (tests/kernel/plugin/test_plugin_checks.cpp).
TEST_CASE("turns count changes of direction") {
  CHECK(count_turns({0, 0, 0}, {}) == 0u);
  CHECK(count_turns({0, 0, 0}, {{0, 1, 0}, {0, 2, 0}}) == 0u);
  CHECK(count_turns({0, 0, 0}, {{0, 1, 0}, {0, 2, 0}, {1, 2, 0}}) == 1u);
  CHECK(count_turns({0, 0, 0}, {{0, 1, 0}, {1, 1, 0}, {1, 2, 0}, {2, 2, 0}}) == 3u);
}

TEST_CASE("random tasks: SplitMix64, connected pairs, the same for the same seed") {
  std::uint64_t state = 0;  // the published first output of SplitMix64 from seed 0
  CHECK(splitmix64(state) == 0xe220a8397b1dcdafULL);
  const auto a = random_tasks(*kRing, 12, 1), b = random_tasks(*kRing, 12, 1),
             c = random_tasks(*kRing, 12, 2);
  REQUIRE(a.size() == 12);
  auto key = [](const std::vector<Task>& ts) {
    std::vector<std::tuple<Cell, Cell>> k;
    for (const auto& t : ts) k.emplace_back(t.start, t.goal);
    return k;
  };
  CHECK(key(a) == key(b));
  CHECK(key(a) != key(c));
  // The first task is the first two draws that differ, as cells of the free list.
  std::uint64_t s = 1;
  const auto& free = kRing->free_cells();
  Cell s0, g0;
  do {
    s0 = free[splitmix64(s) % free.size()];
    g0 = free[splitmix64(s) % free.size()];
  } while (s0 == g0);
  CHECK(a[0].start == s0);
  CHECK(a[0].goal == g0);
  CHECK(a[0].name == "t1");
  for (const auto& t : a) {
    CHECK(t.start != t.goal);
    CHECK(t.shortest == shortest_steps(*kRing, t.start, t.goal));
  }
  // Two free cells that are not connected: no task, after a bounded number of draws.
  CHECK(random_tasks(*grid({".#."}), 5, 1).empty());
}

TEST_CASE("task files: cells of the world's dimension, free, named once") {
  const auto ok = write_temp("ok.yaml",
                             "tasks:\n  - {name: a, start: [0, 0], goal: [2, 0]}\n"
                             "  - {start: [0, 2], goal: [0, 2]}\n");
  const auto tasks = read_task_file(ok, *kRing);
  REQUIRE(tasks.size() == 2);
  CHECK(tasks[0].name == "a");
  CHECK(tasks[0].shortest == 6u);
  CHECK(tasks[1].name == "t2");
  CHECK(tasks[1].shortest == 0u);
  auto refused = [](const std::string& text, const std::string& what) {
    const auto path = write_temp("bad.yaml", text);
    try {
      read_task_file(path, *kRing);
      FAIL("accepted: " << text);
    } catch (const sdk::Error& e) {
      CHECK(std::string(e.code()) == "bad_config");
      CHECK_THAT(e.what(), Catch::Contains(what));
    }
  };
  refused("tasks:\n  - {start: [1, 0], goal: [0, 0]}\n", "[1,0] is not a free cell");
  refused("tasks:\n  - {start: [0, 0, 0], goal: [0, 1]}\n", "must be a cell of 2 integers");
  refused("tasks:\n  - {start: [0, 0], goal: [0, 1], via: [1, 1]}\n", "unknown key 'via'");
  refused(
      "tasks:\n  - {name: x, start: [0, 0], goal: [0, 1]}\n  - {name: x, start: [0, 0], "
      "goal: [0, 2]}\n",
      "two tasks are named 'x'");
  refused("tasks: []\n", "needs 'tasks:");
}

TEST_CASE("experiment files: keys, names and ranges are checked at the boundaries") {
  const std::string head =
      "worlds: [{name: w, plugin: grid2d, file: w.json}]\nplanners: [{plugin: astar}]\n";
  auto load = [&](const std::string& extra) {
    return load_bench_experiment(write_temp("e.yaml", head + extra));
  };
  const auto e = load("repetitions: 1000\ntasks: {random: 100000, seed: 3}\n");
  CHECK(e.repetitions == 1000);
  CHECK(e.tasks.random == 100000);
  CHECK(e.planners[0].name == "astar");
  CHECK(fs::path(e.worlds[0].file).is_absolute());
  auto refused = [&](const std::string& extra, const std::string& what) {
    try {
      load(extra);
      FAIL("accepted: " << extra);
    } catch (const sdk::Error& ex) {
      CHECK(std::string(ex.code()) == "bad_config");
      CHECK_THAT(ex.what(), Catch::Contains(what));
    }
  };
  refused("repetitions: 1001\n", "'repetitions' must be in [1, 1000]");
  refused("repetitions: 0\n", "'repetitions' must be in [1, 1000]");
  refused("tasks: {random: 100001}\n", "'random' must be in [1, 100000]");
  refused("tasks: {random: 0}\n", "'random' must be in [1, 100000]");
  refused("tasks: {random: 3, file: t.yaml}\n", "either 'random' or 'file'");
  refused("seeds: [1, 1]\n", "lists 1 twice");
  refused("seed: [1]\n", "unknown key 'seed'");
  refused("deadline_ms: 0\n", "'deadline_ms' must be at least 1");
  try {
    load_bench_experiment(
        write_temp("d.yaml",
                   "worlds: [{name: w, plugin: grid2d, file: w.json}]\n"
                   "planners: [{plugin: ompl}, {plugin: ompl, params: {planner: rrt}}]\n"));
    FAIL("two planners of one name accepted");
  } catch (const sdk::Error& ex) {
    CHECK_THAT(ex.what(), Catch::Contains("two planners are named 'ompl'"));
  }
}

TEST_CASE("a cell's rows: success against the oracle, invalid paths, varying answers") {
  auto stub = std::make_shared<StubPlanner>();
  const kernel::PluginRef<sdk::Planner> ref(std::static_pointer_cast<sdk::Planner>(stub));
  const std::vector<Task> tasks{{"up", {0, 0, 0}, {0, 2, 0}, 2u}};
  CellSpec cell{"w", "p", "stub", "", 1, 10000};

  stub->answers = {found({{0, 1, 0}, {0, 2, 0}})};
  auto rows = measure_cell(cell, *kRing, ref, tasks);
  REQUIRE(rows.size() == 1);
  CHECK(rows[0].status == "found");
  CHECK(rows[0].success);
  CHECK(rows[0].length == 2u);
  CHECK(rows[0].turns == 0u);
  CHECK(rows[0].expansions == 7u);
  CHECK(row_fields(rows[0])[11] == "1");  // length_ratio
  CHECK(row_fields(rows[0]).size() == run_columns().size());

  stub->answers = {found({{0, 2, 0}})};  // a jump: not a path, refused by the kernel's check
  stub->calls = 0;
  rows = measure_cell(cell, *kRing, ref, tasks);
  CHECK(rows[0].status == "invalid_plan");
  CHECK_FALSE(rows[0].length);
  CHECK_FALSE(rows[0].success);
  CHECK(row_fields(rows[0])[11].empty());

  // Three repetitions, the third different: `varies`, not a success.
  cell.repetitions = 3;
  sdk::PathResult gave_up;
  gave_up.status = sdk::PlanStatus::no_path;
  stub->answers = {found({{0, 1, 0}, {0, 2, 0}}), found({{0, 1, 0}, {0, 2, 0}}), gave_up};
  stub->calls = 0;
  rows = measure_cell(cell, *kRing, ref, tasks);
  CHECK(stub->calls == 3u);
  CHECK(rows[0].status == "varies");
  CHECK_FALSE(rows[0].success);

  // An unreachable goal: no_path is the right answer; a path there is not.
  const std::vector<Task> cut{{"cut", {0, 0, 0}, {0, 2, 0}, std::nullopt}};
  cell.repetitions = 1;
  sdk::PathResult none;
  none.status = sdk::PlanStatus::no_path;
  stub->answers = {none};
  stub->calls = 0;
  rows = measure_cell(cell, *kRing, ref, cut);
  CHECK(rows[0].status == "no_path");
  CHECK(rows[0].success);
  CHECK(row_fields(rows[0])[10].empty());  // shortest

  // A plan that throws is a row with the error's code, and the next task still runs.
  stub->throws = true;
  cell.repetitions = 3;
  rows = measure_cell(cell, *kRing, ref, {tasks[0], cut[0]});
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].status == "plugin_error");
  CHECK(rows[1].status == "plugin_error");
  CHECK_FALSE(rows[0].success);
  CHECK_FALSE(rows[1].success);
  CHECK_FALSE(rows[0].length);
}

TEST_CASE("a plan a time limit stopped says which, in its row and the results table") {
  // docs/planners.md §2 and §5: `stopped` is cpu_budget (the planning thread's CPU time) or
  // wall_backstop (wall time, a runaway guard), apart from planning failures.
  auto stub = std::make_shared<StubPlanner>();
  const kernel::PluginRef<sdk::Planner> ref(std::static_pointer_cast<sdk::Planner>(stub));
  const std::vector<Task> tasks{{"up", {0, 0, 0}, {0, 2, 0}, 2u}};
  CellSpec cell{"w", "p", "stub", "", 1, 600000, 20};
  stub->until = StubPlanner::Until::cpu_spent;
  auto rows = measure_cell(cell, *kRing, ref, tasks);
  REQUIRE(rows.size() == 1);
  CHECK(rows[0].status == "stopped");
  CHECK(rows[0].stopped == "cpu_budget");
  CHECK_FALSE(rows[0].success);
  CHECK(rows[0].cpu_us >= 19000);  // the budget, less the µs between making the stop and the plan
  // The row's `stopped` column (the `cause` column, for processes that died, follows it).
  const auto& columns = run_columns();
  const auto stopped_column = std::find(columns.begin(), columns.end(), "stopped");
  REQUIRE(stopped_column != columns.end());
  CHECK(row_fields(rows[0]).at(static_cast<std::size_t>(stopped_column - columns.begin())) ==
        "cpu_budget");
  // Waiting uses no CPU: only the wall-clock backstop ends it.
  cell.deadline_ms = 20;
  cell.cpu_budget_ms = 600000;
  stub->until = StubPlanner::Until::waited;
  auto waited = measure_cell(cell, *kRing, ref, tasks);
  CHECK(waited[0].status == "stopped");
  CHECK(waited[0].stopped == "wall_backstop");
  // An answer within the limits has no cause.
  stub->until = StubPlanner::Until::answer;
  stub->answers = {found({{0, 1, 0}, {0, 2, 0}})};
  auto ok = measure_cell(cell, *kRing, ref, tasks);
  CHECK(ok[0].stopped.empty());

  record::CsvTable table;
  table.header = run_columns();
  for (const auto& r : {rows[0], waited[0], ok[0]}) table.rows.push_back(row_fields(r));
  const std::string results = results_table(table);
  CHECK_THAT(results, Catch::Contains("| stopped for time |"));
  CHECK_THAT(results,
             Catch::EndsWith("| 3 | 33.3 % (1) | 2.00 | 1.000 | 1.000 | 0.00 | 0 | 1 cpu_budget, "
                             "1 wall_backstop |\n"));
  table.rows.pop_back();
  table.rows.erase(table.rows.begin(), table.rows.begin() + 1);  // the wall-stopped one alone
  CHECK_THAT(results_table(table), Catch::EndsWith("| 1 wall_backstop |\n"));
}
