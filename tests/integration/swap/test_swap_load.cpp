// Same config and seed => byte-identical plans under any load (docs/planners.md §2-§4): every
// world x OMPL planner pair plans a fixed set of path requests, a tour and core-language programs
// (through the kernel's executor: the protocol JSON of each trace) on a quiet machine, again on
// the same planner instances while two child processes burn both cores, and once more on fresh
// instances asked in reverse order; all three must give the same bytes.
#include <catch2/catch.hpp>
#include <chrono>
#include <map>
#include <random>
#include <sstream>

#include "cpu_burners.hpp"
#include "flipper/kernel/executor.hpp"
#include "flipper/kernel/protocol.hpp"
#include "flipper/sdk/canonical.hpp"
#include "space_worlds.hpp"

using namespace flipper;
using sdk::Cell;

namespace {

const std::vector<std::string> kOmplPlanners = {"rrtconnect", "rrt", "rrtstar", "prm"};

struct World {
  std::string name;
  sdk::WorldState state;
  std::vector<std::pair<Cell, sdk::Area>> requests;  // start, goals (sorted)
  std::vector<Cell> tour_points;
  std::vector<std::string> programs;  // canonical text
};

World make_world(const std::string& name) {
  World w;
  w.name = name;
  if (name == "grid2d") {
    w.state = testsupport::load_plugin<sdk::World>("grid2d")->load(
        testsupport::read_text(testsupport::worlds_dir() + "/study2018.json"),
        testsupport::worlds_dir());
    w.programs = {"{{visit {world containing item {is red}}};{pick item {is red}}}",
                  "{visit room4 while avoiding room2}",
                  "{foreach point in {world containing item } {{visit point};{pick every item }}}"};
  } else {
    w.state = testsupport::two_floors();
    // The README's 3-D example, and the way up through the shaft.
    w.programs = {"{{visit {world containing item {is yellow}}};{pick item {is yellow}}}",
                  "{visit room4}"};
  }
  // Start/goal pairs of free cells that astar connects (the hard ones cross the map), drawn
  // with a fixed seed.
  const sdk::Geometry& g = *w.state.geometry;
  const sdk::Area& free = g.free_cells();
  const auto astar = testsupport::load_plugin<sdk::Planner>("astar");
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, free.size() - 1);
  while (w.requests.size() < 8) {
    const Cell start = free[pick(rng)];
    sdk::Area goals{free[pick(rng)]};
    if (goals.front() == start) continue;
    if (astar->plan(g, {start, &goals, nullptr}, {}).status != sdk::PlanStatus::found) continue;
    w.requests.push_back({start, std::move(goals)});
  }
  for (int k = 0; k < 10; ++k) w.tour_points.push_back(free[pick(rng)]);
  return w;
}

std::shared_ptr<sdk::Planner> ompl(const std::string& planner) {
  return testsupport::load_plugin<sdk::Planner>(
      "ompl", sdk::Params({{"planner", planner}, {"seed", std::int64_t{1}}}));
}

// Everything a plan can differ in, as text: per request the status, target, cells, work and
// message; the tour order; per program the trace's protocol JSON, the warnings and any error.
// `reverse` asks in the opposite order (the text is still written in the forward order).
std::string plans(const sdk::Planner& planner, const World& w, bool reverse) {
  const sdk::Geometry& g = *w.state.geometry;
  const int dims = g.dims();
  std::vector<std::string> lines(w.requests.size());
  for (std::size_t n = 0; n < w.requests.size(); ++n) {
    const std::size_t k = reverse ? w.requests.size() - 1 - n : n;
    const auto& [start, goals] = w.requests[k];
    const sdk::PathResult r = planner.plan(g, {start, &goals, nullptr}, {});
    std::ostringstream line;
    line << sdk::to_string(start, dims) << " -> " << sdk::to_string(goals.front(), dims) << ": "
         << sdk::to_string(r.status) << " at " << sdk::to_string(r.target, dims) << " after "
         << r.expansions << " checks [" << r.message << "]";
    for (const Cell& c : r.path) line << ' ' << sdk::to_string(c, dims);
    lines[k] = line.str();
  }
  std::ostringstream out;
  for (const auto& l : lines) out << l << '\n';
  const sdk::TourResult t = planner.tour(g, w.state.robot, w.tour_points, {});
  out << "tour " << sdk::to_string(t.status) << ':';
  for (std::size_t i : t.order) out << ' ' << i;
  out << '\n';
  return out.str();
}

std::string programs(const std::shared_ptr<sdk::Planner>& planner, const World& w) {
  // The plans are compared here, not the runaway deadline (tests/language/exec covers it): far
  // away.
  kernel::ExecLimits limits;
  limits.deadline = std::chrono::minutes(30);
  const kernel::Executor exec(planner, limits);
  std::ostringstream out;
  for (const auto& text : w.programs) {
    const sdk::Outcome o = exec.run(sdk::read_canonical(text), w.state);
    std::string trace;
    kernel::protocol::append_trace_text(trace, o.trace, w.state.geometry->dims());
    out << text << " => " << trace;
    for (const auto& warning : o.warnings) out << " | " << warning;
    if (o.error) out << " | error " << *o.error;
    out << '\n';
  }
  return out.str();
}

}  // namespace

TEST_CASE("swap: OMPL plans are byte-identical quiet, under load and in any order",
          "[swap][ompl][load]") {
  std::vector<World> worlds;
  for (const char* name : {"grid2d", "octomap3d"}) worlds.push_back(make_world(name));
  struct Pair {
    const World* world;
    std::string planner;
    std::shared_ptr<sdk::Planner> instance;
    std::string quiet;
  };
  std::vector<Pair> pairs;
  for (const World& w : worlds)
    for (const auto& p : kOmplPlanners) pairs.push_back({&w, p, ompl(p), {}});

  const auto t0 = std::chrono::steady_clock::now();
  for (Pair& p : pairs) {
    p.quiet = plans(*p.instance, *p.world, false) + programs(p.instance, *p.world);
    INFO(p.world->name << " x " << p.planner << ":\n" << p.quiet);
    // Not vacuous: every request and program is planned (the default budget suffices).
    CHECK(p.quiet.find(": found at") != std::string::npos);
    CHECK(p.quiet.find(": no_path") == std::string::npos);
    CHECK(p.quiet.find("error") == std::string::npos);
  }
  const double quiet_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // The same instances again (a repeat in one process), while both cores are busy.
  std::vector<std::string> loaded;
  std::uint64_t burned = 0;
  {
    const testsupport::CpuBurners burners(2);
    const std::uint64_t before = burners.cpu_ticks();
    for (const Pair& p : pairs)
      loaded.push_back(plans(*p.instance, *p.world, false) + programs(p.instance, *p.world));
    burned = burners.cpu_ticks() - before;
  }
  // Fresh instances, requests in reverse order: nothing depends on what was asked before.
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Pair& p = pairs[i];
    INFO(p.world->name << " x " << p.planner);
    CHECK(loaded[i] == p.quiet);
    const auto fresh = ompl(p.planner);
    CHECK(plans(*fresh, *p.world, true) + programs(fresh, *p.world) == p.quiet);
  }
  WARN("quiet pass " << quiet_s << " s; the burners used " << burned
                     << " clock ticks of CPU during the loaded pass");
  CHECK(burned > 0);  // the loaded pass really ran beside them
}
