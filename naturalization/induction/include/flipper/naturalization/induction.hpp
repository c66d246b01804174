#pragma once
/// @file induction.hpp
/// Grammar induction (docs/naturalization.md §4): from a definition (head := body lines) to new
/// rules. The pieces are free functions so that the generalizer and tests can use each one:
/// matches of head-chart derivations against the body program, simple and best packing, rule
/// construction, and alignment. `Inducer` runs the whole §4 pipeline against a parser.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/derivation.hpp"
#include "flipper/sdk/grammar.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/scorer.hpp"

namespace flipper::naturalization {

/// Stable error codes of definitions.
namespace induction_codes {
inline constexpr const char* kEmptyHead = "empty_head";
inline constexpr const char* kHeadIsCore = "head_is_core";
inline constexpr const char* kBodyUnparsable = "body_unparsable";
}  // namespace induction_codes

/// A head-chart derivation whose (normalised category, program) is that of a body node.
struct Match {
  int start = 0;
  int end = 0;
  std::string category;  ///< normalised ($Actions -> $Action)
  sdk::Program program;
  double score = 0;  ///< best derivation's score for this (span, category, program)
  bool core_only = true;
  /// How many statements of the body hold `program` (the body's top-level sequence; a body that
  /// is no sequence is one statement). Best packing prefers, on equal scores, the packing with
  /// more matches held by several statements (docs/naturalization.md §4.6).
  int statements = 0;
  /// The match lies in the body of a loop (foreach, while) whose guard holds a part of it, the
  /// program of a shorter match inside its span: a hole for this match alone would keep that
  /// part fixed in the guard. Best packing prefers, on equal scores, the packing with fewer
  /// such matches (docs/naturalization.md §4.6).
  bool strands_loop_guard = false;
  /// The head's own reading of a longer phrase splits this match: some head-chart derivation of
  /// a longer span around it (not the whole head) has a constituent boundary strictly inside the
  /// match's span and no constituent for it. Best packing prefers, on equal scores, the packing
  /// with fewer such matches (docs/naturalization.md §4.6).
  bool split_by_head = false;
};

/// The category naming a sort ($Action, $Area, $CountedItem, ...).
std::string category_of_sort(sdk::Sort sort);
/// Whether a program of sort `program` may stand for `category`: same sort, a plain item for a
/// $CountedItem (the grammar's `$CountedItem -> $Item`), a colour or shape word for a $Property
/// (`$Property -> $Color`). Unknown categories never fit.
bool category_fits(const std::string& category, sdk::Sort program);
/// Whether a normalised category is primitive ($Color, $Shape, $Number, $Direction, $Point).
bool is_primitive_category(const std::string& category);

/// Matches (§4.4), one per distinct (span, category, program) keeping the best score, ordered by
/// (start, end, chart order). Derivations of the whole head (if present) are ignored, and so
/// are those through an alignment rule with a category in its RHS unless `packed_alignment`
/// (the February 2018 runs never packed one: §4.8).
std::vector<Match> find_matches(const std::vector<sdk::DerivationPtr>& chart,
                                const sdk::Program& body, int head_length,
                                bool packed_alignment = true);

/// Simple packing (§4.5): core-only, one-token, primitive matches; the first at each position.
std::vector<Match> simple_packing(const std::vector<Match>& matches);
/// Best packing (§4.6): non-overlapping, maximal, greatest total score; on equal totals the one
/// with fewer matches stranding a loop guard's part, then fewer matches the head splits, then
/// more matches held by several body statements, then more head tokens covered, then the first
/// in match order.
std::vector<Match> best_packing(const std::vector<Match>& matches, int head_length);
/// Total score of a packing.
double packing_score(const std::vector<Match>& packing);
/// Score of the best packing of `program` against a head chart (the generalizer's σ₁).
double best_packing_score(const std::vector<sdk::DerivationPtr>& head_chart,
                          const sdk::Program& program, int head_length);

/// Why a packing yields no rule.
enum class RuleRejection { none, single_category, too_many_categories };

/// A rule built from a packing (§4.7); `rule` is empty when rejected.
struct BuiltRule {
  std::optional<sdk::Rule> rule;
  RuleRejection rejection = RuleRejection::none;
};
inline constexpr std::size_t kMaxRuleCategories = 4;

/// LHS = `lhs`; RHS = head tokens with packed spans replaced by their categories; template =
/// body with every subtree equal to a packed (category, program) replaced by its hole (equal
/// packed pairs share the first one's hole). Provenance fields are left for the caller.
BuiltRule build_rule(const std::string& lhs, const std::vector<std::string>& head_tokens,
                     const std::vector<Match>& packing, const sdk::Program& body,
                     sdk::RuleOrigin how);

/// Alignment (§4.8) of a one-line body: the differing stretch of head and body tokens mapped to
/// the category of each body-derivation node spanning exactly the body stretch (outermost first,
/// distinct categories, at most `max_rules`).
std::vector<sdk::Rule> alignment_rules(const std::vector<std::string>& head_tokens,
                                       const std::vector<std::string>& body_tokens,
                                       const sdk::DerivationPtr& body_derivation,
                                       std::size_t max_rules = 4);

/// Window alignment (§4.8, the February 2018 runs' rule) of a one-line body: for each node of
/// the body derivation (outermost first) of an action, area or item category and each head
/// phrase whose neighbouring tokens (or the sentence's ends) are the node's, lengths within 2
/// and not the node's own words, a rule from the phrase to the node's category, its parts
/// packed (§4.6) with the head-chart matches that lie inside both the phrase and the node's
/// body positions (as the 2018 code read them). One rule per (category, phrase), at most
/// `max_rules`.
std::vector<sdk::Rule> window_alignment_rules(const std::vector<std::string>& head_tokens,
                                              const std::vector<std::string>& body_tokens,
                                              const sdk::DerivationPtr& body_derivation,
                                              const std::vector<sdk::DerivationPtr>& head_chart,
                                              std::size_t max_rules = 4);

/// Same LHS, RHS and template (structurally).
bool same_rule(const sdk::Rule& a, const sdk::Rule& b);

struct InductionOptions {
  bool alignment = true;          ///< config induction.alignment
  bool alignment_window = false;  ///< config induction.alignment_mode: window
  int beam = 0;                   ///< parser beam (0: plugin default)
};

/// A definition to induce from.
struct DefinitionInput {
  std::string head;
  std::vector<std::string> body;
  std::string author;
  std::vector<int> body_ranks;  ///< optional: candidate rank per body line (default 0)
  /// Optional per body line: the program the line means (the reading the user accepted for it,
  /// docs/protocol.md § define). A line with one takes the parser's candidate with that program
  /// (its derivation serves alignment) or, when the line does not parse to it, the program alone;
  /// its rank is not used. Null or absent: the candidate of the line's rank.
  std::vector<sdk::Program> body_programs;
};

/// What parsing the definition gave, before rules are built (the generalizer needs it).
struct PreparedDefinition {
  std::vector<std::string> head_tokens;
  std::vector<sdk::DerivationPtr> head_chart;
  sdk::Program body;  ///< the body program (lines as one sequence)
  std::vector<std::vector<std::string>> body_tokens;
  std::vector<sdk::DerivationPtr> body_derivations;  ///< chosen derivation of each line
  std::vector<sdk::Candidate> body_candidates;       ///< chosen candidate of each line
};

/// The rules a definition yields, with the matches that explain them.
struct InductionResult {
  std::vector<sdk::Rule> rules;  ///< ids/created unset: the caller assigns them
  std::vector<Match> matches;
  std::vector<Match> simple;
  std::vector<Match> best;
};

class Inducer {
 public:
  /// `visible` restricts the rules used to parse head and body (the author's view).
  /// Parser calls go through `parser` (PluginRef: failures name the plugin). `usage`, the
  /// kernel's use counters, is handed to the scorer as the session's parses do.
  Inducer(kernel::PluginRef<const sdk::Parser> parser, kernel::PluginRef<const sdk::Scorer> scorer,
          InductionOptions options = {}, const sdk::UsageCounters* usage = nullptr);

  /// §4.1–4.3: checks, body program, head chart. Throws sdk::Error with the codes above
  /// (bad_request for a rank past the candidates; body_unparsable only for a line without a
  /// program). Head and body parses stop at `stop`; a stopped parse refuses the definition
  /// (deadline_exceeded).
  PreparedDefinition prepare(const DefinitionInput& def,
                             const std::function<bool(const sdk::Rule&)>& visible,
                             const sdk::StopCondition& stop = {}) const;

  /// §4.4–4.8 for `winner` (the body, or a rewriting of it): simple packing of the original
  /// body, best packing of the winner (tagged `rewriting` when `winner_is_rewriting`), then
  /// alignment. `exists` tells whether an equal rule is already in the grammar. Within the
  /// definition a rule whose RHS equals an earlier one's is dropped.
  InductionResult induce(const PreparedDefinition& prepared, const sdk::Program& winner,
                         bool winner_is_rewriting,
                         const std::function<bool(const sdk::Rule&)>& exists) const;

  const InductionOptions& options() const { return options_; }

 private:
  kernel::PluginRef<const sdk::Parser> parser_;
  kernel::PluginRef<const sdk::Scorer> scorer_;
  InductionOptions options_;
  const sdk::UsageCounters* usage_;
};

}  // namespace flipper::naturalization
