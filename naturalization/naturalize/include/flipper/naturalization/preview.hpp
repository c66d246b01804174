#pragma once
/// @file preview.hpp
/// Seeing a definition generalise before it counts (docs/naturalization.md §5 "Preview",
/// docs/protocol.md § define, `preview`): for each rule a definition would induce, a few new
/// sentences it makes understandable — the rule's holes filled with short phrases of the core
/// grammar, deterministically — each with the reading the rule gives it and what that reading
/// would do on the current world (a summary of the simulated run).

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/grammar.hpp"

namespace flipper::naturalization {

/// What running a program on a world did (a summary of sdk::Outcome).
struct PlanSummary {
  bool realizable = true;  ///< every primitive succeeded and nothing raised
  std::size_t moves = 0, picks = 0, drops = 0;
  std::optional<sdk::Cell> end;  ///< the robot's last cell (none: it did not move)
  std::vector<std::string> warnings;
  std::string error;  ///< the execution error (empty: none)
};
PlanSummary summarize(const sdk::Outcome& outcome);

/// One example sentence of a rule: its text and the reading the rule gives it.
struct ExampleSentence {
  std::string text;
  sdk::Program program;
};

/// An example sentence with what its reading would do on the current world.
struct PreviewSentence {
  std::string text;
  sdk::Program program;
  PlanSummary plan;       ///< on the session's world
  PlanSummary elsewhere;  ///< on the preview's other world (RulePreview's caller: `other`)
};

/// One rule a definition would induce: its preview id ("newK") and example sentences.
struct RulePreview {
  std::string id;
  std::vector<PreviewSentence> sentences;
};

/// Short phrases of every category of a grammar, with their meanings: for each category at most
/// kPhrasesPerCategory, shortest first (ties: the grammar's rule order), each at most
/// kMaxPhraseTokens tokens. Built once per grammar from its rules and word lists.
class PhraseBook {
 public:
  static constexpr std::size_t kPhrasesPerCategory = 4;
  static constexpr std::size_t kMaxPhraseTokens = 6;
  explicit PhraseBook(const sdk::Grammar& grammar);

  /// Up to `count` sentences of `rule` other than `head` (the phrase it was induced from): the
  /// i-th fills every hole with its category's i-th phrase (wrapping), duplicates skipped. A rule
  /// without holes has none. Its reading is the rule's template applied to the phrases' meanings.
  std::vector<ExampleSentence> examples(const sdk::Rule& rule, const std::string& head,
                                        std::size_t count) const;

 private:
  struct Phrase {
    std::vector<std::string> tokens;
    sdk::Program program;
  };
  const std::vector<Phrase>* phrases_of(const std::string& category) const;
  std::map<std::string, std::vector<Phrase>> by_category_;
};

}  // namespace flipper::naturalization
