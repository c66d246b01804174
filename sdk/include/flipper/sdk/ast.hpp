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
inline namespace v1 {

/// Sorts of the language; each corresponds to a grammar category (in parentheses).
enum class Sort : std::uint8_t {
  Action,       ///< statement ($Action / $Actions)
  Condition,    ///< ($Situation / $Situations)
  Point,        ///< ($Point)
  Area,         ///< ($Area / $Areas)
  Collection,   ///< ($AreaCollection / $AreaCollections)
  Item,         ///< ($Item)
  CountedItem,  ///< `every item ...` ($CountedItem); a plain Item is also accepted where counted
  Filter,       ///< ($PropertySet / $PropertySets)
  Number,       ///< ($Number / $Numbers)
  Direction,    ///< ($Direction)
  Color,        ///< ($Color)
  Shape,        ///< ($Shape)
  ItemAct,      ///< the verb of an item action, `pick` or `drop` ($ItemAct)
  /// A colour or a shape word ($Property): the sort of template holes that either may fill
  /// (`is $1`), so an induced rule can abstract `red` and still take `triangle`. No program
  /// node has this sort; Color and Shape words fit it (see `sort_fits`).
  Property,
};

enum class Kind : std::uint8_t {
  // --- statements (Sort::Action)
  Seq,              ///< kids: >= 2 statements
  Strict,           ///< kids: [statement]
  Move,             ///< kids: [Direction]
  VisitPoint,       ///< kids: [point] or [point, avoid-area]
  VisitArea,        ///< kids: [area] or [area, avoid-area]
  VisitCollection,  ///< kids: [collection] or [collection, avoid-area]
  Pick,             ///< kids: [Item or Every]
  Drop,             ///< kids: [Item or Every]
  ForeachPoint,     ///< kids: [area, body]
  ForeachArea,      ///< kids: [collection, body]
  Repeat,           ///< kids: [number, body]
  If,               ///< kids: [condition, body]
  While,            ///< kids: [condition, body]
  // --- conditions (Sort::Condition)
  CondAnd,       ///< kids: [c1, c2]
  CondOr,        ///< kids: [c1, c2]
  CondNot,       ///< kids: [c]
  ItemAtPoint,   ///< kids: [item, point]
  ItemAtArea,    ///< kids: [item, area]
  RobotHas,      ///< kids: [item]
  RobotAtPoint,  ///< kids: [point]
  RobotAtArea,   ///< kids: [area]
  Possible,      ///< kids: [statement]
  // --- points (Sort::Point)
  PointXY,   ///< kids: [number, number] (or three numbers in 3-D)
  Current,   ///< the robot's cell
  PointVar,  ///< loop variable `point`
  // --- areas (Sort::Area)
  World,           ///< all free cells
  Room,            ///< a named room: leaf, `text` = "room1"
  AreaVar,         ///< loop variable `area`
  PointList,       ///< kids: >= 1 points
  Corners,         ///< kids: [point, point]
  AreaOr,          ///< kids: [a, b]
  AreaAnd,         ///< kids: [a, b]
  AreaMinus,       ///< kids: [a, b]
  AreaContaining,  ///< kids: [area, item]
  // --- collections (Sort::Collection)
  Rooms,           ///< all rooms
  AreaList,        ///< kids: >= 1 areas
  CollOr,          ///< kids: [c, d]
  CollAnd,         ///< kids: [c, d]
  CollMinus,       ///< kids: [c, d]
  CollContaining,  ///< kids: [collection, item]
  // --- items
  Item,       ///< Sort::Item; kids: [] or [filter]
  Every,      ///< Sort::CountedItem; kids: [item]
  FilterIs,   ///< Sort::Filter; kids: [Color or Shape] (a template: a Property hole)
  FilterAnd,  ///< kids: [f, g]
  FilterOr,   ///< kids: [f, g]
  FilterNot,  ///< kids: [f]
  // --- numbers (Sort::Number)
  Num,  ///< value in `number`
  Add,  ///< kids: [a, b]
  Sub,  ///< kids: [a, b]
  // --- words (leaves with `text`)
  Direction,  ///< Sort::Direction, e.g. "up"
  Color,      ///< Sort::Color, e.g. "red" ("grey" is stored as "gray")
  Shape,      ///< Sort::Shape, e.g. "triangle"
  ItemAct,    ///< Sort::ItemAct, "pick" or "drop"
  /// Sort::Action; kids: [ItemAct, CountedItem]. The grammar's view of pick/drop, where the verb
  /// is a node of its own (so an induced rule can abstract it: `$ItemAct $Number items`).
  /// `make` normalises it to Pick/Drop as soon as the verb is a word; it survives only with a
  /// Hole verb (templates) and in `full_form`.
  ItemAction,
  // --- templates
  Hole,  ///< a template hole: `index` (0-based), sort in `sort`
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

}  // namespace v1
}  // namespace flipper::sdk
