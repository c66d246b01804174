#pragma once
/// @file ast.hpp
/// The program representation every component exchanges: an immutable tree of the core
/// language (docs/core-language.md §3). Nodes are shared (`Program` is a shared_ptr to const),
/// carry their sort and a structural hash, and compare structurally — two derivations that yield
/// the same program compare equal. Templates of grammar rules are programs with `Hole` nodes.
///
/// Conventions:
/// - Sequences are n-ary and flat: `seq(seq(a,b),c)` == `seq(a,b,c)`; braces are grouping only
///   and leave no node. A sequence has at least two statements.
/// - Every sort's and/or/not/minus/containing has its own Kind, so the executor dispatches on
///   Kind alone; `sort_of(kind)` gives the sort.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "flipper/sdk/export.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// Sorts of the language; each corresponds to a grammar category (in parentheses).
/// Values cross the plugin boundary: pinned in sdk/src/abi_pins.cpp; never renumber, only append.
enum class Sort : std::uint8_t {
  Action = 0,      ///< statement ($Action / $Actions)
  Condition = 1,   ///< ($Situation / $Situations)
  Point = 2,       ///< ($Point)
  Area = 3,        ///< ($Area / $Areas)
  Collection = 4,  ///< ($AreaCollection / $AreaCollections)
  Item = 5,        ///< ($Item)
  CountedItem =
      6,          ///< `every item ...` ($CountedItem); a plain Item is also accepted where counted
  Filter = 7,     ///< ($PropertySet / $PropertySets)
  Number = 8,     ///< ($Number / $Numbers)
  Direction = 9,  ///< ($Direction)
  Color = 10,     ///< ($Color)
  Shape = 11,     ///< ($Shape)
  ItemAct = 12,   ///< the verb of an item action, `pick` or `drop` ($ItemAct)
  /// A colour or a shape word ($Property): the sort of template holes that either may fill
  /// (`is $1`), so an induced rule can abstract `red` and still take `triangle`. No program
  /// node has this sort; Color and Shape words fit it (see `sort_fits`).
  Property = 13,
};

/// Values cross the plugin boundary: pinned in sdk/src/abi_pins.cpp; never renumber, only append.
enum class Kind : std::uint8_t {
  // --- statements (Sort::Action)
  Seq = 0,              ///< kids: >= 2 statements
  Strict = 1,           ///< kids: [statement]
  Move = 2,             ///< kids: [Direction]
  VisitPoint = 3,       ///< kids: [point] or [point, avoid-area]
  VisitArea = 4,        ///< kids: [area] or [area, avoid-area]
  VisitCollection = 5,  ///< kids: [collection] or [collection, avoid-area]
  Pick = 6,             ///< kids: [Item or Every]
  Drop = 7,             ///< kids: [Item or Every]
  ForeachPoint = 8,     ///< kids: [area, body]
  ForeachArea = 9,      ///< kids: [collection, body]
  Repeat = 10,          ///< kids: [number, body]
  If = 11,              ///< kids: [condition, body]
  While = 12,           ///< kids: [condition, body]
  // --- conditions (Sort::Condition)
  CondAnd = 13,       ///< kids: [c1, c2]
  CondOr = 14,        ///< kids: [c1, c2]
  CondNot = 15,       ///< kids: [c]
  ItemAtPoint = 16,   ///< kids: [item, point]
  ItemAtArea = 17,    ///< kids: [item, area]
  RobotHas = 18,      ///< kids: [item]
  RobotAtPoint = 19,  ///< kids: [point]
  RobotAtArea = 20,   ///< kids: [area]
  Possible = 21,      ///< kids: [statement]
  // --- points (Sort::Point)
  PointXY = 22,   ///< kids: [number, number] (or three numbers in 3-D)
  Current = 23,   ///< the robot's cell
  PointVar = 24,  ///< loop variable `point`
  // --- areas (Sort::Area)
  World = 25,           ///< all free cells
  Room = 26,            ///< a named room: leaf, `text` = "room1"
  AreaVar = 27,         ///< loop variable `area`
  PointList = 28,       ///< kids: >= 1 points
  Corners = 29,         ///< kids: [point, point]
  AreaOr = 30,          ///< kids: [a, b]
  AreaAnd = 31,         ///< kids: [a, b]
  AreaMinus = 32,       ///< kids: [a, b]
  AreaContaining = 33,  ///< kids: [area, item]
  // --- collections (Sort::Collection)
  Rooms = 34,           ///< all rooms
  AreaList = 35,        ///< kids: >= 1 areas
  CollOr = 36,          ///< kids: [c, d]
  CollAnd = 37,         ///< kids: [c, d]
  CollMinus = 38,       ///< kids: [c, d]
  CollContaining = 39,  ///< kids: [collection, item]
  // --- items
  Item = 40,       ///< Sort::Item; kids: [] or [filter]
  Every = 41,      ///< Sort::CountedItem; kids: [item]
  FilterIs = 42,   ///< Sort::Filter; kids: [Color or Shape] (a template: a Property hole)
  FilterAnd = 43,  ///< kids: [f, g]
  FilterOr = 44,   ///< kids: [f, g]
  FilterNot = 45,  ///< kids: [f]
  // --- numbers (Sort::Number)
  Num = 46,  ///< value in `number`
  Add = 47,  ///< kids: [a, b]
  Sub = 48,  ///< kids: [a, b]
  // --- words (leaves with `text`)
  Direction = 49,  ///< Sort::Direction, e.g. "up"
  Color = 50,      ///< Sort::Color, e.g. "red" ("grey" is stored as "gray")
  Shape = 51,      ///< Sort::Shape, e.g. "triangle"
  ItemAct = 52,    ///< Sort::ItemAct, "pick" or "drop"
  /// Sort::Action; kids: [ItemAct, CountedItem]. The grammar's view of pick/drop, where the verb
  /// is a node of its own (so an induced rule can abstract it: `$ItemAct $Number items`).
  /// `make` normalises it to Pick/Drop as soon as the verb is a word; it survives only with a
  /// Hole verb (templates) and in `full_form`.
  ItemAction = 53,
  // --- templates
  Hole = 54,  ///< a template hole: `index` (0-based), sort in `sort`
};

struct Node;
/// An immutable, shareable program (sub)tree.
using Program = std::shared_ptr<const Node>;

struct FLIPPER_SDK_API Node {
  Kind kind = Kind::Seq;
  Sort sort = Sort::Action;
  double number = 0;  ///< Num: value
  std::string text;   ///< word leaves: the word
  int index = -1;     ///< Hole: 0-based hole index
  std::vector<Program> kids;
  std::size_t hash = 0;    ///< structural hash (computed at construction)
  std::uint32_t size = 1;  ///< number of nodes in this subtree
};

/// Whether a program of sort `actual` may stand where `expected` is wanted (a kid, a hole's
/// argument, a category): the same sort, a plain Item for a CountedItem, or a Color or Shape word
/// for a Property.
FLIPPER_SDK_API bool sort_fits(Sort expected, Sort actual);

/// The sort a kind always has (Hole: Sort::Action; use node.sort).
FLIPPER_SDK_API Sort sort_of(Kind kind);
FLIPPER_SDK_API const char* kind_name(Kind kind);
FLIPPER_SDK_API const char* sort_name(Sort sort);

/// Builds a node: checks arity and kid sorts (throws Error(bad_program) on misuse), flattens
/// nested Seq, normalises "grey" to "gray", computes hash and size.
FLIPPER_SDK_API Program make(Kind kind, std::vector<Program> kids = {});
FLIPPER_SDK_API Program make_num(double value);
FLIPPER_SDK_API Program make_word(Kind kind,
                                  std::string text);  ///< Direction/Color/Shape/Room/ItemAct
FLIPPER_SDK_API Program make_hole(int index, Sort sort);
/// Sequence of statements; a single statement is returned as is.
FLIPPER_SDK_API Program make_seq(std::vector<Program> statements);

/// Structural equality (fast path on hash and pointer identity).
FLIPPER_SDK_API bool equal(const Program& a, const Program& b);
struct ProgramHash {
  std::size_t operator()(const Program& p) const { return p ? p->hash : 0; }
};
struct ProgramEqual {
  bool operator()(const Program& a, const Program& b) const { return equal(a, b); }
};

/// Replaces every Hole(i) by args[i]. Throws Error(bad_program) on a missing argument or a sort
/// mismatch (an Item may fill a CountedItem hole, a Color or Shape a Property hole).
FLIPPER_SDK_API Program substitute(const Program& tmpl, const std::vector<Program>& args);
/// Whether the tree contains a Hole.
FLIPPER_SDK_API bool has_holes(const Program& p);
/// Loop-variable check (core-language §3.7): `point`/`area` only inside an enclosing loop body.
FLIPPER_SDK_API bool loop_variables_bound(const Program& p);

/// The program with every Pick/Drop written as ItemAction(ItemAct verb, item): the form whose
/// subtrees are exactly the grammar's categories, used by grammar induction to find and abstract
/// the verb. Everything else is unchanged. `normal_form` undoes it (and is what `make` yields).
FLIPPER_SDK_API Program full_form(const Program& p);
FLIPPER_SDK_API Program normal_form(const Program& p);

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
