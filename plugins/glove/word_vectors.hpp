#pragma once
/// @file word_vectors.hpp
/// A table of word vectors read from GloVe or word2vec text files: one word per line followed
/// by its components; word2vec's "<count> <dims>" header line is recognised and skipped.
/// Stored flat (one float array, words mapped to row numbers).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace flipper::plugins::glove {

class WordVectors {
 public:
  /// Reads `path`. `max_words` > 0 keeps only the first that many words (files are usually
  /// sorted by frequency). Throws sdk::Error(bad_config) naming the file and line on bad input.
  static WordVectors load(const std::string& path, std::size_t max_words = 0);

  std::size_t dims() const { return dims_; }
  std::size_t size() const { return index_.size(); }
  /// The word's vector, or null if unknown.
  const float* find(std::string_view word) const;

 private:
  std::size_t dims_ = 0;
  std::vector<float> data_;
  std::unordered_map<std::string, std::uint32_t> index_;
};

}  // namespace flipper::plugins::glove
