// Repairs of utterances without a parse (repair.hpp, docs/protocol.md § "Repairs"): understood
// phrases and uncovered words from the chart, edited sentences parsed again.
#include "flipper/naturalization/repair.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <set>
#include <utility>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/param_check.hpp"

namespace flipper::naturalization {
namespace {

std::string join(const std::vector<std::string>& tokens, std::size_t from, std::size_t to) {
  std::string s;
  for (std::size_t i = from; i < to; ++i) s += (i > from ? " " : "") + tokens[i];
  return s;
}

std::string join(const std::vector<std::string>& tokens) {
  return join(tokens, 0, tokens.size());
}

// The closest known word of `word` (sdk::did_you_mean's rule), "" when none is close.
std::string closest(const std::string& word, const std::vector<std::string>& vocabulary) {
  const std::string hint = sdk::did_you_mean(word, vocabulary);  // " (did you mean 'x'?)"
  const auto open = hint.find('\'');
  const auto close = hint.rfind('\'');
  return open == std::string::npos || close <= open ? std::string()
                                                    : hint.substr(open + 1, close - open - 1);
}

// Single edits combined in pairs at most (16 * 15 / 2 = 120 pairs to order).
constexpr std::size_t kMaxPairedEdits = 16;

bool alphanumeric(const std::string& s) {
  return !s.empty() &&
         std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isalnum(c) != 0; });
}

// The best root derivation of each span [start, end) whose reading binds its loop variables.
std::map<std::pair<int, int>, sdk::DerivationPtr> root_spans(const RepairInput& in) {
  std::map<std::pair<int, int>, sdk::DerivationPtr> best;
  for (const auto& d : in.chart) {
    if (!d || !d->rule || d->rule->lhs != in.root || !sdk::loop_variables_bound(d->sem)) continue;
    auto& slot = best[{d->start, d->end}];
    if (!slot || d->score > slot->score) slot = d;
  }
  return best;
}

// One edited sentence to try.
struct EditedSentence {
  std::vector<std::string> tokens;
  int edits = 0;
  std::string what;
  bool whole = false;  ///< drops every uncovered word at once: parsed before the small edits
};

// A single-word edit at `at`: drop (no words), replace, or merge with the next word (`span` 2).
struct WordEdit {
  int at = 0, span = 1;
  std::vector<std::string> words;
  std::string what;
};

std::vector<std::string> apply(const std::vector<std::string>& tokens,
                               const std::vector<const WordEdit*>& edits) {
  std::vector<std::string> out;
  std::size_t e = 0;
  for (int i = 0; i < static_cast<int>(tokens.size());) {
    if (e < edits.size() && edits[e]->at == i) {
      out.insert(out.end(), edits[e]->words.begin(), edits[e]->words.end());
      i += edits[e]->span;
      ++e;
    } else {
      out.push_back(tokens[static_cast<std::size_t>(i)]);
      ++i;
    }
  }
  return out;
}

}  // namespace

Repair find_repair(const RepairInput& in) {
  Repair r;
  const auto& tokens = in.tokens;
  const int n = static_cast<int>(tokens.size());
  if (n == 0) return r;

  // Understood phrases: root spans no other root span contains.
  const auto roots = root_spans(in);
  for (const auto& root : roots) {
    const std::pair<int, int>& span = root.first;
    const bool inside = std::any_of(roots.begin(), roots.end(), [&span](const auto& other) {
      return other.first != span && other.first.first <= span.first &&
             span.second <= other.first.second;
    });
    if (!inside)
      r.understood.push_back({span.first, span.second,
                              join(tokens, static_cast<std::size_t>(span.first),
                                   static_cast<std::size_t>(span.second)),
                              root.second->sem});
  }
  std::stable_sort(r.understood.begin(), r.understood.end(), [](const auto& a, const auto& b) {
    return a.end - a.start != b.end - b.start ? a.end - a.start > b.end - b.start
                                              : a.start < b.start;
  });

  // Words no understood phrase covers; a word is known when the vocabulary or a one-word
  // derivation of the chart (a class word: a colour, a number) has it.
  std::vector<bool> covered(static_cast<std::size_t>(n), false), derived(covered);
  for (const auto& p : r.understood)
    for (int i = p.start; i < p.end; ++i) covered[static_cast<std::size_t>(i)] = true;
  for (const auto& d : in.chart)
    if (d && d->end == d->start + 1) derived[static_cast<std::size_t>(d->start)] = true;
  std::vector<int> uncovered;
  for (int i = 0; i < n; ++i) {
    const auto at = static_cast<std::size_t>(i);
    if (covered[at]) continue;
    uncovered.push_back(i);
    RepairWord w;
    w.at = i;
    w.word = tokens[at];
    w.known = derived[at] || sdk::number_value(w.word).has_value() ||
              std::binary_search(in.vocabulary.begin(), in.vocabulary.end(), w.word);
    if (!w.known) w.did_you_mean = closest(w.word, in.vocabulary);
    r.words.push_back(std::move(w));
  }

  // Teach it: the understood phrases that tile the utterance left to right, longest first.
  for (int at = 0; at < n;) {
    const UnderstoodPhrase* next = nullptr;
    for (const auto& p : r.understood)
      if (p.start >= at && (next == nullptr || p.start < next->start ||
                            (p.start == next->start && p.end > next->end)))
        next = &p;
    if (next == nullptr) break;
    r.teach_body.push_back(next->text);
    at = next->end;
  }
  r.teach_head = in.text;

  if (!in.parse) return r;
  if (static_cast<std::size_t>(n) > kMaxRepairTokens) {
    r.limited = "the utterance has " + std::to_string(n) +
                " tokens; edited sentences are tried for " + std::to_string(kMaxRepairTokens) +
                " at most";
    return r;
  }

  // Single-word edits at the uncovered words: drop, replace by the closest known word, merge
  // with a neighbour ("room 3" -> "room3").
  std::vector<WordEdit> singles;
  auto known = [&](const std::string& word) {
    return sdk::number_value(word).has_value() ||
           std::binary_search(in.vocabulary.begin(), in.vocabulary.end(), word);
  };
  for (const RepairWord& w : r.words) {
    singles.push_back({w.at, 1, {}, "drop '" + w.word + "'"});
    if (!w.did_you_mean.empty())
      singles.push_back(
          {w.at, 1, {w.did_you_mean}, "replace '" + w.word + "' by '" + w.did_you_mean + "'"});
    // Two known words typed without a space ("itemis" -> "item is"): the first split that
    // makes both halves known.
    if (!w.known)
      for (std::size_t cut = 1; cut < w.word.size(); ++cut) {
        const std::string left = w.word.substr(0, cut), right = w.word.substr(cut);
        if (known(left) && known(right)) {
          singles.push_back({w.at, 1, {left, right}, "split '" + w.word + "'"});
          break;
        }
      }
  }
  // A colour or shape word before "item(s)" said as the core language says it ("red item" ->
  // "item is red", core-language.md §3.4); the chart's one-word derivations name such words.
  std::vector<bool> property(static_cast<std::size_t>(n), false);
  for (const auto& d : in.chart)
    if (d && d->end == d->start + 1 &&
        (d->rule->lhs.rfind("$Color", 0) == 0 || d->rule->lhs.rfind("$Shape", 0) == 0))
      property[static_cast<std::size_t>(d->start)] = true;
  for (int i = 0; i + 1 < n; ++i) {
    const auto a = static_cast<std::size_t>(i);
    if (property[a] && !(covered[a] && covered[a + 1]) &&
        (tokens[a + 1] == "item" || tokens[a + 1] == "items"))
      singles.push_back(
          {i,
           2,
           {"item", "is", tokens[a]},
           "say '" + tokens[a] + " " + tokens[a + 1] + "' as 'item is " + tokens[a] + "'"});
  }
  for (int i = 0; i + 1 < n; ++i) {
    const auto a = static_cast<std::size_t>(i);
    if ((covered[a] && covered[a + 1]) || !alphanumeric(tokens[a]) || !alphanumeric(tokens[a + 1]))
      continue;
    singles.push_back(
        {i, 2, {tokens[a] + tokens[a + 1]}, "join '" + tokens[a] + " " + tokens[a + 1] + "'"});
  }
  std::stable_sort(singles.begin(), singles.end(),
                   [](const WordEdit& a, const WordEdit& b) { return a.at < b.at; });

  std::vector<EditedSentence> variants;
  variants.reserve(singles.size() + kMaxPairedEdits * kMaxPairedEdits / 2 +
                   2 * r.understood.size() + 1);
  for (const auto& e : singles) variants.push_back({apply(tokens, {&e}), 1, e.what});
  // Understood phrases next to each other: a ';' between them makes a sequence.
  for (const auto& a : r.understood)
    for (const auto& b : r.understood)
      if (a.end == b.start) {
        auto t = tokens;
        t.insert(t.begin() + a.end, ";");
        variants.push_back({std::move(t), 1, "insert ';' after '" + a.text + "'"});
      }
  // A count after an understood phrase ("move right 3", "move right 3 times"): repeat it.
  for (const auto& p : r.understood) {
    const auto at = static_cast<std::size_t>(p.end);
    if (at >= tokens.size() || !sdk::number_value(tokens[at])) continue;
    const std::size_t after = at + 1 < tokens.size() && tokens[at + 1] == "times" ? at + 2 : at + 1;
    std::vector<std::string> t(tokens.begin(), tokens.begin() + p.start);
    t.insert(t.end(), {"repeat", tokens[at], "times"});
    t.insert(t.end(), tokens.begin() + p.start, tokens.begin() + p.end);
    t.insert(t.end(), tokens.begin() + static_cast<std::ptrdiff_t>(after), tokens.end());
    variants.push_back({std::move(t), 2, "repeat '" + p.text + "' " + tokens[at] + " times"});
  }
  // Every uncovered word dropped; each understood phrase alone.
  if (uncovered.size() > 1) {
    std::vector<std::string> t;
    for (int i = 0; i < n; ++i)
      if (covered[static_cast<std::size_t>(i)]) t.push_back(tokens[static_cast<std::size_t>(i)]);
    variants.push_back({std::move(t), static_cast<int>(uncovered.size()),
                        "drop every word outside the understood phrases", true});
  }
  for (const auto& p : r.understood)
    variants.push_back({std::vector<std::string>(tokens.begin() + p.start, tokens.begin() + p.end),
                        n - (p.end - p.start), "keep only '" + p.text + "'", true});
  // Two single edits at different words (of the first kMaxPairedEdits: bounded work).
  const std::size_t paired = std::min(singles.size(), kMaxPairedEdits);
  for (std::size_t x = 0; x < paired; ++x)
    for (std::size_t y = x + 1; y < paired; ++y)
      if (singles[x].at + singles[x].span <= singles[y].at)
        variants.push_back({apply(tokens, {&singles[x], &singles[y]}), 2,
                            singles[x].what + ", " + singles[y].what});
  // Each sentence once, as its fewest edits make it; the whole-phrase variants are parsed first
  // (a long tail of small edits must not crowd them out of the budget), then by edits.
  std::stable_sort(
      variants.begin(), variants.end(),
      [](const EditedSentence& a, const EditedSentence& b) { return a.edits < b.edits; });
  std::set<std::vector<std::string>> seen;
  std::vector<EditedSentence> order;
  for (auto& v : variants)
    if (!v.tokens.empty() && v.tokens != tokens && seen.insert(v.tokens).second)
      order.push_back(std::move(v));
  std::stable_partition(order.begin(), order.end(),
                        [](const EditedSentence& v) { return v.whole; });

  std::vector<NearSentence> found;
  for (const EditedSentence& v : order) {
    if (r.parses == kMaxRepairParses) {
      r.limited =
          "only the first " + std::to_string(kMaxRepairParses) + " edited sentences were tried";
      break;
    }
    ++r.parses;
    const std::vector<sdk::Candidate> cands = in.parse(v.tokens);
    if (cands.empty()) continue;
    found.push_back({join(v.tokens), cands.front().program, cands.front().score, v.edits, v.what});
  }
  std::stable_sort(found.begin(), found.end(), [](const NearSentence& a, const NearSentence& b) {
    return a.edits != b.edits ? a.edits < b.edits : a.score > b.score;
  });
  for (auto& s : found) {
    if (r.nearest.size() == kRepairSuggestions) break;
    if (std::none_of(r.nearest.begin(), r.nearest.end(),
                     [&](const NearSentence& t) { return sdk::equal(t.program, s.program); }))
      r.nearest.push_back(std::move(s));
  }
  // A body of several understood phrases teaches a sequence; otherwise the nearest sentence.
  if (r.teach_body.size() < 2 && !r.nearest.empty()) r.teach_body = {r.nearest.front().text};
  return r;
}

}  // namespace flipper::naturalization
