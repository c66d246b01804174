#pragma once
/// @file rule_oracle.hpp
/// The induced-rule oracle: our rules for a definition against the rules the original system
/// logged for it (definitions.jsonl `induced_rules`), compared as `lhs -> rhs` shapes after
/// mapping the original's category names to ours ($ItemActionFragment is our $ItemAct).
/// The 2018 corpus: templates are not compared (the original printed them as lambda formulas of
/// its own) and alignment rules are left out on both sides (the September runs had none; the
/// February runs' are reproduced, docs/naturalization.md §4.8, but not counted).
/// A studio recording logs each rule's `semantics` in our notation: then every rule, alignment
/// ones too, is compared as `lhs -> rhs => semantics` (docs/studio.md §7).

#include <string>
#include <vector>

#include "flipper/replay/corpus.hpp"

namespace flipper::replay {

/// One of our induced rules as the define answer reports it.
struct RuleShape {
  std::string lhs;
  std::vector<std::string> rhs;
  std::string semantics = {};  ///< the rule's template (canonical text)
  bool alignment = false;      ///< induced by alignment (docs/naturalization.md §4.8)
};

/// "identical" (same set of shapes), "subset" (ours a proper, non-empty subset of the
/// original's), "overlap" (some shape in common otherwise, e.g. we add one), "missing" (none in
/// common, or we induced nothing), or "" when the original logged no comparable rule.
std::string compare_rules(const std::vector<LoggedRule>& original,
                          const std::vector<RuleShape>& ours);

/// The rule-identity classes of a definition (docs/replay.md, induced-rule oracle), compared as
/// `lhs -> rhs` shapes like compare_rules but without the original's `KEYWORD_TOKEN` rules (its
/// lexer's entries for new words, no grammar rule: docs/naturalization.md §4.10):
/// "identical" (same set), "present" (ours a proper subset and every rule of the original we
/// did not induce was already in the author's view of our lexicon before the definition: an
/// earlier identical definition made it), "subset" (ours a proper subset otherwise, also when we
/// induced nothing or refused the definition), "superset", "overlap" (some in common, neither
/// contains the other), "disjoint" (we induced rules, none in common); "" when the original
/// logged no comparable rule. `action_hole`: the definition is not identical/present and some
/// rule of the original has an `$Action` category in its RHS while none of ours has.
struct RuleIdentity {
  std::string cls;
  bool action_hole = false;
};
RuleIdentity classify_rules(const std::vector<LoggedRule>& original,
                            const std::vector<RuleShape>& ours,
                            const std::vector<RuleShape>& present);

/// "lhs -> a $B c" with the original's category names mapped to ours.
std::string original_shape(const LoggedRule& rule);
std::string our_shape(const RuleShape& rule);

}  // namespace flipper::replay
