#include "flipper/replay/rule_oracle.hpp"

#include <algorithm>
#include <set>

namespace flipper::replay {

namespace {

std::string our_category(const std::string& original) {
  return original == "$ItemActionFragment" ? "$ItemAct" : original;
}

std::string shape(const std::string& lhs, const std::vector<std::string>& rhs) {
  std::string s = our_category(lhs) + " ->";
  for (const auto& sym : rhs) s += " " + our_category(sym);
  return s;
}

}  // namespace

std::string original_shape(const LoggedRule& rule) {
  return shape(rule.lhs, rule.rhs);
}

std::string our_shape(const RuleShape& rule) {
  return shape(rule.lhs, rule.rhs);
}

std::string compare_rules(const std::vector<LoggedRule>& original,
                          const std::vector<RuleShape>& ours) {
  std::set<std::string> theirs, mine;
  const bool with_semantics =
      !original.empty() && std::all_of(original.begin(), original.end(),
                                       [](const LoggedRule& r) { return !r.semantics.empty(); });
  for (const auto& r : original)
    if (with_semantics)
      theirs.insert(original_shape(r) + " => " + r.semantics);
    else if (!r.alignment)
      theirs.insert(original_shape(r));
  if (theirs.empty()) return "";
  for (const auto& r : ours)
    mine.insert(our_shape(r) + (with_semantics ? " => " + r.semantics : ""));
  if (mine == theirs) return "identical";
  const bool common = std::any_of(mine.begin(), mine.end(),
                                  [&](const std::string& s) { return theirs.count(s) != 0; });
  if (!common) return "missing";
  const bool inside = std::all_of(mine.begin(), mine.end(),
                                  [&](const std::string& s) { return theirs.count(s) != 0; });
  return inside ? "subset" : "overlap";
}

}  // namespace flipper::replay
