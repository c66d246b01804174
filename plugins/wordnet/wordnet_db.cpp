#include "wordnet_db.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <utility>

#include "flipper/sdk/errors.hpp"

namespace flipper::plugins::wordnet {

namespace {

constexpr const char* kPosName[] = {"noun", "verb", "adj", "adv"};

// WordNet's detachment rules (morph.c), per part of speech.
const std::vector<std::pair<std::string_view, std::string_view>> kRules[] = {
    {{"s", ""},
     {"ses", "s"},
     {"xes", "x"},
     {"zes", "z"},
     {"ches", "ch"},
     {"shes", "sh"},
     {"men", "man"},
     {"ies", "y"}},
    {{"s", ""},
     {"ies", "y"},
     {"es", "e"},
     {"es", ""},
     {"ed", "e"},
     {"ed", ""},
     {"ing", "e"},
     {"ing", ""}},
    {{"er", ""}, {"est", ""}, {"er", "e"}, {"est", "e"}},
    {},
};

// Splits a line into space-separated fields.
std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && line[i] == ' ') ++i;
    const std::size_t s = i;
    while (i < line.size() && line[i] != ' ') ++i;
    if (i > s) out.push_back(line.substr(s, i - s));
  }
  return out;
}

template <class T>
bool parse(std::string_view s, T& out, int base = 10) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out, base);
  return ec == std::errc() && p == s.data() + s.size();
}

// The probe of [lo, hi) in `window`, the file's bytes from `base` on, as DictFile::probe finds it
// in the file: [lo, hi) holds whole lines, so the byte before lo (when in the window) is a newline.
DictFile::Probe probe_in(std::string_view window, std::size_t base, std::size_t lo,
                         std::size_t hi) {
  const std::size_t mid = lo + (hi - lo) / 2 - base;
  const std::size_t nl = window.substr(0, mid).rfind('\n');
  DictFile::Probe p;
  p.start = base + (nl == std::string_view::npos ? 0 : nl + 1);
  const std::size_t from = p.start - base, end = window.find('\n', from);
  const std::string_view line =
      window.substr(from, end == std::string_view::npos ? std::string_view::npos : end - from);
  p.length = line.size();
  p.key = std::string(line.substr(0, line.find(' ')));
  return p;
}

}  // namespace

// The probes of a search over the whole text: each probe's line starts after the last newline
// before its middle, so [lo, hi) always holds whole lines. The first levels' probes come from the
// file's probe cache; once the range is at most kSearchWindow bytes it is read at once and the
// same probes are made in memory, so the line found is the one a probe-by-probe search finds.
std::string find_line(const DictFile& file, std::size_t start, std::string_view key) {
  std::size_t lo = start, hi = file.size();
  std::string window;  // once read: the file's bytes [base, hi) of the range then left
  std::size_t base = 0;
  bool in_window = false;
  while (lo < hi) {
    if (!in_window && hi - lo <= kSearchWindow) {
      window = file.range(lo, hi);
      base = lo;
      in_window = true;
    }
    const DictFile::Probe p = in_window ? probe_in(window, base, lo, hi) : file.probe(lo, hi);
    const int cmp = std::string_view(p.key).compare(key);
    if (cmp == 0)
      return in_window ? window.substr(p.start - base, p.length) : file.line_from(p.start);
    if (cmp < 0)
      lo = p.start + p.length + 1;
    else
      hi = p.start;
  }
  return {};
}

WordNetDb::WordNetDb(std::string dir) : dir_(std::move(dir)) {
  const auto probe = std::filesystem::path(dir_) / "index.noun";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(probe, ec))
    throw sdk::Error(sdk::codes::kBadConfig,
                     "wordnet: no WordNet dictionary in '" + dir_ +
                         "' (index.noun missing; on Debian install the wordnet-base package)");
}

WordNetDb::~WordNetDb() = default;

const WordNetDb::Files& WordNetDb::files(Pos pos) const {
  Files& f = files_[static_cast<std::size_t>(pos)];
  std::call_once(f.once, [&] {
    const std::string name = kPosName[static_cast<std::size_t>(pos)];
    f.index = std::make_unique<DictFile>(dir_ + "/index." + name);
    f.data = std::make_unique<DictFile>(dir_ + "/data." + name);
    f.exceptions = std::make_unique<DictFile>(dir_ + "/" + name + ".exc");
    // The licence header's lines start with two spaces.
    std::size_t s = 0;
    for (std::string line;
         s < f.index->size() && !(line = f.index->line_from(s)).empty() && line[0] == ' ';)
      s = std::min(f.index->size(), s + line.size() + 1);
    f.index_start = s;
  });
  return f;
}

void WordNetDb::lemma_synsets(const Files& f, std::string_view lemma,
                              std::vector<std::uint32_t>& out) const {
  const std::string line = find_line(*f.index, f.index_start, lemma);
  const auto parts = fields(line);
  // lemma pos synset_cnt p_cnt [ptr_symbol...] sense_cnt tagsense_cnt synset_offset...
  std::size_t synset_count = 0, pointer_count = 0;
  if (parts.size() < 4 || !parse(parts[2], synset_count) || !parse(parts[3], pointer_count)) return;
  const std::size_t first = 4 + pointer_count + 2;
  for (std::size_t i = first; i < parts.size() && i < first + synset_count; ++i) {
    std::uint32_t offset = 0;
    if (parse(parts[i], offset) && std::find(out.begin(), out.end(), offset) == out.end())
      out.push_back(offset);
  }
}

std::vector<std::uint32_t> WordNetDb::synsets(std::string_view word, Pos pos) const {
  std::vector<std::uint32_t> out;
  if (word.empty() || word.find('\n') != std::string_view::npos) return out;
  const Files& f = files(pos);
  lemma_synsets(f, word, out);
  // Irregular forms ("mice mouse").
  const std::string exc_line = find_line(*f.exceptions, 0, word);
  const auto exc = fields(exc_line);
  for (std::size_t i = 1; i < exc.size(); ++i) lemma_synsets(f, exc[i], out);
  for (const auto& [suffix, ending] : kRules[static_cast<std::size_t>(pos)]) {
    if (word.size() <= suffix.size() || !word.ends_with(suffix)) continue;
    std::string base(word.substr(0, word.size() - suffix.size()));
    base += ending;
    lemma_synsets(f, base, out);
  }
  return out;
}

std::vector<std::uint32_t> WordNetDb::hypernyms(std::uint32_t offset, Pos pos) const {
  std::vector<std::uint32_t> out;
  const DictFile& data = *files(pos).data;
  if (offset >= data.size()) return out;
  const std::string line = data.line_from(offset);
  const auto parts = fields(line);
  // offset lex_filenum ss_type w_cnt(hex) [word lex_id]... p_cnt [symbol offset pos src/tgt]...
  std::size_t words = 0, pointers = 0;
  if (parts.size() < 4 || !parse(parts[3], words, 16)) return out;
  const std::size_t p = 4 + 2 * words;
  if (p >= parts.size() || !parse(parts[p], pointers)) return out;
  const char pos_char = "nvar"[static_cast<std::size_t>(pos)];
  for (std::size_t i = 0; i < pointers && p + 4 + 4 * i <= parts.size(); ++i) {
    const auto symbol = parts[p + 1 + 4 * i];
    const auto target_pos = parts[p + 3 + 4 * i];
    std::uint32_t target = 0;
    if ((symbol == "@" || symbol == "@i") && target_pos.size() == 1 && target_pos[0] == pos_char &&
        parse(parts[p + 2 + 4 * i], target))
      out.push_back(target);
  }
  return out;
}

}  // namespace flipper::plugins::wordnet
