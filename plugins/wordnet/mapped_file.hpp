#pragma once
/// @file mapped_file.hpp
/// A read-only memory-mapped file: WordNet's dictionary files are searched in place, so only
/// the pages actually touched are read and nothing is copied into the heap.

#include <cstddef>
#include <string>
#include <string_view>

namespace flipper::plugins::wordnet {

class MappedFile {
 public:
  /// Maps `path`; throws sdk::Error(bad_config) if it cannot be opened.
  explicit MappedFile(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  std::string_view text() const { return {data_, size_}; }

 private:
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace flipper::plugins::wordnet
