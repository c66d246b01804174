// Original rule index -> definition -> our rules (see deletion_map.hpp for the reasoning).
#include "flipper/replay/deletion_map.hpp"

#include <algorithm>

namespace flipper::replay {

void DeletionMap::add_definition(const Definition& def, const std::string& user,
                                 std::vector<OurRule> ours) {
  Def d{&def, user, std::move(ours), {}, 0};
  bool simple = false, best = false;
  for (const auto& r : def.rules) (r.simple_packing ? simple : best) = true;
  if (!simple) d.missing.push_back("simple");
  if (!best) d.missing.push_back("best");
  const int index = static_cast<int>(defs_.size());
  defs_.push_back(std::move(d));
  // A repeated definition re-induces rules the log already holds: they are not added again.
  for (const auto& r : def.rules) {
    if (std::find(seen_lines_.begin(), seen_lines_.end(), r.line) != seen_lines_.end()) continue;
    seen_lines_.push_back(r.line);
    entries_.push_back(index);
  }
}

DeletionMap::Mapping DeletionMap::map(const std::string& user, int index) {
  Mapping m;
  if (defs_.empty() || index < 0 || index > static_cast<int>(entries_.size())) {
    m.note = "index " + std::to_string(index) + " outside the reconstructed rule list (" +
             std::to_string(entries_.size()) + " logged rules live)";
    return m;
  }
  const auto size = static_cast<int>(entries_.size());
  const int lo = index > 0 ? entries_[index - 1] : 0;
  const int hi = index < size ? entries_[index] : static_cast<int>(defs_.size()) - 1;
  int chosen = -1, best_score = -1;
  for (int i = lo; i <= hi; ++i) {
    const Def& d = defs_[i];
    const bool lost = d.deleted < static_cast<int>(d.missing.size());
    const int score = (d.user == user ? 2 : 0) + (lost ? 1 : 0);
    if (score >= best_score) best_score = score, chosen = i;  // ties: the latest
  }
  Def& d = defs_[chosen];
  m.def_id = d.def->def_id;
  if (d.deleted >= static_cast<int>(d.missing.size())) {
    m.note = "the definition has no rule missing from the final log";
    return m;
  }
  const std::string& how = d.missing[d.deleted++];
  for (const auto& r : d.ours)
    if (r.how == how) m.ids.push_back(r.id);
  if (m.ids.empty()) m.note = "our definition has no '" + how + "' rule";
  return m;
}

}  // namespace flipper::replay
