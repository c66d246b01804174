#pragma once
/// @file word_similarity.hpp
/// Wu–Palmer similarity of words over WordNet's hypernym graph, with caches so that repeated
/// words (the generalizer compares one head with many candidates) cost a hash lookup.

#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "wordnet_db.hpp"

namespace flipper::plugins::wordnet {

class WordSimilarity {
 public:
  explicit WordSimilarity(const WordNetDb& db) : db_(db) {}

  /// 1 for identical words; for nouns and verbs the best Wu–Palmer score over the two words'
  /// synsets, 2·depth(lcs) / (dist(s1,lcs) + dist(s2,lcs) + 2·depth(lcs)) with depth counted
  /// from 1 at a root; adjectives and adverbs score 1 when they share a synset. Unknown: 0.
  /// Thread-safe.
  double operator()(std::string_view a, std::string_view b) const;

 private:
  using Closure = std::vector<std::pair<std::uint32_t, int>>;  // ancestor, distance; sorted
  static std::uint64_t key(std::uint32_t offset, Pos pos) {
    return (static_cast<std::uint64_t>(pos) << 32) | offset;
  }
  const Closure& closure(std::uint32_t offset, Pos pos) const;
  int depth(std::uint32_t offset, Pos pos) const;
  const std::vector<std::uint32_t>& synsets(const std::string& word, Pos pos) const;
  double synset_score(std::uint32_t a, std::uint32_t b, Pos pos) const;
  double compute(const std::string& a, const std::string& b) const;

  const WordNetDb& db_;
  mutable std::mutex mutex_;
  mutable std::unordered_map<std::uint64_t, Closure> closures_;
  mutable std::unordered_map<std::uint64_t, int> depths_;
  mutable std::unordered_map<std::string, std::vector<std::uint32_t>> synsets_[4];
  mutable std::unordered_map<std::string, double> pairs_;
};

}  // namespace flipper::plugins::wordnet
