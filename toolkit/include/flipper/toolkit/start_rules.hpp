#pragma once
// Per parse: the non-unary rules worth trying from each position of the utterance
// (docs/naturalization.md §2, "Rule selection"). A rule can only match from position i if its
// first symbol fits token i, it is no longer than the rest of the utterance, and every later RHS
// token or class k occurs at or after position i + k (each symbol covers at least one token; the
// floating parser's skipped words only widen the gaps). The index hands out the rules whose anchor
// occurs after i, so the work grows with the rules the utterance could use, not with the lexicon.
// Each list is in rule order, the order the unindexed matcher tried them in, so derivations,
// their order and ties come out exactly as before. `exhaustive` scans every rule instead: the
// unindexed matcher, kept as the oracle of the index tests.
#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "flipper/sdk/parser.hpp"
#include "flipper/toolkit/rule_index.hpp"

namespace flipper::toolkit {

class StartRules {
 public:
  using Visible = sdk::RuleFilter;
  /// `token_ids`/`classes`: per utterance token, as RuleIndex::token_id / classes_of.
  StartRules(const RuleIndex& index, const std::vector<int>& token_ids,
             const std::vector<std::uint8_t>& classes, const Visible& visible, bool exhaustive);

  /// The alive, visible rules whose first symbol is `first` (kind as in RuleIndex::bucket) that
  /// may match from position i, ascending. Computed once per (i, kind, first) and parse; the
  /// span is valid until the next call.
  std::span<const int> at(int i, FirstKind kind, int first);
  /// Whether the request's visibility filter admits the rule (memoised; for unary rules).
  bool visible(int rule);

 private:
  bool fits_after(const CompiledRule& rule, int i) const;
  int last_position(int token) const;
  void scan_all();

  const RuleIndex& index_;
  const Visible visible_fn_;
  const bool exhaustive_;
  const int n_;
  struct List {
    std::uint32_t key, begin, size;  // key: kind and first symbol
  };
  std::vector<std::pair<int, int>> last_at_;  ///< (token id, last position), by token id
  std::vector<std::pair<int, int>> anchors_;  ///< the entries of last_at_ that anchor rules
  std::vector<std::uint8_t> classes_from_;    ///< class bits of the tokens [p, n), per p
  std::vector<std::vector<List>> lists_;      ///< per position: the lists computed, in pool_
  std::vector<int> pool_;
  std::unordered_map<int, bool> visible_;
  std::unordered_map<std::uint32_t, std::vector<int>> all_;  ///< exhaustive: rules by first symbol
};

}  // namespace flipper::toolkit
