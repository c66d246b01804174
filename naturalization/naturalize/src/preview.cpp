// Example sentences of induced rules and plan summaries (docs/naturalization.md §5 "Preview").
#include "flipper/naturalization/preview.hpp"

#include <algorithm>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::naturalization {

PlanSummary summarize(const sdk::Outcome& outcome) {
  PlanSummary s;
  s.realizable = outcome.realizable && !outcome.error;
  for (const auto& step : outcome.trace) {
    switch (step.act) {
      case sdk::TraceStep::Act::move:
        ++s.moves;
        s.end = step.cell;
        break;
      case sdk::TraceStep::Act::pick:
        ++s.picks;
        break;
      case sdk::TraceStep::Act::drop:
        ++s.drops;
        break;
    }
  }
  s.warnings = outcome.warnings;
  if (outcome.error) s.error = *outcome.error;
  return s;
}

namespace {

std::string joined(const std::vector<std::string>& tokens) {
  std::string text;
  for (const auto& t : tokens) (text += text.empty() ? "" : " ") += t;
  return text;
}

/// The words a class symbol matches, in the grammar's order (numbers: 2, 3, 4, 5).
std::vector<std::string> class_words(const sdk::Grammar& g, sdk::Symbol::Type type) {
  switch (type) {
    case sdk::Symbol::Type::number:
      return {"2", "3", "4", "5"};
    case sdk::Symbol::Type::color:
      return g.colors;
    case sdk::Symbol::Type::shape:
      return g.shapes;
    case sdk::Symbol::Type::direction:
      return g.directions.empty() ? std::vector<std::string>{"up", "down", "left", "right"}
                                  : g.directions;
    default:
      return {};
  }
}

}  // namespace

PhraseBook::PhraseBook(const sdk::Grammar& grammar) {
  // Rounds until nothing changes (bounded): each rule is tried with its categories' i-th phrases
  // (i < kPhrasesPerCategory, clamped), so phrases grow from the word classes upwards.
  constexpr int kMaxRounds = 12;
  for (int round = 0; round < kMaxRounds; ++round) {
    bool changed = false;
    for (const auto& rule : grammar.rules) {
      if (!rule || rule->lhs == grammar.root) continue;
      for (std::size_t v = 0; v < kPhrasesPerCategory; ++v) {
        Phrase p;
        std::vector<sdk::Program> kids;
        std::string token;
        bool ok = true;
        for (const auto& sym : rule->rhs) {
          if (sym.type == sdk::Symbol::Type::token) {
            p.tokens.push_back(sym.text);
          } else if (sym.type == sdk::Symbol::Type::category) {
            const auto* list = phrases_of(sym.text);
            if (list == nullptr || list->empty()) {
              ok = false;
              break;
            }
            const Phrase& kid = (*list)[std::min(v, list->size() - 1)];
            p.tokens.insert(p.tokens.end(), kid.tokens.begin(), kid.tokens.end());
            kids.push_back(kid.program);
          } else {
            const auto words = class_words(grammar, sym.type);
            if (words.empty()) {
              ok = false;
              break;
            }
            token = words[v % words.size()];
            p.tokens.push_back(token);
          }
        }
        if (!ok || p.tokens.empty() || p.tokens.size() > kMaxPhraseTokens) continue;
        try {
          p.program = sdk::apply_rule(*rule, kids, token);
        } catch (const sdk::Error&) {
          continue;  // a kid that does not fit this rule
        }
        if (!p.program) continue;
        auto& list = by_category_[rule->lhs];
        if (std::any_of(list.begin(), list.end(),
                        [&](const Phrase& q) { return q.tokens == p.tokens; }))
          continue;
        // Shortest first; equal lengths keep the order they were found in (stable).
        auto at =
            std::upper_bound(list.begin(), list.end(), p.tokens.size(),
                             [](std::size_t n, const Phrase& q) { return n < q.tokens.size(); });
        if (static_cast<std::size_t>(at - list.begin()) >= kPhrasesPerCategory) continue;
        list.insert(at, std::move(p));
        if (list.size() > kPhrasesPerCategory) list.pop_back();
        changed = true;
      }
    }
    if (!changed) break;
  }
}

const std::vector<PhraseBook::Phrase>* PhraseBook::phrases_of(const std::string& category) const {
  if (auto it = by_category_.find(category); it != by_category_.end()) return &it->second;
  // An induced rule names list categories by their element ($Actions -> $Action) and may use
  // the normal form of an auxiliary one.
  if (auto it = by_category_.find(sdk::normalize_category(category)); it != by_category_.end())
    return &it->second;
  return nullptr;
}

std::vector<ExampleSentence> PhraseBook::examples(const sdk::Rule& rule, const std::string& head,
                                                  std::size_t count) const {
  std::vector<ExampleSentence> out;
  if (std::none_of(rule.rhs.begin(), rule.rhs.end(),
                   [](const sdk::Symbol& sym) { return sym.type == sdk::Symbol::Type::category; }))
    return out;
  const std::string head_text = joined(sdk::tokenize(head));
  std::vector<std::string> seen{head_text};
  for (std::size_t i = 0; i < kPhrasesPerCategory && out.size() < count; ++i) {
    std::vector<std::string> tokens;
    std::vector<sdk::Program> kids;
    bool ok = true;
    for (const auto& sym : rule.rhs) {
      if (sym.type != sdk::Symbol::Type::category) {
        tokens.push_back(sym.text);
        continue;
      }
      const auto* list = phrases_of(sym.text);
      if (list == nullptr || list->empty()) {
        ok = false;
        break;
      }
      const Phrase& p = (*list)[i % list->size()];
      tokens.insert(tokens.end(), p.tokens.begin(), p.tokens.end());
      kids.push_back(p.program);
    }
    if (!ok) break;
    std::string text = joined(tokens);
    if (std::find(seen.begin(), seen.end(), text) != seen.end()) continue;
    sdk::Program program;
    try {
      program = sdk::apply_rule(rule, kids);
    } catch (const sdk::Error&) {
      continue;
    }
    seen.push_back(text);
    out.push_back({std::move(text), std::move(program)});
  }
  return out;
}

}  // namespace flipper::naturalization
