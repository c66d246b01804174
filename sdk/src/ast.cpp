#include "flipper/sdk/ast.hpp"

#include <algorithm>
#include <functional>
#include <initializer_list>

#include "flipper/sdk/errors.hpp"
#include "node_check.hpp"
#include "node_storage.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

namespace {

struct KindInfo {
  Kind kind;
  Sort sort;
  const char* name;
};

// One row per Kind, in enum order.
constexpr KindInfo kKindTable[] = {
    {Kind::Seq, Sort::Action, "Seq"},
    {Kind::Strict, Sort::Action, "Strict"},
    {Kind::Move, Sort::Action, "Move"},
    {Kind::VisitPoint, Sort::Action, "VisitPoint"},
    {Kind::VisitArea, Sort::Action, "VisitArea"},
    {Kind::VisitCollection, Sort::Action, "VisitCollection"},
    {Kind::Pick, Sort::Action, "Pick"},
    {Kind::Drop, Sort::Action, "Drop"},
    {Kind::ForeachPoint, Sort::Action, "ForeachPoint"},
    {Kind::ForeachArea, Sort::Action, "ForeachArea"},
    {Kind::Repeat, Sort::Action, "Repeat"},
    {Kind::If, Sort::Action, "If"},
    {Kind::While, Sort::Action, "While"},
    {Kind::CondAnd, Sort::Condition, "CondAnd"},
    {Kind::CondOr, Sort::Condition, "CondOr"},
    {Kind::CondNot, Sort::Condition, "CondNot"},
    {Kind::ItemAtPoint, Sort::Condition, "ItemAtPoint"},
    {Kind::ItemAtArea, Sort::Condition, "ItemAtArea"},
    {Kind::RobotHas, Sort::Condition, "RobotHas"},
    {Kind::RobotAtPoint, Sort::Condition, "RobotAtPoint"},
    {Kind::RobotAtArea, Sort::Condition, "RobotAtArea"},
    {Kind::Possible, Sort::Condition, "Possible"},
    {Kind::PointXY, Sort::Point, "PointXY"},
    {Kind::Current, Sort::Point, "Current"},
    {Kind::PointVar, Sort::Point, "PointVar"},
    {Kind::World, Sort::Area, "World"},
    {Kind::Room, Sort::Area, "Room"},
    {Kind::AreaVar, Sort::Area, "AreaVar"},
    {Kind::PointList, Sort::Area, "PointList"},
    {Kind::Corners, Sort::Area, "Corners"},
    {Kind::AreaOr, Sort::Area, "AreaOr"},
    {Kind::AreaAnd, Sort::Area, "AreaAnd"},
    {Kind::AreaMinus, Sort::Area, "AreaMinus"},
    {Kind::AreaContaining, Sort::Area, "AreaContaining"},
    {Kind::Rooms, Sort::Collection, "Rooms"},
    {Kind::AreaList, Sort::Collection, "AreaList"},
    {Kind::CollOr, Sort::Collection, "CollOr"},
    {Kind::CollAnd, Sort::Collection, "CollAnd"},
    {Kind::CollMinus, Sort::Collection, "CollMinus"},
    {Kind::CollContaining, Sort::Collection, "CollContaining"},
    {Kind::Item, Sort::Item, "Item"},
    {Kind::Every, Sort::CountedItem, "Every"},
    {Kind::FilterIs, Sort::Filter, "FilterIs"},
    {Kind::FilterAnd, Sort::Filter, "FilterAnd"},
    {Kind::FilterOr, Sort::Filter, "FilterOr"},
    {Kind::FilterNot, Sort::Filter, "FilterNot"},
    {Kind::Num, Sort::Number, "Num"},
    {Kind::Add, Sort::Number, "Add"},
    {Kind::Sub, Sort::Number, "Sub"},
    {Kind::Direction, Sort::Direction, "Direction"},
    {Kind::Color, Sort::Color, "Color"},
    {Kind::Shape, Sort::Shape, "Shape"},
    {Kind::ItemAct, Sort::ItemAct, "ItemAct"},
    {Kind::ItemAction, Sort::Action, "ItemAction"},
    {Kind::Hole, Sort::Action, "Hole"},
};

static_assert(sizeof(kKindTable) / sizeof(kKindTable[0]) ==
                  static_cast<std::size_t>(Kind::Hole) + 1,
              "kKindTable must list every Kind in order");

[[noreturn]] void misuse(Kind kind, const std::string& what) {
  throw Error(codes::kBadProgram, std::string(kind_name(kind)) + ": " + what);
}

bool fits(Sort expected, Sort actual) {
  return sort_fits(expected, actual);
}

// Checks that kids match one of the allowed sort signatures.
void expect(Kind kind, const std::vector<Program>& kids,
            std::initializer_list<std::initializer_list<Sort>> signatures) {
  for (const auto& sig : signatures) {
    if (sig.size() != kids.size()) continue;
    bool ok = true;
    std::size_t i = 0;
    for (Sort s : sig) {
      if (!kids[i] || !fits(s, kids[i]->sort)) {
        ok = false;
        break;
      }
      ++i;
    }
    if (ok) return;
  }
  std::string got;
  for (const auto& k : kids)
    got += std::string(got.empty() ? "" : ", ") + (k ? sort_name(k->sort) : "null");
  misuse(kind, "unexpected operands (" + got + ")");
}

void expect_all(Kind kind, const std::vector<Program>& kids, Sort s, std::size_t min_count) {
  if (kids.size() < min_count) misuse(kind, "too few operands");
  for (const auto& k : kids)
    if (!k || !fits(s, k->sort)) misuse(kind, std::string("operands must be ") + sort_name(s));
}

// The two shapes make rewrites instead of building them as they are: a sequence with a sequence
// among its statements (flattened into it) and a word verb's ItemAction (made Pick or Drop).
bool nests_sequence(Kind kind, const std::vector<Program>& kids) {
  return kind == Kind::Seq && std::any_of(kids.begin(), kids.end(), [](const Program& k) {
           return k && k->kind == Kind::Seq;
         });
}
bool is_word_verb_action(Kind kind, const std::vector<Program>& kids) {
  return kind == Kind::ItemAction && !kids.empty() && kids[0] && kids[0]->kind == Kind::ItemAct;
}

void check(Kind kind, const std::vector<Program>& kids) {
  using S = Sort;
  switch (kind) {
    case Kind::Seq:
      expect_all(kind, kids, S::Action, 2);
      break;
    case Kind::Strict:
    case Kind::Possible:
      expect(kind, kids, {{S::Action}});
      break;
    case Kind::Move:
      expect(kind, kids, {{S::Direction}});
      break;
    case Kind::VisitPoint:
      expect(kind, kids, {{S::Point}, {S::Point, S::Area}});
      break;
    case Kind::VisitArea:
      expect(kind, kids, {{S::Area}, {S::Area, S::Area}});
      break;
    case Kind::VisitCollection:
      expect(kind, kids, {{S::Collection}, {S::Collection, S::Area}});
      break;
    case Kind::Pick:
    case Kind::Drop:
      expect(kind, kids, {{S::CountedItem}});
      break;
    case Kind::ForeachPoint:
      expect(kind, kids, {{S::Area, S::Action}});
      break;
    case Kind::ForeachArea:
      expect(kind, kids, {{S::Collection, S::Action}});
      break;
    case Kind::Repeat:
      expect(kind, kids, {{S::Number, S::Action}});
      break;
    case Kind::If:
    case Kind::While:
      expect(kind, kids, {{S::Condition, S::Action}});
      break;
    case Kind::CondAnd:
    case Kind::CondOr:
      expect(kind, kids, {{S::Condition, S::Condition}});
      break;
    case Kind::CondNot:
      expect(kind, kids, {{S::Condition}});
      break;
    case Kind::ItemAtPoint:
      expect(kind, kids, {{S::Item, S::Point}});
      break;
    case Kind::ItemAtArea:
      expect(kind, kids, {{S::Item, S::Area}});
      break;
    case Kind::RobotHas:
      expect(kind, kids, {{S::Item}});
      break;
    case Kind::RobotAtPoint:
      expect(kind, kids, {{S::Point}});
      break;
    case Kind::RobotAtArea:
      expect(kind, kids, {{S::Area}});
      break;
    case Kind::PointXY:
      expect(kind, kids, {{S::Number, S::Number}, {S::Number, S::Number, S::Number}});
      break;
    case Kind::PointList:
      expect_all(kind, kids, S::Point, 1);
      break;
    case Kind::Corners:
      expect(kind, kids, {{S::Point, S::Point}});
      break;
    case Kind::AreaOr:
    case Kind::AreaAnd:
    case Kind::AreaMinus:
      expect(kind, kids, {{S::Area, S::Area}});
      break;
    case Kind::AreaContaining:
      expect(kind, kids, {{S::Area, S::Item}});
      break;
    case Kind::AreaList:
      expect_all(kind, kids, S::Area, 1);
      break;
    case Kind::CollOr:
    case Kind::CollAnd:
    case Kind::CollMinus:
      expect(kind, kids, {{S::Collection, S::Collection}});
      break;
    case Kind::CollContaining:
      expect(kind, kids, {{S::Collection, S::Item}});
      break;
    case Kind::Item:
      expect(kind, kids, {{}, {S::Filter}});
      break;
    case Kind::Every:
      expect(kind, kids, {{S::Item}});
      break;
    case Kind::FilterIs:
      // A Color or Shape word, or a Property hole of a template (`{is $1}`).
      expect(kind, kids, {{S::Property}});
      break;
    case Kind::FilterAnd:
    case Kind::FilterOr:
      expect(kind, kids, {{S::Filter, S::Filter}});
      break;
    case Kind::FilterNot:
      expect(kind, kids, {{S::Filter}});
      break;
    case Kind::Add:
    case Kind::Sub:
      expect(kind, kids, {{S::Number, S::Number}});
      break;
    case Kind::ItemAction:
      expect(kind, kids, {{S::ItemAct, S::CountedItem}});
      break;
    case Kind::Current:
    case Kind::PointVar:
    case Kind::World:
    case Kind::AreaVar:
    case Kind::Rooms:
      if (!kids.empty()) misuse(kind, "takes no operands");
      break;
    case Kind::Num:
    case Kind::Direction:
    case Kind::Color:
    case Kind::Shape:
    case Kind::Room:
    case Kind::ItemAct:
    case Kind::Hole:
      misuse(kind, "is a leaf; use make_num/make_word/make_hole");
  }
}

inline void mix(std::size_t& h, std::size_t v) {
  h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
}

Program finish(Node n) {
  std::size_t h = static_cast<std::size_t>(n.kind) * 1315423911u + static_cast<std::size_t>(n.sort);
  if (n.kind == Kind::Num) mix(h, std::hash<double>{}(n.number));
  if (!n.text.empty()) mix(h, std::hash<std::string>{}(n.text));
  if (n.kind == Kind::Hole) mix(h, static_cast<std::size_t>(n.index));
  std::uint32_t size = 1;
  for (const auto& k : n.kids) {
    mix(h, k->hash);
    size += k->size;
  }
  n.hash = h;
  n.size = size;
  return detail::new_node(std::move(n));
}

}  // namespace

bool sort_fits(Sort expected, Sort actual) {
  if (expected == actual) return true;
  if (expected == Sort::CountedItem) return actual == Sort::Item;
  if (expected == Sort::Property) return actual == Sort::Color || actual == Sort::Shape;
  return false;
}

Sort sort_of(Kind kind) {
  return kKindTable[static_cast<std::size_t>(kind)].sort;
}
const char* kind_name(Kind kind) {
  return kKindTable[static_cast<std::size_t>(kind)].name;
}

const char* sort_name(Sort sort) {
  switch (sort) {
    case Sort::Action:
      return "Action";
    case Sort::Condition:
      return "Condition";
    case Sort::Point:
      return "Point";
    case Sort::Area:
      return "Area";
    case Sort::Collection:
      return "Collection";
    case Sort::Item:
      return "Item";
    case Sort::CountedItem:
      return "CountedItem";
    case Sort::Filter:
      return "Filter";
    case Sort::Number:
      return "Number";
    case Sort::Direction:
      return "Direction";
    case Sort::Color:
      return "Color";
    case Sort::Shape:
      return "Shape";
    case Sort::ItemAct:
      return "ItemAct";
    case Sort::Property:
      return "Property";
  }
  return "?";
}

Program make(Kind kind, std::vector<Program> kids) {
  if (nests_sequence(kind, kids)) {
    std::vector<Program> flat;
    for (auto& k : kids) {
      if (k && k->kind == Kind::Seq)
        flat.insert(flat.end(), k->kids.begin(), k->kids.end());
      else
        flat.push_back(std::move(k));
    }
    kids = std::move(flat);
  }
  check(kind, kids);
  // A verb that is a word decides the action: ItemAction(pick, I) is Pick(I).
  if (is_word_verb_action(kind, kids))
    return make(kids[0]->text == "pick" ? Kind::Pick : Kind::Drop, {kids[1]});
  Node n;
  n.kind = kind;
  n.sort = sort_of(kind);
  n.kids = std::move(kids);
  return finish(std::move(n));
}

Program make_seq(std::vector<Program> statements) {
  if (statements.size() == 1) {
    if (!statements[0] || statements[0]->sort != Sort::Action) misuse(Kind::Seq, "not a statement");
    return statements[0];
  }
  return make(Kind::Seq, std::move(statements));
}

Program make_num(double value) {
  Node n;
  n.kind = Kind::Num;
  n.sort = Sort::Number;
  n.number = value;
  return finish(std::move(n));
}

Program make_word(Kind kind, std::string text) {
  if (kind != Kind::Direction && kind != Kind::Color && kind != Kind::Shape && kind != Kind::Room &&
      kind != Kind::ItemAct)
    misuse(kind, "make_word takes Direction, Color, Shape, Room or ItemAct");
  if (text.empty()) misuse(kind, "empty word");
  if (kind == Kind::ItemAct && text != "pick" && text != "drop")
    misuse(kind, "the verb of an item action is 'pick' or 'drop', not '" + text + "'");
  if (kind == Kind::Color && text == "grey") text = "gray";
  Node n;
  n.kind = kind;
  n.sort = sort_of(kind);
  n.text = std::move(text);
  return finish(std::move(n));
}

Program make_hole(int index, Sort sort) {
  if (index < 0) misuse(Kind::Hole, "negative index");
  Node n;
  n.kind = Kind::Hole;
  n.sort = sort;
  n.index = index;
  return finish(std::move(n));
}

bool equal(const Program& a, const Program& b) {
  if (a == b) return true;
  if (!a || !b) return false;
  if (a->hash != b->hash || a->kind != b->kind || a->sort != b->sort || a->size != b->size)
    return false;
  if (a->number != b->number || a->text != b->text || a->index != b->index) return false;
  if (a->kids.size() != b->kids.size()) return false;
  for (std::size_t i = 0; i < a->kids.size(); ++i)
    if (!equal(a->kids[i], b->kids[i])) return false;
  return true;
}

Program substitute(const Program& t, const std::vector<Program>& args) {
  if (!t) return t;
  if (t->kind == Kind::Hole) {
    if (t->index >= static_cast<int>(args.size()) || !args[static_cast<std::size_t>(t->index)])
      throw Error(codes::kBadProgram,
                  "template hole $" + std::to_string(t->index + 1) + " has no argument");
    const Program& a = args[static_cast<std::size_t>(t->index)];
    if (!fits(t->sort, a->sort))
      throw Error(codes::kBadProgram, "template hole $" + std::to_string(t->index + 1) +
                                          " expects " + sort_name(t->sort) + ", got " +
                                          sort_name(a->sort));
    return a;
  }
  if (t->kids.empty()) return t;
  std::vector<Program> kids;
  kids.reserve(t->kids.size());
  bool changed = false;
  for (const auto& k : t->kids) {
    kids.push_back(substitute(k, args));
    changed = changed || kids.back() != k;
  }
  if (!changed) return t;
  return make(t->kind, std::move(kids));
}

bool has_holes(const Program& p) {
  if (!p) return false;
  if (p->kind == Kind::Hole) return true;
  for (const auto& k : p->kids)
    if (has_holes(k)) return true;
  return false;
}

namespace {
bool bound_ok(const Program& p, int point_depth, int area_depth) {
  switch (p->kind) {
    case Kind::PointVar:
      return point_depth > 0;
    case Kind::AreaVar:
      return area_depth > 0;
    case Kind::ForeachPoint:
      // The domain is evaluated outside the loop; the body inside it.
      return bound_ok(p->kids[0], point_depth, area_depth) &&
             bound_ok(p->kids[1], point_depth + 1, area_depth);
    case Kind::ForeachArea:
      return bound_ok(p->kids[0], point_depth, area_depth) &&
             bound_ok(p->kids[1], point_depth, area_depth + 1);
    default:
      for (const auto& k : p->kids)
        if (!bound_ok(k, point_depth, area_depth)) return false;
      return true;
  }
}
}  // namespace

bool loop_variables_bound(const Program& p) {
  return p && bound_ok(p, 0, 0);
}

Program full_form(const Program& p) {
  if (!p || p->kids.empty()) return p;
  std::vector<Program> kids;
  kids.reserve(p->kids.size() + 1);
  bool changed = false;
  for (const auto& k : p->kids) {
    kids.push_back(full_form(k));
    changed = changed || kids.back() != k;
  }
  if (p->kind == Kind::Pick || p->kind == Kind::Drop) {
    // Built directly: `make` would normalise it straight back to Pick/Drop.
    Node n;
    n.kind = Kind::ItemAction;
    n.sort = Sort::Action;
    n.kids = {make_word(Kind::ItemAct, p->kind == Kind::Pick ? "pick" : "drop"), kids[0]};
    return finish(std::move(n));
  }
  if (!changed) return p;
  Node n = *p;
  n.kids = std::move(kids);
  return finish(std::move(n));
}

Program normal_form(const Program& p) {
  if (!p || p->kids.empty()) return p;
  std::vector<Program> kids;
  kids.reserve(p->kids.size());
  bool changed = false;
  for (const auto& k : p->kids) {
    kids.push_back(normal_form(k));
    changed = changed || kids.back() != k;
  }
  if (!changed && p->kind != Kind::ItemAction) return p;
  return make(p->kind, std::move(kids));
}

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk

namespace flipper::sdk::detail {

void check_operands(Kind kind, const std::vector<Program>& kids) {
  // The shapes make rewrites before or after its check go through make itself.
  if (nests_sequence(kind, kids) || is_word_verb_action(kind, kids))
    (void)make(kind, kids);
  else
    sdk::check(kind, kids);
}

}  // namespace flipper::sdk::detail
