#pragma once
/// @file repair.hpp (the session side: repair_extension.hpp)
/// Answers that repair a query the parser did not understand (docs/protocol.md § "Repairs"):
/// from the parser's own chart of the utterance, the longest sub-phrases it understood (spans
/// that derive the root category), the words no understood phrase covers (unknown to the
/// grammar, or known but misplaced), the nearest understood sentences (small edits at those
/// words, each parsed again, best parse first) and a ready definition that teaches the sentence.
/// The work is bounded by counts, never by wall time: at most kMaxRepairParses edited sentences
/// are parsed, and only for utterances of at most kMaxRepairTokens tokens.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/derivation.hpp"

namespace flipper::naturalization {

/// Edited sentences parsed per repair at most (the rest are not tried: `limited` says so).
inline constexpr std::size_t kMaxRepairParses = 48;
/// Longer utterances get the understood phrases and words only, no edited sentences.
inline constexpr std::size_t kMaxRepairTokens = 64;
/// Nearest sentences kept.
inline constexpr std::size_t kRepairSuggestions = 3;

/// A sub-phrase the parser understood: tokens [start, end) derive the root category.
struct UnderstoodPhrase {
  int start = 0, end = 0;
  std::string text;      ///< its tokens, space-separated
  sdk::Program program;  ///< its best reading
};

/// A word no understood phrase covers.
struct RepairWord {
  int at = 0;  ///< token index
  std::string word;
  bool known = false;        ///< a word of the grammar or lexicon (then it is misplaced)
  std::string did_you_mean;  ///< the closest known word for an unknown one ("" when none)
};

/// An understood sentence near the utterance.
struct NearSentence {
  std::string text;  ///< its tokens, space-separated
  sdk::Program program;
  double score = 0;  ///< the parser's score of that reading
  int edits = 0;     ///< words dropped, replaced, merged or inserted
  std::string edit;  ///< what was changed: "drop 'x'", "replace 'vist' by 'visit'", ...
};

struct Repair {
  std::vector<UnderstoodPhrase> understood;  ///< longest first, then left to right
  std::vector<RepairWord> words;             ///< left to right
  std::vector<NearSentence> nearest;         ///< fewest edits first, then best score
  /// A definition the user could send: head (the utterance) and body lines (the understood
  /// phrases left to right, else the nearest sentence); empty body: no suggestion.
  std::string teach_head;
  std::vector<std::string> teach_body;
  std::string limited;     ///< why fewer sentences were tried ("" when none was left out)
  std::size_t parses = 0;  ///< edited sentences parsed
};

/// What a repair needs from the session.
struct RepairInput {
  std::string text;                       ///< the utterance as typed
  std::vector<std::string> tokens;        ///< its tokens
  std::vector<sdk::DerivationPtr> chart;  ///< every derivation of every proper sub-span
  std::string root = "$ROOT";             ///< the grammar's root category
  std::vector<std::string> vocabulary;    ///< known words (sorted, unique)
  /// Parses an edited sentence: its candidates, best first (empty: not understood).
  std::function<std::vector<sdk::Candidate>(const std::vector<std::string>& tokens)> parse;
};

/// The repair of an utterance without a parse.
Repair find_repair(const RepairInput& input);

}  // namespace flipper::naturalization
