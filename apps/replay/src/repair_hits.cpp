// The repair suggestion hit rate on a replayed corpus (repair_hits.hpp).
#include "flipper/replay/repair_hits.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <unordered_map>
#include <vector>

#include "flipper/corpus/original_text.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::replay {
namespace {

std::string joined_tokens(const std::string& text) {
  std::string s;
  for (const auto& t : sdk::tokenize(text)) s += (s.empty() ? "" : " ") + t;
  return s;
}

// The accepted program as canonical text ("" when the original's answer does not have it or
// it does not read).
std::string accepted_formula(const Corpus& corpus, const Command& accept) {
  auto it = corpus.answers.find(accept.for_qid);
  if (it == corpus.answers.end()) return {};
  const OriginalAnswer::Candidate* chosen = nullptr;
  for (const auto& k : it->second.candidates)
    if (k.formula == accept.formula) chosen = &k;
  const auto& cands = it->second.candidates;
  if (chosen == nullptr)
    if (auto r = it->second.accepted_rank; r && *r >= 0 && *r < static_cast<int>(cands.size()))
      chosen = &cands[static_cast<std::size_t>(*r)];
  if (chosen == nullptr) return {};
  try {
    return sdk::render(sdk::read_canonical(corpus::normalize_original_pretty(chosen->pretty)));
  } catch (const sdk::Error&) {
    return {};
  }
}

std::string percent(std::size_t part, std::size_t whole) {
  if (whole == 0) return "–";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f %%",
                100.0 * static_cast<double>(part) / static_cast<double>(whole));
  return buf;
}

}  // namespace

RepairHits repair_hits(const Corpus& corpus, const ReplayResult& result) {
  std::unordered_map<std::string, const QueryRow*> rows;
  for (const auto& r : result.queries) rows[r.qid] = &r;
  std::unordered_map<std::string, const Command*> accepts;  // for_qid -> accept
  for (const auto& c : corpus.commands)
    if (c.kind == "accept" && !c.for_qid.empty()) accepts.emplace(c.for_qid, &c);

  RepairHits h;
  for (const auto& source : result.runs) {
    const Run* run = corpus.find_run(source);
    if (run == nullptr) continue;
    std::map<std::string, std::vector<const Command*>> by_user;  // the user's queries, in order
    for (std::size_t i : run->commands) {
      const Command& c = corpus.commands[i];
      if (c.kind == "q") by_user[c.user].push_back(&c);
    }
    for (const auto& [user, queries] : by_user)
      for (std::size_t i = 0; i < queries.size(); ++i) {
        const Command& failed = *queries[i];
        if (failed.status != "Nothing") continue;
        const Command* accept = nullptr;
        const Command* next = nullptr;
        for (std::size_t j = i + 1; j <= i + kRepairFollowSteps && j < queries.size(); ++j)
          if (auto a = accepts.find(queries[j]->qid); a != accepts.end()) {
            accept = a->second;
            next = queries[j];
            break;
          }
        auto row = rows.find(failed.qid);
        if (accept == nullptr || row == rows.end()) continue;
        ++h.cases;
        const QueryRow& ours = *row->second;
        if (ours.ours == "error") {
          ++h.errors;
          continue;
        }
        if (ours.ours != "unparsable") {
          ++h.we_parse;
          continue;
        }
        ++h.repaired;
        if (!ours.suggestions.empty()) ++h.with_suggestions;
        const std::string text = joined_tokens(next->utterance);
        const std::string formula = accepted_formula(corpus, *accept);
        const std::size_t top = std::min(kRepairTopK, ours.suggestions.size());
        bool by_text = false, by_program = false;
        for (std::size_t k = 0; k < top; ++k) {
          by_text = by_text || ours.suggestions[k] == text;
          by_program = by_program || (!formula.empty() && k < ours.suggestion_formulas.size() &&
                                      ours.suggestion_formulas[k] == formula);
        }
        if (by_text || by_program) ++h.hits;
        if (by_text) ++h.by_text;
        if (!by_text && by_program) ++h.by_program;
      }
  }
  return h;
}

std::string repair_hits_text(const RepairHits& h) {
  auto row = [](const std::string& what, std::size_t n, const std::string& share) {
    return "| " + what + " | " + std::to_string(n) + " | " + share + " |\n";
  };
  std::string out = "| repair suggestions (dev split) | queries | share |\n|---|---|---|\n";
  out += row("original: no parse; the user's next accepted query within 3 queries", h.cases, "");
  out += row("we parse them", h.we_parse, percent(h.we_parse, h.cases));
  out += row("we refuse them (an error)", h.errors, percent(h.errors, h.cases));
  out += row("unparsable for us too: repaired", h.repaired, percent(h.repaired, h.cases));
  out += row("repairs with a nearest sentence", h.with_suggestions,
             percent(h.with_suggestions, h.repaired));
  out += row("**accepted sentence or program in the top 3**", h.hits,
             "**" + percent(h.hits, h.repaired) + "**");
  out += row("of which the same sentence", h.by_text, percent(h.by_text, h.repaired));
  out += row("of which only the same program", h.by_program, percent(h.by_program, h.repaired));
  return out;
}

}  // namespace flipper::replay
