#pragma once
/// @file wordnet_db.hpp
/// Read access to a WordNet 3.0 dictionary directory (Debian's `wordnet-base`:
/// /usr/share/wordnet/{index,data}.{noun,verb,adj,adv} and *.exc). Files are opened on first
/// use and searched in place with positioned reads (dict_file.hpp): index and exception files
/// by binary search (they are sorted bytewise after the licence header), data files by the
/// synset's byte offset.

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "dict_file.hpp"

namespace flipper::plugins::wordnet {

/// Binary search of a bytewise-sorted file of lines "key ...", from byte `start` (a line start)
/// on: a line whose key (the text before its first space) is `key`, or "" when there is none.
/// Once the range left is at most kSearchWindow bytes it is read at once (wordnet_db.cpp).
std::string find_line(const DictFile& file, std::size_t start, std::string_view key);
inline constexpr std::size_t kSearchWindow = 8192;

enum class Pos : std::uint8_t { noun = 0, verb = 1, adj = 2, adv = 3 };

class WordNetDb {
 public:
  /// Throws sdk::Error(bad_config) if `dir` has no readable index.noun.
  explicit WordNetDb(std::string dir);
  ~WordNetDb();

  /// Synset offsets of `word` in `pos`, for the word itself and every base form WordNet's
  /// morphology (exception lists, then suffix rules) finds; no duplicates.
  std::vector<std::uint32_t> synsets(std::string_view word, Pos pos) const;
  /// Hypernyms and instance hypernyms of a synset (same part of speech).
  std::vector<std::uint32_t> hypernyms(std::uint32_t offset, Pos pos) const;

 private:
  struct Files {
    std::once_flag once;
    std::unique_ptr<DictFile> index, data, exceptions;
    std::size_t index_start = 0;  // first byte after the licence header
  };
  const Files& files(Pos pos) const;
  void lemma_synsets(const Files& f, std::string_view lemma, std::vector<std::uint32_t>& out) const;

  std::string dir_;
  mutable std::array<Files, 4> files_;
};

}  // namespace flipper::plugins::wordnet
