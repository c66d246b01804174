// Constructs of core-language §4, the paper's programs, bad and runaway programs.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <thread>

#include "flipper/repl/outcome_json.hpp"
#include "study_fixture.hpp"

using namespace flipper;
using flipper::testsupport::items_at;
using flipper::testsupport::Study;
using flipper::testsupport::trace_text;
using S = std::vector<std::string>;

TEST_CASE("pick and drop follow the item order rules", "[exec]") {
  Study st;
  auto o = st.run("{{pick every item {is green}};{pick item }}", st.state(7, 4));
  CHECK(trace_text(o.trace) == "p(7,4)green square p(7,4)green circle p(7,4)red circle");
  CHECK(items_at(o.world, 7, 4) == S{"blue circle"});
  // Dropped items go to the end of the lying items; drop takes held items in pick order.
  auto d = st.run("{{pick item {is red}};{drop item };{drop item }}", st.state(7, 4));
  CHECK(items_at(d.world, 7, 4) == S{"blue circle", "green square", "green circle", "red circle"});
  CHECK(d.warnings == S{"Could not complete the action: {drop item } (no item held)"});
  auto h = st.run("{drop every item {not {is red}}}",
                  st.state(2, 4, {{"red", "square"}, {"blue", "circle"}, {"gray", "circle"}}));
  CHECK(trace_text(h.trace) == "d(2,4)blue circle d(2,4)gray circle");
  CHECK(h.world.held.size() == 1);
  auto f = st.run("{pick item {{not {is red}} and {is circle}}}", st.state(7, 4));
  CHECK(trace_text(f.trace) == "p(7,4)blue circle");
  auto none = st.run("{pick item {not {is pink}}}", st.state());  // [decision]: no error
  CHECK_FALSE(none.error);
  CHECK(none.warnings == S{"Could not complete the action: {pick item {not {is pink}}} (no item "
                           "{not {is pink}} here)"});
}

TEST_CASE("visit of areas, collections and ties", "[exec]") {
  Study st;
  // Nearest cell of room1 from (10,8): through (9,6) down to ... room1 lies behind walls; via
  // (8,0).
  auto a = st.run("{visit {area with corners [0,0] and [2,2]}}", st.state());
  CHECK(a.world.robot ==
        sdk::Cell{1, 2, 0});  // 3 steps; (0,2) and (1,2) tie? (1,2) is 3, (0,2) is 4
  auto cur = st.run("{visit current}", st.state());
  CHECK(cur.trace.empty());
  CHECK(cur.realizable);
  auto wall = st.run("{visit [2,6]}", st.state());
  CHECK(wall.warnings == S{"Could not complete the action: {visit [2,6]} ([2,6] is a wall)"});
  auto out = st.run("{visit [20,20]}", st.state());
  CHECK(out.warnings ==
        S{"Could not complete the action: {visit [20,20]} ([20,20] is outside the world)"});
  auto edge = st.run("{visit [13,4]}", st.state());  // [decision] §9: not an error
  CHECK_FALSE(edge.error);
  CHECK_FALSE(edge.realizable);
  auto empty = st.run("{visit {world minus world}}", st.state());
  CHECK(empty.warnings == S{"Could not complete the action: {visit {world minus world}} (no free "
                            "cell in {world minus world})"});
  // A collection: the nearest room wins ([decision] §4.4): room3 contains the robot.
  auto rooms = st.run("{visit rooms}", st.state());
  CHECK(rooms.trace.empty());
  auto r5 = st.run("{visit {[room1, room5]}}", st.state());
  CHECK(r5.world.robot == sdk::Cell{9, 7, 0});  // room5 through (9,6): 10 steps; room1: 13
  // Avoid set for an area target is B minus A: room3 may be crossed when visiting room3 itself.
  auto self = st.run("{visit room3 while avoiding room3}", st.state(1, 1));
  CHECK(self.realizable);
  auto in_avoid = st.run("{visit [3,4] while avoiding room3}", st.state());
  CHECK(in_avoid.warnings == S{"Could not complete the action: {visit [3,4] while avoiding room3} "
                               "([3,4] lies in the avoided area)"});
  auto own = st.run("{visit [2,4] while avoiding room3}", st.state());
  CHECK(own.realizable);
  CHECK(own.warnings.empty());
}

TEST_CASE("loops, conditions and loop variables", "[exec]") {
  Study st;
  auto r = st.run("{repeat 3 times {move right}}", st.state());
  CHECK(trace_text(r.trace) == "m(3,4) m(4,4) m(5,4)");
  auto zero = st.run("{repeat -1 times {move left}}", st.state());
  CHECK(zero.trace.empty());
  CHECK(zero.realizable);
  auto arith = st.run("{visit [{2 + 1},{5 - 1}]}", st.state());
  CHECK(arith.world.robot == sdk::Cell{3, 4, 0});
  auto w = st.run("{while {robot at [2,4]} {{move left};{move right}}}", st.state());
  CHECK(w.trace.size() == 40);  // the while limit: 20 iterations, not a failure
  CHECK(w.realizable);
  auto p = st.run("{if {possible {move left}} {move right}}", st.state());
  CHECK(trace_text(p.trace) == "m(3,4)");
  auto np = st.run("{if {possible {{move up};{move up}}} {move right}}", st.state());
  CHECK(np.trace.empty());
  CHECK(np.warnings.empty());  // trials add nothing
  // Loop variables: the inner loop shadows, and the outer binding is restored afterwards (§4.7).
  auto v = st.run(
      "{foreach point in {[[1,4], [3,4]]} {{foreach point in {[[5,4]]} {visit point}};{visit "
      "point}}}",
      st.state());
  CHECK(v.warnings.empty());
  // Tour from (2,4): (1,4) and (3,4) tie, (1,4) comes first in (x, y) order.
  CHECK(
      trace_text(v.trace) ==
      "m(3,4) m(4,4) m(5,4) m(4,4) m(3,4) m(2,4) m(1,4) m(2,4) m(3,4) m(4,4) m(5,4) m(4,4) m(3,4)");
  auto fa = st.run("{foreach area in rooms {visit area}}", st.state());
  CHECK(fa.warnings.empty());
  auto cond = st.run("{if {item {is red} at room3} {move left}}", st.state());
  CHECK(trace_text(cond.trace) == "m(1,4)");
  auto cond2 = st.run("{if {item {is red} at current} {move left}}", st.state());
  CHECK(cond2.trace.empty());
}

TEST_CASE("paper programs", "[exec][paper]") {
  Study st;
  SECTION("sorting items by colour into rooms") {
    auto o = st.run(
        "{{foreach point in {world containing item } {{visit point};{pick every item }}};"
        "{visit room1};{drop every item {is red}};{visit room4};{drop every item {is blue}}}",
        st.state());
    CHECK(o.warnings.empty());
    CHECK(o.world.held.size() == 5);  // the green and yellow items stay held
    int red_in_room1 = 0, blue_in_room4 = 0;
    for (const auto& li : o.world.items) {
      if (li.item.color == "red" && li.at.x >= 9 && li.at.y <= 2) ++red_in_room1;
      if (li.item.color == "blue" && li.at.x <= 5 && li.at.y >= 7) ++blue_in_room4;
    }
    CHECK(red_in_room1 == 3);
    CHECK(blue_in_room4 == 3);
  }
  SECTION("sorting with foreach area") {
    auto o =
        st.run("{foreach area in {rooms containing item {is red}} {{visit area};{drop item }}}",
               st.state(2, 4, {{"pink", "square"}, {"pink", "circle"}, {"pink", "triangle"}}));
    CHECK(o.warnings.empty());
    CHECK(o.world.held.empty());  // rooms 2, 3 and 5 hold red items: one drop in each
  }
  SECTION("a line of items with while possible") {
    auto o = st.run("{while {possible {{move right};{drop item }}} {{move right};{drop item }}}",
                    st.state(2, 4, {{"red", "square"}, {"blue", "circle"}, {"gray", "circle"}}));
    CHECK(trace_text(o.trace) ==
          "m(3,4) d(3,4)red square m(4,4) d(4,4)blue circle m(5,4) d(5,4)gray circle");
    CHECK(o.warnings.empty());
  }
  SECTION("strict pick-and-move") {
    auto ok = st.run("{strict {{pick item {is red}};{move left}}}", st.state(7, 4));
    CHECK(trace_text(ok.trace) == "p(7,4)red circle m(6,4)");
    auto back = st.run("{strict {{pick item {is red}};{move left}}}", st.state(0, 4));
    CHECK(back.trace.empty());
    CHECK(back.warnings ==
          S{"Could not complete the action: {pick item {is red}} (no red item here)",
            "Could not complete the action: {move left} ([-1,4] is a wall)",
            "Could not complete the action: {strict {{pick item {is red}};{move left}}}"});
  }
}

TEST_CASE("bad programs are execution errors and change nothing", "[exec][errors]") {
  Study st;
  auto room = st.run("{{move right};{visit room9}}", st.state());
  CHECK(room.error_code == "execution_error");
  CHECK_THAT(*room.error, Catch::Contains("room9"));
  CHECK(room.trace.empty());
  CHECK(room.world.robot == sdk::Cell{2, 4, 0});
  auto frac = st.run("{repeat 2.5 times {move left}}", st.state());
  CHECK(frac.error_code == "execution_error");
  CHECK_THAT(*frac.error, Catch::Contains("2.5"));
  auto coord = st.run("{visit [2.5,4]}", st.state());
  CHECK(coord.error_code == "execution_error");
  auto loopvar = st.run("{visit point}", st.state());
  CHECK(loopvar.error_code == "execution_error");
  auto j = repl::outcome_json(room, 2);
  CHECK(j["error"]["code"] == "execution_error");
  CHECK(j["realizable"] == false);
}

TEST_CASE("runaway programs hit a work budget, whatever the machine", "[exec][budget]") {
  Study st;
  // The budgets count work (docs/core-language.md §9): the deadline is far away, so a slow
  // (sanitizer, loaded) build hits the same budget at the same statement.
  kernel::ExecLimits actions;
  actions.deadline = std::chrono::minutes(10);
  auto o = st.run("{repeat 99 times {repeat 99 times {repeat 99 times {move left}}}}", st.state(),
                  actions);
  CHECK(o.error_code == "budget_exceeded");
  CHECK(*o.error ==
        "action budget exceeded: more than 100000 primitive actions (execution.action_budget)");
  CHECK(o.trace.empty());
  CHECK(o.world.robot == sdk::Cell{2, 4, 0});
  // Statements, exactly: `repeat` is one, each of its 3 `if`s one more; the condition is false,
  // so no move runs. 4 fit in a budget of 4, not in one of 3.
  const char* idle = "{repeat 3 times {if {robot at [0,0]} {move left}}}";
  kernel::ExecLimits steps = actions;
  steps.step_budget = 4;
  CHECK_FALSE(st.run(idle, st.state(), steps).error);
  steps.step_budget = 3;
  auto over = st.run(idle, st.state(), steps);
  CHECK(over.error_code == "budget_exceeded");
  CHECK(*over.error == "step budget exceeded: more than 3 statements (execution.step_budget)");
  // Moves count as statements too (failed ones included): 1 + 10.
  steps.step_budget = 11;
  CHECK_FALSE(st.run("{repeat 10 times {move right}}", st.state(), steps).error);
  steps.step_budget = 10;
  CHECK(st.run("{repeat 10 times {move right}}", st.state(), steps).error_code ==
        "budget_exceeded");
  // The default step budget stops a loop of idle statements (no action at all): 1 + 99 + 9801
  // repeats and 970299 x (a sequence and two `if`s) is over a million.
  auto idle_loop = st.run(
      "{repeat 99 times {repeat 99 times {repeat 99 times {{if {robot at [0,0]} {move left}};"
      "{if {robot at [0,0]} {move left}}}}}}",
      st.state(), actions);
  CHECK(idle_loop.error_code == "budget_exceeded");
  CHECK_THAT(*idle_loop.error, Catch::Contains("more than 1000000 statements"));
}

TEST_CASE("the CPU budget stops runaways and the wall backstop hangs, each says which",
          "[exec][budget]") {
  Study st;
  const char* runaway =
      "{repeat 99 times {repeat 99 times {repeat 99 times {{visit [9,8]};{visit [2,4]}}}}}";
  kernel::ExecLimits tight;
  tight.action_budget = 1u << 30;
  tight.step_budget = 1ull << 40;
  tight.cpu_budget = std::chrono::milliseconds(30);
  const auto cpu0 = sdk::cpu_time();
  auto t = st.run(runaway, st.state(), tight);
  // Polled every 1024 statements and planner calls: far less than a second past the budget.
  CHECK(sdk::cpu_time() - cpu0 < std::chrono::seconds(3));
  CHECK(t.error_code == "deadline_exceeded");
  CHECK(t.stopped == sdk::StopCause::cpu_budget);
  CHECK(*t.error ==
        "deadline exceeded: the execution used more CPU time than execution.cpu_budget_ms = 30 "
        "ms (stopped: cpu_budget)");
  CHECK(t.trace.empty());
  CHECK(t.world.robot == sdk::Cell{2, 4, 0});
  // Loops without primitive actions see the clock too.
  auto idle = st.run(
      "{repeat 99 times {repeat 99 times {repeat 99 times {if {robot at {world containing item }} "
      "{move left}}}}}",
      st.state(), tight);
  CHECK(idle.error_code == "deadline_exceeded");
  CHECK(idle.stopped == sdk::StopCause::cpu_budget);
  // The wall-clock backstop, when it comes first, says it is the backstop.
  kernel::ExecLimits wall = tight;
  wall.cpu_budget = std::chrono::minutes(10);
  wall.deadline = std::chrono::milliseconds(30);
  auto w = st.run(runaway, st.state(), wall);
  CHECK(w.error_code == "deadline_exceeded");
  CHECK(w.stopped == sdk::StopCause::wall_backstop);
  CHECK(*w.error ==
        "deadline exceeded: the execution took longer than execution.deadline_ms = 30 ms, the "
        "wall-clock backstop (stopped: wall_backstop)");
  // A request's limit that fires first is named as the request's: its CPU budget (spent
  // already: the deadline is the CPU time now) ...
  const kernel::Executor exec(st.planner, wall);
  const auto program = sdk::read_canonical(runaway);
  sdk::StopCondition spent;
  spent.cpu_clock = sdk::this_thread_cpu_clock();
  spent.cpu_deadline = sdk::cpu_time(spent.cpu_clock);
  auto request = exec.run(program, st.state(), spent);
  CHECK(request.stopped == sdk::StopCause::cpu_budget);
  CHECK(*request.error ==
        "deadline exceeded: the request used more CPU time than session.cpu_budget_ms (stopped: "
        "cpu_budget)");
  // ... or its wall-clock backstop.
  sdk::StopCondition passed;
  passed.deadline = std::chrono::steady_clock::now();
  auto late = exec.run(program, st.state(), passed);
  CHECK(late.stopped == sdk::StopCause::wall_backstop);
  CHECK(*late.error ==
        "deadline exceeded: the request took longer than session.deadline_ms, the wall-clock "
        "backstop (stopped: wall_backstop)");
}

TEST_CASE("the CPU budget counts the thread's CPU time, not the time it waited", "[exec][budget]") {
  Study st;
  kernel::ExecLimits limits;
  limits.cpu_budget = std::chrono::milliseconds(200);
  const kernel::Executor exec(st.planner, limits);
  // A request whose thread has waited (not run) for longer than its CPU budget: the budget is
  // almost whole, so a short program runs. A wall-clock budget would have fired.
  const auto request =
      sdk::StopCondition::within_cpu(std::chrono::milliseconds(100), std::chrono::milliseconds(0));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));  // time passing without CPU
  CHECK(request.cause() == sdk::StopCause::none);
  auto o = exec.run(sdk::read_canonical("{visit [9,8]}"), st.state(), request);
  CHECK_FALSE(o.error);
  CHECK(o.world.robot == sdk::Cell{9, 8, 0});
}

TEST_CASE("protocol JSON of trace steps", "[protocol]") {
  Study st;
  auto o = st.run("{{visit [7,4]};{pick item }}", st.state(6, 4));
  auto j = repl::trace_json(o.trace, 2);
  CHECK(
      j.dump() ==
      R"([{"act":"move","to":[7,4]},{"act":"pick","at":[7,4],"item":{"color":"red","id":4,"shape":"circle"}}])");
  CHECK(repl::cell_json({1, 2, 3}, 3).dump() == "[1,2,3]");
  CHECK(repl::error_json("bad_world", "x").dump() == R"({"code":"bad_world","message":"x"})");
}

TEST_CASE("A containing item keeps the cells of A holding a matching item", "[exec]") {
  // Study map items (configs/worlds/study2018.json): green at (7,4) and (10,8); red at (4,0),
  // (7,4), (10,8); yellow at (3,8) and (4,0); nothing pink.
  Study st;
  auto moves_at = [&](const char* where, int x, int y) {
    // Every cell asked about holds items except (2,4), where the answer is false anyway.
    auto o = st.run(std::string("{if {robot at ") + where + "} {pick item }}", st.state(x, y));
    REQUIRE_FALSE(o.error);
    return !o.trace.empty();
  };
  const char* green_in_world = "{world containing item {is green}}";
  CHECK(moves_at(green_in_world, 7, 4));
  CHECK(moves_at(green_in_world, 10, 8));
  CHECK_FALSE(moves_at(green_in_world, 4, 0));  // red and yellow only
  CHECK_FALSE(moves_at(green_in_world, 3, 8));
  CHECK_FALSE(moves_at(green_in_world, 2, 4));  // no item
  const char* green_in_list = "{[[4,0], [7,4]] containing item {is green}}";
  CHECK(moves_at(green_in_list, 7, 4));
  CHECK_FALSE(moves_at(green_in_list, 4, 0));
  CHECK_FALSE(moves_at("{[[4,0], [3,8]] containing item {is green}}", 7, 4));  // not in the list
  auto item_at_world = [&](const char* color) {
    auto o =
        st.run(std::string("{if {item {is ") + color + "} at world} {move right}}", st.state(2, 4));
    REQUIRE_FALSE(o.error);
    return !o.trace.empty();
  };
  CHECK(item_at_world("yellow"));
  CHECK_FALSE(item_at_world("pink"));
}

TEST_CASE("possible of a lone action answers as the action would, and counts it",
          "[exec][possible]") {
  Study st;
  auto moved = [&](const std::string& prog, const sdk::WorldState& s) {
    auto o = st.run(prog, s);
    REQUIRE_FALSE(o.error);
    return !o.trace.empty();
  };
  // (7,4) holds a red circle and no pink item; (7,5) above it is free.
  CHECK(moved("{if {possible {pick item {is red}}} {move up}}", st.state(7, 4)));
  CHECK_FALSE(moved("{if {possible {pick item {is pink}}} {move up}}", st.state(7, 4)));
  const auto holding = st.state(2, 4, {{"red", "square"}});
  CHECK(moved("{if {possible {drop item {is red}}} {move right}}", holding));
  CHECK_FALSE(moved("{if {possible {drop item {is blue}}} {move right}}", holding));
  CHECK(moved("{if {possible {move right}} {move right}}", st.state(2, 4)));
  CHECK_FALSE(moved("{if {possible {move up}} {move right}}", st.state(2, 5)));  // (2,6): wall
  // The trial counts as one action, as a run of the action on a copy would: with a budget of 4,
  // two rounds of (trial, move) fit and a third does not.
  kernel::ExecLimits four;
  four.action_budget = 4;
  auto two =
      st.run("{repeat 2 times {if {possible {move right}} {move right}}}", st.state(2, 4), four);
  CHECK_FALSE(two.error);
  CHECK(two.world.robot == sdk::Cell{4, 4, 0});
  auto three =
      st.run("{repeat 3 times {if {possible {move right}} {move right}}}", st.state(2, 4), four);
  CHECK(three.error_code == "budget_exceeded");
}

namespace {
// The astar planner, counting its tours and declaring itself deterministic or not.
class CountingPlanner final : public sdk::Planner {
 public:
  CountingPlanner(std::shared_ptr<sdk::Planner> inner, bool deterministic)
      : inner_(std::move(inner)), deterministic_(deterministic) {}
  mutable int tours = 0;

 protected:
  sdk::PathResult do_plan(const sdk::Geometry& g, const sdk::PathRequest& r,
                          const sdk::StopCondition& s) const override {
    return inner_->plan(g, r, s);
  }
  sdk::TourResult do_tour(const sdk::Geometry& g, sdk::Cell start,
                          const std::vector<sdk::Cell>& points,
                          const sdk::StopCondition& s) const override {
    ++tours;
    return inner_->tour(g, start, points, s);
  }
  sdk::PlannerTraits do_traits() const override {
    sdk::PlannerTraits t = inner_->traits();
    t.deterministic = deterministic_;
    return t;
  }

 private:
  std::shared_ptr<sdk::Planner> inner_;
  bool deterministic_;
};
}  // namespace

TEST_CASE("a deterministic planner's foreach-point tour is reused only for the same request",
          "[exec][tour]") {
  Study st;
  auto run = [&](const std::string& prog, bool deterministic, int& tours) {
    auto p = std::make_shared<CountingPlanner>(st.planner, deterministic);
    kernel::Executor exec(p, {});
    auto o = exec.run(sdk::read_canonical(prog), st.state());
    REQUIRE_FALSE(o.error);
    tours = p->tours;
    return trace_text(o.trace);
  };
  int fresh = 0, reused = 0;
  // strict: a trial run, then the real one: the same tour request twice.
  const std::string strict = "{strict {foreach point in room3 {visit point}}}";
  CHECK(run(strict, true, reused) == run(strict, false, fresh));
  CHECK(fresh == 2);
  CHECK(reused == 1);
  // The same cells from another start (the robot moved): a new request, a new tour.
  const std::string moved =
      "{{foreach point in room3 {visit point}};{move right};{foreach point in room3 {visit "
      "point}}}";
  CHECK(run(moved, true, reused) == run(moved, false, fresh));
  CHECK(fresh == 2);
  CHECK(reused == 2);
}
