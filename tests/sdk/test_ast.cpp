#include <pthread.h>

#include <catch2/catch.hpp>
#include <memory>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/errors.hpp"

using namespace flipper::sdk;

TEST_CASE("sequences flatten and compare structurally", "[ast]") {
  auto left = make(Kind::Move, {make_word(Kind::Direction, "left")});
  auto up = make(Kind::Move, {make_word(Kind::Direction, "up")});
  auto a = make(Kind::Seq, {make(Kind::Seq, {left, up}), left});
  auto b = make(Kind::Seq, {left, make(Kind::Seq, {up, left})});
  REQUIRE(a->kids.size() == 3);
  REQUIRE(equal(a, b));
  REQUIRE(a->hash == b->hash);
  REQUIRE(!equal(a, make(Kind::Seq, {left, up})));
  REQUIRE(a->size == 7);
}

TEST_CASE("make rejects wrong operand sorts", "[ast]") {
  auto left = make(Kind::Move, {make_word(Kind::Direction, "left")});
  REQUIRE_THROWS_AS(make(Kind::Pick, {left}), Error);
  REQUIRE_THROWS_AS(make(Kind::Seq, {left}), Error);
  REQUIRE_NOTHROW(make(Kind::Pick, {make(Kind::Item)}));
  REQUIRE_NOTHROW(make(Kind::Pick, {make(Kind::Every, {make(Kind::Item)})}));
}

TEST_CASE("substitute fills holes and checks sorts", "[ast]") {
  auto tmpl = make(Kind::Repeat, {make_hole(0, Sort::Number),
                                  make(Kind::Pick, {make_hole(1, Sort::CountedItem)})});
  auto p = substitute(tmpl, {make_num(3), make(Kind::Item)});
  REQUIRE(!has_holes(p));
  REQUIRE(p->kids[0]->number == 3);
  REQUIRE(has_holes(tmpl));
  REQUIRE_THROWS_AS(substitute(tmpl, {make(Kind::Item), make(Kind::Item)}), Error);
  REQUIRE_THROWS_AS(substitute(tmpl, {make_num(3)}), Error);
}

TEST_CASE("grey is gray", "[ast]") {
  REQUIRE(equal(make_word(Kind::Color, "grey"), make_word(Kind::Color, "gray")));
}

TEST_CASE("loop variables must be bound by an enclosing loop body", "[ast]") {
  auto visit_point = make(Kind::VisitPoint, {make(Kind::PointVar)});
  REQUIRE(!loop_variables_bound(visit_point));
  auto dom = make(Kind::PointList, {make(Kind::PointXY, {make_num(1), make_num(4)})});
  auto loop = make(Kind::ForeachPoint, {dom, visit_point});
  REQUIRE(loop_variables_bound(loop));
  // The loop's own domain is outside the loop.
  auto bad = make(Kind::ForeachPoint, {make(Kind::PointList, {make(Kind::PointVar)}), visit_point});
  REQUIRE(!loop_variables_bound(bad));
  auto nested = make(Kind::ForeachPoint,
                     {dom, make(Kind::ForeachPoint,
                                {make(Kind::PointList, {make(Kind::PointVar)}), visit_point})});
  REQUIRE(loop_variables_bound(nested));
  REQUIRE(!loop_variables_bound(make(Kind::VisitArea, {make(Kind::AreaVar)})));
}

TEST_CASE("an item action with a known verb is pick or drop", "[ast]") {
  auto pick = make(Kind::ItemAction, {make_word(Kind::ItemAct, "pick"), make(Kind::Item)});
  REQUIRE(pick->kind == Kind::Pick);
  REQUIRE(equal(pick, make(Kind::Pick, {make(Kind::Item)})));
  REQUIRE_THROWS_AS(make_word(Kind::ItemAct, "throw"), Error);
  // With a hole for the verb it stays an ItemAction (a rule template) until filled.
  auto tmpl =
      make(Kind::Repeat, {make_hole(1, Sort::Number),
                          make(Kind::ItemAction, {make_hole(0, Sort::ItemAct), make(Kind::Item)})});
  REQUIRE(tmpl->kids[1]->kind == Kind::ItemAction);
  auto drop2 = substitute(tmpl, {make_word(Kind::ItemAct, "drop"), make_num(2)});
  REQUIRE(drop2->kids[1]->kind == Kind::Drop);
}

TEST_CASE("full form spells out the verb and normal form undoes it", "[ast]") {
  auto body = make(Kind::Repeat, {make_num(3), make(Kind::Pick, {make(Kind::Item)})});
  auto full = full_form(body);
  REQUIRE(full->kids[1]->kind == Kind::ItemAction);
  REQUIRE(full->kids[1]->kids[0]->kind == Kind::ItemAct);
  REQUIRE(full->kids[1]->kids[0]->text == "pick");
  REQUIRE(!equal(full, body));
  REQUIRE(equal(normal_form(full), body));
  // Programs without pick/drop are returned as they are.
  auto mv = make(Kind::Move, {make_word(Kind::Direction, "up")});
  REQUIRE(full_form(mv) == mv);
}

TEST_CASE("a colour or a shape fills a Property hole, nothing else does", "[ast]") {
  REQUIRE(sort_fits(Sort::Property, Sort::Color));
  REQUIRE(sort_fits(Sort::Property, Sort::Shape));
  REQUIRE(!sort_fits(Sort::Color, Sort::Shape));
  REQUIRE(!sort_fits(Sort::Color, Sort::Property));  // a Property is not always a colour
  REQUIRE(!sort_fits(Sort::Property, Sort::Number));
  REQUIRE(sort_fits(Sort::CountedItem, Sort::Item));
  REQUIRE(std::string(sort_name(Sort::Property)) == "Property");

  // `pick every item is $1`: the template of `collect $Property`.
  auto tmpl =
      make(Kind::Pick,
           {make(Kind::Every,
                 {make(Kind::Item, {make(Kind::FilterIs, {make_hole(0, Sort::Property)})})})});
  auto red = substitute(tmpl, {make_word(Kind::Color, "red")});
  auto tri = substitute(tmpl, {make_word(Kind::Shape, "triangle")});
  auto filter = [](const Program& p) { return p->kids[0]->kids[0]->kids[0]->kids[0]; };
  REQUIRE(filter(red)->kind == Kind::Color);
  REQUIRE(filter(tri)->kind == Kind::Shape);
  REQUIRE(filter(tri)->text == "triangle");
  REQUIRE_THROWS_AS(substitute(tmpl, {make_num(2)}), Error);
  REQUIRE_THROWS_AS(substitute(tmpl, {make_word(Kind::Direction, "up")}), Error);
  // A Color hole still takes colours only.
  auto color_only = make(Kind::FilterIs, {make_hole(0, Sort::Color)});
  REQUIRE_THROWS_AS(substitute(color_only, {make_word(Kind::Shape, "circle")}), Error);
  REQUIRE_THROWS_AS(make(Kind::FilterIs, {make_num(1)}), Error);
}

namespace {
/// Runs `fn` on a thread of its own with a stack of `bytes` (std::thread cannot choose it).
template <class F>
void on_stack_of(std::size_t bytes, F fn) {
  pthread_attr_t attr;
  REQUIRE(pthread_attr_init(&attr) == 0);
  REQUIRE(pthread_attr_setstacksize(&attr, bytes) == 0);
  pthread_t thread;
  auto run = [](void* f) -> void* {
    (*static_cast<F*>(f))();
    return nullptr;
  };
  REQUIRE(pthread_create(&thread, &attr, run, &fn) == 0);
  pthread_join(thread, nullptr);
  pthread_attr_destroy(&attr);
}
}  // namespace

TEST_CASE("a program of any depth is destroyed in constant stack", "[ast][depth]") {
  // 200,000 levels, destroyed on a thread with a 256 KiB stack. Destroyed recursively, a level
  // takes some 40 bytes of stack in Release (200,000 levels overflow a 2 MiB stack, fit in 8 MiB)
  // and several hundred instrumented at -O0. The SDK's nodes hand their kids to a queue instead
  // (sdk/src/node_storage.hpp).
  Program leaf = make(Kind::RobotAtPoint, {make(Kind::Current)});
  const std::weak_ptr<const Node> deepest = leaf;
  Program middle;
  Program top = std::move(leaf);
  for (int i = 0; i < 200000; ++i) {
    top = make(Kind::CondNot, {top});
    if (i == 100000) middle = top;
  }
  REQUIRE(top->size == 200002u);
  // The upper half dies; the lower half is still held through `middle`, whole.
  on_stack_of(256 * 1024, [&top] { top.reset(); });
  REQUIRE(top == nullptr);
  REQUIRE_FALSE(deepest.expired());
  CHECK(middle->size == 100003u);
  std::size_t depth = 0;
  for (const Node* n = middle.get(); !n->kids.empty(); n = n->kids.front().get()) ++depth;
  CHECK(depth == 100002u);
  on_stack_of(256 * 1024, [&middle] { middle.reset(); });
  CHECK(deepest.expired());
}

TEST_CASE("a program held by a static dies at exit, after the thread's storage", "[ast][depth]") {
  // Statics die after the main thread's thread_local objects: a program a static holds must not
  // need any of them then (a thread_local queue did: freed memory written at exit, which ASan
  // reports here; in Release only glibc's malloc checks saw it, in other tests' processes). The
  // verdict is this process's exit: ctest runs each test case in a process of its own and fails
  // one that aborts after its checks passed.
  static Program kept;
  Program top = make(Kind::RobotAtPoint, {make(Kind::Current)});
  for (int i = 0; i < 1000; ++i) top = make(Kind::CondNot, {top});
  kept = top;
  top.reset();  // only a reference goes: nothing dies yet
  Program dies = make(Kind::CondNot, {make(Kind::CondNot, {kept->kids.front()->kids.front()})});
  dies.reset();  // a death that queues (an inner kid dies with it)
  CHECK(kept->size == 1002u);
}
