// The dictionary search of the wordnet plugin (plugins/wordnet/wordnet_db.hpp find_line): cached
// first probes and one read of the last kSearchWindow bytes find exactly the line the plain
// probe-by-probe binary search finds, for every key present and absent, on synthetic files on
// both sides of the window and on WordNet's own index; and a warm search costs one read.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "dict_file.hpp"
#include "wordnet_db.hpp"

namespace fs = std::filesystem;
using flipper::plugins::wordnet::DictFile;
using flipper::plugins::wordnet::find_line;
using flipper::plugins::wordnet::kSearchWindow;

namespace {

// The oracle: the search as it was before the probe cache and the window, one probe at a time.
std::string probe_by_probe(const DictFile& file, std::size_t start, std::string_view key) {
  std::size_t lo = start, hi = file.size();
  while (lo < hi) {
    const std::size_t s = file.line_start(lo + (hi - lo) / 2, lo);
    const std::string line = file.line_from(s);
    const int cmp = std::string_view(line).substr(0, line.find(' ')).compare(key);
    if (cmp == 0) return line;
    if (cmp < 0)
      lo = s + line.size() + 1;
    else
      hi = s;
  }
  return {};
}

struct SearchDir {
  fs::path dir = fs::temp_directory_path() / ("flipper-wn-search-" + std::to_string(::getpid()));
  SearchDir() {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~SearchDir() { fs::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    const auto path = (dir / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
};

// Checks find_line against the oracle for every key of `keys` and, around each, keys that are
// absent (just after it, a prefix of it, and four outside every range); returns the number of
// distinct keys of `keys` found.
int check_all(const DictFile& file, std::size_t start, const std::vector<std::string>& keys) {
  std::set<std::string> probes{"", "\x01", "~~~~", "\xff"};
  for (const auto& k : keys) {
    probes.insert(k);
    probes.insert(k + "!");
    probes.insert(k.substr(0, k.size() - 1));
  }
  for (const auto& k : probes) {
    INFO("key '" << k << "'");
    REQUIRE(find_line(file, start, k) == probe_by_probe(file, start, k));
  }
  int found = 0;
  for (const auto& k : std::set<std::string>(keys.begin(), keys.end()))
    found += find_line(file, start, k).rfind(k + " ", 0) == 0 ? 1 : 0;
  return found;
}

// A sorted file of lines "keyNNNNNN <payload>" of random payload lengths (one key in nine
// twice), exactly `bytes` long (at least 16: one line), the last line with or without its newline.
std::string sorted_text(std::size_t bytes, bool final_newline, unsigned seed,
                        std::vector<std::string>& keys) {
  std::mt19937 rng(seed);
  std::string text;
  for (int i = 0;; ++i) {
    const std::string key = "key" + std::to_string(100000 + i);
    const int copies = rng() % 9 == 0 ? 2 : 1;
    for (int c = 0; c < copies; ++c) {
      const std::string line =
          key + " " + std::string(5 + rng() % 70, static_cast<char>('a' + c)) + "\n";
      if (text.size() + line.size() > bytes) {
        if (text.empty()) {  // one line, its payload cut to the size
          text = key + " " + std::string(bytes - key.size() - 2, 'p') + "\n";
          keys.push_back(key);
        }
        // The last line's payload padded (before its newline) to the exact size.
        text.insert(text.size() - 1, bytes - text.size(), 'p');
        if (!final_newline) text.back() = 'z';
        return text;
      }
      text += line;
      keys.push_back(key);
    }
  }
}

}  // namespace

TEST_CASE("wordnet search: the same line as probe by probe, around the window's size",
          "[wordnet][search]") {
  SearchDir dir;
  for (std::size_t bytes : {std::size_t{16}, kSearchWindow - 1, kSearchWindow, kSearchWindow + 1,
                            2 * kSearchWindow + 1, 300 * kSearchWindow / 7})
    for (bool newline : {true, false}) {
      std::vector<std::string> keys;
      const std::string text = sorted_text(bytes, newline, static_cast<unsigned>(bytes), keys);
      REQUIRE(text.size() == bytes);
      DictFile file(dir.write("f" + std::to_string(bytes), text));
      INFO(bytes << " bytes, final newline " << newline);
      const int found = check_all(file, 0, keys);
      CHECK(found == static_cast<int>(std::set<std::string>(keys.begin(), keys.end()).size()));
      CHECK(file.cached_probes() <= DictFile::kProbes);
      // Small files are read in one piece, never probed.
      if (bytes <= kSearchWindow) CHECK(file.cached_probes() == 0);
      if (bytes > kSearchWindow) CHECK(file.cached_probes() > 0);
    }
}

TEST_CASE("wordnet search: the probes kept stop at the bound, for N and N + 1",
          "[wordnet][search]") {
  SearchDir dir;
  std::vector<std::string> keys;
  const std::string path = dir.write("big", sorted_text(64 * kSearchWindow, true, 7, keys));
  for (std::size_t bound : {std::size_t{0}, std::size_t{5}, std::size_t{6}}) {
    DictFile file(path, bound);
    INFO("at most " << bound << " probes");
    check_all(file, 0, keys);
    CHECK(file.cached_probes() == bound);
  }
  // Unbounded, a search of this file probes its top 6 levels: 63 probes at most.
  DictFile file(path, 1000);
  check_all(file, 0, keys);
  CHECK(file.cached_probes() == 63);
}

TEST_CASE("wordnet search: WordNet's noun index, and what a warm search reads",
          "[wordnet][search]") {
  const std::string index = "/usr/share/wordnet/index.noun";
  DictFile file(index);
  std::ifstream in(index);
  std::vector<std::string> keys;
  std::size_t start = 0, at = 0;
  int n = 0;
  for (std::string line; std::getline(in, line); at += line.size() + 1) {
    if (line.rfind("  ", 0) == 0) {  // the licence header
      start = at + line.size() + 1;
      continue;
    }
    if (n++ % 41 == 0) keys.push_back(line.substr(0, line.find(' ')));
  }
  REQUIRE(keys.size() > 2000);
  CHECK(check_all(file, start, keys) ==
        static_cast<int>(std::set<std::string>(keys.begin(), keys.end()).size()));
  CHECK(file.cached_probes() <= DictFile::kProbes);
  // Warm: the probes down to the window are cached; a search reads its window once (an
  // uncached deeper probe reads at most twice more: its line's start and the line).
  const std::size_t before = file.reads();
  CHECK(find_line(file, start, "robot").rfind("robot n ", 0) == 0);
  CHECK(file.reads() - before <= 3);
  const std::size_t again = file.reads();
  CHECK(find_line(file, start, "robot").rfind("robot n ", 0) == 0);
  CHECK(file.reads() - again == 1);
  CHECK(probe_by_probe(file, start, "robot") == find_line(file, start, "robot"));
}
