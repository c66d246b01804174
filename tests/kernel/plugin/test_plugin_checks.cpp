// The checks of plugin answers (sdk/answer_check.hpp, applied by kernel/plugin_checks.hpp;
// docs/plugins-untrusted.md) at their boundaries: a path
// of no steps, the last step on the goal, a diagonal step, one cell outside each bound, walls,
// the avoid area, tours that are not permutations, parser candidates and scores. Every message
// is asserted exactly (they are what a plugin author reads).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/sdk/answer_check.hpp"
#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"

using namespace flipper;
using sdk::Cell;
using sdk::path_violation;
using sdk::tour_violation;

namespace {

// A 2-D grid from rows of text, top row first ('#' a wall), y up, bounds [0, w-1] x [0, h-1],
// 4-neighbourhood in the grid's tie order (right, left, up, down).
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
// y=0  . # .
const auto kRing = grid({"...", ".#.", ".#."});
const auto kOpen = grid({"...", "...", "..."});

sdk::PathResult found(Cell target, std::vector<Cell> path) {
  sdk::PathResult r;
  r.status = sdk::PlanStatus::found;
  r.target = target;
  r.path = std::move(path);
  return r;
}

// What is wrong with `r` as the answer to "from start to the goal cells", or "ok".
std::string check(const sdk::Geometry& g, Cell start, sdk::Area goals, const sdk::PathResult& r,
                  sdk::Area avoid = {}) {
  sdk::areas::normalize(goals);
  sdk::areas::normalize(avoid);
  const sdk::PathRequest req{start, &goals, avoid.empty() ? nullptr : &avoid};
  return path_violation(g, req, r).value_or("ok");
}

sdk::TourResult tour(std::vector<std::size_t> order) {
  sdk::TourResult t;
  t.order = std::move(order);
  return t;
}

}  // namespace

TEST_CASE("a path of no steps is valid when the start is the goal, and only then",
          "[plugin_checks]") {
  CHECK(check(*kRing, {0, 0, 0}, {{0, 0, 0}}, found({0, 0, 0}, {})) == "ok");
  CHECK(check(*kRing, {0, 0, 0}, {{0, 1, 0}}, found({0, 0, 0}, {})) ==
        "the path ends at [0,0], which is not a goal of the request");
  CHECK(check(*kRing, {0, 0, 0}, {{0, 1, 0}}, found({0, 1, 0}, {})) ==
        "the path ends at [0,0], not at the target it reports, [0,1]");
}

TEST_CASE("the last step must be on the goal the path reports, and the goal one asked for",
          "[plugin_checks]") {
  const std::vector<Cell> around{{0, 1, 0}, {0, 2, 0}, {1, 2, 0}, {2, 2, 0}, {2, 1, 0}, {2, 0, 0}};
  CHECK(check(*kRing, {0, 0, 0}, {{2, 0, 0}}, found({2, 0, 0}, around)) == "ok");
  // One of several goals: any one of them.
  CHECK(check(*kRing, {0, 0, 0}, {{2, 0, 0}, {0, 2, 0}},
              found({0, 2, 0}, {{0, 1, 0}, {0, 2, 0}})) == "ok");
  // One step short of the goal.
  std::vector<Cell> short_one(around.begin(), around.end() - 1);
  CHECK(check(*kRing, {0, 0, 0}, {{2, 0, 0}}, found({2, 0, 0}, short_one)) ==
        "the path ends at [2,1], not at the target it reports, [2,0]");
  // Ends where it says, but that is not a goal.
  CHECK(check(*kRing, {0, 0, 0}, {{2, 0, 0}}, found({2, 1, 0}, short_one)) ==
        "the path ends at [2,1], which is not a goal of the request");
  // One step past the goal.
  std::vector<Cell> past = around;
  past.push_back({2, 1, 0});
  CHECK(check(*kRing, {0, 0, 0}, {{2, 0, 0}}, found({2, 0, 0}, past)) ==
        "the path ends at [2,1], not at the target it reports, [2,0]");
  // A goal cell that is a wall is no goal (the request's goals are ignored where not free).
  CHECK(check(*kRing, {1, 2, 0}, {{1, 1, 0}}, found({1, 1, 0}, {{1, 1, 0}})) ==
        "step 1 enters wall [1,1]");
}

TEST_CASE("every step is one neighbour offset: no diagonal, no jump, no standing still",
          "[plugin_checks]") {
  CHECK(check(*kOpen, {0, 0, 0}, {{1, 1, 0}}, found({1, 1, 0}, {{1, 0, 0}, {1, 1, 0}})) == "ok");
  CHECK(check(*kOpen, {0, 0, 0}, {{1, 1, 0}}, found({1, 1, 0}, {{1, 1, 0}})) ==
        "step 1 jumps from [0,0] to [1,1], which is not a neighbour");
  CHECK(
      check(*kOpen, {0, 0, 0}, {{0, 2, 0}}, found({0, 2, 0}, {{0, 1, 0}, {0, 1, 0}, {0, 2, 0}})) ==
      "step 2 jumps from [0,1] to [0,1], which is not a neighbour");
  CHECK(check(*kOpen, {0, 0, 0}, {{0, 2, 0}}, found({0, 2, 0}, {{0, 2, 0}})) ==
        "step 1 jumps from [0,0] to [0,2], which is not a neighbour");
}

TEST_CASE("a step one cell outside each bound leaves the world, the bound itself is inside",
          "[plugin_checks]") {
  // kOpen is [0, 2] x [0, 2].
  CHECK(check(*kOpen, {0, 1, 0}, {{-1, 1, 0}}, found({-1, 1, 0}, {{-1, 1, 0}})) ==
        "step 1 leaves the world at [-1,1]");
  CHECK(check(*kOpen, {2, 1, 0}, {{3, 1, 0}}, found({3, 1, 0}, {{3, 1, 0}})) ==
        "step 1 leaves the world at [3,1]");
  CHECK(check(*kOpen, {1, 0, 0}, {{1, -1, 0}}, found({1, -1, 0}, {{1, -1, 0}})) ==
        "step 1 leaves the world at [1,-1]");
  CHECK(check(*kOpen, {1, 2, 0}, {{1, 3, 0}}, found({1, 3, 0}, {{1, 3, 0}})) ==
        "step 1 leaves the world at [1,3]");
  // The cells on each bound are inside.
  CHECK(check(*kOpen, {1, 1, 0}, {{0, 1, 0}}, found({0, 1, 0}, {{0, 1, 0}})) == "ok");
  CHECK(check(*kOpen, {1, 1, 0}, {{2, 1, 0}}, found({2, 1, 0}, {{2, 1, 0}})) == "ok");
  CHECK(check(*kOpen, {1, 1, 0}, {{1, 0, 0}}, found({1, 0, 0}, {{1, 0, 0}})) == "ok");
  CHECK(check(*kOpen, {1, 1, 0}, {{1, 2, 0}}, found({1, 2, 0}, {{1, 2, 0}})) == "ok");
  // 3-D: the z bounds, and coordinates written with z.
  const auto cube = std::make_shared<const sdk::Geometry>(
      3, Cell{0, 0, 0}, Cell{1, 1, 1}, std::vector<std::uint8_t>(8, 1),
      std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
      std::vector<std::pair<std::string, Cell>>{});
  CHECK(check(*cube, {0, 0, 0}, {{0, 0, 1}}, found({0, 0, 1}, {{0, 0, 1}})) == "ok");
  CHECK(check(*cube, {0, 0, 0}, {{0, 0, -1}}, found({0, 0, -1}, {{0, 0, -1}})) ==
        "step 1 leaves the world at [0,0,-1]");
  CHECK(check(*cube, {0, 0, 1}, {{0, 0, 2}}, found({0, 0, 2}, {{0, 0, 2}})) ==
        "step 1 leaves the world at [0,0,2]");
}

TEST_CASE("a step into a wall or the avoided area is refused, the start is exempt",
          "[plugin_checks]") {
  CHECK(check(*kRing, {0, 0, 0}, {{2, 0, 0}}, found({2, 0, 0}, {{1, 0, 0}, {2, 0, 0}})) ==
        "step 1 enters wall [1,0]");
  CHECK(check(*kOpen, {0, 0, 0}, {{0, 2, 0}}, found({0, 2, 0}, {{0, 1, 0}, {0, 2, 0}}),
              {{0, 1, 0}}) == "step 1 enters [0,1], which the request avoids");
  // The robot may leave an avoided cell it stands on.
  CHECK(check(*kOpen, {0, 0, 0}, {{0, 2, 0}}, found({0, 2, 0}, {{0, 1, 0}, {0, 2, 0}}),
              {{0, 0, 0}}) == "ok");
}

TEST_CASE("answers other than found are not acted on and not checked", "[plugin_checks]") {
  sdk::PathResult r = found({9, 9, 0}, {{5, 5, 0}});
  for (auto s : {sdk::PlanStatus::no_path, sdk::PlanStatus::stopped, sdk::PlanStatus::invalid}) {
    r.status = s;
    CHECK(check(*kRing, {0, 0, 0}, {{2, 0, 0}}, r) == "ok");
  }
}

TEST_CASE("a tour's order is a permutation of the points asked", "[plugin_checks]") {
  CHECK_FALSE(tour_violation(3, tour({2, 0, 1})));
  CHECK_FALSE(tour_violation(0, tour({})));
  CHECK(tour_violation(3, tour({0, 1, 0})).value_or("ok") ==
        "the tour order [0,1,0] is not a permutation of the 3 points asked");
  CHECK(tour_violation(3, tour({0, 1})).value_or("ok") ==
        "the tour order [0,1] is not a permutation of the 3 points asked");
  CHECK(tour_violation(2, tour({0, 1, 2})).value_or("ok") ==
        "the tour order [0,1,2] is not a permutation of the 2 points asked");
  CHECK(tour_violation(2, tour({0, 2})).value_or("ok") ==
        "the tour order [0,2] is not a permutation of the 2 points asked");
  sdk::TourResult stopped = tour({7});
  stopped.status = sdk::PlanStatus::stopped;
  CHECK_FALSE(tour_violation(2, stopped));
}

namespace {

class StubPlanner : public sdk::Planner {
 public:
  sdk::PathResult answer;
  sdk::TourResult tour_answer;

 protected:
  sdk::PathResult do_plan(const sdk::Geometry&, const sdk::PathRequest&,
                          const sdk::StopCondition&) const override {
    return answer;
  }
  sdk::TourResult do_tour(const sdk::Geometry&, Cell, const std::vector<Cell>&,
                          const sdk::StopCondition&) const override {
    return tour_answer;
  }
  sdk::PlannerTraits do_traits() const override { return {}; }
};

std::string error_of(const std::function<void()>& f, std::string& code) {
  try {
    f();
  } catch (const sdk::Error& e) {
    code = e.code();
    return e.what();
  }
  code = "(none)";
  return "(no error)";
}

}  // namespace

TEST_CASE("checked_plan and checked_tour refuse with invalid_plan, naming the plugin",
          "[plugin_checks]") {
  auto stub = std::make_shared<StubPlanner>();
  const kernel::PluginRef<const sdk::Planner> ref(
      std::static_pointer_cast<const sdk::Planner>(stub),
      kernel::PluginId{"planner", "stub", "/plugins/libstub.so"});
  sdk::Area goals{{2, 0, 0}};
  const sdk::PathRequest req{{0, 0, 0}, &goals, nullptr};
  std::string code;
  stub->answer = found({2, 0, 0}, {{1, 0, 0}, {2, 0, 0}});
  CHECK(error_of([&] { (void)kernel::checked_plan(ref, *kRing, req, {}); }, code) ==
        "plugin 'stub' (/plugins/libstub.so): step 1 enters wall [1,0]");
  CHECK(code == "invalid_plan");
  stub->answer =
      found({2, 0, 0}, {{0, 1, 0}, {0, 2, 0}, {1, 2, 0}, {2, 2, 0}, {2, 1, 0}, {2, 0, 0}});
  CHECK(kernel::checked_plan(ref, *kRing, req, {}).path.size() == 6u);

  const std::vector<Cell> points{{0, 0, 0}, {2, 0, 0}};
  stub->tour_answer = tour({1, 1});
  CHECK(error_of(
            [&] {
              (void)kernel::checked_tour(ref, *kRing, {0, 0, 0}, points, {});
            },
            code) ==
        "plugin 'stub' (/plugins/libstub.so): the tour order [1,1] is not a permutation of the 2 "
        "points asked");
  CHECK(code == "invalid_plan");
  stub->tour_answer = tour({1, 0});
  CHECK(kernel::checked_tour(ref, *kRing, {0, 0, 0}, points, {}).order ==
        std::vector<std::size_t>{1, 0});
}

namespace {

// A candidate for "move up" (tokens [0, 2)) with one derivation, score `score`.
sdk::Candidate move_up(double score = 1.5) {
  auto rule = std::make_shared<sdk::Rule>();
  rule->id = "core:1";
  rule->lhs = "$ROOT";
  auto d = std::make_shared<sdk::Derivation>();
  d->rule = rule;
  d->start = 0;
  d->end = 2;
  d->score = score;
  d->sem = sdk::read_canonical("{move up}");
  sdk::Candidate c;
  c.program = d->sem;
  c.derivations = {d};
  c.score = score;
  return c;
}

std::string parse_check(sdk::ParseResult r, std::vector<std::string> tokens = {"move", "up"}) {
  sdk::ParseRequest req;
  req.tokens = std::move(tokens);
  const auto v = sdk::parse_violation(req, r);
  return v ? std::string(v->code) + ": " + v->what : "ok";
}

sdk::ParseResult one(sdk::Candidate c) {
  sdk::ParseResult r;
  r.candidates.push_back(std::move(c));
  return r;
}

// A derivation like `of`'s first one, over tokens [start, end), with `kid` beneath it.
sdk::Candidate with_derivation(sdk::Candidate c, int start, int end, double score = 1.5) {
  auto d = std::make_shared<sdk::Derivation>(*c.derivations[0]);
  d->start = start;
  d->end = end;
  d->score = score;
  c.derivations = {d};
  return c;
}

}  // namespace

TEST_CASE("a parser's candidates: well-formed statements over the utterance, finite scores",
          "[plugin_checks]") {
  CHECK(parse_check(one(move_up())) == "ok");
  CHECK(parse_check({}) == "ok");  // no candidates is an answer (no parse)

  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(parse_check(one(move_up(nan))) == "invalid_score: candidate 0 has the score nan");
  sdk::Candidate c = move_up();
  c.derivations = {};
  c.score = -inf;
  CHECK(parse_check(one(c)) == "invalid_score: candidate 0 has the score -inf");
  c = with_derivation(move_up(), 0, 2, inf);
  CHECK(parse_check(one(c)) ==
        "invalid_score: candidate 0: a derivation over tokens [0, 2) has the score inf");

  // Spans: the whole utterance [0, 2) for a candidate; kids within their parent.
  CHECK(parse_check(one(with_derivation(move_up(), 0, 1))) ==
        "invalid_candidate: candidate 0 has a derivation over tokens [0, 1), not the whole "
        "utterance [0, 2)");
  CHECK(parse_check(one(move_up()), {"move", "up", "now"}) ==
        "invalid_candidate: candidate 0 has a derivation over tokens [0, 2), not the whole "
        "utterance [0, 3)");
  sdk::Candidate parent = move_up();
  auto kid = std::make_shared<sdk::Derivation>(*parent.derivations[0]);
  kid->start = 1;
  kid->end = 3;  // one token past its parent and the utterance
  auto top = std::make_shared<sdk::Derivation>(*parent.derivations[0]);
  top->kids = {kid};
  parent.derivations = {top};
  CHECK(parse_check(one(parent)) ==
        "invalid_candidate: candidate 0: a derivation spans tokens [1, 3), outside [0, 2)");
  kid->end = 2;  // on the bound: inside
  CHECK(parse_check(one(parent)) == "ok");

  // Programs: present, a statement, no holes, made as sdk::make makes them, loop variables bound.
  c = move_up();
  c.program = nullptr;
  CHECK(parse_check(one(c)) ==
        "invalid_candidate: candidate 0 is not a program: a missing (null) program node");
  c.program = sdk::read_canonical("red", sdk::Sort::Color);
  CHECK(parse_check(one(c)) == "invalid_candidate: candidate 0 is a Color, not a statement");
  c.program = sdk::make_hole(0, sdk::Sort::Action);
  CHECK(parse_check(one(c)) ==
        "invalid_candidate: candidate 0 is not a program: a template hole where a program was "
        "expected");
  auto seq = std::make_shared<sdk::Node>(*sdk::read_canonical("{{move up};{move left}}"));
  seq->kids.pop_back();  // a sequence of one statement: `make` never builds it
  c.program = seq;
  CHECK(parse_check(one(c)).rfind(
            "invalid_candidate: candidate 0 is not a program: a malformed Seq node (", 0) == 0);
  // What make accepts by rewriting it, the check accepts: a sequence whose one statement is a
  // sequence (make flattens it into two), an item action whose verb is a word (make's Pick).
  auto nested = std::make_shared<sdk::Node>(*seq);
  nested->kids = {sdk::read_canonical("{{move up};{move left}}")};
  c.program = nested;
  CHECK(parse_check(one(c)) == "ok");
  auto verb = std::make_shared<sdk::Node>();
  verb->kind = sdk::Kind::ItemAction;
  verb->sort = sdk::Sort::Action;
  verb->kids = {sdk::make_word(sdk::Kind::ItemAct, "pick"), sdk::make(sdk::Kind::Item)};
  c.program = verb;
  CHECK(parse_check(one(c)) == "ok");
  verb->kids[1] = sdk::read_canonical("red", sdk::Sort::Color);  // no item to pick
  CHECK(parse_check(one(c)).rfind(
            "invalid_candidate: candidate 0 is not a program: a malformed ItemAction node (", 0) ==
        0);
  c.program = sdk::read_canonical("{foreach point in world {visit point}}");
  CHECK(parse_check(one(c)) == "ok");
  c.program = c.program->kids[1];  // `visit point` without its loop
  CHECK(parse_check(one(c)) ==
        "invalid_candidate: candidate 0 uses 'point' or 'area' outside a loop (core-language "
        "§3.7)");
}

TEST_CASE("a parser's candidates: shared derivations and nodes are checked once, however many",
          "[plugin_checks]") {
  // A chain of 101 derivations, each over both of its kids the one below: 2^100 paths down, each
  // derivation checked once (the check keeps what it has seen, past its first 48 without a
  // hash set too).
  sdk::Candidate c = move_up();
  const sdk::DerivationPtr bottom = c.derivations[0];
  auto chain = [&](const sdk::DerivationPtr& leaf) {
    sdk::DerivationPtr d = leaf;
    for (int i = 0; i < 100; ++i) {
      auto up = std::make_shared<sdk::Derivation>(*bottom);
      up->kids = {d, d};
      d = up;
    }
    return d;
  };
  c.derivations = {chain(bottom)};
  CHECK(parse_check(one(c)) == "ok");
  auto bad = std::make_shared<sdk::Derivation>(*bottom);
  bad->score = std::numeric_limits<double>::infinity();
  c.derivations = {chain(bad)};
  CHECK(parse_check(one(c)) ==
        "invalid_score: candidate 0: a derivation over tokens [0, 2) has the score inf");

  // A sequence of 100 statements, all one shared `move up`, then one distinct malformed one.
  auto seq = std::make_shared<sdk::Node>(*sdk::read_canonical("{{move up};{move left}}"));
  const sdk::Program up = seq->kids[0];
  seq->kids.assign(100, up);
  for (int i = 0; i < 60; ++i) seq->kids.push_back(sdk::read_canonical("{move left}"));
  c = move_up();
  c.program = seq;
  CHECK(parse_check(one(c)) == "ok");
  auto no_direction = std::make_shared<sdk::Node>(*up);
  no_direction->kids.clear();
  seq->kids.push_back(no_direction);
  CHECK(parse_check(one(c)).rfind(
            "invalid_candidate: candidate 0 is not a program: a malformed Move node (", 0) == 0);
}
