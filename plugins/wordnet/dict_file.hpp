#pragma once
/// @file dict_file.hpp
/// A read-only WordNet dictionary file, read in place with positioned reads (pread): the
/// binary searches and synset look-ups touch a few hundred bytes each, which then live in the
/// kernel's page cache, shared by every process, and never in this one's resident set. (A
/// memory map was shared too, but every page it faulted in, with the kernel's fault-around,
/// counted as this process's memory: ~16 MiB over one study run.)

#include <cstddef>
#include <string>

namespace flipper::plugins::wordnet {

class DictFile {
 public:
  /// Opens `path`; throws sdk::Error(bad_config) if it cannot be opened.
  explicit DictFile(const std::string& path);
  ~DictFile();
  DictFile(const DictFile&) = delete;
  DictFile& operator=(const DictFile&) = delete;

  std::size_t size() const { return size_; }
  /// The bytes from `start` to the next newline (excluded) or the end of the file.
  std::string line_from(std::size_t start) const;
  /// The first byte after the last newline in [lo, pos), or `lo` if there is none: the start
  /// of the line holding `pos` when lines before `lo` do not matter.
  std::size_t line_start(std::size_t pos, std::size_t lo) const;

 private:
  /// Reads [at, at + n) (clamped to the file); throws sdk::Error(internal) on a read error.
  std::size_t read(std::size_t at, char* buf, std::size_t n) const;

  int fd_ = -1;
  std::string path_;
  std::size_t size_ = 0;
};

}  // namespace flipper::plugins::wordnet
