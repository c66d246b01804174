#include "word_vectors.hpp"

#include <charconv>
#include <fstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::plugins::glove {

namespace {

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

bool is_integer(std::string_view s) {
  long v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}

[[noreturn]] void bad(const std::string& path, std::size_t line, const std::string& what) {
  throw sdk::Error(sdk::codes::kBadConfig,
                   "glove: " + path + ":" + std::to_string(line) + ": " + what);
}

}  // namespace

WordVectors WordVectors::load(const std::string& path, std::size_t max_words) {
  std::ifstream in(path);
  if (!in)
    throw sdk::Error(sdk::codes::kBadConfig, "glove: cannot open word vector file '" + path + "'");
  WordVectors table;
  std::string line;
  std::size_t line_no = 0;
  std::vector<std::string_view> fields;
  while (std::getline(in, line)) {
    ++line_no;
    fields = split(line);
    if (fields.empty()) continue;
    if (line_no == 1 && fields.size() == 2 && is_integer(fields[0]) && is_integer(fields[1]))
      continue;  // word2vec header
    if (table.dims_ == 0) {
      if (fields.size() < 2) bad(path, line_no, "expected a word followed by its vector");
      table.dims_ = fields.size() - 1;
    }
    if (fields.size() < table.dims_ + 1)
      bad(path, line_no,
          "expected " + std::to_string(table.dims_) + " components, got " +
              std::to_string(fields.size() - 1));
    // A few published files have words containing spaces: the components are the last fields.
    const std::size_t word_fields = fields.size() - table.dims_;
    const char* word_end = fields[word_fields - 1].data() + fields[word_fields - 1].size();
    std::string word(fields[0].data(), static_cast<std::size_t>(word_end - fields[0].data()));
    const auto row = static_cast<std::uint32_t>(table.index_.size());
    if (!table.index_.emplace(std::move(word), row).second) continue;  // first occurrence wins
    for (std::size_t i = word_fields; i < fields.size(); ++i) {
      float v = 0;
      auto [p, ec] = std::from_chars(fields[i].data(), fields[i].data() + fields[i].size(), v);
      if (ec != std::errc() || p != fields[i].data() + fields[i].size())
        bad(path, line_no, "'" + std::string(fields[i]) + "' is not a number");
      table.data_.push_back(v);
    }
    if (max_words > 0 && table.index_.size() >= max_words) break;
  }
  if (table.index_.empty())
    throw sdk::Error(sdk::codes::kBadConfig, "glove: no word vectors in '" + path + "'");
  return table;
}

const float* WordVectors::find(std::string_view word) const {
  auto it = index_.find(std::string(word));
  return it == index_.end() ? nullptr : data_.data() + static_cast<std::size_t>(it->second) * dims_;
}

}  // namespace flipper::plugins::glove
