#pragma once
/// @file dict_file.hpp
/// A read-only WordNet dictionary file, read in place with positioned reads (pread): the
/// binary searches and synset look-ups touch a few hundred bytes each, which then live in the
/// kernel's page cache, shared by every process, and never in this one's resident set. (A
/// memory map was shared too, but every page it faulted in, with the kernel's fault-around,
/// counted as this process's memory: ~16 MiB over one study run.)

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <unordered_map>

namespace flipper::plugins::wordnet {

class DictFile {
 public:
  /// Opens `path`; throws sdk::Error(bad_config) if it cannot be opened. Keeps up to
  /// `max_probes` probes (below).
  explicit DictFile(const std::string& path, std::size_t max_probes = kProbes);
  ~DictFile();
  DictFile(const DictFile&) = delete;
  DictFile& operator=(const DictFile&) = delete;

  std::size_t size() const { return size_; }
  /// The bytes from `start` to the next newline (excluded) or the end of the file.
  std::string line_from(std::size_t start) const;
  /// The first byte after the last newline in [lo, pos), or `lo` if there is none: the start
  /// of the line holding `pos` when lines before `lo` do not matter.
  std::size_t line_start(std::size_t pos, std::size_t lo) const;
  /// The bytes [lo, hi) (clamped to the file), in one read.
  std::string range(std::size_t lo, std::size_t hi) const;

  /// The probe of a binary search over the lines in [lo, hi): the line holding the middle
  /// byte, its start, length (no newline) and key (the text before its first space). The
  /// probes of the first levels are the same for every search of a file, so up to kProbes of
  /// them (the constructor's `max_probes`) are kept: a search then reads only its last, narrow
  /// range (wordnet_db.cpp). ~50 bytes each: at most ~200 KiB a file.
  struct Probe {
    std::size_t start = 0, length = 0;
    std::string key;
  };
  Probe probe(std::size_t lo, std::size_t hi) const;
  static constexpr std::size_t kProbes = 4096;
  /// Probes kept, and positioned reads made so far (what a search costs, for the tests).
  std::size_t cached_probes() const {
    std::lock_guard<std::mutex> lock(probes_mutex_);
    return probes_.size();
  }
  std::size_t reads() const { return reads_.load(std::memory_order_relaxed); }

 private:
  /// Reads [at, at + n) (clamped to the file); throws sdk::Error(internal) on a read error.
  std::size_t read(std::size_t at, char* buf, std::size_t n) const;

  int fd_ = -1;
  std::string path_;
  std::size_t size_ = 0;
  std::size_t max_probes_;
  mutable std::atomic<std::size_t> reads_{0};
  mutable std::mutex probes_mutex_;
  mutable std::unordered_map<std::uint64_t, Probe> probes_;  // by lo << 32 | hi
};

}  // namespace flipper::plugins::wordnet
