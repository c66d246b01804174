#pragma once
/// @file repair_hits.hpp
/// How often a repair's suggestions name what the user went on to say (docs/replay.md "Repair
/// suggestions"): for each query the original answered with no parse (`Nothing`) whose same
/// user's next accepted query comes within the user's next three queries of the run, is that
/// accepted sentence (its tokens) or its program (the original's accepted candidate, read as
/// core-language text) among our top three suggestions (QueryRow::suggestions of a replay with
/// ReplayOptions::repair)?

#include <cstddef>
#include <string>

#include "flipper/replay/corpus.hpp"
#include "flipper/replay/records.hpp"

namespace flipper::replay {

/// Queries the user's next accepted query is looked for in (after the failed one).
inline constexpr std::size_t kRepairFollowSteps = 3;
/// Suggestions compared.
inline constexpr std::size_t kRepairTopK = 3;

struct RepairHits {
  std::size_t cases = 0;             ///< original `Nothing`, an accepted query of the user follows
  std::size_t we_parse = 0;          ///< of them, queries we answer with candidates (no repair)
  std::size_t errors = 0;            ///< of them, queries we refused (an error code)
  std::size_t repaired = 0;          ///< of them, unparsable for us too: repairs asked for
  std::size_t with_suggestions = 0;  ///< repairs with at least one nearest sentence
  std::size_t hits = 0;              ///< repairs whose top three hold the accepted sentence
  std::size_t by_text = 0;           ///< hits by the sentence's tokens
  std::size_t by_program = 0;        ///< hits by the program only
};

/// Counts over a replay of `corpus` made with ReplayOptions::repair.
RepairHits repair_hits(const Corpus& corpus, const ReplayResult& result);

/// The figure block of docs and README: one Markdown table and the method in a sentence.
std::string repair_hits_text(const RepairHits& hits);

}  // namespace flipper::replay
