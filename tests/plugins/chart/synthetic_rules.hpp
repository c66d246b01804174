#pragma once
// Synthetic induced rules for the rule-index tests: seeded, over a given vocabulary, in shapes that
// take every path of the index (docs/naturalization.md §2, "Rule selection"): token-first with
// and without an anchor, a token repeated, a single token, category-first with and without an
// anchor. (The grammar reader allows a token class only as a whole RHS: class-first rules are
// the core grammar's.) Rules are written as grammar lines and read by the SDK's grammar reader, so
// they are exactly what a grammar file or the lexicon would give the parser.
#include <algorithm>
#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/grammar.hpp"

namespace flipper::indextest {

/// The induced rule `lhs -> rhs => sem` as the lexicon would hand it over.
inline sdk::RulePtr induced_rule(const std::string& line, const std::string& id,
                                 std::int64_t created, const std::string& author) {
  sdk::Grammar g =
      sdk::parse_grammar(line + "\n", "synthetic", {"red", "blue", "green"}, {"circle", "square"});
  auto r = std::make_shared<sdk::Rule>(*g.rules.at(0));
  r->id = id;
  r->induced = true;
  r->how = sdk::RuleOrigin::best;
  r->created = created;
  r->author = author;
  return r;
}

/// One grammar line of shape `shape` (0-9) over words drawn by `word()`.
template <class Word>
std::string synthetic_line(int shape, Word&& word) {
  const std::string a = word(), b = word(), c = word();
  switch (shape) {
    case 0:
      return "$Action -> " + a + " $Action " + b + " => {repeat 2 times $1}";
    case 1:
      return "$Action -> " + a + " " + b + " => {move left}";
    case 2:
      return "$Action -> " + a + " => {pick item}";  // a single token: no anchor
    case 3:
      return "$Action -> " + a + " $Area => {visit $1}";  // no token after the first: no anchor
    case 4:
      return "$Action -> $Action " + a + " $Action => {$1;$2}";  // category-first, anchor a
    case 5:
      return "$Action -> $Number " + a + " " + b + " => {repeat $1 times {move right}}";
    case 6:
      return "$Action -> $Number " + a + " $Action => {repeat $1 times $2}";
    case 7:
      return "$Action -> " + a + " " + b + " " + a + " $Action => {strict $1}";  // repeated token
    case 8:
      return "$Action -> $Color " + a + " => {visit {world containing item {is $1}}}";
    default:
      return "$Action -> " + a + " $Direction " + b + " " + c + " => {move $1}";
  }
}

/// `n` induced rules, ids "s1".."sN", created 1..N, authors u0..u4 in turn. Each word is one of
/// `words` with probability min(1, 1000 / n), else a made-up one (`z0`, `z1`, ... from a pool of
/// n / 8): as the lexicon grows, the rules a query can use stay about as many as with 1,000
/// rules (a big lexicon is mostly rules about other things), which is what the index is for.
inline std::vector<sdk::RulePtr> synthetic_rules(int n, const std::vector<std::string>& words,
                                                 std::uint32_t seed) {
  std::mt19937 rng(seed);
  const double known = std::min(1.0, 1000.0 / std::max(n, 1));
  const std::uint32_t pool = static_cast<std::uint32_t>(std::max(n / 8, 1));
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  auto word = [&] {
    return coin(rng) < known ? words[rng() % words.size()] : "z" + std::to_string(rng() % pool);
  };
  std::vector<sdk::RulePtr> rules;
  rules.reserve(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    rules.push_back(induced_rule(synthetic_line(k % 10, word), "s" + std::to_string(k + 1), k + 1,
                                 "u" + std::to_string(k % 5)));
  return rules;
}

/// The dev corpus's distinct query utterances, in corpus order.
inline std::vector<std::string> dev_utterances() {
  std::ifstream in(std::string(FLIPPER_STUDY_DIR) + "/dev/queries.jsonl");
  if (!in) throw std::runtime_error("no dev corpus under " + std::string(FLIPPER_STUDY_DIR));
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line);
    if (j.value("kind", "") == "q" && j["utterance"].is_string() &&
        seen.insert(j["utterance"].get<std::string>()).second)
      out.push_back(j["utterance"].get<std::string>());
  }
  return out;
}

/// The `count` most frequent lower-case words of the utterances (ties: alphabetical), so that
/// synthetic rules match real queries often.
inline std::vector<std::string> frequent_words(const std::vector<std::string>& utterances,
                                               std::size_t count) {
  std::map<std::string, int> freq;
  for (const auto& u : utterances)
    for (const auto& t : sdk::tokenize(u)) {
      bool word = !t.empty();
      for (char ch : t) word = word && ch >= 'a' && ch <= 'z';
      if (word) ++freq[t];
    }
  std::vector<std::pair<int, std::string>> order;
  for (const auto& [w, f] : freq) order.emplace_back(-f, w);
  std::sort(order.begin(), order.end());
  std::vector<std::string> out;
  for (std::size_t k = 0; k < order.size() && k < count; ++k) out.push_back(order[k].second);
  return out;
}

}  // namespace flipper::indextest
