#pragma once
/// @file grammar.hpp
/// Grammar rules `LHS -> RHS => template` (docs/naturalization.md §1), shared by parser, scorer,
/// inducer and lexicon. Core rules come from a grammar file (data, not code); induced rules come
/// from definitions and carry their provenance and use counters.
///
/// Grammar file format (configs/grammars/*.grammar), one rule per line, `#` comments:
/// @code
///   $Action -> visit $Point while avoiding $Areas => {visit $1 while avoiding $2}
///   $Actions -> $Actions ; $Action => {$1;$2}
///   $Number -> @number                 # any number token (core-language §2.6)
///   $Color -> @color                   # any colour word of the `colors` list
///   $Shape -> @shape                   # any shape word of the `shapes` list
///   $Direction -> @direction           # any direction word of the `directions` list
///   $PointList -> $PointList , $Point => @append   # list append (built in)
///   $ROOT -> $Actions => $1            # the root category is $ROOT
/// @endcode
/// The template is canonical text (canonical.hpp) with `$1`, `$2`, ... naming the RHS
/// categories in order; its sort is that of the LHS category.
///
/// Extensions:
/// - A rule whose RHS is a single class symbol (`@number`, `@color`, `@shape`, `@direction`) has
///   no template: its meaning is the matched token's value (`sem` is null).
/// - `=> @append` (only for `$PointList`/`$AreaList` with RHS `$L , $X`): appends $2 to the list
///   $1 (a template cannot splice); `sem` is null. A single-category RHS defaults to `=> $1`.
/// - Auxiliary categories `$Cat.suffix` (e.g. `$Number.token`) have the sort of `$Cat` and
///   normalise to it. The core grammar uses them to reproduce the original's derivation nodes
///   (its `$TOKEN`, `$Property` and `$ItemActionFragment` nodes), so initial scores match.
/// Use `apply_rule` to compute a derivation's meaning for any rule.

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/export.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// One RHS symbol.
struct Symbol {
  /// Values cross the plugin boundary: pinned in sdk/src/abi_pins.cpp; never renumber, only append.
  enum class Type : std::uint8_t {
    token = 0,      ///< an exact token, e.g. "visit"
    category = 1,   ///< a category, e.g. "$Area"
    number = 2,     ///< any number token; semantics Num(value)
    color = 3,      ///< any colour word; semantics Color(word)
    shape = 4,      ///< any shape word; semantics Shape(word)
    direction = 5,  ///< any direction word; semantics Direction(word)
  };
  Type type = Type::token;
  std::string text;  ///< token text or category name ("$Area"); "@number" etc. for classes
  friend bool operator==(const Symbol&, const Symbol&) = default;
};

/// How a rule came to be.
/// Values cross the plugin boundary: pinned in sdk/src/abi_pins.cpp; never renumber, only append.
enum class RuleOrigin : std::uint8_t {
  core = 0,
  simple = 1,
  best = 2,
  alignment = 3,
  rewriting = 4
};
FLIPPER_SDK_API const char* to_string(RuleOrigin o);  ///< "core", "simple", ...

struct Rule {
  std::string id;   ///< stable id: "core:<line>" for core rules, lexicon ids for induced ones
  std::string lhs;  ///< category, e.g. "$Action"
  std::vector<Symbol> rhs;
  Program sem;  ///< template with holes $1.. for the RHS categories, in order
  bool induced = false;
  RuleOrigin how = RuleOrigin::core;
  // Provenance (induced rules).
  std::string author;
  std::string head;
  std::vector<std::string> body;
  std::int64_t created = 0;  ///< creation sequence number (orders candidates on score ties)
  // How often the rule was used is not here: the kernel owns the counters and hands them to
  // scorers in ScoreContext::usage (a rule is immutable once shared).
  /// Number of RHS categories (= holes).
  std::size_t arity() const;
};

using RulePtr = std::shared_ptr<const Rule>;

/// A set of rules: core rules first (file order), then induced rules in creation order.
struct Grammar {
  std::string root = "$ROOT";
  std::vector<std::string> colors;  ///< words matched by @color ("grey" maps to "gray")
  std::vector<std::string> shapes;  ///< words matched by @shape
  std::vector<std::string>
      directions;  ///< words matched by @direction (default up/down/left/right)
  std::vector<RulePtr> rules;
};

/// Maps a category to its sort: $Action/$Actions -> Action, $Area/$Areas -> Area, ...
/// Unknown categories throw Error(bad_grammar).
FLIPPER_SDK_API Sort category_sort(const std::string& category);
/// List categories normalised to their element category ($Actions -> $Action, $Areas -> $Area,
/// $Numbers -> $Number, $Situations -> $Situation, $PropertySets -> $PropertySet,
/// $AreaCollections -> $AreaCollection); others unchanged (docs/naturalization.md §4.4).
FLIPPER_SDK_API std::string normalize_category(const std::string& category);

/// Parses grammar text (format above). `source` names the file in error messages; errors throw
/// Error(bad_grammar) naming the line.
FLIPPER_SDK_API Grammar parse_grammar(const std::string& text, const std::string& source,
                                      std::vector<std::string> colors,
                                      std::vector<std::string> shapes);
FLIPPER_SDK_API Grammar load_grammar_file(const std::string& path, std::vector<std::string> colors,
                                          std::vector<std::string> shapes);

/// Same, with the direction words matched by `@direction` (empty: up, down, left, right).
FLIPPER_SDK_API Grammar parse_grammar(const std::string& text, const std::string& source,
                                      std::vector<std::string> colors,
                                      std::vector<std::string> shapes,
                                      std::vector<std::string> directions);
FLIPPER_SDK_API Grammar load_grammar_file(const std::string& path, std::vector<std::string> colors,
                                          std::vector<std::string> shapes,
                                          std::vector<std::string> directions);

/// Whether `token` matches the class symbol `type` (number/color/shape/direction) in `grammar`.
FLIPPER_SDK_API bool class_matches(const Grammar& grammar, Symbol::Type type,
                                   std::string_view token);
/// The meaning of `rule` applied to `kids` (one per RHS category); `token` is the matched token
/// of a class rule. Throws Error(bad_program) when a kid does not fit (callers drop the parse).
FLIPPER_SDK_API Program apply_rule(const Rule& rule, const std::vector<Program>& kids,
                                   std::string_view token = {});

/// "LHS -> rhs tokens => template" for listings.
FLIPPER_SDK_API std::string describe(const Rule& rule);

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
