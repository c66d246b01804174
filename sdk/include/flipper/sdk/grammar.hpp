#pragma once
/// @file grammar.hpp
/// Grammar rules `LHS -> RHS => template` (naturalization.md §1), shared by parser, scorer,
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
///   $ROOT -> $Actions => $1            # the root category is $ROOT
/// @endcode
/// The template is canonical text (canonical.hpp) with `$1`, `$2`, ... naming the RHS
/// categories in order; its sort is that of the LHS category.

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/export.hpp"

namespace flipper::sdk {
inline namespace v1 {

/// One RHS symbol.
struct Symbol {
  enum class Type : std::uint8_t {
    token,     ///< an exact token, e.g. "visit"
    category,  ///< a category, e.g. "$Area"
    number,    ///< any number token; semantics Num(value)
    color,     ///< any colour word; semantics Color(word)
    shape,     ///< any shape word; semantics Shape(word)
  };
  Type type = Type::token;
  std::string text;  ///< token text or category name ("$Area"); "@number" etc. for classes
  friend bool operator==(const Symbol&, const Symbol&) = default;
};

/// How a rule came to be.
enum class RuleOrigin : std::uint8_t { core, simple, best, alignment, rewriting };
FLIPPER_SDK_API const char* to_string(RuleOrigin o);  ///< "core", "simple", ...

/// Use counters of an induced rule; updated by the kernel on accept, read by scorers.
struct RuleUsage {
  std::atomic<std::uint64_t> by_author{0};
  std::atomic<std::uint64_t> by_others{0};
};

struct Rule {
  std::string id;   ///< stable id: "core:<line>" for core rules, lexicon ids for induced ones
  std::string lhs;  ///< category, e.g. "$Action"
  std::vector<Symbol> rhs;
  Program sem;      ///< template with holes $1.. for the RHS categories, in order
  bool induced = false;
  RuleOrigin how = RuleOrigin::core;
  // Provenance (induced rules).
  std::string author;
  std::string head;
  std::vector<std::string> body;
  std::int64_t created = 0;  ///< creation sequence number (orders candidates on score ties)
  std::shared_ptr<RuleUsage> usage = std::make_shared<RuleUsage>();
  /// Number of RHS categories (= holes).
  std::size_t arity() const;
};

using RulePtr = std::shared_ptr<const Rule>;

/// A set of rules: core rules first (file order), then induced rules in creation order.
struct Grammar {
  std::string root = "$ROOT";
  std::vector<std::string> colors;  ///< words matched by @color ("grey" maps to "gray")
  std::vector<std::string> shapes;  ///< words matched by @shape
  std::vector<RulePtr> rules;
};

/// Maps a category to its sort: $Action/$Actions -> Action, $Area/$Areas -> Area, ...
/// Unknown categories throw Error(bad_grammar).
FLIPPER_SDK_API Sort category_sort(const std::string& category);
/// List categories normalised to their element category ($Actions -> $Action, $Areas -> $Area,
/// $Numbers -> $Number, $Situations -> $Situation, $PropertySets -> $PropertySet,
/// $AreaCollections -> $AreaCollection); others unchanged (naturalization.md §4.4).
FLIPPER_SDK_API std::string normalize_category(const std::string& category);

/// Parses grammar text (format above). `source` names the file in error messages; errors throw
/// Error(bad_grammar) naming the line.
FLIPPER_SDK_API Grammar parse_grammar(const std::string& text, const std::string& source,
                                      std::vector<std::string> colors,
                                      std::vector<std::string> shapes);
FLIPPER_SDK_API Grammar load_grammar_file(const std::string& path, std::vector<std::string> colors,
                                          std::vector<std::string> shapes);

/// "LHS -> rhs tokens => template" for listings.
FLIPPER_SDK_API std::string describe(const Rule& rule);

}  // namespace v1
}  // namespace flipper::sdk
