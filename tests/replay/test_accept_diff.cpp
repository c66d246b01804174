// The accept classifier (kernel/corpus/accept_diff.hpp) on hand-made worlds: each class is
// reached by the case it names, and the first matching class wins.
#include <catch2/catch.hpp>
#include <set>

#include "flipper/kernel/corpus/accept_diff.hpp"
#include "flipper/sdk/canonical.hpp"

using namespace flipper;
using namespace flipper::kernel::corpus;
using nlohmann::json;

namespace {

// A protocol world: robot at (x, y), items as (x, y, colour) circles.
json world(int x, int y, const std::vector<std::tuple<int, int, std::string>>& items,
           json walls = json::array({json::array({0, 0})})) {
  json w{{"robot", {{"x", x}, {"y", y}, {"holding", json::array()}}},
         {"walls", std::move(walls)},
         {"rooms", json::object()},
         {"items", json::array()}};
  for (const auto& [ix, iy, c] : items)
    w["items"].push_back({{"x", ix}, {"y", iy}, {"color", c}, {"shape", "circle"}});
  return w;
}

sdk::WorldState state(int x, int y, const std::vector<std::tuple<int, int, std::string>>& items) {
  sdk::WorldState s;
  s.robot = {x, y, 0};
  for (const auto& [ix, iy, c] : items) s.items.push_back({{0, c, "circle"}, {ix, iy, 0}});
  return s;
}

struct Case {
  json before, after;
  std::string program = "{move left}";
  sdk::WorldState start, ours;
  std::vector<std::string> warnings;
  std::vector<sdk::TraceStep> trace;
  std::optional<std::string> error, error_code;
  json path;
  std::string next_id = "w0";

  AcceptClass classify() const {
    const sdk::Program p = sdk::read_canonical(program);
    sdk::Outcome o;
    o.world = ours;
    o.warnings = warnings;
    o.trace = trace;
    o.error = error;
    o.error_code = error_code;
    return classify_accept({before, after, next_id, p, start, o, path.is_null() ? nullptr : &path});
  }
};

Case moved_left() {
  Case c;
  c.before = world(3, 3, {{5, 5, "red"}});
  c.start = state(3, 3, {{5, 5, "red"}});
  c.ours = state(2, 3, {{5, 5, "red"}});
  c.after = world(2, 3, {{5, 5, "red"}});
  c.trace = {{sdk::TraceStep::Act::move, {2, 3, 0}, {}}};
  return c;
}

}  // namespace

TEST_CASE("snapshots of protocol worlds and states compare as multisets") {
  CHECK(snapshot(world(1, 2, {{4, 4, "red"}, {3, 3, "blue"}})) ==
        snapshot(state(1, 2, {{3, 3, "blue"}, {4, 4, "red"}})));
  CHECK_FALSE(snapshot(world(1, 2, {{4, 4, "red"}})) == snapshot(state(1, 2, {{4, 4, "blue"}})));
}

TEST_CASE("the original's path is read as core-language §5 says") {
  const json path = json::parse(R"([[3,3,"path","null","null",true],[2,3,"path","null","null",true],
      [2,3,"destination","null","null",true],[1,3,"path","null","null",false],
      [2,3,"pickitem","red","circle",true]])");
  CHECK(original_steps(path, {3, 3, 0}) == Steps{"m 2 3", "p 2 3 red circle"});
  CHECK(our_steps({{sdk::TraceStep::Act::move, {2, 3, 0}, {}},
                   {sdk::TraceStep::Act::pick, {2, 3, 0}, {1, "red", "circle"}}}) ==
        Steps{"m 2 3", "p 2 3 red circle"});
}

TEST_CASE("each class is reached by its case") {
  Case c = moved_left();
  CHECK(c.classify() == AcceptClass::agree);

  SECTION("errors come first") {
    c.error = "budget";
    c.error_code = "budget_exceeded";
    CHECK(c.classify() == AcceptClass::budget_exceeded);
    c.error_code = "execution_error";
    CHECK(c.classify() == AcceptClass::execution_error);
  }
  SECTION("a start other than the logged world before is a replay fault") {
    c.after = world(1, 3, {{5, 5, "red"}});
    c.start = state(4, 3, {{5, 5, "red"}});
    CHECK(c.classify() == AcceptClass::start_differs);
    CHECK(is_unexplained(AcceptClass::start_differs));
  }
  SECTION("resets: items appear, the layout changes, or the start world comes back") {
    c.after = world(2, 3, {{5, 5, "red"}, {6, 6, "blue"}});
    CHECK(c.classify() == AcceptClass::reset);
    c.after = world(1, 3, {{5, 5, "red"}}, json::array({json::array({0, 1})}));
    CHECK(c.classify() == AcceptClass::reset);
    c.after = world(1, 3, {{5, 5, "red"}});
    c.next_id = std::string(kStudyStartWorld);
    CHECK(c.classify() == AcceptClass::reset);
  }
  SECTION("the client logged the world before again") {
    c.after = c.before;
    CHECK(c.classify() == AcceptClass::no_change_logged);
  }
  SECTION("our trace is the original's own run") {
    c.after = world(1, 3, {{5, 5, "red"}});
    c.path =
        json::parse(R"([[3,3,"path","null","null",true],[2,3,"destination","null","null",true]])");
    CHECK(c.classify() == AcceptClass::client_state);
    c.path =
        json::parse(R"([[3,3,"path","null","null",true],[1,3,"destination","null","null",true]])");
    CHECK(c.classify() == AcceptClass::unexplained);
  }
  SECTION("spec decisions by program shape") {
    c.after = world(1, 3, {{5, 5, "red"}});
    c.warnings = {"{move left} failed: blocked"};
    CHECK(c.classify() == AcceptClass::failed_movement);
    c.warnings.clear();
    c.program = "{foreach point in room1 {move left}}";
    CHECK(c.classify() == AcceptClass::loop_order);
    c.program = "{visit rooms}";
    CHECK(c.classify() == AcceptClass::visit_collection);
    c.program = "{visit room1}";
    CHECK(c.classify() == AcceptClass::nearest_cell);
    c.program = "{move left}";
    CHECK(c.classify() == AcceptClass::unexplained);
    CHECK(is_unexplained(AcceptClass::unexplained));
  }
  SECTION("same cell and held count, other items: item choice") {
    c.before = world(3, 3, {{5, 5, "red"}, {2, 3, "blue"}});
    c.start = state(3, 3, {{5, 5, "red"}, {2, 3, "blue"}});
    c.ours = state(2, 3, {{5, 5, "red"}, {2, 3, "green"}});
    c.after = world(2, 3, {{5, 5, "red"}, {2, 3, "blue"}});
    CHECK(c.classify() == AcceptClass::item_choice);
  }
}

TEST_CASE("class ids round-trip and are distinct") {
  std::set<std::string> ids;
  for (AcceptClass c : all_classes()) {
    ids.insert(class_id(c));
    CHECK(class_from_id(class_id(c)) == c);
  }
  CHECK(ids.size() == all_classes().size());
  CHECK_FALSE(class_from_id("no_such_class"));
}
